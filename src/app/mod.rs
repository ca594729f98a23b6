//! The interactive viewer (eframe/egui): a side panel of physics controls, the progressively
//! refined image in the central viewport and a status bar. Rendering runs behind the
//! [`backend::Backend`] trait and never blocks the UI thread. Controls never change the scene
//! themselves: they push an [`Edit`], and [`ViewerApp::apply`] (src/app/edit.rs) applies it.
//!
//! [`ViewerApp::show`] draws the whole UI into any `egui::Ui`, so the same code runs in the
//! window ([`run`]) and in the `egui_kittest` tests without a window.

pub mod backend;
pub mod edit;
pub mod inspect;
pub mod inspect_overlay;
pub mod layer_view;
pub mod lecture;
pub mod panels;
pub mod screenshot;
pub mod viewport;

use crate::bvh::Bvh;
use crate::render::Device;
use crate::render::settings::{DEFAULT_SCENE, ViewerSettings};
use crate::scene::edits::Orbit;
use crate::scene::gltf_load::LoadLimits;
use crate::scene::{Material, Scene};
use backend::{Backend, CpuBackend, DisplayParams};
pub use edit::{Edit, EnvEdit};
use eframe::egui;
use std::path::PathBuf;
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// How long a new viewport size must hold before the image restarts at it.
pub const VIEWPORT_SETTLE: Duration = Duration::from_millis(250);

/// eframe storage key of the persisted [`ViewerSettings`].
pub const STORAGE_KEY: &str = "refract-settings";

/// Command-line options of `refract view`.
#[derive(Clone, Debug, Default)]
pub struct ViewOptions {
    /// `builtin:NAME` or a .glb/.gltf path; None = [`DEFAULT_SCENE`] (or nothing persisted).
    pub scene: Option<String>,
    /// Close after this many frames (CI, screenshots).
    pub frames: Option<u64>,
    /// Close after this much time.
    pub exit_after: Option<Duration>,
    /// Open with the path inspector on this pixel (lectures, screenshots).
    pub inspect: Option<(u32, u32)>,
    /// Which renderer drives the viewport.
    pub device: Device,
    /// Budgets and URI permission of every glTF the viewer opens.
    pub limits: LoadLimits,
    /// `--env`, `--env-strength`, `--env-rotation`.
    pub env: Option<EnvOverride>,
    /// `--view`: what the viewport shows first (`layer_view`).
    pub view: layer_view::ViewMode,
    /// `--lecture KEY`: open this demonstration with large type.
    pub lecture: Option<&'static str>,
    /// `--light-line NM`: the scene opens lit by one spectral line (its "as loaded" light).
    pub light_line: Option<f32>,
}

/// An environment image given on the command line.
#[derive(Clone, Debug, Default)]
pub struct EnvOverride {
    pub file: Option<std::path::PathBuf>,
    pub strength: Option<f32>,
    pub rotation: Option<f32>,
}

/// A message shown at the top of the side panel until dismissed.
#[derive(Clone, Debug, Default)]
pub struct Messages {
    pub error: Option<String>,
    pub info: Option<String>,
}

/// Frame timing of the UI (what the README reports).
#[derive(Clone, Copy, Debug)]
struct FrameStats {
    started: Instant,
    last: Option<Instant>,
    frames: u64,
    interval_sum: Duration,
    ui_sum: Duration,
    /// Exponential moving averages for the status bar.
    interval_ema: f64,
    ui_ema: f64,
}

