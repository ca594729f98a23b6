//! WGSL assembly, pipeline specialisation and the pipeline cache.
//!
//! The kernel is specialised by WGSL override constants (`HAS_*`), so features a scene lacks
//! are compiled out by the driver. The key is derived from the scene's *kinds* (which BSDFs
//! and light types exist), never from parameter values, so moving a slider (IOR, colour,
//! roughness within a kind, emission, environment) never recompiles. Pipelines are cached per
//! key.

use super::GpuContext;
use super::layout::{GpuLayout, ProbeCase, ProbeOut};
use crate::scene::Features;
use anyhow::Result;
use std::collections::HashMap;

const COMMON: &str = include_str!("../shaders/common.wgsl");
const RNG: &str = include_str!("../shaders/rng.wgsl");
const SPECTRUM: &str = include_str!("../shaders/spectrum.wgsl");
// The BSDFs: one file per src/bsdf/*.rs, the dispatch (mod.rs) first.
const BSDF: &str = include_str!("../shaders/bsdf.wgsl");
const FRESNEL: &str = include_str!("../shaders/fresnel.wgsl");
const MICROFACET: &str = include_str!("../shaders/microfacet.wgsl");
const DIFFUSE: &str = include_str!("../shaders/diffuse.wgsl");
const CONDUCTOR: &str = include_str!("../shaders/conductor.wgsl");
const DIELECTRIC: &str = include_str!("../shaders/dielectric.wgsl");
const THIN: &str = include_str!("../shaders/thin.wgsl");
const GLOSSY: &str = include_str!("../shaders/glossy.wgsl");
const ROUGH_DIELECTRIC: &str = include_str!("../shaders/rough_dielectric.wgsl");
const METAL_ROUGH: &str = include_str!("../shaders/metal_rough.wgsl");
const SCENE: &str = include_str!("../shaders/scene.wgsl");
const LIGHT: &str = include_str!("../shaders/light.wgsl");
const SPECTRAL: &str = include_str!("../shaders/spectral.wgsl");
const MATERIAL: &str = include_str!("../shaders/material.wgsl");
const PATH_FILTER: &str = include_str!("../shaders/path_filter.wgsl");
const INTERACTION: &str = include_str!("../shaders/interaction.wgsl");
const INTEGRATOR: &str = include_str!("../shaders/integrator.wgsl");
const LIGHT_TRACING: &str = include_str!("../shaders/light_tracing.wgsl");
const PHOTON: &str = include_str!("../shaders/photon.wgsl");
const PROBE: &str = include_str!("../shaders/probe.wgsl");
const LIGHT_PROBE: &str = include_str!("../shaders/light_probe.wgsl");

/// The maths shared by every kernel, in assembly order (twins of src/math and src/bsdf).
const MATHS: &[&str] = &[
    COMMON,
    RNG,
    SPECTRUM,
    BSDF,
    FRESNEL,
    MICROFACET,
    DIFFUSE,
    CONDUCTOR,
    DIELECTRIC,
    THIN,
    GLOSSY,
    ROUGH_DIELECTRIC,
    METAL_ROUGH,
];

/// Every kernel source file by name (tests check that none defines a prelude constant).
pub const SHADER_FILES: &[(&str, &str)] = &[
    ("common.wgsl", COMMON),
    ("rng.wgsl", RNG),
    ("spectrum.wgsl", SPECTRUM),
    ("bsdf.wgsl", BSDF),
    ("fresnel.wgsl", FRESNEL),
    ("microfacet.wgsl", MICROFACET),
    ("diffuse.wgsl", DIFFUSE),
    ("conductor.wgsl", CONDUCTOR),
    ("dielectric.wgsl", DIELECTRIC),
    ("thin.wgsl", THIN),
    ("glossy.wgsl", GLOSSY),
    ("rough_dielectric.wgsl", ROUGH_DIELECTRIC),
    ("metal_rough.wgsl", METAL_ROUGH),
    ("scene.wgsl", SCENE),
    ("light.wgsl", LIGHT),
    ("spectral.wgsl", SPECTRAL),
    ("material.wgsl", MATERIAL),
    ("path_filter.wgsl", PATH_FILTER),
    ("interaction.wgsl", INTERACTION),
    ("integrator.wgsl", INTEGRATOR),
    ("light_tracing.wgsl", LIGHT_TRACING),
    ("photon.wgsl", PHOTON),
    ("probe.wgsl", PROBE),
    ("light_probe.wgsl", LIGHT_PROBE),
];

