//! [`GpuRenderer`]: progressive accumulation on the GPU with the same estimator and RNG as the
//! CPU path tracer. Each dispatch adds a batch of k samples per pixel, summed in f32 and folded
//! into an f32 running mean with weights n/(n+k) and 1/(n+k) (no drift from a growing sum).
//! Non-finite and negative samples are dropped and counted by an atomic counter.

use super::GpuContext;
use super::buffers::{checked_bytes, checked_storage, storage, zeroed_storage};
use super::layout::{self, GpuLayout, Params};
use super::photons::{self, PhotonStore};
use super::pipeline::{Kernel, Pipelines, Specialization};
use super::submissions::Submissions;
use super::upload::{self, GpuBvh};
use crate::film::Film;
use crate::paths::{DfaTable, PathFilter};
use crate::render::{Estimator, RenderOptions, RenderStats};
use crate::scene::{Camera, Features, Material, Scene, light::LightSet};
use anyhow::{Result, ensure};
use glam::{Vec3, Vec4};
use std::time::{Duration, Instant};
use wgpu::util::DeviceExt;

/// The accumulated image: per-pixel mean radiance (row-major, top row first).
#[derive(Clone, Debug)]
pub struct GpuImage {
    pub width: u32,
    pub height: u32,
    pub mean: Vec<Vec3>,
    pub spp: u64,
    pub dropped: u64,
}

impl GpuImage {
    /// A `film::Film` holding the same image (sums = mean · spp in f64).
    pub fn to_film(&self) -> Film {
        let mut film = Film::new(self.width, self.height);
        let n = self.spp as f64;
        for (s, m) in film.sums_mut().iter_mut().zip(&self.mean) {
            *s = [m.x as f64 * n, m.y as f64 * n, m.z as f64 * n];
        }
        film.spp = self.spp;
        film.dropped = self.dropped;
        film
    }
}

/// Vertices of one recorded path (the first sample of a batch at the debug pixel).
#[derive(Clone, Debug, Default)]
pub struct DebugPath {
    pub camera_dir: Vec3,
    /// Hit point and t of each vertex.
    pub hits: Vec<Vec4>,
    /// Throughput β after scattering at each vertex.
    pub betas: Vec<Vec3>,
    /// Direction leaving each vertex and the scene triangle it was on.
    pub dirs: Vec<(Vec3, u32)>,
    /// The sample value and the RNG dimensions it consumed.
    pub value: Vec3,
    pub dims: u32,
}

struct Buffers {
    params: wgpu::Buffer,
    nodes: wgpu::Buffer,
    triangles: wgpu::Buffer,
    vertices: wgpu::Buffer,
    materials: wgpu::Buffer,
    lights: wgpu::Buffer,
    accum: wgpu::Buffer,
    stats: wgpu::Buffer,
    texels: wgpu::Buffer,
    filter: wgpu::Buffer,
    /// Light-tracing splats: per pixel and channel a 64-bit fixed-point sum (two u32).
    splats: wgpu::Buffer,
    /// `sppm`: the photons and their hash grid (placeholders otherwise).
    photon_store: PhotonStore,
    /// Where the environment image's block starts in `texels` (`upload::pack_environment`).
    env_offset: u32,
    /// The wavefront's path states and chunk table (placeholders for the megakernel).
    wavefront: wavefront::WavefrontBuffers,
}

/// The GPU progressive renderer for one scene.
pub struct GpuRenderer {
    ctx: GpuContext,
    scene: Scene,
    opts: RenderOptions,
    bvh: GpuBvh,
    light_set: LightSet,
    light_count: u32,
    pipelines: Pipelines,
    spec: Specialization,
    buffers: Buffers,
    bind_group: wgpu::BindGroup,
    spp: u64,
    elapsed: Duration,
    /// Batch and band sizes from measured submission times.
    submissions: Submissions,
    debug_pixel: u32,
    /// Texture reference slots of each material (`upload::pack_textures`).
    tex_slots: Vec<upload::TexSlots>,
    /// The scene's features (the specialisation without filter and estimator).
    features: Features,
    /// `sppm`: the first iteration's photon radius r₁ (`photons::radius0`).
    photon_r0: f32,
    /// Compile new specialisations on a worker thread (the viewer) instead of in the call
    /// that changes the specialisation (the CLI, tests).
    background_compile: bool,
    /// A reset waits for the new specialisation's pipelines: the film is cleared by the
    /// first submission, and until then still holds the last image (the viewer shows it).
    clear_pending: bool,
    /// Submissions [`GpuRenderer::render_with`] keeps queued (2: the next waits while one runs).
    batches_in_flight: usize,
    /// An image larger than one binding (`film_rows`): the whole running mean, kept on the
    /// CPU while the film holds one tile of rows at a time (`tiles`).
    tiled: Option<Vec<[f32; 4]>>,
    /// First image row the film holds (0 unless tiled).
    film_y0: u32,
    /// Whether an image larger than one binding may render in tiles (headless renders; not
    /// the viewer, whose display reads the whole film and which falls back to the CPU).
    tiles: bool,
    /// Camera walk as a wavefront or not regardless of `Specialization::wants_wavefront`
    /// (None: the rule; `REFRACT_GPU_WAVEFRONT=on|off` sets it for the CLI).
    wavefront_override: Option<bool>,
    /// Wavefront bounces sized by indirect dispatch (where the adapter has it).
    wavefront_indirect: bool,
    /// `wf_advance`'s dispatch-size buffer and its bind group.
    wf_args: wavefront::AdvanceArgs,
}

/// Submissions [`GpuRenderer::render_with`] keeps queued by default: while the GPU runs one,
/// the next is already submitted, so it never idles while the CPU plans and encodes.
pub const BATCHES_IN_FLIGHT: usize = 2;

/// A submission of [`GpuRenderer::render_with`] not yet known to be finished.
struct Queued {
    index: wgpu::SubmissionIndex,
    submitted: Instant,
    /// Pixel samples it adds.
    samples: u64,
    /// The spp accumulated once it finishes, where it completes a pass.
    completes: Option<u64>,
}

/// Rows of the image the accumulation film holds: all of them when they fit one binding of
/// `cap` bytes (or when `whole_image` submissions are needed: the caller then refuses the
/// size), else the most whole workgroup rows (8) that fit — the image is rendered in tiles.
fn film_rows(opts: &RenderOptions, cap: u64, whole_image: bool) -> u32 {
    let row = u64::from(opts.width) * 16;
    if whole_image || row * u64::from(opts.height) <= cap {
        return opts.height;
    }
    ((cap / row.max(1)) as u32 / 8 * 8).clamp(8, opts.height)
}