/// The viewer: scene model, edits, selection and the backend rendering them.
pub struct ViewerApp {
    /// Budgets and URI permission of the glTF files opened from the viewer.
    pub load_limits: LoadLimits,
    /// Every setting (persisted; written as the screenshot sidecar).
    pub settings: ViewerSettings,
    /// The scene as loaded.
    pub base: Scene,
    /// `base` with the edits applied: what the backend renders.
    pub scene: Scene,
    /// BVH of `scene` for picking in the viewport.
    pick_bvh: Bvh,
    /// Camera orbit the mouse drives (copied into `settings.camera.orbit` once used).
    pub orbit: Orbit,
    /// Selected material index (click in the viewport or pick in the list).
    pub selected: Option<usize>,
    /// Path filter text as typed (may be invalid; `settings.render.paths` is the last valid).
    pub filter_text: String,
    pub filter_error: Option<String>,
    pub messages: Messages,
    /// Scene path typed into the Scene panel.
    pub open_path: String,
    /// Environment image path typed into the Environment panel.
    pub env_path: String,
    /// Where screenshots go (`screenshots/` by default).
    pub screenshot_dir: PathBuf,
    pub paused: bool,
    /// The Inspect mode: paths through a clicked pixel.
    pub inspector: inspect::Inspector,
    /// What the viewport shows: the image or a layer view (`layer_view`, CPU only).
    pub view: layer_view::ViewMode,
    /// Lecture mode: the demo on screen and large type.
    pub lecture: lecture::Lecture,
    /// A viewport size waiting to hold for [`VIEWPORT_SETTLE`], and since when.
    viewport_pending: Option<((u32, u32), Instant)>,
    backend: Box<dyn Backend>,
    /// The adapter that draws the UI (status bar).
    display_device: String,
    dialog: Option<mpsc::Receiver<Option<PathBuf>>>,
    exit_frames: Option<u64>,
    exit_after: Option<Duration>,
    stats: FrameStats,
    dragging: bool,
    closing: bool,
    /// Edits pushed this frame, applied by [`ViewerApp::apply`] (src/app/edit.rs).
    edits: Vec<Edit>,
}

impl ViewerApp {
    /// A viewer on `base` (loaded from `settings.scene`) with the CPU backend. `repaint` is
    /// woken by the render thread after every pass (None in tests, which poll).
    pub fn new(
        base: Scene,
        settings: ViewerSettings,
        repaint: Option<egui::Context>,
    ) -> anyhow::Result<ViewerApp> {
        ViewerApp::with_backend(base, settings, Box::new(CpuBackend::new(repaint)))
    }

    /// A viewer on `base` rendered by `backend` (`app::run` picks the CPU or GPU backend).
    pub fn with_backend(
        base: Scene,
        settings: ViewerSettings,
        backend: Box<dyn Backend>,
    ) -> anyhow::Result<ViewerApp> {
        base.validate()?;
        let (scene, warnings) = settings.apply(&base);
        let pick_bvh = Bvh::build(&scene.mesh);
        let orbit = settings.camera.orbit(&base);
        let filter_text = settings.render.paths.clone();
        let mut app = ViewerApp {
            settings,
            base,
            scene,
            pick_bvh,
            orbit,
            selected: None,
            filter_text,
            filter_error: None,
            messages: Messages::default(),
            open_path: String::new(),
            env_path: String::new(),
            screenshot_dir: PathBuf::from("screenshots"),
            paused: false,
            inspector: inspect::Inspector::default(),
            view: layer_view::ViewMode::Beauty,
            lecture: lecture::Lecture::default(),
            viewport_pending: None,
            backend,
            display_device: String::new(),
            dialog: None,
            exit_frames: None,
            load_limits: LoadLimits::default(),
            exit_after: None,
            stats: FrameStats {
                started: Instant::now(),
                last: None,
                frames: 0,
                interval_sum: Duration::ZERO,
                ui_sum: Duration::ZERO,
                interval_ema: 0.0,
                ui_ema: 0.0,
            },
            dragging: false,
            closing: false,
            edits: Vec::new(),
        };
        app.report_warnings(&warnings);
        app.backend.set_scene(&app.scene);
        app.options_follow();
        Ok(app)
    }

    /// A viewer on a scene spec with default settings (tests, headless use).
    pub fn open(spec: &str) -> anyhow::Result<ViewerApp> {
        let base = Scene::load(spec)?;
        ViewerApp::new(base, ViewerSettings::for_scene(spec), None)
    }

    pub fn backend(&self) -> &dyn Backend {
        self.backend.as_ref()
    }

    /// Show `mode`; a backend that cannot (the GPU) keeps the image and says so.
    pub fn set_view(&mut self, mode: layer_view::ViewMode) {
        if self.backend.set_view(mode) {
            self.view = mode;
        } else {
            self.view = layer_view::ViewMode::Beauty;
            self.messages.info = Some(
                "the path-class and heatmap views are CPU only: switch the device to CPU"
                    .to_owned(),
            );
        }
    }

