//! [`GpuBackend`]: the viewer's wgpu backend (the GPU side of [`super`]).
//!
//! It renders with [`crate::gpu::GpuRenderer`] on eframe's own device (the
//! `egui_wgpu::RenderState`, created in `app::wgpu_configuration` with the adapter's limits),
//! so the accumulated image never leaves the GPU:
//!
//! - [`Backend::step`] (UI thread, once per frame) keeps at most two batches queued (the next
//!   waits in the queue while one runs) where submissions are asynchronous, one on GL and on
//!   software drivers, and never waits for the GPU. While a new specialisation's pipelines
//!   compile on a worker thread it queues nothing and the last image stays on screen (not on
//!   GL: its one context would be held by the compiling thread, so there they compile in the
//!   edit). Completion is signalled by `Queue::on_submitted_work_done`; a helper
//!   thread drives `device.poll(PollType::Poll)` while a batch is in flight so the callback
//!   fires (and is timed) within about a millisecond, and wakes the UI. On wgpu's GL backend
//!   there is no helper thread: GL has one context, whose lock the submitting thread holds
//!   while the driver runs the batch (wgpu-hal panics after waiting 1 s for it), so the UI
//!   thread polls in each `step` and a batch is timed from before its submission. The samples per pixel
//!   of the next batch follow the measured time per pixel sample so that a batch takes about
//!   the frame budget. While the user drags, and when one sample per pixel at full resolution
//!   would not fit the budget, the backend renders at quarter resolution (like `CpuBackend`).
//! - [`Backend::display_texture`] tone-maps the accumulation buffer on the GPU
//!   ([`crate::gpu::tonemap`]) into an `Rgba8Unorm` storage texture holding sRGB-encoded
//!   bytes; an `Rgba8UnormSrgb` view of it (on adapters without view formats, such as wgpu's
//!   GL backend, an `Rgba8UnormSrgb` copy of its bytes) is registered with egui-wgpu (the
//!   format of egui's own textures), so the screen shows exactly the bytes `film::to_srgb8`
//!   computes, like the CPU path. The tone map reruns only when the generation, the spp or the display settings
//!   change, and only while no batch is in flight (it is queued right after a batch finishes,
//!   before the next one), as is the dropped-sample counter copy: no submission of ours waits
//!   behind a running batch. (Software drivers such as lavapipe execute a submission before
//!   accepting the next, so there eframe's own frame submission still waits for the batch:
//!   that is why `--device auto` keeps the CPU backend on software adapters.)
//! - Only [`Backend::read_image`] (screenshots) reads the accumulation buffer back.
//! - Edits apply synchronously to the renderer (buffers rewritten in place, BVH kept where
//!   possible); queue order guarantees that a batch already in flight finishes before the
//!   reset, and its samples are not counted for the new generation.
//! - A scene or setting the GPU kernel cannot handle (`upload::check_supported`, buffers over
//!   the limit), or a GPU error (error scopes, the device's uncaptured-error handler, device
//!   loss: [`GpuContext`]), switches to a [`CpuBackend`] with a message; the next scene or
//!   options change tries the GPU again.
//!
//! Files: `poller` (completion polling), `batching` (sizing and queueing batches),
//! `completion` (finished batches and the stats readback), `display` (the tone-mapped
//! image), `backend` (the [`Backend`] trait); this file holds the state, edits and fallback.

use super::{Backend, CpuBackend, DisplayParams};
use crate::gpu::tonemap::ToneMapper;
use crate::gpu::{GpuContext, GpuRenderer};
use crate::render::{Estimator, Polarization, RenderOptions};
use crate::scene::Scene;
use anyhow::{Context as _, Result};
use eframe::egui;
use eframe::egui::mutex::RwLock;
use eframe::egui_wgpu;
use eframe::wgpu;
use std::collections::VecDeque;
use std::sync::Arc;
use std::sync::atomic::AtomicU8;
use std::time::{Duration, Instant};

mod backend;
mod batching;
mod completion;
mod cpu_image;
mod display;
mod poller;

use completion::{Batch, MAP_PENDING, StatsReadback};
use poller::Poller;

/// Upper bound of samples per pixel in one batch (keeps single dispatches short).
const MAX_BATCH_SPP: u32 = 256;