/// The generated prelude, then `parts`.
fn assemble(parts: &[&str]) -> String {
    let mut s = super::prelude::wgsl_prelude();
    for p in parts {
        s.push('\n');
        s.push_str(p);
    }
    s
}

/// The integrator kernel's full WGSL source: prelude, maths, scene, lights, the per-vertex
/// step, then the walks (camera, light, photon).
pub fn integrator_source() -> String {
    let kernel = [
        SCENE,
        LIGHT,
        SPECTRAL,
        MATERIAL,
        PATH_FILTER,
        INTERACTION,
        INTEGRATOR,
        LIGHT_TRACING,
        PHOTON,
    ];
    assemble(&[MATHS, &kernel].concat())
}

/// The probe kernel's full WGSL source (prelude and maths only, no scene).
pub fn probe_source() -> String {
    assemble(&[MATHS, &[PROBE]].concat())
}

/// The light probe kernel's full WGSL source: prelude, maths, scene bindings, lights.
pub fn light_probe_source() -> String {
    assemble(&[MATHS, &[SCENE, LIGHT, LIGHT_PROBE]].concat())
}

/// Which parts of the kernel a scene needs (the pipeline cache key). The environment is
/// always compiled in (its radiance is a slider: value edits must not recompile).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Specialization {
    pub lambert: bool,
    pub mirror: bool,
    pub smooth_dielectric: bool,
    pub thin_dielectric: bool,
    pub rough_dielectric: bool,
    pub rough_conductor: bool,
    pub metal_rough: bool,
    /// Tabulated metals with the conductor Fresnel term (smooth or rough).
    pub conductor: bool,
    /// Microfacet distributions in use (rough glass / glossy metal; metal-rough is GGX).
    pub ggx: bool,
    pub beckmann: bool,
    /// Emissive triangles (area lights).
    pub area_lights: bool,
    pub punctual_lights: bool,
    /// An environment image (next-event estimation samples it; escaping rays weight it).
    pub env_image: bool,
    /// Solid glass exists (absorption is a slider on it, so keyed by the kind).
    pub absorption: bool,
    /// Some BSDF reads a texture.
    pub textures: bool,
    /// A Heckbert path filter is set (the table itself is a uniform: edits do not recompile).
    pub filter: bool,
    /// Hero-wavelength spectral transport (a dispersive material exists).
    pub spectral: bool,
    /// Light tracing combined with path tracing by MIS (`lt+pt`; the estimator, not the scene).
    pub light_tracing: bool,
    /// Path tracing with photon-mapped caustics (`sppm`; the estimator, not the scene).
    pub sppm: bool,
    /// Nested dielectric volumes: paths keep the medium stack and pass false hits.
    pub nested: bool,
}

impl Specialization {
    /// The kernel parts `f` needs (no filter, path tracing).
    pub fn from_features(f: Features) -> Specialization {
        Specialization {
            lambert: f.contains(Features::DIFFUSE),
            mirror: f.contains(Features::MIRROR),
            smooth_dielectric: f.contains(Features::SMOOTH_GLASS),
            thin_dielectric: f.contains(Features::THIN_GLASS),
            rough_dielectric: f.contains(Features::ROUGH_GLASS),
            rough_conductor: f.contains(Features::GLOSSY_METAL),
            metal_rough: f.contains(Features::METAL_ROUGH),
            conductor: f.intersects(Features::SMOOTH_CONDUCTOR | Features::ROUGH_FRESNEL_CONDUCTOR),
            ggx: f.contains(Features::GGX),
            beckmann: f.contains(Features::BECKMANN),
            area_lights: f.contains(Features::AREA_LIGHTS),
            punctual_lights: f.contains(Features::PUNCTUAL_LIGHTS),
            env_image: f.contains(Features::ENV_IMAGE),
            absorption: f.intersects(Features::SMOOTH_GLASS | Features::ROUGH_GLASS),
            textures: f.contains(Features::TEXTURES),
            filter: false,
            spectral: f.contains(Features::DISPERSION),
            light_tracing: false,
            sppm: false,
            nested: f.contains(Features::NESTED),
        }
    }

    /// Every part compiled in (the worst case for registers), with light tracing as the
    /// estimator: the estimators are exclusive (the renderer sets at most one of
    /// `light_tracing` and `sppm`), so [`Specialization::all_sppm`] is the other worst case.
    pub fn all() -> Specialization {
        Specialization {
            lambert: true,
            mirror: true,
            smooth_dielectric: true,
            thin_dielectric: true,
            rough_dielectric: true,
            rough_conductor: true,
            metal_rough: true,
            conductor: true,
            ggx: true,
            beckmann: true,
            area_lights: true,
            punctual_lights: true,
            absorption: true,
            textures: true,
            filter: true,
            spectral: true,
            light_tracing: true,
            sppm: false,
            nested: true,
            env_image: true,
        }
    }

