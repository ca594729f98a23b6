//! WGSL assembly, pipeline specialisation and the pipeline cache.
//!
//! The kernel is specialised by WGSL override constants (`HAS_*`), so features a scene lacks
//! are compiled out by the driver. The key is derived from the scene's *kinds* (which BSDFs
//! and light types exist), never from parameter values, so moving a slider (IOR, colour,
//! roughness within a kind, emission, environment) never recompiles. Pipelines are cached per
//! key, in memory and, through the driver's pipeline cache, on disk (`pipeline_cache`).
//! [`Pipelines::compile_in_background`] compiles a specialisation on a worker thread, so the
//! viewer keeps drawing while the driver compiles (seconds for every feature on RADV).

use super::GpuContext;
use super::layout::{GpuLayout, ProbeCase, ProbeOut};
use super::pipeline_cache::DiskPipelineCache;
use crate::scene::Features;
use anyhow::{Context, Result};
use std::collections::HashMap;
use std::sync::Arc;
use std::time::{Duration, Instant};

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
const WAVEFRONT: &str = include_str!("../shaders/wavefront.wgsl");
const LIGHT_WAVEFRONT: &str = include_str!("../shaders/light_wavefront.wgsl");
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
    ("wavefront.wgsl", WAVEFRONT),
    ("light_wavefront.wgsl", LIGHT_WAVEFRONT),
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
        WAVEFRONT,
        LIGHT_WAVEFRONT,
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
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
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
    /// A material has a tangent-space normal map (the mesh carries tangents).
    pub normal_map: bool,
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
    /// Camera paths by the wavefront kernels (`Kernel::WfStart` … `WfFinish`, and for lt+pt
    /// `LtWfStart` … `LtWfFinish` instead of `light_trace`) instead of `render`:
    /// chosen where the megakernel needs more registers than a GPU can give without
    /// losing occupancy ([`Specialization::wants_wavefront`]).
    pub wavefront: bool,
    /// Traversal stack entries per invocation (`upload::bvh_stack_entries` of the uploaded
    /// tree's depth; the full 64 where the tree is not known). Workgroup memory, so it
    /// bounds occupancy: 64 entries allow 4 subgroups per SIMD on RDNA2, 24 allow 10.
    pub bvh_stack: u32,
}