    fn report_warnings(&mut self, warnings: &[String]) {
        if !warnings.is_empty() {
            self.messages.info = Some(warnings.join("\n"));
        }
    }

    /// Apply a material edit now (headless callers; the panels push [`Edit::Material`]).
    pub fn set_material(&mut self, index: usize, material: Material) {
        self.apply(Edit::Material {
            index,
            material: Box::new(material),
        });
    }

    /// `settings.render` was changed in place (headless callers): apply it now.
    pub fn options_changed(&mut self) {
        self.options_follow();
    }

    pub fn pick(&self, sx: f32, sy: f32) -> Option<usize> {
        let (w, h) = self.settings.resolution(&self.scene);
        let cam = &self.scene.camera;
        let dir = cam.ray_dir(sx, sy, w as f32 / h as f32);
        let hit = self.pick_bvh.intersect(cam.position, dir, f32::INFINITY)?;
        self.scene
            .mesh
            .tri_material
            .get(hit.tri as usize)
            .map(|&m| m as usize)
    }

    pub fn display_params(&self) -> DisplayParams {
        DisplayParams {
            exposure: self.settings.display.exposure,
            tone_map: self.settings.display.tone_map,
        }
    }

    /// Open the system file dialog on a helper thread (xdg-desktop-portal on Linux).
    pub fn open_dialog(&mut self) {
        let (tx, rx) = mpsc::channel();
        let spawned = std::thread::Builder::new()
            .name("refract-file-dialog".into())
            .spawn(move || {
                let picked = rfd::FileDialog::new()
                    .add_filter("glTF scene", &["glb", "gltf"])
                    .pick_file();
                let _ = tx.send(picked);
            });
        match spawned {
            Ok(_) => self.dialog = Some(rx),
            Err(e) => self.messages.error = Some(format!("cannot open a file dialog: {e}")),
        }
    }

    fn poll_dialog(&mut self) {
        let Some(rx) = &self.dialog else { return };
        match rx.try_recv() {
            Ok(Some(path)) => {
                self.dialog = None;
                let spec = path.display().to_string();
                self.open_path = spec.clone();
                self.push(Edit::OpenScene(spec));
            }
            Ok(None) => {
                self.dialog = None;
                self.messages.info = Some(
                    "No file chosen. If no dialog appeared, this desktop has no \
                     xdg-desktop-portal: drop a .glb/.gltf on the window or type its path."
                        .into(),
                );
            }
            Err(mpsc::TryRecvError::Empty) => {}
            Err(mpsc::TryRecvError::Disconnected) => self.dialog = None,
        }
    }

    /// Save the screenshot triple (PNG as shown, linear EXR, JSON sidecar).
    pub fn save_screenshot(&mut self) -> anyhow::Result<screenshot::Saved> {
        let r = screenshot::save(self);
        match &r {
            Ok(s) => {
                self.messages.info = Some(format!("saved {}", s.png.display()));
            }
            Err(e) => self.messages.error = Some(format!("screenshot failed: {e:#}")),
        }
        r
    }

    fn handle_input(&mut self, ctx: &egui::Context) {
        use egui::{Key, Modifiers};
        // Dropped files: open the first .glb/.gltf.
        let dropped: Vec<PathBuf> = ctx.input(|i| {
            i.raw
                .dropped_files
                .iter()
                .map(|f| f.path().to_path_buf())
                .filter(|p| !p.as_os_str().is_empty())
                .collect()
        });
        if let Some(p) = dropped.first() {
            let spec = p.display().to_string();
            let is_env = p
                .extension()
                .and_then(|e| e.to_str())
                .is_some_and(|e| e.eq_ignore_ascii_case("hdr") || e.eq_ignore_ascii_case("exr"));
            if is_env {
                self.env_path = spec.clone();
                self.push(Edit::Environment(EnvEdit::Load(spec)));
            } else {
                self.open_path = spec.clone();
                self.push(Edit::OpenScene(spec));
            }
        }
        let (f12, ctrl_s) = ctx.input_mut(|i| {
            (
                i.consume_key(Modifiers::NONE, Key::F12),
                i.consume_key(Modifiers::COMMAND, Key::S),
            )
        });
        if f12 || ctrl_s {
            let _ = self.save_screenshot();
        }
        if !ctx.egui_wants_keyboard_input() {
            let (space, r, esc) = ctx.input_mut(|i| {
                (
                    i.consume_key(Modifiers::NONE, Key::Space),
                    i.consume_key(Modifiers::NONE, Key::R),
                    i.consume_key(Modifiers::NONE, Key::Escape),
                )
            });
            if space {
                self.push(Edit::Pause(!self.paused));
            }
            if r {
                self.push(Edit::ResetCamera);
            }
            if esc {
                self.selected = None;
            }
        }
    }