/// Bytes of the light-tracing splat film per pixel (3 channels × 2 × u32).
const SPLAT_BYTES_PER_PIXEL: u64 = 24;

/// Whether `opts` make the kernels trace light subpaths in `scene` (`lt+pt`, or `auto`
/// resolving to it).
fn light_tracing_for(opts: &RenderOptions, scene: &Scene) -> bool {
    matches!(opts.estimator.resolve_gpu_why(scene).0, Estimator::LtPt)
}

/// Whether `opts` make the kernels photon-map caustics in `scene` (`sppm`, or `auto`
/// resolving to it).
fn sppm_for(opts: &RenderOptions, scene: &Scene) -> bool {
    matches!(opts.estimator.resolve_gpu_why(scene).0, Estimator::Sppm)
}

/// Photon paths per iteration: one per pixel with `sppm` (`cpu::sppm::PHOTONS_PER_PIXEL`),
/// else a placeholder store of one.
fn photon_paths(sppm: bool, opts: &RenderOptions) -> u32 {
    if sppm {
        opts.width.saturating_mul(opts.height)
    } else {
        1
    }
}

/// The splat film's size: the whole image with light tracing; without it the binding still
/// needs a buffer, so one pixel (path tracing at 4K no longer pays 24 B per pixel for it).
fn splat_film_bytes(light_tracing: bool, opts: &RenderOptions) -> u64 {
    let pixels = if light_tracing {
        opts.width as u64 * opts.height as u64
    } else {
        1
    };
    pixels * SPLAT_BYTES_PER_PIXEL
}

/// A zeroed splat film of `bytes`.
fn splat_film(ctx: &GpuContext, bytes: u64) -> wgpu::Buffer {
    zeroed_storage(
        ctx,
        "light-tracing splats",
        bytes,
        wgpu::BufferUsages::COPY_DST,
    )
}

/// Buffers, light count and the texture reference slots of each material.
type BuiltBuffers = (Buffers, u32, Vec<upload::TexSlots>);

const STATS_BYTES: u64 = (layout::DEBUG_RECORDS * 16 + 16) as u64;

/// The accumulation film's and the splat film's sizes in bytes for `opts`, or an error when
/// either is larger than one binding. Path tracing renders an image larger than one binding
/// in tiles of rows (`tiles`); light tracing and photons need the whole image in every
/// submission.
fn film_bytes(
    ctx: &GpuContext,
    scene: &Scene,
    opts: &RenderOptions,
    tiles: bool,
) -> Result<(u64, u64)> {
    let light_tracing = light_tracing_for(opts, scene);
    let splat_bytes = splat_film_bytes(light_tracing, opts);
    let cap = ctx.max_binding_bytes();
    let whole = !tiles || light_tracing || sppm_for(opts, scene);
    let accum_bytes = u64::from(opts.width) * 16 * u64::from(film_rows(opts, cap, whole));
    ensure!(
        accum_bytes.max(splat_bytes) <= cap,
        "image {}x{} too large for this GPU: its {} film needs {} MiB, the device binds at \
         most {} MiB per buffer",
        opts.width,
        opts.height,
        if splat_bytes > accum_bytes {
            "light-tracing splat"
        } else {
            "accumulation"
        },
        accum_bytes.max(splat_bytes) >> 20,
        cap >> 20
    );
    Ok((accum_bytes, splat_bytes))
}

/// The estimator the GPU kernels run for `estimator` on `scene`: path tracing, lt+pt or sppm.
pub fn gpu_estimator(estimator: Estimator, scene: &Scene) -> Result<Estimator> {
    match estimator.resolve_gpu_why(scene).0 {
        e @ (Estimator::Path | Estimator::LtPt | Estimator::Sppm) => Ok(e),
        e => anyhow::bail!(
            "the GPU renderer implements path, lt+pt and sppm (estimator '{e}' needs --device cpu)"
        ),
    }
}

/// `REFRACT_GPU_WAVEFRONT`: `on` or `off` forces the wavefront integrator on or off;
/// unset or anything else leaves the choice to the renderer.
fn wavefront_override_from_env() -> Option<bool> {
    match std::env::var("REFRACT_GPU_WAVEFRONT").as_deref() {
        Ok("on") => Some(true),
        Ok("off") => Some(false),
        _ => None,
    }
}

impl GpuRenderer {
    /// Open the best adapter and prepare `scene`. Errors: no adapter, invalid scene, features
    /// the GPU kernel lacks, buffers over 128 MiB, validation or out-of-memory errors of the
    /// device (never a panic).
    pub fn new(scene: Scene, opts: RenderOptions) -> Result<GpuRenderer> {
        let ctx = GpuContext::new()?;
        Self::with_context(ctx, scene, opts)
    }

    /// Prepare `scene` on an existing device (its pipelines compiled before this returns).
    pub fn with_context(ctx: GpuContext, scene: Scene, opts: RenderOptions) -> Result<GpuRenderer> {
        Self::build(ctx, scene, opts, false, true)
    }

    /// [`GpuRenderer::with_context`] for the viewer's progressive display where pipelines must
    /// compile in the call (GL): an image larger than one binding is an error (no tiles).
    pub fn with_context_untiled(
        ctx: GpuContext,
        scene: Scene,
        opts: RenderOptions,
    ) -> Result<GpuRenderer> {
        Self::build(ctx, scene, opts, false, false)
    }

    /// Prepare `scene` on an existing device, compiling its pipelines, and those of every
    /// later specialisation, on a worker thread: see [`GpuRenderer::pipelines_ready`].
    /// Dispatching before they are ready waits for them. The viewer's renderer: an image larger
    /// than one binding is an error here (no tiles; its display reads the whole film).
    pub fn with_context_in_background(
        ctx: GpuContext,
        scene: Scene,
        opts: RenderOptions,
    ) -> Result<GpuRenderer> {
        Self::build(ctx, scene, opts, true, false)
    }