impl Default for Specialization {
    /// No part compiled in, the full traversal stack.
    fn default() -> Self {
        Specialization::from_features(Features::empty())
    }
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
            normal_map: f.contains(Features::NORMAL_MAP),
            filter: false,
            spectral: f.contains(Features::DISPERSION),
            light_tracing: false,
            sppm: false,
            nested: f.contains(Features::NESTED),
            wavefront: false,
            bvh_stack: super::upload::MAX_BVH_DEPTH,
        }
    }

    /// Whether the camera walk should run as a wavefront: where the megakernel needs more
    /// than 128 VGPRs on RADV navi21 (fewer than 8 waves per SIMD) — measured for every
    /// built-in with each GPU estimator and for the all-features worst cases, and checked
    /// against the compiler by `tests/gpu_registers.rs`: the image environment, textures, or
    /// light tracing or photon mapping together with spectral, nested or filtered paths or
    /// the metal-rough material, or light tracing with rough glass. Elsewhere the
    /// megakernel fits and keeps its paths in registers.
    pub fn wants_wavefront(&self) -> bool {
        let joint = self.light_tracing || self.sppm;
        self.env_image
            || self.textures
            || (joint && (self.spectral || self.nested || self.filter || self.metal_rough))
            || (self.light_tracing && self.rough_dielectric)
    }

    /// The kernel parts `scene` needs (as [`Specialization::from_features`]) with the
    /// traversal stack sized for the BVH2 the renderer uploads for it (built here) and the
    /// camera walk's form by [`Specialization::wants_wavefront`] — what the renderer runs
    /// for the path estimator.
    pub fn for_scene(scene: &crate::scene::Scene) -> anyhow::Result<Specialization> {
        let depth = super::upload::build_bvh(scene)?.depth;
        Ok(Specialization::from_features(scene.features())
            .with_bvh_depth(depth)
            .with_wavefront_rule())
    }

    /// The same parts with `wavefront` set by [`Specialization::wants_wavefront`].
    pub fn with_wavefront_rule(self) -> Specialization {
        Specialization {
            wavefront: self.wants_wavefront(),
            ..self
        }
    }

    /// The same kernel parts with the traversal stack sized for a BVH2 of `depth` levels.
    pub fn with_bvh_depth(self, depth: u32) -> Specialization {
        Specialization {
            bvh_stack: super::upload::bvh_stack_entries(depth),
            ..self
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
            normal_map: true,
            filter: true,
            spectral: true,
            light_tracing: true,
            sppm: false,
            nested: true,
            env_image: true,
            wavefront: true,
            bvh_stack: super::upload::MAX_BVH_DEPTH,
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
            ("HAS_NORMAL_MAP", b(self.normal_map)),
            ("HAS_FILTER", b(self.filter)),
            ("HAS_SPECTRAL", b(self.spectral)),
            ("HAS_LT", b(self.light_tracing)),
            ("HAS_SPPM", b(self.sppm)),
            ("HAS_NESTED", b(self.nested)),
            ("BVH_STACK_SIZE", f64::from(self.bvh_stack)),
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
    /// `render` as a wavefront (wavefront.wgsl, with `Specialization::wavefront`): camera
    /// rays, then per bounce closest hits, next-event estimates, the rest of the vertex and
    /// the estimates' shadow rays, then the film.
    WfStart,
    WfExtend,
    WfNee,
    WfShade,
    WfConnect,
    WfFinish,
    /// Between a wavefront's bounces (camera or light): the next queue of live paths made
    /// the running one, its dispatch size written.
    WfAdvance,
    /// `light_trace` as a wavefront (light_wavefront.wgsl, lt+pt with
    /// `Specialization::wavefront`): subpath starts, per bounce closest hits, vertices and
    /// camera connections' shadow rays (splats), then the rejected count.
    LtWfStart,
    LtWfExtend,
    LtWfShade,
    LtWfSplat,
    LtWfFinish,
}

impl Kernel {
    /// Every kernel of the integrator module.
    pub const ALL: [Kernel; 15] = [
        Kernel::Render,
        Kernel::LightTrace,
        Kernel::PhotonTrace,
        Kernel::WfStart,
        Kernel::WfExtend,
        Kernel::WfNee,
        Kernel::WfShade,
        Kernel::WfConnect,
        Kernel::WfFinish,
        Kernel::WfAdvance,
        Kernel::LtWfStart,
        Kernel::LtWfExtend,
        Kernel::LtWfShade,
        Kernel::LtWfSplat,
        Kernel::LtWfFinish,
    ];

    /// The WGSL entry point's name.
    pub fn entry(self) -> &'static str {
        match self {
            Kernel::Render => "render",
            Kernel::LightTrace => "light_trace",
            Kernel::PhotonTrace => "photon_trace",
            Kernel::WfStart => "wf_start",
            Kernel::WfExtend => "wf_extend",
            Kernel::WfNee => "wf_nee",
            Kernel::WfShade => "wf_shade",
            Kernel::WfConnect => "wf_connect",
            Kernel::WfFinish => "wf_finish",
            Kernel::WfAdvance => "wf_advance",
            Kernel::LtWfStart => "lt_wf_start",
            Kernel::LtWfExtend => "lt_wf_extend",
            Kernel::LtWfShade => "lt_wf_shade",
            Kernel::LtWfSplat => "lt_wf_splat",
            Kernel::LtWfFinish => "lt_wf_finish",
        }
    }
}

/// Storage buffers the integrator binds (group 0: bindings 1–8, 10–13, 15 and 16; and
/// `wf_advance`'s group 1).
pub const STORAGE_BUFFERS: u32 = 15;

/// The integrator's bind group layout, shader module and specialised pipelines.
pub struct Pipelines {
    pub bind_group_layout: wgpu::BindGroupLayout,
    /// Group 1 of `wf_advance` alone: the wavefront's indirect dispatch size, which the other
    /// kernels' layouts leave out so that it can be their indirect argument in the same pass.
    pub advance_group_layout: wgpu::BindGroupLayout,
    device: wgpu::Device,
    layout: wgpu::PipelineLayout,
    advance_layout: wgpu::PipelineLayout,
    module: wgpu::ShaderModule,
    /// The driver's pipeline cache, kept on disk (None: the device has none).
    disk_cache: Option<Arc<DiskPipelineCache>>,
    cache: HashMap<(Specialization, Kernel), wgpu::ComputePipeline>,
    /// Specialisations being compiled on worker threads.
    pending: Vec<Pending>,
    /// Number of pipelines compiled so far (tests check that edits do not recompile).
    pub compiled: u32,
    /// Wall time of the last specialisation's pipeline creation (all its kernels).
    pub last_compile: Option<Duration>,
}

/// The compiled kernels of one specialisation, and how long their creation took.
type Compiled = Result<(Vec<(Kernel, wgpu::ComputePipeline)>, Duration)>;

/// A specialisation's pipelines being compiled on a worker thread.
struct Pending {
    spec: Specialization,
    thread: std::thread::JoinHandle<Compiled>,
}