    /// Draw the whole viewer into `ui` (window or test harness).
    pub fn show(&mut self, ui: &mut egui::Ui) {
        let t0 = Instant::now();
        let ctx = ui.ctx().clone();
        self.begin_frame(&ctx);
        self.side_panels(ui);
        egui::CentralPanel::no_frame().show(ui, |ui| self.central_image(&ctx, ui));
        self.apply_queued();
        self.end_frame(&ctx, t0.elapsed());
    }

    /// Before drawing: dialog result, keys, lecture zoom, a slice of rendering, its message.
    fn begin_frame(&mut self, ctx: &egui::Context) {
        self.poll_dialog();
        self.handle_input(ctx);
        if let Some(zoom) = self.lecture.zoom_change() {
            ctx.set_zoom_factor(zoom);
        }
        self.backend.step(Duration::from_millis(8));
        if let Some(m) = self.backend.take_message() {
            self.messages.info = Some(m);
        }
    }

    /// The status bar, the controls panel and the inspector panel (before the central image,
    /// which takes the space they leave).
    fn side_panels(&mut self, ui: &mut egui::Ui) {
        egui::Panel::bottom("status").show(ui, |ui| self.status_bar(ui));
        egui::Panel::left("controls")
            .default_size(340.0)
            .resizable(true)
            .show(ui, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| panels::side_panel(self, ui));
            });
        self.apply_queued();
        self.lecture_follow();
        self.inspect_follow();
        panels::inspect::side(self, ui);
    }

    /// The central panel: the rendered image with orbit, picking and inspection, and its
    /// overlays.
    fn central_image(&mut self, ctx: &egui::Context, ui: &mut egui::Ui) {
        self.viewport_follow(ctx, ui.available_size() * ctx.pixels_per_point());
        let tex = self.backend.display_texture(ctx, &self.display_params());
        let res = self.settings.resolution(&self.scene);
        let yfov = self.scene.camera.yfov;
        let mut orbit = self.orbit;
        let r = viewport::show(ui, tex, res, &mut orbit, yfov);
        if r.camera_changed {
            self.push(Edit::Orbit(orbit));
        }
        self.viewport_interaction(ctx, &r);
        self.inspector.image_rect = Some(r.image_rect);
        self.image_overlays(ui, r.image_rect);
    }

    /// React to a drag starting or ending and to a click on the image (inspect or pick).
    fn viewport_interaction(&mut self, ctx: &egui::Context, r: &viewport::ViewportResponse) {
        if r.dragging != self.dragging {
            self.dragging = r.dragging;
            self.backend.set_interactive(r.dragging);
        }
        if let Some((sx, sy)) = r.clicked {
            if r.alt || self.inspector.enabled {
                self.lecture.inspect_point = None;
                self.inspector.request((sx, sy));
                ctx.request_repaint();
            } else {
                self.selected = self.pick(sx, sy);
            }
        }
    }

    /// Draw the lecture caption and the inspected path over the image at `rect`.
    fn image_overlays(&self, ui: &egui::Ui, rect: egui::Rect) {
        if let Some(caption) = self.lecture_caption() {
            lecture::draw_caption(&ui.painter_at(rect), rect, caption);
        }
        if let Some(t) = &self.inspector.traced {
            let painter = ui.painter_at(rect);
            inspect_overlay::draw(&painter, rect, t, self.inspector.highlight);
        }
    }

    /// After drawing: record the frame's UI time and keep repainting while work is under way.
    fn end_frame(&mut self, ctx: &egui::Context, ui_time: Duration) {
        self.record_frame(ui_time);
        if self.backend.is_rendering() || self.dialog.is_some() || self.inspector.is_tracing() {
            ctx.request_repaint_after(Duration::from_millis(100));
        }
    }

    /// The image area measures `physical` pixels: with `fit_viewport`, a new size restarts
    /// accumulation at that size (× render scale) once it has held for [`VIEWPORT_SETTLE`]
    /// (the first size at once). The settle time keeps a window drag from restarting every
    /// frame and breaks layout feedback: the inspector's panel re-laid after each restart's
    /// re-trace changed the image width by a few pixels, which restarted it again, forever.
    /// Sizes under 16 pixels (a collapsed layout) are ignored.
    fn viewport_follow(&mut self, ctx: &egui::Context, physical: egui::Vec2) {
        let px = (physical.x.round() as u32, physical.y.round() as u32);
        if px.0 < 16 || px.1 < 16 || self.settings.viewport == Some(px) {
            self.viewport_pending = None;
            return;
        }
        let now = Instant::now();
        let settled = match self.viewport_pending {
            _ if self.settings.viewport.is_none() => true,
            Some((p, since)) if p == px => now - since >= VIEWPORT_SETTLE,
            _ => {
                self.viewport_pending = Some((px, now));
                false
            }
        };
        if !settled {
            ctx.request_repaint_after(VIEWPORT_SETTLE);
            return;
        }
        self.viewport_pending = None;
        let before = self.settings.resolution(&self.scene);
        self.settings.viewport = Some(px);
        if self.settings.resolution(&self.scene) != before {
            self.options_follow();
        }
    }

    /// Start or collect the inspector's trace for the scene and options as they are now.
    fn inspect_follow(&mut self) {
        let generation = self.backend.generation();
        let (settings, scene) = (&self.settings, &self.scene);
        self.inspector
            .update(scene, generation, || settings.render_options(scene));
    }

    fn record_frame(&mut self, ui_time: Duration) {
        let now = Instant::now();
        let s = &mut self.stats;
        if let Some(last) = s.last {
            let dt = now - last;
            s.interval_sum += dt;
            s.interval_ema = 0.9 * s.interval_ema + 0.1 * dt.as_secs_f64();
        }
        s.last = Some(now);
        s.frames += 1;
        s.ui_sum += ui_time;
        s.ui_ema = 0.9 * s.ui_ema + 0.1 * ui_time.as_secs_f64();
    }

    fn status_bar(&mut self, ui: &mut egui::Ui) {
        let b = self.backend.as_ref();
        let (w, h) = self.settings.resolution(&self.scene);
        ui.horizontal_wrapped(|ui| {
            let spp = b.spp();
            let target = self.settings.render.spp_target;
            let state = if self.paused {
                "paused"
            } else if b.is_rendering() {
                "rendering"
            } else {
                "done"
            };
            ui.label(if target > 0 {
                format!("{spp} / {target} spp")
            } else {
                format!("{spp} spp")
            })
            .on_hover_text("Samples per pixel averaged so far; noise falls as 1/√spp.");
            ui.separator();
            ui.label(format!("{:.2} M samples/s", b.samples_per_sec() / 1e6))
                .on_hover_text("Camera paths traced per second (pixels × spp / render time).");
            ui.separator();
            ui.label(format!("{:.1} s", b.elapsed().as_secs_f64()))
                .on_hover_text("Render time spent on the current image.");
            ui.separator();
            let dropped = b.dropped();
            let text = format!("{dropped} NaN/dropped");
            if dropped > 0 {
                ui.colored_label(egui::Color32::from_rgb(255, 160, 60), text)
            } else {
                ui.label(text)
            }
            .on_hover_text(
                "Samples refused by the film's firewall (NaN, infinite or negative radiance).",
            );
            ui.separator();
            ui.label(format!("{w}×{h} · {state}"));
            ui.separator();
            let mut dev = format!("render: {}", b.device_name());
            if !self.display_device.is_empty() {
                dev.push_str(&format!(" · display: {}", self.display_device));
            }
            ui.label(dev);
            ui.separator();
            ui.label(format!(
                "frame {:.1} ms (UI {:.1} ms)",
                self.stats.interval_ema * 1e3,
                self.stats.ui_ema * 1e3
            ))
            .on_hover_text("Time between UI frames and the part of it spent building the UI.");
        });
    }

    /// One line summarising the frame times (printed when `--frames`/`--exit-after` ends).
    pub fn frame_summary(&self) -> String {
        let s = &self.stats;
        let n = s.frames.max(1);
        format!(
            "{} frames in {:.2} s: mean frame interval {:.2} ms, mean UI build {:.2} ms; {} spp at {}x{}; render: {}",
            s.frames,
            s.started.elapsed().as_secs_f64(),
            s.interval_sum.as_secs_f64() * 1e3 / (n.saturating_sub(1)).max(1) as f64,
            s.ui_sum.as_secs_f64() * 1e3 / n as f64,
            self.backend.spp(),
            self.settings.resolution(&self.scene).0,
            self.settings.resolution(&self.scene).1,
            self.backend.device_name(),
        )
    }

    /// `--frames N`: after N frames — and, when `--exit-after` bounds the wait, not before the
    /// image has its first sample (a GPU pipeline still compiling in the background would
    /// otherwise leave a black window for the screenshot). `--exit-after`: after that time.
    fn should_exit(&self) -> bool {
        let sampled = self.exit_after.is_none() || self.backend.spp() >= 1;
        self.exit_frames
            .is_some_and(|n| self.stats.frames >= n && sampled)
            || self
                .exit_after
                .is_some_and(|d| self.stats.started.elapsed() >= d)
    }
}

