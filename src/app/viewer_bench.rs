//! `refract bench --viewer` (issue 36): the viewer itself measured without a window or a
//! display. The real `ViewerApp` — panels, edits, backend and all — runs in a headless
//! `egui::Context` at 60 frames/s (a display's refresh emulated by sleeping out each frame),
//! with a window of 1280×820 points, through a scripted lecture: open the default scene, drag
//! the glass's IOR from 1.0 to 2.42 over five seconds, make it rough, switch GGX → Beckmann,
//! turn dispersion on and off, open the `caustic` demo. Per edit: whether it changed the GPU
//! kernel, the time to the first frame whose image has samples of the edited scene, and how
//! long the specialised kernel took to compile. Then frames/s and samples/s at the image size
//! asked for. The GPU backend renders headless (its image read back), as under glow.

use super::backend::{Backend, CpuBackend, GpuBackend};
use super::{Edit, ViewerApp, lecture};
use crate::bsdf::MicrofacetDistribution;
use crate::gpu::GpuContext;
use crate::render::settings::{DEFAULT_SCENE, ViewerSettings};
use crate::scene::Scene;
use anyhow::{Context as _, Result};
use eframe::egui;
use serde::Serialize;
use std::time::{Duration, Instant};

/// The glass sphere of the default scene.
const GLASS: usize = 4;
/// A frame of a 60 Hz display.
const FRAME: Duration = Duration::from_micros(16_667);
/// The longest wait for an image or a compilation before the bench gives up on it.
const PATIENCE: Duration = Duration::from_secs(600);

/// What to measure.
#[derive(Clone, Debug)]
pub struct ViewerBenchOptions {
    /// Render on the GPU (headless, the image read back) or the CPU.
    pub gpu: bool,
    /// The rendered image for the throughput figures (the edits run at the window's size).
    pub width: u32,
    pub height: u32,
    /// How long the IOR drag takes (5 s in the script; shorter in tests).
    pub drag: Duration,
    /// How long each throughput measurement runs.
    pub measure: Duration,
}

/// One edit of the script.
#[derive(Clone, Debug, Serialize)]
pub struct EditTiming {
    pub name: String,
    /// The GPU kernel had to change (a new specialisation).
    pub kernel_change: bool,
    /// The first image came from the family's general kernel (not after the compile).
    pub general_kernel: bool,
    /// Edit to the first frame showing samples of the edited scene (for the drag: its p95
    /// over every step).
    pub first_image_ms: f64,
    /// The drag's median; equal to `first_image_ms` for a single edit.
    pub first_image_p50_ms: f64,
    /// Edits whose image was shown (a drag's step superseded by the next before its first
    /// image never shows; the latency of the one that does counts).
    pub count: usize,
    /// Edits made (the drag's steps; 1 for a single edit).
    pub steps: usize,
    /// Edit to the specialised kernel's being ready (None: no compilation).
    pub compile_ms: Option<f64>,
}

/// Frames and samples per second at one image size.
#[derive(Clone, Debug, Serialize)]
pub struct Throughput {
    pub width: u32,
    pub height: u32,
    pub frames_per_s: f64,
    pub spp_per_s: f64,
    /// Samples per pixel per frame.
    pub spp_per_frame: f64,
}

/// The bench's result (written as JSON).
#[derive(Clone, Debug, Serialize)]
pub struct ViewerBenchReport {
    pub adapter: String,
    pub device: String,
    pub edits: Vec<EditTiming>,
    /// Longest and 95th-percentile UI-thread frame (UI build + backend step) during the edits.
    pub ui_step_max_ms: f64,
    pub ui_step_p95_ms: f64,
    /// At the asked-for size, and in the default window (the viewport's size).
    pub frames_per_s: f64,
    pub spp_per_s: f64,
    pub throughput: Vec<Throughput>,
}

/// The viewer in a headless egui context.
struct Headless {
    ctx: egui::Context,
    app: ViewerApp,
    started: Instant,
    /// UI-thread time of every frame.
    steps: Vec<Duration>,
}

impl Headless {
    /// One frame, then sleep out the rest of a 60 Hz refresh.
    fn frame(&mut self) {
        let t = Instant::now();
        let input = egui::RawInput {
            screen_rect: Some(egui::Rect::from_min_size(
                egui::Pos2::ZERO,
                egui::vec2(1280.0, 820.0),
            )),
            time: Some(self.started.elapsed().as_secs_f64()),
            ..Default::default()
        };
        let app = &mut self.app;
        let _ = self.ctx.run_ui(input, |ui| app.show(ui));
        let took = t.elapsed();
        self.steps.push(took);
        if let Some(rest) = FRAME.checked_sub(took) {
            std::thread::sleep(rest);
        }
    }