/// What a compilation needs (wgpu handles are reference-counted and `Send + Sync`: a worker
/// thread compiles while the caller's thread keeps submitting).
#[derive(Clone)]
struct Compiler {
    device: wgpu::Device,
    layout: wgpu::PipelineLayout,
    advance_layout: wgpu::PipelineLayout,
    module: wgpu::ShaderModule,
    disk_cache: Option<Arc<DiskPipelineCache>>,
}

impl Compiler {
    /// Create the pipelines of `kernels` for `spec` in error scopes (validation and
    /// out-of-memory errors are an `Err`), then write the pipeline cache back to disk (a
    /// failed write is a warning).
    fn compile(&self, spec: Specialization, kernels: &[Kernel]) -> Compiled {
        let start = Instant::now();
        let pipelines =
            super::context::scoped_on(&self.device, "cannot compile the GPU kernels", || {
                kernels
                    .iter()
                    .map(|&k| (k, self.create(spec, k)))
                    .collect::<Vec<_>>()
            })?;
        let took = start.elapsed();
        if let Some(c) = &self.disk_cache
            && let Err(e) = c.save()
        {
            eprintln!("refract: warning: {e:#}");
        }
        Ok((pipelines, took))
    }

    fn create(&self, spec: Specialization, kernel: Kernel) -> wgpu::ComputePipeline {
        let constants = spec.constants();
        self.device
            .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(kernel.entry()),
                layout: Some(if kernel == Kernel::WfAdvance {
                    &self.advance_layout
                } else {
                    &self.layout
                }),
                module: &self.module,
                entry_point: Some(kernel.entry()),
                compilation_options: wgpu::PipelineCompilationOptions {
                    constants: &constants,
                    zero_initialize_workgroup_memory: false,
                },
                cache: self.disk_cache.as_ref().map(|c| &c.cache),
            })
    }
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

/// Fail with a clear message when the adapter allows fewer storage buffers per shader
/// stage than the integrator binds.
fn check_storage_buffer_limit(ctx: &GpuContext) -> Result<()> {
    let max = ctx.device.limits().max_storage_buffers_per_shader_stage;
    anyhow::ensure!(
        max >= STORAGE_BUFFERS,
        "GPU adapter '{}' allows {max} storage buffers per shader stage; refract needs \
         {STORAGE_BUFFERS} (use --device cpu)",
        ctx.info.name
    );
    Ok(())
}

/// The integrator bind group's layout entries, bindings 0..=16 in order.
fn integrator_entries() -> Vec<wgpu::BindGroupLayoutEntry> {
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
    // The wavefront's path states and its chunk table (wavefront.wgsl; placeholders for
    // the megakernel), the latter read at a dynamic offset per dispatch.
    entries.push(storage_entry(13, false));
    entries.push(wgpu::BindGroupLayoutEntry {
        binding: 14,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: true,
            min_binding_size: wgpu::BufferSize::new(16),
        },
        count: None,
    });
    // The light wavefront's subpath states (light_wavefront.wgsl; a placeholder).
    entries.push(storage_entry(15, false));
    // The wavefronts' queues of live paths (wavefront.wgsl's `WfQueue`; a placeholder).
    entries.push(storage_entry(16, false));
    entries
}

/// The bind group and pipeline layouts of the integrator kernels and of `wf_advance`.
struct IntegratorLayouts {
    /// The integrator's bind group (group 0 of every kernel).
    bind_group: wgpu::BindGroupLayout,
    /// Group 1 of `wf_advance`: the wavefront dispatch size.
    advance_group: wgpu::BindGroupLayout,
    /// The pipeline layout of every kernel but `wf_advance`.
    layout: wgpu::PipelineLayout,
    /// The pipeline layout of `wf_advance` (groups 0 and 1).
    advance: wgpu::PipelineLayout,
}

impl IntegratorLayouts {
    /// Create the layouts on `ctx`'s device (integrator group, its pipeline layout, the
    /// dispatch-size group, the `wf_advance` pipeline layout, in that order).
    fn new(ctx: &GpuContext) -> IntegratorLayouts {
        let bind_group = ctx
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("integrator"),
                entries: &integrator_entries(),
            });
        let layout = ctx
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("integrator"),
                bind_group_layouts: &[Some(&bind_group)],
                immediate_size: 0,
            });
        let advance_group = ctx
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("wavefront dispatch size"),
                entries: &[storage_entry(0, false)],
            });
        let advance = ctx
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("wf_advance"),
                bind_group_layouts: &[Some(&bind_group), Some(&advance_group)],
                immediate_size: 0,
            });
        IntegratorLayouts {
            bind_group,
            advance_group,
            layout,
            advance,
        }
    }
}