/// Frame budget assumed before the first `step`.
const DEFAULT_BUDGET: Duration = Duration::from_millis(8);

/// Interactive rendering on eframe's wgpu device (see the module documentation).
pub struct GpuBackend {
    ctx: GpuContext,
    /// egui-wgpu's renderer on the same device, which samples the tone-mapped texture; None
    /// when the window is drawn by something else (glow): the image is then read back.
    egui_renderer: Option<Arc<RwLock<egui_wgpu::Renderer>>>,
    /// The read-back image (headless backends only).
    cpu_image: cpu_image::CpuImage,
    repaint: Option<egui::Context>,
    renderer: Option<GpuRenderer>,
    /// Set while the GPU cannot render the current scene/options: everything goes here.
    fallback: Option<CpuBackend>,
    /// What the viewer asked for (replayed into the fallback, or into a new renderer).
    scene: Option<Scene>,
    options: Option<RenderOptions>,
    interactive: bool,
    paused: bool,
    spp_target: u64,
    generation: u64,
    /// Samples per pixel of the current generation whose batch has finished.
    done_spp: u64,
    elapsed: Duration,
    dropped: u64,
    /// Batches queued and not yet finished, oldest first.
    in_flight: VecDeque<Batch>,
    /// Most batches in flight: 2 where submissions are asynchronous (the next waits in the
    /// queue while one runs, so the GPU never idles between frames), else 1.
    depth: usize,
    /// When the GPU finished the last collected batch (the next one started then).
    last_done: Option<Instant>,
    /// A banded pass under way: (samples per pixel, first row not yet submitted). Used where
    /// one sample of the whole image would overrun the frame budget (a slow GPU, GL's
    /// synchronous submissions), so no frame waits for more than a band.
    pass: Option<(u32, u32)>,
    /// Measured GPU time per pixel sample (moving average over batches).
    sec_per_sample: Option<f64>,
    budget: Duration,
    tonemap: ToneMapper,
    /// The egui id of the tone-mapped texture's sRGB view (None before the first image).
    image_id: Option<egui::TextureId>,
    /// (generation, spp, size, display) of the tone-mapped texture.
    shown: Option<(u64, u64, [u32; 2], DisplayParams)>,
    /// Display settings of the last `display_texture` call.
    display: Option<DisplayParams>,
    readback: StatsReadback,
    /// Compile general kernels ahead of need regardless of the adapter (None: the
    /// renderer's default, off on software drivers).
    compile_ahead: Option<bool>,
    /// Run only the general kernels (`GpuRenderer::set_general_kernel`): nothing compiles
    /// once each family's is, whatever the edits (soak tests, comparisons).
    general_kernel: bool,
    /// The pipeline cache's capacity in specialisations (None: the renderer's default).
    pipeline_capacity: Option<usize>,
    poller: Poller,
    message: Option<String>,
    /// The polarising filter's angle (radians; `Backend::set_polarizer`): polarised
    /// transport, the path estimator over every path (as `CpuBackend`).
    polarizer: Option<f32>,
}

impl GpuBackend {
    /// A backend on eframe's device. `repaint` is woken whenever a batch finishes.
    pub fn from_render_state(
        rs: &egui_wgpu::RenderState,
        repaint: Option<egui::Context>,
    ) -> Result<GpuBackend> {
        let ctx = GpuContext::from_parts(rs.adapter.clone(), rs.device.clone(), rs.queue.clone());
        GpuBackend::new(ctx, Arc::clone(&rs.renderer), repaint)
    }

    /// A backend on `ctx`, registering its image with `egui_renderer` (which must draw with
    /// the same device).
    pub fn new(
        ctx: GpuContext,
        egui_renderer: Arc<RwLock<egui_wgpu::Renderer>>,
        repaint: Option<egui::Context>,
    ) -> Result<GpuBackend> {
        GpuBackend::with_display(ctx, Some(egui_renderer), repaint)
    }

    /// A backend on a device of its own, for a window that egui-wgpu does not draw (glow):
    /// each new tone-mapped image is read back and uploaded as an egui texture.
    pub fn headless(ctx: GpuContext, repaint: Option<egui::Context>) -> Result<GpuBackend> {
        GpuBackend::with_display(ctx, None, repaint)
    }