    /// Frames until the image has samples of the current generation; the time it took.
    fn until_image(&mut self, since: Instant) -> Result<Duration> {
        Ok(self.settle(since)?.first)
    }

    /// Frames until the image has samples of the current generation and no kernel compiles:
    /// when each happened, and whether the first image came from a general kernel.
    fn settle(&mut self, since: Instant) -> Result<Settled> {
        let generation = self.app.backend().generation();
        let compiling = self.app.backend().compiling();
        let (mut first, mut general, mut compiled) = (None, false, None);
        while first.is_none() || (compiling && compiled.is_none()) {
            self.frame();
            let b = self.app.backend();
            if first.is_none() && b.generation() >= generation && b.spp() >= 1 {
                first = Some(since.elapsed());
                general = b.general_kernel();
            }
            if compiling && compiled.is_none() && !b.compiling() {
                compiled = Some(since.elapsed());
            }
            anyhow::ensure!(
                since.elapsed() < PATIENCE,
                "no image or kernel within {PATIENCE:?}"
            );
        }
        Ok(Settled {
            first: first.unwrap_or_default(),
            general,
            compiled,
        })
    }

    /// Apply `edit`, then measure it: its first image and its compilation.
    fn timed(&mut self, name: &str, edit: Edit) -> Result<EditTiming> {
        let t = Instant::now();
        self.app.apply(edit);
        let kernel_change = self.app.backend().compiling();
        let s = self.settle(t)?;
        Ok(single(name, kernel_change, &s))
    }

    /// The glass material as it is now, changed by `f`.
    fn glass_edit(&self, f: impl FnOnce(&mut crate::scene::Material)) -> Edit {
        let mut m = self.app.scene.materials[GLASS].clone();
        f(&mut m);
        Edit::Material {
            index: GLASS,
            material: Box::new(m),
        }
    }
}

/// What followed an edit.
struct Settled {
    /// Its first image.
    first: Duration,
    /// That image came from a general kernel.
    general: bool,
    /// The specialised kernel was ready (None: none compiled).
    compiled: Option<Duration>,
}

/// One edit's timing.
fn single(name: &str, kernel_change: bool, s: &Settled) -> EditTiming {
    let ms = s.first.as_secs_f64() * 1e3;
    let compiled = s.compiled;
    EditTiming {
        name: name.to_owned(),
        kernel_change,
        general_kernel: s.general,
        first_image_ms: ms,
        first_image_p50_ms: ms,
        count: 1,
        steps: 1,
        compile_ms: compiled.map(|c| c.as_secs_f64() * 1e3),
    }
}

/// The `q` quantile of `v` (sorted here).
fn quantile(v: &mut [f64], q: f64) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    v[((v.len() - 1) as f64 * q).round() as usize]
}

/// Run the bench.
pub fn run(opts: &ViewerBenchOptions) -> Result<ViewerBenchReport> {
    let (backend, adapter) = backend(opts.gpu)?;
    let device = backend.device_name();
    let base = Scene::load(DEFAULT_SCENE)?;
    let t = Instant::now();
    let app = ViewerApp::with_backend(base, ViewerSettings::for_scene(DEFAULT_SCENE), backend)?;
    let mut h = Headless {
        ctx: egui::Context::default(),
        app,
        started: Instant::now(),
        steps: Vec::new(),
    };
    let first = h.settle(t).context("the default scene's first image")?;
    let mut edits = vec![single("open the default scene", opts.gpu, &first)];
    edits.push(drag_ior(&mut h, opts.drag)?);
    let rough = h.glass_edit(|m| m.roughness = 0.3);
    edits.push(h.timed("rough glass (roughness 0.3)", rough)?);
    let beckmann = h.glass_edit(|m| m.distribution = MicrofacetDistribution::Beckmann);
    edits.push(h.timed("GGX -> Beckmann", beckmann)?);
    let on = h.glass_edit(|m| m.abbe = Some(30.0));
    edits.push(h.timed("dispersion on (Abbe 30)", on)?);
    let off = h.glass_edit(|m| m.abbe = None);
    edits.push(h.timed("dispersion off", off)?);
    edits.push(open_demo(&mut h, "caustic")?);
    let mut steps: Vec<f64> = h.steps.iter().map(|d| d.as_secs_f64() * 1e3).collect();
    let ui_step_p95_ms = quantile(&mut steps, 0.95);
    let ui_step_max_ms = steps.last().copied().unwrap_or(0.0);
    let sized = throughput(&mut h, Some((opts.width, opts.height)), opts.measure)?;
    let window = throughput(&mut h, None, opts.measure)?;
    Ok(ViewerBenchReport {
        adapter,
        device,
        edits,
        ui_step_max_ms,
        ui_step_p95_ms,
        frames_per_s: sized.frames_per_s,
        spp_per_s: sized.spp_per_s,
        throughput: vec![sized, window],
    })
}