    /// Every part compiled in, with photon mapping as the estimator (`sppm`).
    pub fn all_sppm() -> Specialization {
        Specialization {
            light_tracing: false,
            sppm: true,
            ..Specialization::all()
        }
    }

    /// The override constants that specialise the integrator module.
    pub fn constants(&self) -> Vec<(&'static str, f64)> {
        let b = |x: bool| if x { 1.0 } else { 0.0 };
        vec![
            ("HAS_LAMBERT", b(self.lambert)),
            ("HAS_MIRROR", b(self.mirror)),
            ("HAS_SMOOTH_DIELECTRIC", b(self.smooth_dielectric)),
            ("HAS_THIN_DIELECTRIC", b(self.thin_dielectric)),
            ("HAS_ROUGH_DIELECTRIC", b(self.rough_dielectric)),
            ("HAS_ROUGH_CONDUCTOR", b(self.rough_conductor)),
            ("HAS_METAL_ROUGH", b(self.metal_rough)),
            ("HAS_CONDUCTOR", b(self.conductor)),
            ("HAS_GGX", b(self.ggx)),
            ("HAS_BECKMANN", b(self.beckmann)),
            ("HAS_LIGHTS", b(self.area_lights)),
            ("HAS_PUNCTUAL", b(self.punctual_lights)),
            ("HAS_ENVIRONMENT", 1.0),
            ("HAS_ENV_IMAGE", b(self.env_image)),
            ("HAS_ABSORPTION", b(self.absorption)),
            ("HAS_TEXTURES", b(self.textures)),
            ("HAS_FILTER", b(self.filter)),
            ("HAS_SPECTRAL", b(self.spectral)),
            ("HAS_LT", b(self.light_tracing)),
            ("HAS_SPPM", b(self.sppm)),
            ("HAS_NESTED", b(self.nested)),
        ]
    }
}

/// The entry points of the integrator module.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Kernel {
    /// Camera paths (`render`): path tracing, plus folding light-tracing splats into the film.
    Render,
    /// Light subpaths connected to the camera (`light_trace`, only with `light_tracing`).
    LightTrace,
    /// Caustic photons stored in the hash grid (`photon_trace`, only with `sppm`).
    PhotonTrace,
}

impl Kernel {
    /// Every kernel of the integrator module.
    pub const ALL: [Kernel; 3] = [Kernel::Render, Kernel::LightTrace, Kernel::PhotonTrace];

    /// The WGSL entry point's name.
    pub fn entry(self) -> &'static str {
        match self {
            Kernel::Render => "render",
            Kernel::LightTrace => "light_trace",
            Kernel::PhotonTrace => "photon_trace",
        }
    }
}

/// Storage buffers the integrator binds (bindings 1–8 and 10–12).
pub const STORAGE_BUFFERS: u32 = 11;

/// The integrator's bind group layout, shader module and specialised pipelines.
pub struct Pipelines {
    pub bind_group_layout: wgpu::BindGroupLayout,
    layout: wgpu::PipelineLayout,
    module: wgpu::ShaderModule,
    cache: HashMap<(Specialization, Kernel), wgpu::ComputePipeline>,
    /// Number of pipelines compiled so far (tests check that edits do not recompile).
    pub compiled: u32,
}

/// A compute-stage buffer binding of type `ty`.
fn buffer_entry(binding: u32, ty: wgpu::BufferBindingType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

fn storage_entry(binding: u32, read_only: bool) -> wgpu::BindGroupLayoutEntry {
    buffer_entry(binding, wgpu::BufferBindingType::Storage { read_only })
}

fn uniform_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    buffer_entry(binding, wgpu::BufferBindingType::Uniform)
}

/// Compile a WGSL module, turning validation errors into `Err` instead of a panic.
pub fn create_module(ctx: &GpuContext, label: &str, source: String) -> Result<wgpu::ShaderModule> {
    // Validate with naga first: a clear error message, and wgpu would panic on a bad module.
    let module = naga::front::wgsl::parse_str(&source)
        .map_err(|e| anyhow::anyhow!("{label}: {}", e.emit_to_string(&source)))?;
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .map_err(|e| anyhow::anyhow!("{label}: {}", e.emit_to_string(&source)))?;
    Ok(ctx
        .device
        .create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(label),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        }))
}

