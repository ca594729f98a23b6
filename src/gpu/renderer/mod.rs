//! [`GpuRenderer`]: progressive accumulation on the GPU with the same estimator and RNG as the
//! CPU path tracer. Each dispatch adds a batch of k samples per pixel, summed in f32 and folded
//! into an f32 running mean with weights n/(n+k) and 1/(n+k) (no drift from a growing sum).
//! Non-finite and negative samples are dropped and counted by an atomic counter.
//!
//! One `impl GpuRenderer` block per facet: `build` (buffers and bind groups), `submit`
//! (dispatch, submission, pipelines readiness), `readback` (image, counters, debug path),
//! `edit` (parameter edits and respecialisation), `accessors`, `tiles`, [`wavefront`].

mod accessors;
mod build;
mod edit;
mod readback;
mod submit;
mod tiles;
pub mod wavefront;

use super::GpuContext;
use super::buffers::zeroed_storage;
use super::layout;
use super::photons::PhotonStore;
use super::pipeline::{Pipelines, Specialization};
use super::submissions::Submissions;
use super::upload::{self, GpuBvh};
use crate::film::Film;
use crate::render::photon_aim::PhotonTargets;
use crate::render::{EstimatorPlan, Polarization, RenderOptions, Runner};
use crate::scene::{Features, Scene, light::LightSet};
use anyhow::{Result, ensure};
use glam::{Vec3, Vec4};
use std::time::Duration;

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
    /// `sppm`: where finite lights aim their photons, and the share of the lights' power
    /// that goes there (`render::photon_aim`), found at the first `sppm` submission after
    /// a material or light edit (`fit_photon_aim` forgets it).
    photon_aim: std::sync::OnceLock<(PhotonTargets, f32)>,
    /// Compile new specialisations on a worker thread (the viewer) instead of in the call
    /// that changes the specialisation (the CLI, tests).
    background_compile: bool,
    /// Always run the general kernel of the family (`set_general_kernel`; comparisons).
    general_only: bool,
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
    /// Polarised transport with this filter (`set_polarization`; None: unpolarised).
    polarization: Option<Polarization>,
    /// The row the sensor reads instead of the filter's (`set_analyzer`; Stokes views).
    analyzer: Option<Vec4>,
}

/// Submissions [`GpuRenderer::render_with`] keeps queued by default: while the GPU runs one,
/// the next is already submitted, so it never idles while the CPU plans and encodes.
pub const BATCHES_IN_FLIGHT: usize = 2;
/// Rows of the image the accumulation film (and, with light tracing, the splat film) holds:
/// all of them when they fit one binding of `cap` bytes (or when `whole_image` submissions
/// are needed: the caller then refuses the size), else the most whole workgroup rows (8)
/// that fit — the image is rendered in tiles.
fn film_rows(opts: &RenderOptions, cap: u64, whole_image: bool, light_tracing: bool) -> u32 {
    let per_pixel = if light_tracing {
        SPLAT_BYTES_PER_PIXEL
    } else {
        16
    };
    let row = u64::from(opts.width) * per_pixel;
    if whole_image || row * u64::from(opts.height) <= cap {
        return opts.height;
    }
    ((cap / row.max(1)) as u32 / 8 * 8).clamp(8, opts.height)
}

/// Bytes of the light-tracing splat film per pixel (3 channels × 2 × u32).
const SPLAT_BYTES_PER_PIXEL: u64 = 24;

/// The GPU's plan for `opts.estimator` on `scene` (the one decision, `render::estimator_plan`).
fn gpu_plan(opts: &RenderOptions, scene: &Scene) -> EstimatorPlan {
    EstimatorPlan::decide(opts.estimator, scene, Runner::Gpu)
}

/// Photon slots per iteration: one per pixel with `sppm` (`cpu::sppm::PHOTONS_PER_PIXEL`;
/// the aimed paths of an iteration, `render::photon_aim::photon_paths`, are at most that),
/// else a placeholder store of one.
fn photon_paths(sppm: bool, opts: &RenderOptions) -> u32 {
    if sppm {
        opts.width.saturating_mul(opts.height)
    } else {
        1
    }
}

/// The splat film's size: `rows` whole image rows with light tracing (the film's rows);
/// without it the binding still needs a buffer, so one pixel (path tracing at 4K no longer
/// pays 24 B per pixel for it).
fn splat_film_bytes(light_tracing: bool, opts: &RenderOptions, rows: u32) -> u64 {
    let pixels = if light_tracing {
        opts.width as u64 * rows as u64
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
/// either is larger than one binding. With `tiles`, an image larger than one binding renders
/// in tiles of rows: sppm traces every iteration's photons again for each tile, lt+pt every
/// light subpath (each tile keeps the splats on its rows).
fn film_bytes(
    ctx: &GpuContext,
    scene: &Scene,
    opts: &RenderOptions,
    tiles: bool,
) -> Result<(u64, u64)> {
    let light_tracing = gpu_plan(opts, scene).light_tracing();
    let cap = ctx.max_binding_bytes();
    let rows = film_rows(opts, cap, !tiles, light_tracing);
    let accum_bytes = u64::from(opts.width) * 16 * u64::from(rows);
    let splat_bytes = splat_film_bytes(light_tracing, opts, rows);
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
        Self::build(ctx, scene, opts, (false, true), None)
    }

    /// [`GpuRenderer::with_context`] for the viewer's progressive display where pipelines must
    /// compile in the call (GL): an image larger than one binding is an error (no tiles).
    pub fn with_context_untiled(
        ctx: GpuContext,
        scene: Scene,
        opts: RenderOptions,
    ) -> Result<GpuRenderer> {
        Self::build(ctx, scene, opts, (false, false), None)
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
        Self::build(ctx, scene, opts, (true, false), None)
    }

    /// [`GpuRenderer::with_context`] tracing polarised light behind `pol`'s filter from the
    /// start (`set_polarization`, without compiling the unpolarised kernel first).
    pub fn with_context_polarized(
        ctx: GpuContext,
        scene: Scene,
        opts: RenderOptions,
        pol: Polarization,
    ) -> Result<GpuRenderer> {
        Self::build(ctx, scene, opts, (false, true), Some(pol))
    }
}
