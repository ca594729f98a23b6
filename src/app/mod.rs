//! The interactive viewer (eframe/egui): a side panel of physics controls, the progressively
//! refined image in the central viewport and a status bar. Rendering runs behind the
//! [`backend::Backend`] trait and never blocks the UI thread. Controls never change the scene
//! themselves: they push an [`Edit`], and [`ViewerApp::apply`] (src/app/edit.rs) applies it.
//!
//! [`ViewerApp::show`] draws the whole UI into any `egui::Ui`, so the same code runs in the
//! window ([`run`]) and in the `egui_kittest` tests without a window.
//!
//! One concept per file: `construct` (constructors, backend choice), `control` (direct
//! controls), `input`, `frame` (the per-frame steps), `status` (status bar, frame timing) and
//! `window` (`refract view`).

pub mod backend;
pub mod denoise_view;
pub mod edit;
pub mod inspect;
pub mod inspect_overlay;
pub mod layer_view;
pub mod lecture;
pub mod panels;
pub mod present;
pub mod screenshot;
pub mod viewer_bench;
pub mod viewport;

mod construct;
mod control;
mod frame;
mod input;
mod status;
mod wgpu_setup;
mod window;

use crate::bvh::Bvh;
use crate::gltf_io::load::LoadLimits;
use crate::render::Estimator;
use crate::render::settings::ViewerSettings;
use crate::scene::Scene;
use crate::scene::edits::Orbit;
use backend::Backend;
pub use edit::{Edit, EnvEdit};
use eframe::egui;
use std::path::PathBuf;
use std::sync::mpsc;
use std::time::{Duration, Instant};
pub use wgpu_setup::{wgpu_configuration, wgpu_configuration_on};
pub use window::{EnvOverride, ViewOptions, run};

/// How long a new viewport size must hold before the image restarts at it.
pub const VIEWPORT_SETTLE: Duration = Duration::from_millis(250);

/// eframe storage key of the persisted [`ViewerSettings`].
pub const STORAGE_KEY: &str = "refract-settings";

/// A message shown at the top of the side panel until dismissed.
#[derive(Clone, Debug, Default)]
pub struct Messages {
    pub error: Option<String>,
    pub info: Option<String>,
}

/// Frame timing of the UI (what docs/viewer.md reports).
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
    /// The polarising filter in front of the sensor, in degrees (None: unpolarised; CPU
    /// only, `cpu::polarized`).
    pub polarizer: Option<f32>,
    /// Lecture mode: the demo on screen and large type.
    pub lecture: lecture::Lecture,
    /// The live view's denoiser: toggle, split-screen compare and badge (off by default).
    pub denoise: denoise_view::DenoiseView,
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
    /// A drag made by a script, not the pointer (`viewer_bench`): interactive as a real one.
    scripted_drag: bool,
    closing: bool,
    /// Edits pushed this frame, applied by [`ViewerApp::apply`] (src/app/edit.rs).
    edits: Vec<Edit>,
    /// What `auto` picks for the scene, and when that was worked out: it walks the mesh
    /// (~40–90 ms at a million triangles), so the estimator panel reuses it until an edit
    /// (or a second) passes (`ViewerApp::auto_choice`).
    auto_memo: Option<(Instant, (Estimator, &'static str))>,
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
