//! The viewer window (`refract view`): command-line options, the wgpu setup, loading the
//! startup scene and creating the app with its persisted settings.

use super::construct::choose_backend;
use super::present::{self, WindowRenderer};
use super::{STORAGE_KEY, ViewerApp, layer_view, lecture};
use crate::gltf_io::load::LoadLimits;
use crate::render::Device;
use crate::render::settings::{DEFAULT_SCENE, ViewerSettings};
use crate::scene::Scene;
use eframe::egui;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

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
    /// `--window-renderer`: what draws the window (`present`).
    pub window_renderer: WindowRenderer,
}

/// An environment image given on the command line.
#[derive(Clone, Debug, Default)]
pub struct EnvOverride {
    pub file: Option<std::path::PathBuf>,
    pub strength: Option<f32>,
    pub rotation: Option<f32>,
}

/// Open the viewer window (blocks until it is closed). The window's renderer is the first
/// of `present::plan` that presents (see `present`); each one tried and what it said is in
/// the error when none does.
pub fn run(opts: ViewOptions) -> anyhow::Result<()> {
    let spec = opts
        .scene
        .as_deref()
        .map_or_else(|| DEFAULT_SCENE.to_owned(), Scene::canonical_spec);
    // Load before opening the window so a bad path is a plain CLI error.
    let base = load_startup_scene(&spec, &opts)?;
    let env = eframe::wgpu::Backends::from_env();
    let mut tried = Vec::new();
    for (i, p) in present::plan(opts.window_renderer, env)
        .into_iter()
        .enumerate()
    {
        if present::needs_probe(p, i)
            && let Err(why) = present::probe_in_child(p)
        {
            tried.push((p, why));
            continue;
        }
        let created = Arc::new(AtomicBool::new(false));
        let flag = Arc::clone(&created);
        let (base, spec2, opts2) = (base.clone(), spec.clone(), opts.clone());
        let create: eframe::AppCreator<'_> = Box::new(move |cc| {
            let app = create_app(cc, base, &spec2, opts2)?;
            flag.store(true, Ordering::SeqCst);
            Ok(Box::new(app))
        });
        let options = p.native_options(viewport(&spec));
        match present::run_guarded("refract", options, create, &created) {
            present::Outcome::Done(r) => return r,
            present::Outcome::CannotPresent { why, poisoned } => {
                tried.push((p, why));
                if poisoned {
                    break;
                }
            }
        }
    }
    Err(present::nothing_presents(&tried, env))
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

/// The viewer window: titled after `spec`, 1280×820, accepting dropped files.
fn viewport(spec: &str) -> egui::ViewportBuilder {
    egui::ViewportBuilder::default()
        .with_title(format!("refract — {spec}"))
        .with_inner_size([1280.0, 820.0])
        .with_drag_and_drop(true)
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
    } else if cc.gl.is_some() {
        app.display_device = "OpenGL (glow)".to_owned();
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