    fn with_display(
        ctx: GpuContext,
        egui_renderer: Option<Arc<RwLock<egui_wgpu::Renderer>>>,
        repaint: Option<egui::Context>,
    ) -> Result<GpuBackend> {
        let tonemap = ToneMapper::new(&ctx).context("cannot build the GPU tone-map pipeline")?;
        let readback = StatsReadback {
            staging: ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("stats readback"),
                size: 16,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            pending: None,
            state: Arc::new(AtomicU8::new(MAP_PENDING)),
        };
        let poller = Poller::new(ctx.device.clone(), ctx.info.backend != wgpu::Backend::Gl);
        // GL runs a batch inside `submit`, and software Vulkan drivers (lavapipe) finish one
        // submission before accepting the next: a second batch would block the UI thread.
        // A read-back image waits for the queue, so there one batch is queued at a time too.
        let depth = if poller.thread.is_some() && !ctx.is_software() && egui_renderer.is_some() {
            2
        } else {
            1
        };
        Ok(GpuBackend {
            ctx,
            egui_renderer,
            cpu_image: cpu_image::CpuImage::default(),
            repaint,
            renderer: None,
            fallback: None,
            scene: None,
            options: None,
            interactive: false,
            paused: false,
            spp_target: 0,
            generation: 0,
            done_spp: 0,
            elapsed: Duration::ZERO,
            dropped: 0,
            in_flight: VecDeque::new(),
            depth,
            last_done: None,
            pass: None,
            sec_per_sample: None,
            budget: DEFAULT_BUDGET,
            tonemap,
            image_id: None,
            shown: None,
            display: None,
            readback,
            compile_ahead: None,
            general_kernel: false,
            pipeline_capacity: None,
            poller,
            message: None,
            polarizer: None,
        })
    }

    /// The device the backend renders on.
    pub fn context(&self) -> &GpuContext {
        &self.ctx
    }

    /// True while the CPU renders instead (the GPU cannot handle the scene or options).
    pub fn is_fallback(&self) -> bool {
        self.fallback.is_some()
    }

    /// True while a batch is queued on the GPU and not yet finished.
    pub fn batch_in_flight(&self) -> bool {
        !self.in_flight.is_empty()
    }

    /// Batches queued on the GPU and not yet finished.
    pub fn batches_in_flight(&self) -> usize {
        self.in_flight.len()
    }

    /// Keep up to `n` batches in flight (at least 1; default 2 on hardware Vulkan, Metal and
    /// DX12, 1 on GL and software drivers, whose submissions block).
    pub fn set_batches_in_flight(&mut self, n: usize) {
        self.depth = n.max(1);
    }

    /// True while the current specialisation's pipelines compile on a worker thread (the
    /// last image stays on screen meanwhile).
    pub fn is_compiling(&self) -> bool {
        self.fallback.is_none() && self.renderer.as_ref().is_some_and(|r| r.is_compiling())
    }

    /// True while the current specialisation's own kernels compile and its family's general
    /// kernel renders instead (`GpuRenderer::is_general`).
    pub fn runs_general_kernel(&self) -> bool {
        self.fallback.is_none() && self.renderer.as_ref().is_some_and(|r| r.is_general())
    }

    /// Compile general kernels ahead of need (`on`) whatever the adapter (by default not on
    /// software drivers); applies to the renderer now and to later ones.
    pub fn set_compile_ahead(&mut self, on: bool) {
        self.compile_ahead = Some(on);
        if let Some(r) = self.renderer.as_mut() {
            r.set_compile_ahead(on);
        }
    }

    /// Run the general kernel of each family only (`on`), never the specialised ones: edits
    /// compile nothing once the families they visit have theirs. Applies to the renderer
    /// now and to later ones.
    pub fn set_general_kernel(&mut self, on: bool) {
        self.general_kernel = on;
        if let Some(r) = self.renderer.as_mut() {
            r.set_general_kernel(on);
        }
    }

    /// Keep at most `n` specialisations' pipelines compiled (`Pipelines::set_capacity`), in
    /// the renderer now and in later ones.
    pub fn set_pipeline_capacity(&mut self, n: usize) {
        self.pipeline_capacity = Some(n);
        if let Some(r) = self.renderer.as_mut() {
            r.set_pipeline_capacity(n);
        }
    }

