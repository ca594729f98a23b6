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

use super::{Accumulated, Backend, CpuBackend, DisplayParams, DisplayTexture};
use crate::gpu::tonemap::ToneMapper;
use crate::gpu::{GpuContext, GpuRenderer};
use crate::render::{Estimator, RenderOptions};
use crate::scene::{Camera, Material, Scene};
use anyhow::{Context as _, Result};
use eframe::egui;
use eframe::egui::mutex::RwLock;
use eframe::egui_wgpu;
use eframe::wgpu;
use std::collections::VecDeque;
use std::sync::atomic::{AtomicBool, AtomicU8, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// Upper bound of samples per pixel in one batch (keeps single dispatches short).
const MAX_BATCH_SPP: u32 = 256;

/// Frame budget assumed before the first `step`.
const DEFAULT_BUDGET: Duration = Duration::from_millis(8);

// ---------------------------------------------------------------------------------------------
// Completion polling
// ---------------------------------------------------------------------------------------------

/// Polls the device (never waits on it) while a batch is in flight. A blocking
/// `PollType::Wait` would hold the device's fence lock and stall the UI thread's submissions.
struct Poller {
    /// Batches in flight (their callbacks decrement it).
    busy: Arc<AtomicUsize>,
    quit: Arc<AtomicBool>,
    thread: Option<std::thread::JoinHandle<()>>,
}

impl Poller {
    /// A poller with a helper thread, or (`threaded` false, for GL) without one.
    fn new(device: wgpu::Device, threaded: bool) -> Poller {
        let busy = Arc::new(AtomicUsize::new(0));
        let quit = Arc::new(AtomicBool::new(false));
        let (b, q) = (Arc::clone(&busy), Arc::clone(&quit));
        if !threaded {
            return Poller {
                busy,
                quit,
                thread: None,
            };
        }
        let thread = std::thread::Builder::new()
            .name("refract-gpu-poll".into())
            .spawn(move || {
                while !q.load(Ordering::Acquire) {
                    if b.load(Ordering::Acquire) > 0 {
                        let _ = device.poll(wgpu::PollType::Poll);
                        std::thread::sleep(Duration::from_micros(500));
                    } else {
                        std::thread::park_timeout(Duration::from_millis(100));
                    }
                }
            })
            .ok();
        Poller { busy, quit, thread }
    }

    /// A batch was queued: poll until its callback decrements `busy`.
    fn kick(&self) {
        self.busy.fetch_add(1, Ordering::AcqRel);
        if let Some(t) = &self.thread {
            t.thread().unpark();
        }
    }
}

impl Drop for Poller {
    fn drop(&mut self) {
        self.quit.store(true, Ordering::Release);
        if let Some(t) = self.thread.take() {
            t.thread().unpark();
            let _ = t.join();
        }
    }
}

/// One queued dispatch.
/// Pixels of the first, untimed band of a viewer pass.
const PROBE_PIXELS: u32 = 1 << 14;

struct Batch {
    /// Samples per pixel of its pass.
    k: u32,
    /// Pixels it covers (the whole image, or a band of rows).
    pixels: u64,
    /// Samples per pixel it completes for the whole image when it finishes: `k` for a
    /// whole-image batch or a pass's last band, 0 for an earlier band.
    completes: u32,
    generation: u64,
    submitted: Instant,
    /// Set by the `on_submitted_work_done` callback: when the GPU finished.
    done: Arc<Mutex<Option<Instant>>>,
}

/// Asynchronous readback of the 16-byte stats header (dropped-sample counter).
struct StatsReadback {
    staging: wgpu::Buffer,
    /// Generation of the copy in flight; None = the staging buffer is free.
    pending: Option<u64>,
    /// Set by the `map_async` callback: [`MAP_PENDING`], [`MAP_OK`] or [`MAP_FAILED`].
    state: Arc<AtomicU8>,
}

const MAP_PENDING: u8 = 0;
const MAP_OK: u8 = 1;
const MAP_FAILED: u8 = 2;

// ---------------------------------------------------------------------------------------------
// The backend
// ---------------------------------------------------------------------------------------------

/// Interactive rendering on eframe's wgpu device (see the module documentation).
pub struct GpuBackend {
    ctx: GpuContext,
    egui_renderer: Arc<RwLock<egui_wgpu::Renderer>>,
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
    poller: Poller,
    message: Option<String>,
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
        let depth = if poller.thread.is_some() && !ctx.is_software() {
            2
        } else {
            1
        };
        Ok(GpuBackend {
            ctx,
            egui_renderer,
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
            poller,
            message: None,
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
        if let Some(r) = self.renderer.as_mut() {
            r.set_filter_table(o.filter);
        }
        self.sync_estimator();
        Ok(true)
    }

    /// The GPU estimator for the viewer's choice: path tracing, photon mapping (sppm) and
    /// auto (resolved by the renderer for the scene, as on the CPU) run as chosen; the
    /// bidirectional choices (lt+pt, and bdpt / lt, which exist only on the CPU) run light +
    /// path tracing with MIS.
    fn wanted_estimator(&self) -> Estimator {
        match self.options.map(|o| o.estimator) {
            None | Some(Estimator::Path) => Estimator::Path,
            Some(e @ (Estimator::Sppm | Estimator::Auto)) => e,
            Some(_) => Estimator::LtPt,
        }
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
        let Some(r) = self.renderer.as_mut() else {
            return self.sync_full().map(|_| ());
        };
        r.set_options(gopts)?;
        if r.filter().copied() != o.filter {
            r.set_filter_table(o.filter);
        }
        self.sync_estimator();
        Ok(())
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

    /// Collect a finished batch and the stats readback (never waits).
    fn collect(&mut self) {
        let _ = self.ctx.device.poll(wgpu::PollType::Poll);
        // A GPU error no scope caught (a failed submission, a lost device): the CPU takes over.
        if let Err(e) = self.ctx.check_errors() {
            self.enter_fallback(&e);
            return;
        }
        // Batches finish in submission order.
        while let Some(t) = self
            .in_flight
            .front()
            .and_then(|b| *b.done.lock().unwrap_or_else(|e| e.into_inner()))
            && let Some(b) = self.in_flight.pop_front()
        {
            // A batch queued behind another started when that one finished.
            let began = self.last_done.map_or(b.submitted, |d| d.max(b.submitted));
            self.last_done = Some(t);
            let dt = t.saturating_duration_since(began);
            let per = dt.as_secs_f64() / (b.k as f64 * b.pixels as f64).max(1.0);
            self.sec_per_sample = Some(match self.sec_per_sample {
                Some(s) => 0.5 * s + 0.5 * per,
                None => per,
            });
            if b.generation == self.generation {
                self.done_spp += b.completes as u64;
                self.elapsed += dt;
            }
        }
        // Without a poller thread nobody wakes the UI when the batch finishes: keep stepping.
        if !self.in_flight.is_empty()
            && self.poller.thread.is_none()
            && let Some(c) = &self.repaint
        {
            c.request_repaint();
        }
        let Some(generation) = self.readback.pending else {
            return;
        };
        match self.readback.state.load(Ordering::Acquire) {
            MAP_OK => {
                let slice = self.readback.staging.slice(..);
                if let Ok(view) = slice.get_mapped_range() {
                    let s: crate::gpu::layout::Stats = bytemuck::pod_read_unaligned(&view[..16]);
                    if generation == self.generation {
                        self.dropped = s.dropped_lo as u64 | (s.dropped_hi as u64) << 32;
                    }
                }
                self.readback.staging.unmap();
            }
            MAP_FAILED => {}
            _ => return, // still pending
        }
        self.readback.state.store(MAP_PENDING, Ordering::Release);
        self.readback.pending = None;
    }

    /// Queue the stats header copy after a batch (if the staging buffer is free).
    fn start_readback(&mut self) {
        let Some(r) = self.renderer.as_ref() else {
            return;
        };
        if self.readback.pending.is_some() || r.spp() == 0 {
            return;
        }
        let mut enc = self
            .ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
        enc.copy_buffer_to_buffer(r.stats_buffer(), 0, &self.readback.staging, 0, 16);
        self.ctx.queue.submit([enc.finish()]);
        let state = Arc::clone(&self.readback.state);
        self.readback
            .staging
            .slice(..)
            .map_async(wgpu::MapMode::Read, move |res| {
                let s = if res.is_ok() { MAP_OK } else { MAP_FAILED };
                state.store(s, Ordering::Release);
            });
        self.readback.pending = Some(self.generation);
    }

    /// Re-run the tone map if the generation, the spp or the display settings changed, and
    /// only while no batch is in flight (otherwise the next `step` does it, right after the
    /// batch finishes: the image and a new exposure appear within one batch).
    fn refresh_display(&mut self) {
        if self.in_flight.len() >= self.depth {
            return;
        }
        let (Some(r), Some(display)) = (self.renderer.as_ref(), self.display) else {
            return;
        };
        let size = [r.options().width, r.options().height];
        let key = (self.generation, r.spp(), size, display);
        // While a new specialisation compiles the film still holds the last image (its clear
        // waits for the first batch): tone-map it on display changes.
        let stale = r.spp() == 0 && r.is_compiling() && self.shown.is_some_and(|s| s.2 == size);
        // Nothing rendered for this generation yet: keep showing the previous image.
        if (r.spp() > 0 || stale) && self.shown != Some(key) {
            if self.tonemap.ensure_target(&self.ctx, size) {
                register_image(
                    &self.ctx,
                    &self.egui_renderer,
                    &self.tonemap,
                    &mut self.image_id,
                );
            }
            self.tonemap.run(
                &self.ctx,
                r.accum_buffer(),
                display.tone_map,
                display.exposure,
            );
            self.shown = Some(key);
        }
    }

    fn wants_samples(&self, queued: u64) -> bool {
        !self.paused && (self.spp_target == 0 || queued < self.spp_target)
    }
}

/// Register the (new) tone-map target's sRGB view with egui-wgpu, under the old id if there
/// is one.
fn register_image(
    ctx: &GpuContext,
    egui_renderer: &RwLock<egui_wgpu::Renderer>,
    tonemap: &ToneMapper,
    image_id: &mut Option<egui::TextureId>,
) {
    let Some(view) = tonemap.srgb_view() else {
        return;
    };
    let filter = wgpu::FilterMode::Linear;
    let mut r = egui_renderer.write();
    *image_id = Some(match *image_id {
        Some(id) => {
            r.update_egui_texture_from_wgpu_texture(&ctx.device, &view, filter, id);
            id
        }
        None => r.register_native_texture(&ctx.device, &view, filter),
    });
}

impl Drop for GpuBackend {
    fn drop(&mut self) {
        if let Some(id) = self.image_id.take() {
            self.egui_renderer.write().free_texture(&id);
        }
    }
}

impl Backend for GpuBackend {
    fn set_scene(&mut self, scene: &Scene) {
        self.bump();
        self.scene = Some(scene.clone());
        if let Some(cpu) = self.fallback.as_mut() {
            cpu.set_scene(scene);
            self.retry_gpu();
            return;
        }
        if let Err(e) = self.sync_full() {
            self.enter_fallback(&e);
        }
    }

    fn update_material(&mut self, index: usize, material: &Material) {
        if material.validate().is_err() {
            return; // the CPU backend ignores invalid materials the same way
        }
        self.bump();
        if let Some(slot) = self.scene.as_mut().and_then(|s| s.materials.get_mut(index)) {
            *slot = material.clone();
        }
        if let Some(cpu) = self.fallback.as_mut() {
            cpu.update_material(index, material);
            return;
        }
        let m = material.clone();
        self.with_renderer(|r| r.set_material(index, m));
    }

    fn update_lights(&mut self, scene: &Scene, geometry_changed: bool) {
        self.bump();
        let old = self.scene.replace(scene.clone());
        if let Some(cpu) = self.fallback.as_mut() {
            cpu.update_lights(scene, geometry_changed);
            return;
        }
        let scene = scene.clone();
        self.with_renderer(|r| {
            let rebuild = geometry_changed
                || old.as_ref().is_none_or(|o| {
                    o.punctual_lights != scene.punctual_lights
                        || o.materials.len() != scene.materials.len()
                        || o.env_map != scene.env_map
                });
            if rebuild {
                let opts = *r.options();
                return r.set_scene(scene, opts);
            }
            // Same geometry: rewrite the changed materials (emission → light CDF) in place.
            for (i, m) in scene.materials.iter().enumerate() {
                if r.scene().materials.get(i) != Some(m) {
                    r.set_material(i, m.clone())?;
                }
            }
            r.set_environment(scene.environment)?;
            Ok(())
        });
    }

    fn update_camera(&mut self, camera: &Camera) {
        if camera.validate().is_err() {
            return;
        }
        self.bump();
        if let Some(s) = self.scene.as_mut() {
            s.camera = *camera;
        }
        if let Some(cpu) = self.fallback.as_mut() {
            cpu.update_camera(camera);
            return;
        }
        let c = *camera;
        self.with_renderer(|r| r.set_camera(c));
    }

    fn set_options(&mut self, options: &RenderOptions) {
        self.bump();
        // The estimator is applied by `sync_options`/`sync_full` (`wanted_estimator`).
        self.options = Some(*options);
        if let Some(cpu) = self.fallback.as_mut() {
            cpu.set_options(options);
            self.retry_gpu();
            return;
        }
        if let Err(e) = self.sync_options() {
            self.enter_fallback(&e);
        }
    }

    fn set_interactive(&mut self, interactive: bool) {
        if self.interactive == interactive {
            return;
        }
        self.bump();
        self.interactive = interactive;
        if let Some(cpu) = self.fallback.as_mut() {
            cpu.set_interactive(interactive);
            return;
        }
        if let Err(e) = self.sync_options() {
            self.enter_fallback(&e);
        }
    }

    fn set_paused(&mut self, paused: bool) {
        self.paused = paused;
        if let Some(cpu) = self.fallback.as_mut() {
            cpu.set_paused(paused);
        }
    }

    fn set_spp_target(&mut self, spp: u64) {
        self.spp_target = spp;
        if let Some(cpu) = self.fallback.as_mut() {
            cpu.set_spp_target(spp);
        }
    }

    fn reset(&mut self) {
        self.bump();
        if let Some(cpu) = self.fallback.as_mut() {
            cpu.reset();
            return;
        }
        if let Some(r) = self.renderer.as_mut() {
            r.reset();
        }
    }

    fn step(&mut self, frame_budget: Duration) {
        if let Some(cpu) = self.fallback.as_mut() {
            cpu.step(frame_budget);
            return;
        }
        self.budget = frame_budget;
        self.collect();
        if self.fallback.is_some() {
            return; // a GPU error: the CPU renders from the next step on
        }
        if self.in_flight.len() >= self.depth {
            return; // at most `depth` batches in flight
        }
        // The GPU is idle now (or, with two in flight, runs one batch): tone-map and copy the
        // counters before the next batch, so no submission of ours ever queues behind more
        // than one batch (software drivers such as lavapipe block `queue.submit` until the
        // previous submission has finished: there `depth` is 1).
        self.refresh_display();
        self.start_readback();
        // A new specialisation compiles on a worker thread: keep showing the last image.
        match self.renderer.as_mut().map(|r| r.pipelines_ready()) {
            None | Some(Ok(true)) => {}
            Some(Ok(false)) => {
                if let Some(c) = &self.repaint {
                    c.request_repaint_after(Duration::from_millis(10));
                }
                return;
            }
            Some(Err(e)) => {
                self.enter_fallback(&e);
                return;
            }
        }
        while self.in_flight.len() < self.depth && self.queue_batch(frame_budget) {}
    }

    fn spp(&self) -> u64 {
        match &self.fallback {
            Some(cpu) => cpu.spp(),
            None => self.done_spp,
        }
    }

    fn samples_per_sec(&self) -> f64 {
        if let Some(cpu) = &self.fallback {
            return cpu.samples_per_sec();
        }
        let pixels = self
            .renderer
            .as_ref()
            .map_or(0, |r| r.options().width as u64 * r.options().height as u64);
        (self.done_spp * pixels) as f64 / self.elapsed.as_secs_f64().max(1e-9)
    }

    fn elapsed(&self) -> Duration {
        match &self.fallback {
            Some(cpu) => cpu.elapsed(),
            None => self.elapsed,
        }
    }

    fn dropped(&self) -> u64 {
        match &self.fallback {
            Some(cpu) => cpu.dropped(),
            None => self.dropped,
        }
    }

    fn device_name(&self) -> String {
        let gpu = format!("{} ({:?})", self.ctx.info.name, self.ctx.info.backend);
        if let Some(cpu) = &self.fallback {
            return format!("{} (GPU {gpu} cannot render this scene)", cpu.device_name());
        }
        let Some(r) = &self.renderer else {
            return format!("GPU {gpu}");
        };
        let running = r.effective_estimator();
        match self.options.map(|o| o.estimator) {
            Some(e @ (Estimator::Bdpt | Estimator::Lt)) => {
                format!("GPU {gpu}, {running} ({e} runs on the CPU backend only)")
            }
            _ => format!("GPU {gpu}, {running}"),
        }
    }

    fn is_rendering(&self) -> bool {
        if let Some(cpu) = &self.fallback {
            return cpu.is_rendering();
        }
        !self.in_flight.is_empty()
            || self
                .renderer
                .as_ref()
                .is_some_and(|r| self.wants_samples(r.spp()))
    }

    fn generation(&self) -> u64 {
        self.generation
    }

    fn material(&self, index: usize) -> Option<Material> {
        match &self.fallback {
            Some(cpu) => cpu.material(index),
            None => self
                .renderer
                .as_ref()
                .and_then(|r| r.scene().materials.get(index).cloned()),
        }
    }

    fn display_texture(
        &mut self,
        ctx: &egui::Context,
        display: &DisplayParams,
    ) -> Option<DisplayTexture> {
        if let Some(cpu) = self.fallback.as_mut() {
            return cpu.display_texture(ctx, display);
        }
        self.display = Some(*display);
        self.refresh_display();
        let size = self.tonemap.target()?.size;
        Some(DisplayTexture {
            id: self.image_id?,
            size,
        })
    }

    fn read_image(&self) -> Option<Accumulated> {
        if let Some(cpu) = &self.fallback {
            return cpu.read_image();
        }
        let r = self.renderer.as_ref()?;
        if r.spp() == 0 {
            return None;
        }
        let img = r.image().ok()?;
        Some(Accumulated {
            generation: self.generation,
            width: img.width,
            height: img.height,
            pixels: img.mean,
            spp: img.spp,
            dropped: img.dropped,
            elapsed: self.elapsed,
        })
    }

    fn take_message(&mut self) -> Option<String> {
        self.message.take()
    }
}

impl GpuBackend {
    /// Queue the next batch (a whole image, or the next band of a pass); false when there is
    /// nothing to render (paused, the spp target reached, no renderer).
    fn queue_batch(&mut self, frame_budget: Duration) -> bool {
        let (generation, budget, per) = (self.generation, frame_budget, self.sec_per_sample);
        let Some(r) = self.renderer.as_mut() else {
            return false;
        };
        let queued = r.spp();
        if self.paused || (self.spp_target > 0 && queued >= self.spp_target) {
            return false;
        }
        let band_time = band_time(self.poller.thread.is_none(), r, budget);
        let band_rows = band_rows(r, per, band_time);
        if self.pass.is_some() || band_rows.is_some() {
            let (batch, before) = queue_band(r, &self.poller, &mut self.pass, band_rows);
            self.track(batch, generation, before);
            return true;
        }
        let o = r.options();
        let pixels = o.width as u64 * o.height as u64;
        let k = whole_image_spp(per, queued, budget, pixels, self.spp_target);
        // Mark busy before the callback can possibly run.
        self.poller.kick();
        let before = Instant::now();
        r.dispatch(k);
        self.track((k, pixels, k), generation, before);
        true
    }

    /// Follow the submission just made: (samples per pixel, pixels covered, samples per pixel
    /// it completes), submitted at `before`.
    fn track(&mut self, (k, pixels, completes): (u32, u64, u32), generation: u64, before: Instant) {
        let done = Arc::new(Mutex::new(None));
        {
            let done = Arc::clone(&done);
            let busy = Arc::clone(&self.poller.busy);
            let repaint = self.repaint.clone();
            self.ctx.queue.on_submitted_work_done(move || {
                *done.lock().unwrap_or_else(|e| e.into_inner()) = Some(Instant::now());
                busy.fetch_sub(1, Ordering::AcqRel);
                if let Some(c) = repaint {
                    c.request_repaint();
                }
            });
        }
        self.in_flight.push_back(Batch {
            k,
            pixels,
            completes,
            generation,
            // Without a poller thread (GL) the driver may run the batch inside the submission.
            submitted: match self.poller.thread {
                Some(_) => Instant::now(),
                None => before,
            },
            done,
        });
    }
}

/// The longest a band of rows may take, or None to render whole images: with synchronous
/// submissions (GL: the batch runs inside `submit`, which froze the UI for 0.7 s on
/// llvmpipe) the frame budget; on a hardware GPU (watchdogs) at least `SUBMISSION_BUDGET`.
/// A software Vulkan device runs asynchronously and has no watchdog: whole images.
fn band_time(synchronous: bool, r: &GpuRenderer, budget: Duration) -> Option<Duration> {
    if synchronous {
        Some(budget)
    } else if r.is_software() {
        None
    } else {
        Some(budget.max(crate::gpu::SUBMISSION_BUDGET))
    }
}

/// Rows per band (a multiple of 8, at least 8) where one sample of the whole image would take
/// longer than `band_time` at `per` seconds per pixel sample; None for whole images. Untimed,
/// a first band of ~2¹⁴ pixels measures the device.
fn band_rows(r: &GpuRenderer, per: Option<f64>, band_time: Option<Duration>) -> Option<u32> {
    let o = r.options();
    let (w, h) = (o.width, o.height);
    match (per, band_time) {
        _ if r.needs_whole_image() => None,
        (_, None) => None,
        (Some(s), Some(t)) => {
            let rows = (t.as_secs_f64() / (s * w.max(1) as f64)) as u32 / 8 * 8;
            (rows < h).then_some(rows.max(8))
        }
        (None, Some(_)) => {
            let rows = (PROBE_PIXELS / w.max(1)) / 8 * 8;
            (rows < h).then_some(rows.max(8))
        }
    }
}

/// Dispatch the next band of the pass in `pass` (or of a new one-sample pass) of at most
/// `band_rows` rows, ending the pass at the last row; returns the batch for
/// [`GpuBackend::track`] and when it was submitted.
fn queue_band(
    r: &mut GpuRenderer,
    poller: &Poller,
    pass: &mut Option<(u32, u32)>,
    band_rows: Option<u32>,
) -> ((u32, u64, u32), Instant) {
    let o = r.options();
    let (w, h) = (o.width, o.height);
    let (k, y0) = pass.unwrap_or((1, 0));
    let rows = band_rows.unwrap_or(h).min(h - y0);
    let last = y0 + rows >= h;
    poller.kick();
    let before = Instant::now();
    r.dispatch_band(k, y0, rows);
    if last {
        r.end_pass(k);
    }
    *pass = (!last).then_some((k, y0 + rows));
    (
        (k, w as u64 * rows as u64, if last { k } else { 0 }),
        before,
    )
}

/// Samples per pixel of the next whole-image batch: one for the first batch of a
/// generation (to show the edit at once) or when untimed, else what fits `budget` at `per`
/// seconds per pixel sample, at most `MAX_BATCH_SPP` and what `spp_target` still needs.
fn whole_image_spp(
    per: Option<f64>,
    queued: u64,
    budget: Duration,
    pixels: u64,
    spp_target: u64,
) -> u32 {
    let mut k = match per {
        // The first batch of a generation: one sample, to show the edit at once.
        _ if queued == 0 => 1,
        Some(s) => {
            let fit = budget.as_secs_f64() / (s * pixels.max(1) as f64);
            fit.clamp(1.0, MAX_BATCH_SPP as f64) as u32
        }
        None => 1,
    };
    if spp_target > 0 {
        k = k.min((spp_target - queued).min(MAX_BATCH_SPP as u64) as u32);
    }
    k.max(1)
}