impl eframe::App for ViewerApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        self.show(ui);
        if self.exit_frames.is_some() || self.exit_after.is_some() {
            if self.closing {
                // Close already requested; frames may still arrive until the window goes.
            } else if self.should_exit() {
                self.closing = true;
                eprintln!("refract view: {}", self.frame_summary());
                ui.ctx().send_viewport_cmd(egui::ViewportCommand::Close);
            } else {
                ui.ctx().request_repaint();
            }
        }
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        let mut s = self.settings.clone();
        s.capture = None;
        s.environment = None;
        eframe::set_value(storage, STORAGE_KEY, &s);
    }
}

/// The wgpu setup: our own device with the adapter's full limits (eframe's default asks for
/// WebGL2-level limits, too small for compute). The GPU backend renders on this device.
pub fn wgpu_configuration() -> eframe::egui_wgpu::WgpuConfiguration {
    use eframe::egui_wgpu::{WgpuConfiguration, WgpuSetup, WgpuSetupCreateNew};
    use eframe::wgpu;
    let mut create = WgpuSetupCreateNew::without_display_handle();
    create.instance_descriptor.flags =
        crate::gpu::context::instance_flags(create.instance_descriptor.flags);
    create.device_descriptor =
        std::sync::Arc::new(|adapter: &wgpu::Adapter| wgpu::DeviceDescriptor {
            label: Some("refract device"),
            required_limits: adapter.limits(),
            // The driver pipeline cache where there is one (gpu::pipeline_cache).
            required_features: adapter.features() & wgpu::Features::PIPELINE_CACHE,
            ..Default::default()
        });
    WgpuConfiguration {
        wgpu_setup: WgpuSetup::CreateNew(create),
        ..Default::default()
    }
}