    fn build(
        ctx: GpuContext,
        scene: Scene,
        opts: RenderOptions,
        background_compile: bool,
        tiles: bool,
    ) -> Result<GpuRenderer> {
        Self::check_renderable(&scene, &opts)?;
        let features = scene.features();
        // The tree first: its depth sizes the kernels' traversal stack.
        let bvh = upload::build_bvh(&scene)?;
        let wavefront_override = wavefront_override_from_env();
        let spec = Self::specialization_for(features, &opts, &scene, bvh.depth, wavefront_override);
        let pipelines = Self::compiled_pipelines(&ctx, spec, background_compile)?;
        let light_set = LightSet::build(&scene);
        let (buffers, light_count, tex_slots) =
            Self::create_buffers(&ctx, &scene, &bvh, &light_set, &opts, tiles)?;
        let (bind_group, wf_args) = Self::create_bind_groups(&ctx, &pipelines, &buffers)?;
        let mut r = GpuRenderer {
            ctx,
            scene,
            opts,
            bvh,
            light_set,
            light_count,
            pipelines,
            spec,
            buffers,
            bind_group,
            spp: 0,
            elapsed: Duration::ZERO,
            submissions: Submissions::default(),
            debug_pixel: u32::MAX,
            tex_slots,
            features,
            photon_r0: 0.0,
            background_compile,
            clear_pending: false,
            batches_in_flight: BATCHES_IN_FLIGHT,
            tiled: None,
            film_y0: 0,
            tiles,
            wavefront_override,
            wavefront_indirect: false,
            wf_args,
        };
        r.fit_to_scene();
        Ok(r)
    }

    /// The checks before any GPU work: a valid scene the kernels support, valid options and
    /// an estimator the GPU implements.
    fn check_renderable(scene: &Scene, opts: &RenderOptions) -> Result<()> {
        scene.validate()?;
        upload::check_supported(scene)?;
        opts.check()?;
        gpu_estimator(opts.estimator, scene)?;
        Ok(())
    }

    /// The pipeline layouts (in an error scope) with the kernels of `spec` compiled now, or
    /// on a worker thread when `background_compile`.
    fn compiled_pipelines(
        ctx: &GpuContext,
        spec: Specialization,
        background_compile: bool,
    ) -> Result<Pipelines> {
        let mut pipelines = ctx.scoped("cannot create the GPU pipeline layout", || {
            Pipelines::new(ctx)
        })??;
        if background_compile {
            pipelines.compile_in_background(spec)?;
        } else {
            pipelines.compile(spec)?;
        }
        Ok(pipelines)
    }

    /// The integrator's bind group over `buffers` and the wavefront's dispatch-size
    /// arguments, in an error scope.
    fn create_bind_groups(
        ctx: &GpuContext,
        pipelines: &Pipelines,
        buffers: &Buffers,
    ) -> Result<(wgpu::BindGroup, wavefront::AdvanceArgs)> {
        ctx.scoped("cannot bind the GPU buffers", || {
            (
                Self::bind(ctx, pipelines, buffers),
                wavefront::AdvanceArgs::new(ctx, pipelines),
            )
        })
    }

    /// Settle a freshly assembled renderer: indirect wavefront dispatch, tiles and wavefront
    /// sized to the image, the SPPM start radius and the filter table.
    fn fit_to_scene(&mut self) {
        self.set_wavefront_indirect(true);
        self.fit_tiles();
        self.fit_wavefront();
        self.photon_r0 = self.sppm_radius0();
        self.write_filter_table();
    }

    /// [`GpuRenderer::build_buffers`] in error scopes: a validation or out-of-memory error is
    /// an `Err`.
    fn create_buffers(
        ctx: &GpuContext,
        scene: &Scene,
        bvh: &GpuBvh,
        light_set: &LightSet,
        opts: &RenderOptions,
        tiles: bool,
    ) -> Result<BuiltBuffers> {
        ctx.scoped("cannot create the GPU buffers", || {
            Self::build_buffers(ctx, scene, bvh, light_set, opts, tiles)
        })?
    }

