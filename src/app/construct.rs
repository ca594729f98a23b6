//! Building a viewer: the constructors (on a given backend) and the choice of backend for
//! `--device` on the adapter eframe opened.

use super::backend::{self, Backend, CpuBackend};
use super::{FrameStats, Messages, ViewerApp, inspect, layer_view, lecture};
use crate::bvh::Bvh;
use crate::gltf_io::load::LoadLimits;
use crate::gpu::GpuContext;
use crate::render::Device;
use crate::render::settings::ViewerSettings;
use crate::scene::Scene;
use eframe::egui;
use std::path::PathBuf;
use std::time::{Duration, Instant};

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
            polarizer: None,
            lecture: lecture::Lecture::default(),
            denoise: Default::default(),
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
            scripted_drag: false,
            closing: false,
            edits: Vec::new(),
            auto_memo: None,
        };
        app.report_warnings(&warnings);
        app.backend.set_scene(&app.scene);
        app.options_follow();
        // A screenshot's sidecar opened again: behind its polariser.
        if let Some(deg) = app.settings.render.polarizer.filter(|d| d.is_finite()) {
            app.set_polarizer(Some(deg));
        }
        Ok(app)
    }

    /// A viewer on a scene spec with default settings (tests, headless use).
    pub fn open(spec: &str) -> anyhow::Result<ViewerApp> {
        let base = Scene::load(spec)?;
        ViewerApp::new(base, ViewerSettings::for_scene(spec), None)
    }

    pub(super) fn report_warnings(&mut self, warnings: &[String]) {
        if !warnings.is_empty() {
            self.messages.info = Some(warnings.join("\n"));
        }
    }
}

/// The backend for `--device` on the adapter eframe opened, and a note for the user when the
/// choice was not what was asked for.
pub(super) fn choose_backend(
    device: Device,
    cc: &eframe::CreationContext<'_>,
) -> anyhow::Result<(Box<dyn Backend>, Option<String>)> {
    let repaint = Some(cc.egui_ctx.clone());
    if device == Device::Cpu {
        return Ok((cpu_backend(repaint), None));
    }
    let Some(rs) = &cc.wgpu_render_state else {
        // The window is drawn by glow: the GPU renders on a device of its own.
        return Ok(headless_backend(device, repaint));
    };
    let info = rs.adapter.get_info();
    if device == Device::Auto && info.device_type == eframe::wgpu::DeviceType::Cpu {
        // lavapipe & co. are ~15x slower than the CPU renderer on the same cores.
        return Ok((cpu_backend(repaint), None));
    }
    match backend::GpuBackend::from_render_state(rs, repaint.clone()) {
        Ok(g) => Ok((Box::new(g), None)),
        Err(e) => Ok((
            cpu_backend(repaint),
            Some(format!(
                "The GPU backend could not start on {} ({e:#}); rendering on the CPU.",
                info.name
            )),
        )),
    }
}

fn cpu_backend(repaint: Option<egui::Context>) -> Box<dyn Backend> {
    Box::new(CpuBackend::new(repaint))
}

/// The backend for a window that egui-wgpu does not draw: the GPU renderer headless on the
/// best adapter (its image read back through the CPU), or the CPU renderer where there is
/// no adapter, or only a software one and `device` is auto; with a note saying which.
fn headless_backend(
    device: Device,
    repaint: Option<egui::Context>,
) -> (Box<dyn Backend>, Option<String>) {
    let drawn = "The window is drawn with OpenGL (glow)";
    let ctx = match GpuContext::headless() {
        Ok(ctx) => ctx,
        Err(e) => {
            let note =
                format!("{drawn}; no GPU adapter renders here ({e:#}): rendering on the CPU.");
            return (cpu_backend(repaint), Some(note));
        }
    };
    let name = ctx.info.name.clone();
    if device == Device::Auto && ctx.is_software() {
        let note = format!(
            "{drawn}; the only GPU adapter is software ({name}), slower than the CPU renderer: \
             rendering on the CPU (--device gpu renders on it anyway)."
        );
        return (cpu_backend(repaint), Some(note));
    }
    match backend::GpuBackend::headless(ctx, repaint.clone()) {
        Ok(g) => {
            let note = format!(
                "{drawn}; the GPU ({name}) renders headless and each new image is copied \
                 through the CPU."
            );
            (Box::new(g), Some(note))
        }
        Err(e) => {
            let note = format!(
                "{drawn}; the GPU backend could not start on {name} ({e:#}): rendering on the CPU."
            );
            (cpu_backend(repaint), Some(note))
        }
    }
}