/// The backend for `--device` on the adapter eframe opened, and a note for the user when the
/// choice was not what was asked for.
fn choose_backend(
    device: Device,
    cc: &eframe::CreationContext<'_>,
) -> anyhow::Result<(Box<dyn Backend>, Option<String>)> {
    let repaint = Some(cc.egui_ctx.clone());
    let cpu = |repaint| -> Box<dyn Backend> { Box::new(CpuBackend::new(repaint)) };
    if device == Device::Cpu {
        return Ok((cpu(repaint), None));
    }
    let Some(rs) = &cc.wgpu_render_state else {
        anyhow::ensure!(
            device != Device::Gpu,
            "--device gpu needs the wgpu renderer, which did not start"
        );
        return Ok((cpu(repaint), None));
    };
    let info = rs.adapter.get_info();
    if device == Device::Auto && info.device_type == eframe::wgpu::DeviceType::Cpu {
        // lavapipe & co. are ~15x slower than the CPU renderer on the same cores.
        return Ok((cpu(repaint), None));
    }
    match backend::GpuBackend::from_render_state(rs, repaint.clone()) {
        Ok(g) => Ok((Box::new(g), None)),
        Err(e) => Ok((
            cpu(repaint),
            Some(format!(
                "The GPU backend could not start on {} ({e:#}); rendering on the CPU.",
                info.name
            )),
        )),
    }
}

