//! The light twin probe: runs `src/shaders/light_probe.wgsl` (light.wgsl's `light_sample_li`,
//! `light_pdf_li`, `light_le`, `light_sample_le`, `light_pdf_le`, `light_set_pick`,
//! `light_set_area`) on a scene's packed lights, so `tests/light_twin.rs` can compare every
//! light type with the Rust `scene::light::Light` methods.

use super::buffers::{checked_storage, zeroed_storage};
use super::layout::{GpuLayout, LightProbeCase, LightProbeOut, LightProbeParams};
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
    let module = create_module(ctx, "light_probe.wgsl", light_probe_source())?;
    let params = ctx
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("light probe params"),
            contents: bytemuck::bytes_of(&params),
            usage: wgpu::BufferUsages::UNIFORM,
        });
    let triangles = checked_storage(ctx, "triangles", "triangles", &triangles)?;
    let vertices = upload::pack_vertices(scene);
    let vertices = checked_storage(ctx, "vertices", "vertices", &vertices)?;
    let materials = checked_storage(ctx, "materials", "materials", &materials)?;
    let lights = checked_storage(ctx, "lights", "lights", &lights)?;
    let texels = checked_storage(ctx, "texels", "textures", &texels)?;
    let input = checked_storage(ctx, "light probe cases", "light probe cases", cases)?;
    let out_size = (cases.len() * LightProbeOut::size() as usize) as u64;
    let output = zeroed_storage(
        ctx,
        "light probe out",
        out_size,
        wgpu::BufferUsages::COPY_SRC,
    );
    // Binding numbers of scene.wgsl (triangles 2, vertices 3 (emissive textures' uv),
    // materials 4, lights 5, texels 8) and light_probe.wgsl.
    dispatch_once(
        ctx,
        &module,
        "light_probe",
        &[
            (0, &params),
            (2, &triangles),
            (3, &vertices),
            (4, &materials),
            (5, &lights),
            (6, &input),
            (7, &output),
            (8, &texels),
        ],
        cases.len() as u32,
    );
    let bytes = ctx.read_buffer(&output, out_size)?;
    Ok(bytemuck::pod_collect_to_vec(&bytes))
}