impl Pipelines {
    pub fn new(ctx: &GpuContext) -> Result<Pipelines> {
        let max = ctx.device.limits().max_storage_buffers_per_shader_stage;
        anyhow::ensure!(
            max >= STORAGE_BUFFERS,
            "GPU adapter '{}' allows {max} storage buffers per shader stage; refract needs \
             {STORAGE_BUFFERS} (use --device cpu)",
            ctx.info.name
        );
        let module = create_module(ctx, "integrator.wgsl", integrator_source())?;
        let mut entries = vec![uniform_entry(0)];
        for b in 1..=5 {
            entries.push(storage_entry(b, true));
        }
        entries.push(storage_entry(6, false));
        entries.push(storage_entry(7, false));
        // Texture references + texels (8 storage buffers in all), the path filter (uniform).
        entries.push(storage_entry(8, true));
        entries.push(uniform_entry(9));
        // Light-tracing splats (fixed-point atomics).
        entries.push(storage_entry(10, false));
        // The photon grid (atomics) and the photons (`sppm`, photon.wgsl).
        entries.push(storage_entry(11, false));
        entries.push(storage_entry(12, false));
        let bind_group_layout =
            ctx.device
                .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                    label: Some("integrator"),
                    entries: &entries,
                });
        let layout = ctx
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("integrator"),
                bind_group_layouts: &[Some(&bind_group_layout)],
                immediate_size: 0,
            });
        Ok(Pipelines {
            bind_group_layout,
            layout,
            module,
            cache: HashMap::new(),
            compiled: 0,
        })
    }

    /// The `render` pipeline for `spec` (compiled on first use, then cached).
    pub fn get(&mut self, ctx: &GpuContext, spec: Specialization) -> &wgpu::ComputePipeline {
        self.get_kernel(ctx, spec, Kernel::Render)
    }

    /// The pipeline of `kernel` for `spec` (compiled on first use, then cached).
    pub fn get_kernel(
        &mut self,
        ctx: &GpuContext,
        spec: Specialization,
        kernel: Kernel,
    ) -> &wgpu::ComputePipeline {
        let (layout, module, compiled) = (&self.layout, &self.module, &mut self.compiled);
        self.cache.entry((spec, kernel)).or_insert_with(|| {
            *compiled += 1;
            let constants = spec.constants();
            ctx.device
                .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some("integrator"),
                    layout: Some(layout),
                    module,
                    entry_point: Some(kernel.entry()),
                    compilation_options: wgpu::PipelineCompilationOptions {
                        constants: &constants,
                        zero_initialize_workgroup_memory: false,
                    },
                    cache: None,
                })
        })
    }
}

/// Run the probe kernel (src/shaders/probe.wgsl) on `cases`.
pub fn run_probe(ctx: &GpuContext, cases: &[ProbeCase]) -> Result<Vec<ProbeOut>> {
    use wgpu::util::DeviceExt;
    anyhow::ensure!(!cases.is_empty(), "no probe cases");
    let module = create_module(ctx, "probe.wgsl", probe_source())?;
    let input = ctx
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("probe cases"),
            contents: bytemuck::cast_slice(cases),
            usage: wgpu::BufferUsages::STORAGE,
        });
    let out_size = (cases.len() * ProbeOut::size() as usize) as u64;
    let output = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("probe out"),
        size: out_size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    dispatch_once(
        ctx,
        &module,
        "probe",
        &[(0, &input), (1, &output)],
        cases.len() as u32,
    );
    let bytes = ctx.read_buffer(&output, out_size)?;
    Ok(bytemuck::pod_collect_to_vec(&bytes))
}

/// Run entry point `entry` of `module` once over `threads` invocations (workgroups of 64)
/// with `buffers` bound at their binding numbers of group 0 (the layout derived from the
/// shader), and submit it (the probe kernels; the caller reads its output buffer back).
pub(crate) fn dispatch_once(
    ctx: &GpuContext,
    module: &wgpu::ShaderModule,
    entry: &str,
    buffers: &[(u32, &wgpu::Buffer)],
    threads: u32,
) {
    let pipeline = ctx
        .device
        .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(entry),
            layout: None,
            module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            cache: None,
        });
    let entries: Vec<wgpu::BindGroupEntry> = buffers
        .iter()
        .map(|&(binding, b)| wgpu::BindGroupEntry {
            binding,
            resource: b.as_entire_binding(),
        })
        .collect();
    let bg = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(entry),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &entries,
    });
    let mut enc = ctx
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
    {
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bg, &[]);
        pass.dispatch_workgroups(threads.div_ceil(64), 1, 1);
    }
    ctx.queue.submit([enc.finish()]);
}