    /// (pipelines compiled so far, specialisations cached now); None before the renderer
    /// exists.
    pub fn pipeline_stats(&self) -> Option<(u32, usize)> {
        let r = self.renderer.as_ref()?;
        Some((r.pipelines_compiled(), r.cached_specializations()))
    }

    /// True while any kernel compiles on a worker thread (the current one, or a general
    /// kernel compiled ahead).
    pub fn compiles_in_background(&self) -> bool {
        self.renderer
            .as_ref()
            .is_some_and(|r| r.background_compiles_pending())
    }

    /// Samples per pixel queued for the current generation (finished or not).
    pub fn queued_spp(&self) -> u64 {
        self.renderer.as_ref().map_or(0, |r| r.spp())
    }

    /// Read the tone-mapped texture back: (width, height, RGBA8 sRGB bytes). Blocking; for
    /// tests and debugging only (the viewer never reads it back).
    pub fn read_display_pixels(&self) -> Result<(u32, u32, Vec<u8>)> {
        self.tonemap.read_pixels(&self.ctx)
    }

    /// Tone map through the copy into an `Rgba8UnormSrgb` texture, as on adapters without
    /// `DownlevelFlags::VIEW_FORMATS` (wgpu's GL backend), whatever this adapter supports: for
    /// tests of that path on any adapter.
    pub fn force_tone_map_copy(&mut self) -> Result<()> {
        self.tonemap = ToneMapper::with_view_formats(&self.ctx, false)
            .context("cannot build the GPU tone-map pipeline")?;
        self.shown = None;
        Ok(())
    }

    /// Every edit: a new generation with no samples.
    fn bump(&mut self) {
        self.generation += 1;
        self.pass = None;
        self.done_spp = 0;
        self.elapsed = Duration::ZERO;
        self.dropped = 0;
    }

    /// The renderer's options for the current viewer options, interactive state and speed.
    fn gpu_options(&self) -> Option<RenderOptions> {
        let o = self.options?;
        let (mut w, mut h) = (o.width, o.height);
        // Quarter resolution while dragging, when one full-resolution sample per pixel would
        // not fit the frame budget (as `CpuBackend`, which always drops to a quarter).
        let full = w as f64 * h as f64;
        let slow = self
            .sec_per_sample
            .is_some_and(|s| s * full > self.budget.as_secs_f64());
        if self.interactive && slow {
            w = (w / 4).max(1);
            h = (h / 4).max(1);
        }
        Some(RenderOptions {
            width: w,
            height: h,
            estimator: self.wanted_estimator(),
            batch_spp: None,
            ..o
        })
    }

    /// (Re)build the GPU state from the mirrored scene and options. Ok(false): not enough
    /// to render yet (no scene or no options).
    fn sync_full(&mut self) -> Result<bool> {
        let (Some(scene), Some(gopts), Some(o)) =
            (self.scene.clone(), self.gpu_options(), self.options)
        else {
            return Ok(false);
        };
        match self.renderer.as_mut() {
            Some(r) => r.set_scene(scene, gopts)?,
            None => {
                // GL has one context, which a compiling thread holds (wgpu-hal panics after
                // waiting 1 s for it): there the pipelines compile in the edit, as before.
                let ctx = self.ctx.clone();
                self.renderer = Some(if self.ctx.info.backend == wgpu::Backend::Gl {
                    GpuRenderer::with_context_untiled(ctx, scene, gopts)?
                } else {
                    GpuRenderer::with_context_in_background(ctx, scene, gopts)?
                });
            }
        }
        let table = self.wanted_filter(&o);
        if let Some(r) = self.renderer.as_mut() {
            r.set_polarization(None)?;
            r.set_filter_table(table);
            if let Some(on) = self.compile_ahead {
                r.set_compile_ahead(on);
            }
            if let Some(n) = self.pipeline_capacity {
                r.set_pipeline_capacity(n);
            }
            if self.general_kernel {
                r.set_general_kernel(true);
            }
        }
        self.sync_estimator();
        self.sync_polarizer()?;
        Ok(true)
    }