/// Open the viewer window (blocks until it is closed).
pub fn run(opts: ViewOptions) -> anyhow::Result<()> {
    let spec = opts
        .scene
        .clone()
        .unwrap_or_else(|| DEFAULT_SCENE.to_owned());
    // Load before opening the window so a bad path is a plain CLI error.
    let base = load_startup_scene(&spec, &opts)?;
    let native = native_options(&spec);
    let result = eframe::run_native(
        "refract",
        native,
        Box::new(move |cc| Ok(Box::new(create_app(cc, base, &spec, opts)?))),
    );
    result.map_err(|e| anyhow::anyhow!("cannot open the viewer window: {e}"))
}

/// The scene `spec` with the command line's environment and light-line overrides, validated;
/// its warnings are printed to stderr.
fn load_startup_scene(spec: &str, opts: &ViewOptions) -> anyhow::Result<Scene> {
    let mut base = Scene::load_with(spec, &opts.limits)?;
    if let Some(e) = &opts.env {
        let warnings = crate::scene::env_map::override_environment(
            &mut base,
            e.file.as_deref(),
            e.strength,
            e.rotation,
        )?;
        base.warnings.extend(warnings);
    }
    if let Some(nm) = opts.light_line {
        base.settings.light_line_nm = Some(nm);
    }
    base.validate()?;
    for w in &base.warnings {
        eprintln!("warning: {w}");
    }
    Ok(base)
}

/// The viewer window's options: titled after `spec`, 1280×820, accepting dropped files,
/// drawn with wgpu.
fn native_options(spec: &str) -> eframe::NativeOptions {
    eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_title(format!("refract — {spec}"))
            .with_inner_size([1280.0, 820.0])
            .with_drag_and_drop(true),
        renderer: eframe::Renderer::Wgpu,
        wgpu_options: wgpu_configuration(),
        ..Default::default()
    }
}

/// The viewer on `base` for the window of `cc`: the persisted settings, the backend chosen
/// for `opts.device`, and the command line's view options.
fn create_app(
    cc: &eframe::CreationContext<'_>,
    base: Scene,
    spec: &str,
    opts: ViewOptions,
) -> anyhow::Result<ViewerApp> {
    let settings = startup_settings(cc, spec);
    let (backend, note) = choose_backend(opts.device, cc)?;
    let mut app = ViewerApp::with_backend(base, settings, backend)?;
    if let Some(rs) = &cc.wgpu_render_state {
        let info = rs.adapter.get_info();
        app.display_device = format!("{} ({:?})", info.name, info.backend);
    }
    if let Some(n) = note {
        app.messages.info = Some(n);
    }
    apply_view_options(&mut app, opts);
    Ok(app)
}

/// The settings persisted in `cc`'s storage (or the defaults for `spec`) without a pending
/// capture or environment; the scene edits are dropped when they belong to another scene.
fn startup_settings(cc: &eframe::CreationContext<'_>, spec: &str) -> ViewerSettings {
    let persisted: Option<ViewerSettings> =
        cc.storage.and_then(|s| eframe::get_value(s, STORAGE_KEY));
    let mut settings = persisted.unwrap_or_else(|| ViewerSettings::for_scene(spec));
    settings.capture = None;
    settings.environment = None;
    if settings.scene != spec {
        // Keep render/display preferences; edits belong to the other scene.
        settings.scene = spec.to_owned();
        settings.clear_scene_edits();
    }
    settings
}

/// The command line's inspected pixel, view mode, lecture demo and exit and load limits.
fn apply_view_options(app: &mut ViewerApp, opts: ViewOptions) {
    if let Some(px) = opts.inspect {
        let size = (app.scene.settings.width, app.scene.settings.height);
        app.inspector.enabled = true;
        app.inspector.request_pixel(px, size);
    }
    if opts.view != layer_view::ViewMode::Beauty {
        app.set_view(opts.view);
    }
    if let Some(i) = opts
        .lecture
        .and_then(|k| lecture::DEMOS.iter().position(|d| d.key == k))
    {
        app.start_demo(i);
    }
    app.exit_frames = opts.frames;
    app.load_limits = opts.limits;
    app.exit_after = opts.exit_after;
}
