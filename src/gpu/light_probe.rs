//! The light twin probe: runs `src/gpu/light_probe.wgsl` (light.wgsl's `light_sample_li`,
//! `light_pdf_li`, `light_le`, `light_sample_le`, `light_pdf_le`, `light_set_pick`,
//! `light_set_area`) on a scene's packed lights, so `tests/light_twin.rs` can compare every
//! light type with the Rust `scene::light::Light` methods.

use super::buffers::{checked_storage, zeroed_storage};
use super::layout::{
    GpuLayout, Light as GpuLight, LightProbeCase, LightProbeOut, LightProbeParams, Material,
    Triangle,
};
use super::pipeline::{create_module, dispatch_once, light_probe_source};
use super::{GpuContext, upload};
use crate::scene::Scene;
use crate::scene::light::{Light, LightSet};
use anyhow::Result;
use wgpu::util::DeviceExt;

/// Evaluate the WGSL lights of `scene` (packed as the renderer packs them: `LightSet::build`,
/// BVH leaf order, `upload::pack_lights`) on `cases`.
pub fn run_light_probe(
    ctx: &GpuContext,
    scene: &Scene,
    cases: &[LightProbeCase],
) -> Result<Vec<LightProbeOut>> {
    anyhow::ensure!(!cases.is_empty(), "no light probe cases");
    let packed = PackedProbeScene::new(scene)?;
    let module = create_module(ctx, "light_probe.wgsl", light_probe_source())?;
    let buffers = ProbeBuffers::new(ctx, scene, packed, cases)?;
    buffers.dispatch(ctx, &module, cases.len() as u32);
    let bytes = ctx.read_buffer(&buffers.output, buffers.out_size)?;
    Ok(bytemuck::pod_collect_to_vec(&bytes))
}

/// The scene data the probe binds, packed on the CPU as the renderer packs it.
struct PackedProbeScene {
    params: LightProbeParams,
    triangles: Vec<Triangle>,
    materials: Vec<Material>,
    lights: Vec<GpuLight>,
    texels: Vec<[f32; 4]>,
}

impl PackedProbeScene {
    /// Pack `scene`'s triangles (BVH leaf order), textures, environment, materials and
    /// lights, and the probe's parameters.
    fn new(scene: &Scene) -> Result<PackedProbeScene> {
        let set = LightSet::build(scene);
        let bvh = upload::build_bvh(scene)?;
        let triangles = upload::pack_triangles(scene, &bvh, &set);
        let (mut texels, tex_slots) = upload::pack_textures(scene);
        let env_offset = upload::pack_environment(&set, &mut texels);
        let materials = upload::pack_materials(scene, &tex_slots);
        let (lights, light_count) = upload::pack_lights(&bvh, &set, env_offset);
        let e = scene.environment;
        // The uniform environment's bounding sphere (the probe's `light_environment`).
        let sphere = match &set.environment {
            Light::Environment(u) => u.center.extend(u.radius).to_array(),
            _ => [0.0; 4],
        };
        let params = LightProbeParams {
            environment: [e.x, e.y, e.z, 0.0],
            sphere,
            light_count,
            ..Default::default()
        };
        Ok(PackedProbeScene {
            params,
            triangles,
            materials,
            lights,
            texels,
        })
    }
}

/// The probe's GPU buffers: the packed scene, the cases and the zeroed output.
struct ProbeBuffers {
    params: wgpu::Buffer,
    triangles: wgpu::Buffer,
    vertices: wgpu::Buffer,
    materials: wgpu::Buffer,
    lights: wgpu::Buffer,
    texels: wgpu::Buffer,
    input: wgpu::Buffer,
    output: wgpu::Buffer,
    /// Bytes of `output`: one `LightProbeOut` per case.
    out_size: u64,
}

impl ProbeBuffers {
    /// Upload `packed` (and `scene`'s vertices) and `cases`; an error names what is larger
    /// than one binding of the device.
    fn new(
        ctx: &GpuContext,
        scene: &Scene,
        packed: PackedProbeScene,
        cases: &[LightProbeCase],
    ) -> Result<ProbeBuffers> {
        let params = ctx
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("light probe params"),
                contents: bytemuck::bytes_of(&packed.params),
                usage: wgpu::BufferUsages::UNIFORM,
            });
        let triangles = checked_storage(ctx, "triangles", "triangles", &packed.triangles)?;
        let vertices = upload::pack_vertices(scene);
        let vertices = checked_storage(ctx, "vertices", "vertices", &vertices)?;
        let materials = checked_storage(ctx, "materials", "materials", &packed.materials)?;
        let lights = checked_storage(ctx, "lights", "lights", &packed.lights)?;
        let texels = checked_storage(ctx, "texels", "textures", &packed.texels)?;
        let input = checked_storage(ctx, "light probe cases", "light probe cases", cases)?;
        let out_size = (cases.len() * LightProbeOut::size() as usize) as u64;
        let output = zeroed_storage(
            ctx,
            "light probe out",
            out_size,
            wgpu::BufferUsages::COPY_SRC,
        );
        Ok(ProbeBuffers {
            params,
            triangles,
            vertices,
            materials,
            lights,
            texels,
            input,
            output,
            out_size,
        })
    }

    /// Run `light_probe` of `module` once over `count` cases.
    fn dispatch(&self, ctx: &GpuContext, module: &wgpu::ShaderModule, count: u32) {
        // Binding numbers of scene.wgsl (triangles 2, vertices 3 (emissive textures' uv),
        // materials 4, lights 5, texels 8) and light_probe.wgsl.
        dispatch_once(
            ctx,
            module,
            "light_probe",
            &[
                (0, &self.params),
                (2, &self.triangles),
                (3, &self.vertices),
                (4, &self.materials),
                (5, &self.lights),
                (6, &self.input),
                (7, &self.output),
                (8, &self.texels),
            ],
            count,
        );
    }
}