    /// The scene's buffers and a film for `opts`; `tiles`: an image larger than one binding
    /// may render in tiles (headless renders), else it is refused (the viewer).
    fn build_buffers(
        ctx: &GpuContext,
        scene: &Scene,
        bvh: &GpuBvh,
        light_set: &LightSet,
        opts: &RenderOptions,
        tiles: bool,
    ) -> Result<BuiltBuffers> {
        let tris = upload::pack_triangles(scene, bvh, light_set);
        let verts = upload::pack_vertices(scene);
        let (mut texels, tex_slots) = upload::pack_textures(scene);
        let env_offset = upload::pack_environment(light_set, &mut texels);
        let mats = upload::pack_materials(scene, &tex_slots);
        let (lights, light_count) = upload::pack_lights(bvh, light_set, env_offset);
        let (accum_bytes, splat_bytes) = film_bytes(ctx, scene, opts, tiles)?;
        let copyable = wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST;
        let buffers = Buffers {
            params: ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("params"),
                size: Params::size() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            nodes: checked_storage(ctx, "bvh nodes", "BVH", &bvh.nodes)?,
            triangles: checked_storage(ctx, "triangles", "triangles", &tris)?,
            vertices: checked_storage(ctx, "vertices", "vertices", &verts)?,
            materials: checked_storage(ctx, "materials", "materials", &mats)?,
            lights: checked_storage(ctx, "lights", "lights", &lights)?,
            accum: zeroed_storage(ctx, "accum", accum_bytes, copyable),
            stats: zeroed_storage(ctx, "stats", STATS_BYTES, copyable),
            texels: checked_storage(ctx, "texels", "textures", &texels)?,
            filter: ctx
                .device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("path filter"),
                    contents: bytemuck::cast_slice(&[0u32; layout::FILTER_WORDS]),
                    usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                }),
            splats: splat_film(ctx, splat_bytes),
            photon_store: PhotonStore::new(ctx, photon_paths(sppm_for(opts, scene), opts))?,
            env_offset,
            wavefront: wavefront::WavefrontBuffers::placeholder(ctx),
        };
        Ok((buffers, light_count, tex_slots))
    }

    fn bind(ctx: &GpuContext, p: &Pipelines, b: &Buffers) -> wgpu::BindGroup {
        let bufs = [
            &b.params,
            &b.nodes,
            &b.triangles,
            &b.vertices,
            &b.materials,
            &b.lights,
            &b.accum,
            &b.stats,
            &b.texels,
            &b.filter,
        ];
        let mut entries: Vec<wgpu::BindGroupEntry> = bufs
            .iter()
            .enumerate()
            .map(|(i, buf)| wgpu::BindGroupEntry {
                binding: i as u32,
                resource: buf.as_entire_binding(),
            })
            .collect();
        for (binding, buf) in [
            (10, &b.splats),
            (11, &b.photon_store.grid),
            (12, &b.photon_store.photons),
            (13, &b.wavefront.paths),
            (15, &b.wavefront.light_paths),
            (16, &b.wavefront.queue),
        ] {
            entries.push(wgpu::BindGroupEntry {
                binding,
                resource: buf.as_entire_binding(),
            });
        }
        // One chunk entry, at the dynamic offset each dispatch gives.
        entries.push(wgpu::BindGroupEntry {
            binding: 14,
            resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                buffer: &b.wavefront.chunks,
                offset: 0,
                size: wgpu::BufferSize::new(16),
            }),
        });
        ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("integrator"),
            layout: &p.bind_group_layout,
            entries: &entries,
        })
    }

    pub fn adapter_info(&self) -> &wgpu::AdapterInfo {
        &self.ctx.info
    }
    /// True on a CPU-emulated adapter (lavapipe …).
    pub fn is_software(&self) -> bool {
        self.ctx.is_software()
    }
    pub fn context(&self) -> &GpuContext {
        &self.ctx
    }
    pub fn scene(&self) -> &Scene {
        &self.scene
    }
    pub fn options(&self) -> &RenderOptions {
        &self.opts
    }
    /// Samples per pixel accumulated since the last reset.
    pub fn spp(&self) -> u64 {
        self.spp
    }
    /// Pipelines compiled so far (parameter edits must not add any).
    pub fn pipelines_compiled(&self) -> u32 {
        self.pipelines.compiled
    }
    /// Wall time of the last specialisation's pipeline creation.
    pub fn last_compile_time(&self) -> Option<Duration> {
        self.pipelines.last_compile
    }
    /// Bytes of driver pipeline cache data loaded from disk when the renderer was created
    /// (None: the device has no pipeline cache; 0: a cold cache).
    pub fn pipeline_cache_loaded(&self) -> Option<usize> {
        self.pipelines.disk_cache().map(|c| c.loaded_bytes)
    }
    /// The pipeline cache file (None: no cache, or no cache directory).
    pub fn pipeline_cache_path(&self) -> Option<&std::path::Path> {
        self.pipelines.disk_cache().and_then(|c| c.path.as_deref())
    }

    /// Collect pipelines compiled on a worker thread (never waits): Ok(true) once those of
    /// the current specialisation are ready, an `Err` if their compilation failed.
    pub fn pipelines_ready(&mut self) -> Result<bool> {
        self.pipelines.poll()?;
        Ok(self.pipelines.is_ready(self.spec))
    }

    /// True while the current specialisation's pipelines are not compiled yet.
    pub fn is_compiling(&self) -> bool {
        !self.pipelines.is_ready(self.spec)
    }

    /// Submissions [`GpuRenderer::render_with`] keeps queued (at least 1; default
    /// [`BATCHES_IN_FLIGHT`]).
    pub fn set_batches_in_flight(&mut self, n: usize) {
        self.batches_in_flight = n.max(1);
    }
    pub fn specialization(&self) -> Specialization {
        self.spec
    }
    /// BVH2 build time and depth.
    pub fn bvh_info(&self) -> (Duration, u32, usize) {
        (self.bvh.build_time, self.bvh.depth, self.bvh.nodes.len())
    }

    /// Drop all accumulated samples and counters (the next sample index is 0 again). While
    /// the specialisation's pipelines compile, the film keeps the last image until the first
    /// submission clears it (the viewer shows it meanwhile).
    pub fn reset(&mut self) {
        if self.pipelines.is_ready(self.spec) {
            let mut enc = self
                .ctx
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
            self.encode_clear(&mut enc);
            self.ctx.queue.submit([enc.finish()]);
            self.clear_pending = false;
        } else {
            self.clear_pending = true;
        }
        self.spp = 0;
        self.elapsed = Duration::ZERO;
        self.photon_r0 = self.sppm_radius0();
        if let Some(mean) = &mut self.tiled {
            mean.fill([0.0; 4]);
        }
    }

    /// Zero the film, the counters, the splats and the photon grid.
    fn encode_clear(&self, enc: &mut wgpu::CommandEncoder) {
        enc.clear_buffer(&self.buffers.accum, 0, None);
        enc.clear_buffer(&self.buffers.stats, 0, None);
        enc.clear_buffer(&self.buffers.splats, 0, None);
        enc.clear_buffer(&self.buffers.photon_store.grid, 0, None);
    }

    /// The uniforms of a dispatch adding `batch` samples per pixel to the `first` accumulated.
    fn params(&self, first: u64, batch: u32) -> Params {
        let cam = &self.scene.camera;
        let (w, h) = (self.opts.width, self.opts.height);
        let n = first as f64;
        let k = batch as f64;
        let rot = cam.rotation;
        // sppm: one iteration per dispatch, iteration s = sample index s.
        let paths = f64::from(photon_paths(true, &self.opts));
        let r = photons::radius(self.photon_r0, first as u32);
        Params {
            cam_pos: cam.position.extend((0.5 * cam.yfov).tan()).to_array(),
            cam_right: rot.x_axis.extend(w as f32 / h as f32).to_array(),
            cam_up: rot.y_axis.extend(0.0).to_array(),
            cam_back: rot.z_axis.extend(0.0).to_array(),
            environment: self.scene.environment.extend(0.0).to_array(),
            width: w,
            height: h,
            seed: self.opts.seed,
            max_depth: self.opts.max_depth.max(1),
            rr_depth: self.opts.rr_depth,
            sample_offset: first as u32,
            batch,
            light_count: self.light_count,
            w_old: (n / (n + k)) as f32,
            w_new: (1.0 / (n + k)) as f32,
            debug_pixel: self.debug_pixel,
            offset_scale: self.bvh.offset_scale,
            tile_y0: 0,
            film_y0: self.film_y0,
            photon_radius: r,
            photon_norm: (1.0 / (paths * std::f64::consts::PI * f64::from(r) * f64::from(r)))
                as f32,
            grid_mask: self.buffers.photon_store.buckets - 1,
            _pad0: 0,
            _pad1: 0,
            _pad2: 0,
        }
    }

    /// r₁ of `sppm` for the current camera, scene and image size.
    fn sppm_radius0(&self) -> f32 {
        photons::radius0(&self.scene.camera, self.scene.bounds(), self.opts.height)
    }

    /// Samples per pixel per dispatch: [`RenderOptions::pass_spp`] until a submission has
    /// been timed, then what [`GpuRenderer::render_with`] last planned.
    pub fn batch_spp(&self) -> u32 {
        self.submissions
            .last_k
            .unwrap_or_else(|| self.opts.pass_spp())
    }

    /// Bound the wall time of one submission of [`GpuRenderer::render_with`] (default
    /// [`SUBMISSION_BUDGET`]).
    pub fn set_submission_budget(&mut self, budget: Duration) {
        self.submissions.budget = budget;
    }

    /// Queue one dispatch adding `k` samples per pixel to the whole image (does not wait).
    pub fn dispatch(&mut self, k: u32) {
        if k == 0 || self.refuse_tiled() {
            return;
        }
        self.submit(k, 0, self.opts.height);
        self.spp += k as u64;
    }

    /// Queue `k` samples per pixel for the rows `y0 .. y0 + rows` only (does not wait): one
    /// band of a pass the caller completes with [`GpuRenderer::end_pass`] once every row has
    /// its `k` samples (the viewer's bounded frames). Not with light tracing, whose splats need
    /// whole-image passes, nor with sppm, whose iterations are whole-image submissions (the
    /// band is ignored there; [`GpuRenderer::needs_whole_image`]).
    pub fn dispatch_band(&mut self, k: u32, y0: u32, rows: u32) {
        if k > 0 && rows > 0 && y0 < self.opts.height && !self.refuse_tiled() {
            self.submit(k, y0, rows.min(self.opts.height - y0));
        }
    }

    /// Every row of a banded pass now has `k` more samples.
    pub fn end_pass(&mut self, k: u32) {
        self.spp += k as u64;
    }

    /// True when every submission must cover the whole image (light tracing, sppm).
    pub fn needs_whole_image(&self) -> bool {
        self.spec.light_tracing || self.spec.sppm
    }

    /// Queue `k` samples per pixel for image rows `y0 .. y0 + rows` (all rows with light
    /// tracing, whose splats land anywhere, and with sppm, one submission per iteration);
    /// `self.spp` is not advanced.
    /// Returns the last submission's index (None: nothing submitted, the pipelines failed
    /// to compile; the error is recorded for [`GpuContext::check_errors`]).
    fn submit(&mut self, k: u32, y0: u32, rows: u32) -> Option<wgpu::SubmissionIndex> {
        if self.spec.sppm {
            // Iteration s = sample index s: its own photons, then its camera paths.
            let mut last = None;
            for i in 0..u64::from(k) {
                last = self.submit_pass(self.spp + i, 1, 0, self.opts.height);
            }
            last
        } else if self.spec.wavefront {
            // As many samples per submission as the chunk table holds.
            let pixels = self.opts.width * rows;
            let part =
                wavefront::samples_per_submission(pixels, k, self.buffers.wavefront.max_paths);
            let (mut last, mut done) = (None, 0);
            while done < k {
                let kk = part.min(k - done);
                last = self.submit_pass(self.spp + u64::from(done), kk, y0, rows);
                done += kk;
            }
            last
        } else {
            self.submit_pass(self.spp, k, y0, rows)
        }
    }

    /// The current specialisation's pipelines, waiting for (or doing) their compilation;
    /// false (the error recorded) if it fails.
    fn ensure_pipelines(&mut self) -> bool {
        if self.pipelines.is_ready(self.spec) {
            return true;
        }
        match self.pipelines.compile(self.spec) {
            Ok(()) => true,
            Err(e) => {
                super::context::record(&self.ctx.errors, format!("{e:#}"));
                false
            }
        }
    }

    /// Compile the current specialisation's pipelines (on a worker thread with background
    /// compilation); a failure is recorded for [`GpuContext::check_errors`].
    fn request_pipelines(&mut self) {
        let r = if self.background_compile {
            self.pipelines.compile_in_background(self.spec)
        } else {
            self.pipelines.compile(self.spec)
        };
        if let Err(e) = r {
            super::context::record(&self.ctx.errors, format!("{e:#}"));
        }
    }

    /// One submission: `k` samples per pixel from sample index `first` for rows `y0 ..`.
    fn submit_pass(
        &mut self,
        first: u64,
        k: u32,
        y0: u32,
        rows: u32,
    ) -> Option<wgpu::SubmissionIndex> {
        if !self.ensure_pipelines() {
            return None;
        }
        let mut params = self.params(first, k);
        params.tile_y0 = y0;
        self.ctx
            .queue
            .write_buffer(&self.buffers.params, 0, bytemuck::bytes_of(&params));
        let mut enc = self
            .ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
        if std::mem::take(&mut self.clear_pending) {
            self.encode_clear(&mut enc);
        }
        let groups = (self.opts.width.div_ceil(8), rows.div_ceil(8));
        // Light subpaths first: `render` folds their splats into the film; photons first:
        // `render` gathers them (wgpu orders the passes' storage accesses).
        if self.spec.light_tracing && !self.spec.wavefront {
            self.encode_kernel(&mut enc, Kernel::LightTrace, groups);
        }
        if self.spec.sppm {
            self.buffers.photon_store.encode_clear(&mut enc);
            self.encode_kernel(&mut enc, Kernel::PhotonTrace, groups);
        }
        if self.spec.wavefront {
            self.encode_wavefront(&mut enc, self.opts.width * rows, k);
        } else {
            self.encode_kernel(&mut enc, Kernel::Render, groups);
        }
        Some(self.ctx.queue.submit([enc.finish()]))
    }

    /// Record one compute pass of `kernel` over `groups` workgroups (its pipeline is
    /// compiled: [`GpuRenderer::ensure_pipelines`]; the wavefront's kernels are recorded by
    /// `encode_wavefront`).
    fn encode_kernel(&self, enc: &mut wgpu::CommandEncoder, kernel: Kernel, groups: (u32, u32)) {
        let Some(pipeline) = self.pipelines.get_kernel(self.spec, kernel) else {
            return;
        };
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(kernel.entry()),
            timestamp_writes: None,
        });
        pass.set_pipeline(pipeline);
        // The chunk table's dynamic offset: only the wavefront's kernels read it.
        pass.set_bind_group(0, &self.bind_group, &[0]);
        pass.dispatch_workgroups(groups.0, groups.1, 1);
    }

    /// Add `spp` samples per pixel (in batches) and return the accumulated image.
    pub fn render(&mut self, spp: u32) -> Result<GpuImage> {
        self.render_with(spp, None, |_| {})
    }

    /// Add up to `spp` samples per pixel, stopping early once `budget` is spent (at least one
    /// batch); `progress` gets the spp accumulated after each batch. Up to
    /// [`GpuRenderer::set_batches_in_flight`] submissions are queued at a time: the next is
    /// submitted before waiting for the one running. The submissions, and so the image, are
    /// those of one at a time; only the waiting differs.
    pub fn render_with(
        &mut self,
        spp: u32,
        budget: Option<Duration>,
        mut progress: impl FnMut(u64),
    ) -> Result<GpuImage> {
        if self.tiled.is_some() {
            return self.render_tiled(spp, budget, progress);
        }
        self.pipelines.compile(self.spec)?;
        let start = Instant::now();
        let mut queued = std::collections::VecDeque::new();
        // When the GPU finished the last retired submission (the next one starts then).
        let mut last_done = start;
        let mut done = 0u32;
        while done < spp && !budget.is_some_and(|b| done > 0 && start.elapsed() >= b) {
            let (w, h) = (self.opts.width, self.opts.height);
            let (k, rows) = self
                .submissions
                .plan(w, h, spp - done, self.needs_whole_image());
            for y0 in (0..h).step_by(rows as usize) {
                let band = rows.min(h - y0);
                let submitted = Instant::now();
                let index = self.submit(k, y0, band);
                let last_band = y0 + band >= h;
                let Some(index) = index else {
                    return Err(self
                        .ctx
                        .check_errors()
                        .err()
                        .unwrap_or_else(|| anyhow::anyhow!("the GPU kernels are not compiled")));
                };
                queued.push_back(Queued {
                    index,
                    submitted,
                    samples: u64::from(w) * u64::from(band) * u64::from(k),
                    completes: last_band.then_some(self.spp + u64::from(k)),
                });
                while queued.len() >= self.batches_in_flight {
                    self.retire(&mut queued, &mut last_done, &mut progress)?;
                }
            }
            self.spp += k as u64;
            done += k;
        }
        while !queued.is_empty() {
            self.retire(&mut queued, &mut last_done, &mut progress)?;
        }
        self.elapsed += start.elapsed();
        self.image()
    }

    /// Wait for the oldest queued submission and time it: from its submission, or from when
    /// the one before it finished if that was later (it waited in the queue until then).
    fn retire(
        &mut self,
        queued: &mut std::collections::VecDeque<Queued>,
        last_done: &mut Instant,
        progress: &mut impl FnMut(u64),
    ) -> Result<()> {
        let Some(q) = queued.pop_front() else {
            return Ok(());
        };
        self.ctx.wait_for(q.index)?;
        let now = Instant::now();
        let began = q.submitted.max(*last_done);
        self.submissions
            .observe(now.saturating_duration_since(began), q.samples);
        *last_done = now;
        if let Some(spp) = q.completes {
            progress(spp);
        }
        Ok(())
    }

    fn read_stats(&self) -> Result<(layout::Stats, Vec<Vec4>)> {
        let bytes = self.ctx.read_buffer(&self.buffers.stats, STATS_BYTES)?;
        let head: layout::Stats = bytemuck::pod_read_unaligned(&bytes[..16]);
        let recs: Vec<[f32; 4]> = bytemuck::pod_collect_to_vec(&bytes[16..]);
        Ok((head, recs.into_iter().map(Vec4::from_array).collect()))
    }

    /// Read the accumulated image back.
    pub fn image(&self) -> Result<GpuImage> {
        let px: Vec<[f32; 4]> = match &self.tiled {
            Some(mean) => mean.clone(),
            None => {
                let pixels = self.opts.width as u64 * self.opts.height as u64;
                let bytes = self.ctx.read_buffer(&self.buffers.accum, pixels * 16)?;
                bytemuck::pod_collect_to_vec(&bytes)
            }
        };
        let (stats, _) = self.read_stats()?;
        Ok(GpuImage {
            width: self.opts.width,
            height: self.opts.height,
            mean: px.iter().map(|p| Vec3::new(p[0], p[1], p[2])).collect(),
            spp: self.spp,
            dropped: stats.dropped_lo as u64 | (stats.dropped_hi as u64) << 32,
        })
    }

    /// `sppm`: (photons the last iteration stored, photons refused by a full store since the
    /// last reset; 0 unless the store is undersized).
    pub fn photon_counts(&self) -> Result<(u32, u32)> {
        self.buffers.photon_store.counts(&self.ctx)
    }

    /// Counters since the last reset.
    pub fn stats(&self) -> Result<RenderStats> {
        let (s, _) = self.read_stats()?;
        Ok(RenderStats {
            spp: self.spp,
            dropped: s.dropped_lo as u64 | (s.dropped_hi as u64) << 32,
            segments: Some(s.segments_lo as u64 | (s.segments_hi as u64) << 32),
            elapsed: self.elapsed,
            pixels: self.opts.pixels(),
        })
    }

    /// Record the first sample of every later batch at `pixel` (linear index); None = off.
    pub fn set_debug_pixel(&mut self, pixel: Option<u32>) {
        self.debug_pixel = pixel.unwrap_or(u32::MAX);
    }

    /// The path recorded at the debug pixel by the last dispatch.
    pub fn debug_path(&self) -> Result<DebugPath> {
        let (_, r) = self.read_stats()?;
        let dims = r[1 + layout::DEBUG_STRIDE * layout::DEBUG_MAX_VERTICES].w as u32;
        let value = r[1 + layout::DEBUG_STRIDE * layout::DEBUG_MAX_VERTICES].truncate();
        let mut p = DebugPath {
            camera_dir: r[0].truncate(),
            value,
            dims,
            ..Default::default()
        };
        for v in 0..layout::DEBUG_MAX_VERTICES {
            let hit = r[1 + layout::DEBUG_STRIDE * v];
            if hit.w <= 0.0 {
                break;
            }
            p.hits.push(hit);
            let b = r[2 + layout::DEBUG_STRIDE * v];
            if b.w as usize == v + 1 {
                p.betas.push(b.truncate());
                let d = r[3 + layout::DEBUG_STRIDE * v];
                p.dirs.push((d.truncate(), d.w as u32));
            }
        }
        Ok(p)
    }

    /// Clear the debug records (so a shorter path does not show an older one's tail).
    pub fn clear_debug(&mut self) {
        let mut enc = self
            .ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
        enc.clear_buffer(&self.buffers.stats, 16, None);
        self.ctx.queue.submit([enc.finish()]);
    }

    /// Change material `index` (colour, IOR, roughness, emission …): buffers are rewritten in
    /// place, the BVH is kept, and the pipeline is only switched if the material's *kind*
    /// changes the specialisation (then compiled once and cached). Accumulation restarts.
    pub fn set_material(&mut self, index: usize, material: Material) -> Result<()> {
        material.validate()?;
        ensure!(
            index < self.scene.materials.len(),
            "material index {index} out of range ({} materials)",
            self.scene.materials.len()
        );
        let emission_changed = self.scene.materials[index].emission != material.emission
            || self.scene.materials[index].double_sided != material.double_sided;
        let old = std::mem::replace(&mut self.scene.materials[index], material);
        if let Err(e) = upload::check_supported(&self.scene) {
            self.scene.materials[index] = old;
            return Err(e);
        }
        let textures_changed = {
            let (a, b) = (&old, &self.scene.materials[index]);
            a.base_color_texture != b.base_color_texture
                || a.metallic_roughness_texture != b.metallic_roughness_texture
                || a.emissive_texture != b.emissive_texture
                || a.normal_texture != b.normal_texture
                || a.kind != b.kind
        };
        if textures_changed {
            let (mut texels, slots) = upload::pack_textures(&self.scene);
            let env_offset = upload::pack_environment(&self.light_set, &mut texels);
            self.buffers.texels = storage(
                &self.ctx,
                "texels",
                checked_bytes("textures", &texels, self.ctx.max_binding_bytes())?,
            );
            let mats = upload::pack_materials(&self.scene, &slots);
            self.ctx.queue.write_buffer(
                &self.buffers.materials,
                0,
                checked_bytes("materials", &mats, self.ctx.max_binding_bytes())?,
            );
            self.tex_slots = slots;
            self.bind_group = Self::bind(&self.ctx, &self.pipelines, &self.buffers);
            if env_offset != self.buffers.env_offset {
                self.buffers.env_offset = env_offset;
                self.rebuild_lights()?;
            }
        }
        let packed = upload::pack_material(
            &self.scene,
            &self.scene.materials[index],
            self.tex_slots[index],
        );
        self.ctx.queue.write_buffer(
            &self.buffers.materials,
            (index * std::mem::size_of::<layout::Material>()) as u64,
            bytemuck::bytes_of(&packed),
        );
        if emission_changed {
            self.rebuild_lights()?;
        }
        self.features = self.scene.features();
        self.respecialize();
        self.fit_splat_film()?;
        self.fit_photon_store()?;
        self.reset();
        Ok(())
    }

    /// The kernel parts for `features` with the filter and estimator of `opts`.
    fn specialization_for(
        features: Features,
        opts: &RenderOptions,
        scene: &Scene,
        bvh_depth: u32,
        wavefront: Option<bool>,
    ) -> Specialization {
        let mut spec = Specialization::from_features(features).with_bvh_depth(bvh_depth);
        spec.filter = opts.filter.is_some();
        spec.light_tracing = light_tracing_for(opts, scene);
        spec.sppm = sppm_for(opts, scene);
        match wavefront {
            Some(w) => Specialization {
                wavefront: w,
                ..spec
            },
            None => spec.with_wavefront_rule(),
        }
    }

    /// Give the splat film the size the current specialisation needs (a whole film with light
    /// tracing, one pixel's worth otherwise) and rebind when it changes.
    fn fit_splat_film(&mut self) -> Result<()> {
        let want = splat_film_bytes(self.spec.light_tracing, &self.opts);
        if want == self.buffers.splats.size() {
            return Ok(());
        }
        let cap = self.ctx.max_binding_bytes();
        ensure!(
            want <= cap,
            "image {}x{} too large for light tracing on this GPU: its splat film needs {} MiB, \
             the device binds at most {} MiB per buffer",
            self.opts.width,
            self.opts.height,
            want >> 20,
            cap >> 20
        );
        self.buffers.splats = self.ctx.scoped("cannot create the splat film", || {
            splat_film(&self.ctx, want)
        })?;
        self.bind_group = Self::bind(&self.ctx, &self.pipelines, &self.buffers);
        Ok(())
    }

    /// Give the photon store the size the current specialisation needs (one slot per pixel
    /// with sppm, a placeholder otherwise) and rebind when it changes.
    fn fit_photon_store(&mut self) -> Result<()> {
        let paths = photon_paths(self.spec.sppm, &self.opts).max(1);
        if paths == self.buffers.photon_store.paths {
            return Ok(());
        }
        self.buffers.photon_store = self.ctx.scoped("cannot create the photon store", || {
            PhotonStore::new(&self.ctx, paths)
        })??;
        self.bind_group = Self::bind(&self.ctx, &self.pipelines, &self.buffers);
        Ok(())
    }

    /// Select the specialisation for the current features, filter and estimator, and have
    /// its pipelines compiled (cached; on a worker thread with background compilation).
    fn respecialize(&mut self) {
        self.spec = Self::specialization_for(
            self.features,
            &self.opts,
            &self.scene,
            self.bvh.depth,
            self.wavefront_override,
        );
        self.fit_wavefront();
        self.request_pipelines();
    }

    /// Run the camera walk as a wavefront (`Some(true)`), as the megakernel (`Some(false)`) or
    /// as `Specialization::wants_wavefront` decides (`None`); accumulation restarts.
    pub fn set_wavefront(&mut self, wavefront: Option<bool>) {
        self.wavefront_override = wavefront;
        self.respecialize();
        self.reset();
    }

    /// Size the wavefront's bounces by indirect dispatch (`true`, the default, where the
    /// adapter has `DownlevelFlags::INDIRECT_EXECUTION`) or dispatch every bounce over the
    /// whole chunk (`false`; for tests: the same image either way).
    pub fn set_wavefront_indirect(&mut self, on: bool) {
        let flags = self.ctx.adapter.get_downlevel_capabilities().flags;
        self.wavefront_indirect = on && flags.contains(wgpu::DownlevelFlags::INDIRECT_EXECUTION);
    }

    /// Choose the estimator: path, lt+pt or sppm (`auto` resolves to one of them for the scene);
    /// compiles its pipelines on first use; accumulation restarts.
    pub fn set_estimator(&mut self, estimator: Estimator) -> Result<()> {
        gpu_estimator(estimator, &self.scene)?;
        let whole = light_tracing_for(
            &RenderOptions {
                estimator,
                ..self.opts
            },
            &self.scene,
        ) || sppm_for(
            &RenderOptions {
                estimator,
                ..self.opts
            },
            &self.scene,
        );
        ensure!(
            !(whole && self.tiled.is_some()),
            "image {}x{} is larger than one GPU binding and renders in tiles, which only path \
             tracing does (light tracing and photons need the whole image at once)",
            self.opts.width,
            self.opts.height
        );
        self.opts.estimator = estimator;
        self.respecialize();
        self.fit_splat_film()?;
        self.fit_photon_store()?;
        self.reset();
        Ok(())
    }

    /// The estimator asked for.
    pub fn estimator(&self) -> Estimator {
        self.opts.estimator
    }

    /// The estimator the kernels run.
    pub fn effective_estimator(&self) -> Estimator {
        if self.spec.light_tracing {
            Estimator::LtPt
        } else if self.spec.sppm {
            Estimator::Sppm
        } else {
            Estimator::Path
        }
    }

    /// Light distribution changed (emission edits): rewrite triangles (pick probabilities) and
    /// the light CDF; the BVH is kept.
    fn rebuild_lights(&mut self) -> Result<()> {
        self.light_set = LightSet::build(&self.scene);
        let tris = upload::pack_triangles(&self.scene, &self.bvh, &self.light_set);
        self.ctx.queue.write_buffer(
            &self.buffers.triangles,
            0,
            checked_bytes("triangles", &tris, self.ctx.max_binding_bytes())?,
        );
        let (lights, count) =
            upload::pack_lights(&self.bvh, &self.light_set, self.buffers.env_offset);
        let bytes = checked_bytes("lights", &lights, self.ctx.max_binding_bytes())?;
        if bytes.len() as u64 <= self.buffers.lights.size() {
            self.ctx.queue.write_buffer(&self.buffers.lights, 0, bytes);
        } else {
            self.buffers.lights = storage(&self.ctx, "lights", bytes);
            self.bind_group = Self::bind(&self.ctx, &self.pipelines, &self.buffers);
        }
        self.light_count = count;
        Ok(())
    }

    /// Uniform environment radiance (no recompilation). Accumulation restarts.
    pub fn set_environment(&mut self, radiance: Vec3) -> Result<()> {
        ensure!(
            radiance.is_finite() && radiance.min_element() >= 0.0,
            "environment radiance must be finite and non-negative"
        );
        self.scene.environment = radiance;
        self.reset();
        Ok(())
    }

    /// Move the camera. Accumulation restarts.
    pub fn set_camera(&mut self, camera: Camera) -> Result<()> {
        camera.validate()?;
        self.scene.camera = camera;
        self.reset();
        Ok(())
    }

    /// Change seed, depth limits, batch or image size (size changes reallocate the image
    /// buffer). The filter and estimator stay as they are (see [`GpuRenderer::set_filter`]
    /// and [`GpuRenderer::set_estimator`]).
    pub fn set_options(&mut self, opts: RenderOptions) -> Result<()> {
        opts.check()?;
        let opts = self.keep_filter_and_estimator(opts);
        let resized = (opts.width, opts.height) != (self.opts.width, self.opts.height);
        self.opts = opts;
        if resized {
            let (buffers, count, slots) = Self::create_buffers(
                &self.ctx,
                &self.scene,
                &self.bvh,
                &self.light_set,
                &opts,
                self.tiles_allowed(),
            )?;
            self.buffers = buffers;
            self.light_count = count;
            self.tex_slots = slots;
            self.write_filter_table();
            self.bind_group = Self::bind(&self.ctx, &self.pipelines, &self.buffers);
            self.fit_tiles();
            self.fit_wavefront();
        }
        self.reset();
        Ok(())
    }

    /// `opts` with the filter and estimator in use.
    fn keep_filter_and_estimator(&self, opts: RenderOptions) -> RenderOptions {
        RenderOptions {
            filter: self.opts.filter,
            filter_forward: self.opts.filter_forward,
            estimator: self.opts.estimator,
            ..opts
        }
    }

    /// Replace the scene: BVH, buffers and (if its features differ) the pipeline are rebuilt;
    /// compiled pipelines stay cached. Options as [`GpuRenderer::set_options`] (the filter
    /// and estimator stay).
    pub fn set_scene(&mut self, scene: Scene, opts: RenderOptions) -> Result<()> {
        scene.validate()?;
        upload::check_supported(&scene)?;
        opts.check()?;
        let opts = self.keep_filter_and_estimator(opts);
        let bvh = upload::build_bvh(&scene)?;
        let light_set = LightSet::build(&scene);
        let (buffers, count, slots) = Self::create_buffers(
            &self.ctx,
            &scene,
            &bvh,
            &light_set,
            &opts,
            self.tiles_allowed(),
        )?;
        self.tex_slots = slots;
        self.scene = scene;
        self.opts = opts;
        self.bvh = bvh;
        self.light_set = light_set;
        self.buffers = buffers;
        self.light_count = count;
        self.bind_group = Self::bind(&self.ctx, &self.pipelines, &self.buffers);
        self.features = self.scene.features();
        self.write_filter_table();
        self.respecialize();
        self.fit_tiles();
        self.reset();
        Ok(())
    }

    /// Set the Heckbert path filter (None or an accept-all filter = every path). Only the
    /// uniform table is rewritten when a filter replaces another; switching between filtered
    /// and unfiltered selects the other specialisation (compiled once, then cached).
    /// Accumulation restarts.
    pub fn set_filter(&mut self, filter: Option<&PathFilter>) {
        self.opts.set_filter(filter);
        self.write_filter_table();
        self.respecialize();
        self.reset();
    }

    /// The eye→light table in use (None = unfiltered).
    pub fn filter(&self) -> Option<&DfaTable> {
        self.opts.filter.as_ref()
    }

    fn write_filter_table(&self) {
        let mut words = [0u32; layout::FILTER_WORDS];
        if let Some(t) = self.opts.filter {
            let w = t.words();
            words[..w.len()].copy_from_slice(&w);
        }
        self.ctx
            .queue
            .write_buffer(&self.buffers.filter, 0, bytemuck::cast_slice(&words));
    }

    // ---- BEGIN viewer accessors (used by app::backend::gpu; keep this block last) ----------

    /// The accumulation buffer: `array<vec4<f32>>`, per-pixel MEAN radiance (linear Rec.709),
    /// row-major, top row first, `width × height` entries. The viewer tone-maps it on the GPU.
    pub fn accum_buffer(&self) -> &wgpu::Buffer {
        &self.buffers.accum
    }

    /// The stats buffer; its first 16 bytes are the [`layout::Stats`] counters.
    pub fn stats_buffer(&self) -> &wgpu::Buffer {
        &self.buffers.stats
    }

    /// Set the path filter from an eye→light table (as [`RenderOptions::filter`]; None =
    /// every path; the GPU has no use for the light→eye table). Like
    /// [`GpuRenderer::set_filter`]; accumulation restarts.
    pub fn set_filter_table(&mut self, table: Option<DfaTable>) {
        self.opts.filter = table;
        self.write_filter_table();
        self.respecialize();
        self.reset();
    }

    // ---- END viewer accessors ---------------------------------------------------------------
}

mod tiles;
pub mod wavefront;