impl Pipelines {
    pub fn new(ctx: &GpuContext) -> Result<Pipelines> {
        check_storage_buffer_limit(ctx)?;
        let module = create_module(ctx, "integrator.wgsl", integrator_source())?;
        let layouts = IntegratorLayouts::new(ctx);
        let disk_cache =
            DiskPipelineCache::open(ctx, ctx.pipeline_cache_dir.as_deref()).map(Arc::new);
        Ok(Pipelines {
            bind_group_layout: layouts.bind_group,
            advance_group_layout: layouts.advance_group,
            device: ctx.device.clone(),
            layout: layouts.layout,
            advance_layout: layouts.advance,
            module,
            disk_cache,
            cache: HashMap::new(),
            pending: Vec::new(),
            compiled: 0,
            last_compile: None,
        })
    }

    /// The driver pipeline cache in use (None: the device has none, e.g. wgpu's GL backend).
    pub fn disk_cache(&self) -> Option<&DiskPipelineCache> {
        self.disk_cache.as_deref()
    }

    fn compiler(&self) -> Compiler {
        Compiler {
            device: self.device.clone(),
            layout: self.layout.clone(),
            advance_layout: self.advance_layout.clone(),
            module: self.module.clone(),
            disk_cache: self.disk_cache.clone(),
        }
    }

    /// The kernels of `spec` not compiled yet.
    fn missing(&self, spec: Specialization) -> Vec<Kernel> {
        super::kernels::kernels_of(&spec)
            .into_iter()
            .filter(|&k| !self.cache.contains_key(&(spec, k)))
            .collect()
    }

    /// True when every kernel `spec` dispatches is compiled.
    pub fn is_ready(&self, spec: Specialization) -> bool {
        self.missing(spec).is_empty()
    }

    /// Compile the pipelines `spec` dispatches now, on this thread (waiting for a worker
    /// already compiling them).
    pub fn compile(&mut self, spec: Specialization) -> Result<()> {
        if let Some(i) = self.pending.iter().position(|p| p.spec == spec) {
            let p = self.pending.swap_remove(i);
            return self.finish(p);
        }
        let missing = self.missing(spec);
        if missing.is_empty() {
            return Ok(());
        }
        let compiled = self.compiler().compile(spec, &missing);
        self.store(spec, compiled)
    }

    /// Start compiling the pipelines `spec` dispatches on a worker thread (nothing to do when
    /// they are compiled or being compiled); [`Pipelines::poll`] collects them.
    pub fn compile_in_background(&mut self, spec: Specialization) -> Result<()> {
        let missing = self.missing(spec);
        if missing.is_empty() || self.pending.iter().any(|p| p.spec == spec) {
            return Ok(());
        }
        let compiler = self.compiler();
        let thread = std::thread::Builder::new()
            .name("refract-gpu-compile".into())
            .spawn(move || compiler.compile(spec, &missing))
            .context("cannot start the GPU kernel compiler thread")?;
        self.pending.push(Pending { spec, thread });
        Ok(())
    }

    /// True while some specialisation is being compiled on a worker thread.
    pub fn is_compiling(&self) -> bool {
        !self.pending.is_empty()
    }

    /// Collect the pipelines of finished worker threads (never waits). An `Err` if one
    /// failed.
    pub fn poll(&mut self) -> Result<()> {
        let mut result = Ok(());
        let mut i = 0;
        while i < self.pending.len() {
            if self.pending[i].thread.is_finished() {
                let p = self.pending.swap_remove(i);
                let r = self.finish(p);
                if result.is_ok() {
                    result = r;
                }
            } else {
                i += 1;
            }
        }
        result
    }

    /// Join the worker compiling `p` and keep its pipelines.
    fn finish(&mut self, p: Pending) -> Result<()> {
        let compiled = p
            .thread
            .join()
            .map_err(|_| anyhow::anyhow!("the GPU kernel compiler thread panicked"))
            .and_then(|r| r);
        self.store(p.spec, compiled)
    }

    fn store(&mut self, spec: Specialization, compiled: Compiled) -> Result<()> {
        let (pipelines, took) = compiled?;
        for (kernel, pipeline) in pipelines {
            self.compiled += 1;
            self.cache.insert((spec, kernel), pipeline);
        }
        self.last_compile = Some(took);
        Ok(())
    }

    /// The compiled pipeline of `kernel` for `spec` (None: not compiled, see
    /// [`Pipelines::compile`]).
    pub fn get_kernel(
        &self,
        spec: Specialization,
        kernel: Kernel,
    ) -> Option<&wgpu::ComputePipeline> {
        self.cache.get(&(spec, kernel))
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