    /// The viewer's choice, as asked: the renderer plans what runs for it
    /// (`render::estimator_plan`, the same decision as `render --device gpu`: auto resolved
    /// for the scene, bdpt and lt as lt+pt).
    /// With the polarising filter the path tracer runs (`CpuBackend` does the same).
    fn wanted_estimator(&self) -> Estimator {
        match self.options {
            Some(o) if self.polarizer.is_none() => o.estimator,
            _ => Estimator::Path,
        }
    }

    /// The path filter of `o`, none with the polarising filter (polarised transport
    /// renders every path, as on the CPU).
    fn wanted_filter(&self, o: &RenderOptions) -> Option<crate::paths::DfaTable> {
        o.filter.filter(|_| self.polarizer.is_none())
    }

    /// Give the renderer the polarising filter: taken away first, then the filter and
    /// estimator it needs, then set (each step only where something changes).
    fn sync_polarizer(&mut self) -> Result<()> {
        let want = self.polarizer.map(|a| Polarization { filter: Some(a) });
        let table = self.options.map(|o| self.wanted_filter(&o));
        let Some(r) = self.renderer.as_mut() else {
            return Ok(());
        };
        if r.polarization() == want {
            return Ok(());
        }
        r.set_polarization(None)?;
        if let Some(table) = table
            && r.filter().copied() != table
        {
            r.set_filter_table(table);
        }
        self.sync_estimator();
        let Some(r) = self.renderer.as_mut() else {
            return Ok(());
        };
        r.set_polarization(want)
    }

    /// Apply the wanted estimator (only when it changed: switching restarts accumulation).
    fn sync_estimator(&mut self) {
        let want = self.wanted_estimator();
        let Some(r) = self.renderer.as_mut() else {
            return;
        };
        if r.estimator() == want {
            return;
        }
        if let Err(e) = r.set_estimator(want) {
            self.message = Some(format!(
                "{e:#}; rendering with {}.",
                r.effective_estimator()
            ));
        }
    }

    /// Options changed on a working renderer.
    fn sync_options(&mut self) -> Result<()> {
        let (Some(gopts), Some(o)) = (self.gpu_options(), self.options) else {
            return Ok(());
        };
        let table = self.wanted_filter(&o);
        let Some(r) = self.renderer.as_mut() else {
            return self.sync_full().map(|_| ());
        };
        r.set_options(gopts)?;
        if r.filter().copied() != table {
            r.set_filter_table(table);
        }
        self.sync_estimator();
        self.sync_polarizer()
    }

    /// Render on the CPU from now on (state replayed), with a message saying why.
    fn enter_fallback(&mut self, why: &anyhow::Error) {
        self.in_flight.clear();
        self.message = Some(format!(
            "The GPU renderer cannot render this ({why:#}); rendering on the CPU instead."
        ));
        let mut cpu = CpuBackend::new(self.repaint.clone());
        if let Some(s) = &self.scene {
            cpu.set_scene(s);
        }
        if let Some(o) = &self.options {
            cpu.set_options(o);
        }
        cpu.set_interactive(self.interactive);
        cpu.set_paused(self.paused);
        cpu.set_spp_target(self.spp_target);
        self.fallback = Some(cpu);
    }

    /// A whole-scene or options change while on the CPU fallback: try the GPU again.
    fn retry_gpu(&mut self) -> bool {
        match self.sync_full() {
            Ok(true) => {
                self.fallback = None;
                self.shown = None;
                self.message = Some("Rendering on the GPU again.".into());
                true
            }
            _ => false,
        }
    }

    /// Apply `f` to the renderer; an error switches to the CPU fallback.
    fn with_renderer(&mut self, f: impl FnOnce(&mut GpuRenderer) -> Result<()>) {
        if let Some(r) = self.renderer.as_mut()
            && let Err(e) = f(r)
        {
            self.enter_fallback(&e);
        }
    }

    fn wants_samples(&self, queued: u64) -> bool {
        !self.paused && (self.spp_target == 0 || queued < self.spp_target)
    }
}

impl Drop for GpuBackend {
    fn drop(&mut self) {
        if let (Some(id), Some(r)) = (self.image_id.take(), &self.egui_renderer) {
            r.write().free_texture(&id);
        }
    }
}