/// The backend to measure, and the adapter's description.
fn backend(gpu: bool) -> Result<(Box<dyn Backend>, String)> {
    if !gpu {
        let threads = rayon::current_num_threads();
        return Ok((
            Box::new(CpuBackend::new(None)),
            format!("CPU, {threads} threads"),
        ));
    }
    let ctx = GpuContext::headless()?;
    let adapter = ctx.describe();
    Ok((Box::new(GpuBackend::headless(ctx, None)?), adapter))
}

/// Drag the glass's IOR from 1.0 to 2.42 over `over`, one step a frame: each step's time to
/// its first image (p50, p95).
fn drag_ior(h: &mut Headless, over: Duration) -> Result<EditTiming> {
    h.app.hold_drag(true);
    let start = Instant::now();
    let (mut latencies, mut steps) = (Vec::new(), 0);
    // Steps waiting for their first image: (generation after the edit, when it was made).
    let mut waiting: Vec<(u64, Instant)> = Vec::new();
    while start.elapsed() < over {
        let f = (start.elapsed().as_secs_f64() / over.as_secs_f64()).min(1.0) as f32;
        let edit = h.glass_edit(|m| m.ior = 1.0 + 1.42 * f);
        h.app.apply(edit);
        steps += 1;
        waiting.push((h.app.backend().generation(), Instant::now()));
        h.frame();
        let (generation, spp) = (h.app.backend().generation(), h.app.backend().spp());
        // A newer edit supersedes the older ones still waiting: they never get an image,
        // and the newest one's latency counts when it shows.
        if spp >= 1
            && let Some(&(g, at)) = waiting.last()
            && generation >= g
        {
            latencies.push(at.elapsed().as_secs_f64() * 1e3);
            waiting.clear();
        }
    }
    if let Some(&(_, at)) = waiting.last() {
        h.until_image(at)?;
        latencies.push(at.elapsed().as_secs_f64() * 1e3);
    }
    h.app.hold_drag(false);
    let count = latencies.len();
    Ok(EditTiming {
        name: "drag IOR 1.0 -> 2.42".into(),
        kernel_change: false,
        general_kernel: false,
        first_image_p50_ms: quantile(&mut latencies, 0.5),
        first_image_ms: quantile(&mut latencies, 0.95),
        count,
        steps,
        compile_ms: None,
    })
}

/// Open the lecture demo `key`.
fn open_demo(h: &mut Headless, key: &str) -> Result<EditTiming> {
    let index = lecture::DEMOS
        .iter()
        .position(|d| d.key == key)
        .with_context(|| format!("no lecture demo '{key}'"))?;
    let t = Instant::now();
    h.app.start_demo(index);
    let kernel_change = h.app.backend().compiling();
    let s = h.settle(t)?;
    Ok(single(&format!("lecture demo '{key}'"), kernel_change, &s))
}

/// Frames and samples per second over `measure`: at `size` (the viewport not followed), or
/// in the default window (None: the image follows the viewport, as the viewer opens).
fn throughput(h: &mut Headless, size: Option<(u32, u32)>, measure: Duration) -> Result<Throughput> {
    h.app.apply(Edit::OpenScene(DEFAULT_SCENE.to_owned()));
    let mut render = ViewerSettings::for_scene(DEFAULT_SCENE).render;
    render.fit_viewport = size.is_none();
    if let Some((w, hh)) = size {
        render.render_scale = 1.0;
        h.app.scene.settings.width = w;
        h.app.scene.settings.height = hh;
        h.app.base.settings.width = w;
        h.app.base.settings.height = hh;
    }
    h.app.apply(Edit::Render(render));
    h.settle(Instant::now())?;
    let (spp0, frames0, t0) = (h.app.backend().spp(), h.steps.len(), Instant::now());
    while t0.elapsed() < measure {
        h.frame();
    }
    let secs = t0.elapsed().as_secs_f64();
    let frames = (h.steps.len() - frames0) as f64;
    let (w, hh) = h.app.settings.resolution(&h.app.scene);
    let spp = (h.app.backend().spp() - spp0) as f64;
    Ok(Throughput {
        width: w,
        height: hh,
        frames_per_s: frames / secs,
        spp_per_s: spp * f64::from(w) * f64::from(hh) / secs,
        spp_per_frame: spp / frames.max(1.0),
    })
}
