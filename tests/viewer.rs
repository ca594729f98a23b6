//! Viewer tests: the UI driven through egui_kittest (AccessKit) without a window, the
//! screenshot triple and its headless re-render, and the real window under Xvfb.

use eframe::egui;
use egui::accesskit::Role;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use refract::app::ViewerApp;
use refract::render::settings::DEFAULT_SCENE;
use std::path::{Path, PathBuf};

mod xvfb;
use std::process::Command;
use std::time::{Duration, Instant};

/// The glass sphere of the default scene.
const GLASS: usize = 4;

/// A viewer on the default scene at a small resolution (fast on 2 cores).
fn small_app() -> ViewerApp {
    let mut app = ViewerApp::open(DEFAULT_SCENE).expect("default scene opens");
    app.settings.render.render_scale = 0.125; // 64×64: of the scene's 512², not the viewport
    app.settings.render.fit_viewport = false;
    app.options_changed();
    app
}

fn harness(app: ViewerApp) -> Harness<'static, ViewerApp> {
    let mut h = Harness::builder()
        .with_size(egui::vec2(1280.0, 2400.0)) // tall: the whole side panel fits, no scrolling
        .build_ui_state(|ui, app: &mut ViewerApp| app.show(ui), app);
    h.step();
    h
}

/// Step the UI until `cond` holds (the render thread works in the background).
fn step_until(h: &mut Harness<'static, ViewerApp>, what: &str, cond: impl Fn(&ViewerApp) -> bool) {
    let start = Instant::now();
    while !cond(h.state()) {
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "timed out waiting for {what}"
        );
        std::thread::sleep(Duration::from_millis(20));
        h.step();
    }
}

fn scratch_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("refract-viewer-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn starts_on_the_default_scene_and_renders() {
    let mut h = harness(small_app());
    assert_eq!(h.state().settings.scene, "builtin:cornell-glass");
    assert_eq!(h.state().scene.name, "cornell-glass");
    // The scene panel shows its name, the status bar the device.
    h.get_by_label_contains("cornell-glass: ");
    h.get_by_label_contains("render: CPU");
    step_until(&mut h, "first samples", |a| a.backend().spp() >= 2);
}

#[test]
fn ior_slider_updates_the_backend_and_restarts_accumulation() {
    let mut h = harness(small_app());
    h.state_mut().selected = Some(GLASS);
    h.step();
    step_until(&mut h, "a few samples", |a| a.backend().spp() >= 2);
    let gen0 = h.state().backend().generation();
    h.get_by_role_and_label(Role::Slider, "IOR")
        .set_value_accesskit(2.0);
    h.step();
    h.step();
    assert_eq!(h.state().scene.materials[GLASS].ior, 2.0);
    assert!(
        h.state().backend().generation() > gen0,
        "edit bumps the generation"
    );
    // No sample from before the edit survives: the counter restarted.
    assert!(
        h.state().backend().spp() <= 1,
        "spp {} after an edit",
        h.state().backend().spp()
    );
    step_until(&mut h, "the backend to apply the IOR", |a| {
        a.backend().material(GLASS).is_some_and(|m| m.ior == 2.0)
    });
    // Out-of-range values are clamped by the slider, never sent as is.
    h.get_by_role_and_label(Role::Slider, "IOR")
        .set_value_accesskit(-5.0);
    h.step();
    h.step();
    assert_eq!(h.state().scene.materials[GLASS].ior, 1.0);
    h.get_by_role_and_label(Role::Slider, "IOR")
        .set_value_accesskit(f64::NAN);
    h.step();
    h.step();
    let ior = h.state().scene.materials[GLASS].ior;
    assert!(ior.is_finite() && ior >= 1.0, "IOR {ior}");
}

/// An edited value is validated once, at the edit (`scene::Checked`): an invalid IOR is
/// refused there with a message naming it, the scene and the backend keep the old value, and
/// the accumulation is not restarted.
#[test]
fn an_invalid_edit_is_refused_at_the_edit_with_a_message() {
    use refract::app::Edit;
    let mut h = harness(small_app());
    step_until(&mut h, "samples", |a| a.backend().spp() >= 1);
    let generation = h.state().backend().generation();
    let mut m = h.state().scene.materials[GLASS].clone();
    let ior = m.ior;
    m.ior = f32::NAN;
    h.state_mut().push(Edit::Material {
        index: GLASS,
        material: Box::new(m),
    });
    h.step();
    let error = h.state().messages.error.clone().unwrap_or_default();
    assert!(error.contains("IOR NaN"), "message: {error:?}");
    assert_eq!(h.state().scene.materials[GLASS].ior, ior);
    assert_eq!(
        h.state().backend().material(GLASS).map(|m| m.ior),
        Some(ior)
    );
    assert_eq!(h.state().backend().generation(), generation, "restarted");
}

#[test]
fn ior_preset_sets_the_ior() {
    let mut h = harness(small_app());
    h.state_mut().selected = Some(GLASS);
    h.step();
    h.get_by_label("diamond").click();
    h.step();
    h.step();
    assert_eq!(h.state().scene.materials[GLASS].ior, 2.42);
    h.get_by_label("water").click();
    h.step();
    h.step();
    assert_eq!(h.state().scene.materials[GLASS].ior, 1.333);
    // The Fresnel panel follows: critical angle of water asin(1/1.333) = 48.6°.
    h.get_by_label_contains("critical angle (leaving): 48.6°");
}

#[test]
fn fresnel_panel_plots_a_selected_conductor_with_schlick() {
    let mut app = ViewerApp::open("builtin:metals").expect("metals scene opens");
    app.settings.render.render_scale = 0.125;
    app.settings.render.fit_viewport = false;
    app.options_changed();
    let gold = app
        .scene
        .materials
        .iter()
        .position(|m| m.name == "Au")
        .expect("gold sphere");
    let mut h = harness(app);
    h.state_mut().selected = Some(gold);
    h.step();
    h.step();
    h.get_by_label_contains("'Au': conductor Au");
    h.get_by_label_contains("dashed: Schlick");
    // Gold's red channel (Mitsuba's RGB η 0.143, k 3.98): F0 ≈ 0.96.
    h.get_by_label_contains("R: η = 0.14");
    // The glass mode is gone.
    assert!(h.query_by_label_contains("Brewster angle").is_none());
}

#[test]
fn clicking_the_sphere_selects_the_glass() {
    let app = small_app();
    // Film point of the sphere's centre (0.35, 0.35, 0.3) seen from the default camera.
    let cam = app.scene.camera;
    let p = glam::Vec3::new(0.35, 0.35, 0.3);
    let local = cam.rotation.transpose() * (p - cam.position);
    let t = (0.5 * cam.yfov).tan();
    let sx = 0.5 + 0.5 * local.x / (-local.z * t);
    let sy = 0.5 - 0.5 * local.y / (-local.z * t);
    assert_eq!(app.pick(sx, sy), Some(GLASS));
    assert_eq!(app.pick(0.5, 0.1), Some(0), "the white ceiling");
    assert_eq!(app.pick(0.5, 0.005), None, "above the open front: nothing");
}

#[test]
fn invalid_path_filter_shows_an_error_and_keeps_the_last_valid_one() {
    let mut h = harness(small_app());
    h.get_by_label("LS+DE").click();
    h.step();
    h.step();
    assert_eq!(h.state().settings.render.paths, "LS+DE");
    let generation = h.state().backend().generation();
    let field = h.get_by_label("Path filter (Heckbert, light to eye)");
    field.click();
    h.step();
    h.get_by_label("Path filter (Heckbert, light to eye)")
        .type_text("(D");
    h.step();
    h.step();
    assert_eq!(h.state().filter_text, "LS+DE(D");
    assert!(h.state().filter_error.is_some());
    h.get_by_label_contains("invalid: ");
    h.get_by_label_contains("still rendering 'LS+DE'");
    assert_eq!(h.state().settings.render.paths, "LS+DE");
    assert_eq!(
        h.state().backend().generation(),
        generation,
        "an invalid filter must not restart rendering"
    );
    let spp = h.state().backend().spp();
    step_until(&mut h, "rendering to go on", |a| a.backend().spp() > spp);
}

#[test]
fn malformed_glb_shows_an_error_and_keeps_the_old_scene() {
    let dir = scratch_dir("badglb");
    let bad = dir.join("broken.glb");
    std::fs::write(&bad, b"glTF\x02\x00\x00\x00garbage that is not a glb").unwrap();
    let mut h = harness(small_app());
    step_until(&mut h, "first samples", |a| a.backend().spp() >= 1);
    h.state_mut().open_path = bad.display().to_string();
    h.step();
    h.get_by_label("Open").click();
    h.step();
    h.step();
    let err = h.state().messages.error.clone().expect("an error is shown");
    assert!(err.contains("broken.glb"), "{err}");
    h.get_by_label_contains("Error: could not open");
    assert_eq!(h.state().settings.scene, DEFAULT_SCENE);
    assert_eq!(h.state().scene.name, "cornell-glass");
    let spp = h.state().backend().spp();
    step_until(&mut h, "the old scene to keep rendering", |a| {
        a.backend().spp() > spp
    });
}

fn mean_and_pixels(path: &Path) -> (f64, Vec<f64>) {
    let (_, _, px) = refract::film::load_exr(path).unwrap();
    let v: Vec<f64> = px.iter().map(|p| (p.x + p.y + p.z) as f64 / 3.0).collect();
    (v.iter().sum::<f64>() / v.len() as f64, v)
}

#[test]
fn screenshot_writes_three_files_and_rerenders_headless() {
    let dir = scratch_dir("shot");
    let mut app = small_app();
    app.screenshot_dir = dir.clone();
    app.settings.render.spp_target = 16;
    app.settings.display.exposure = 0.5;
    let mut m = app.scene.materials[GLASS].clone();
    m.ior = 1.8;
    app.set_material(GLASS, m);
    app.options_changed();
    let mut h = harness(app);
    step_until(&mut h, "16 spp", |a| a.backend().spp() >= 16);
    h.get_by_label("Screenshot").click();
    h.step();
    h.step();
    let names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    for ext in ["png", "exr", "json"] {
        assert!(
            names
                .iter()
                .any(|n| n.starts_with("cornell-glass-") && n.ends_with(ext)),
            "no .{ext} in {names:?}"
        );
    }
    let json = dir.join(names.iter().find(|n| n.ends_with(".json")).unwrap());
    let exr = json.with_extension("exr");
    let sidecar = refract::render::settings::ViewerSettings::load(&json).unwrap();
    assert_eq!(sidecar.capture.as_ref().unwrap().spp, 16);
    assert_eq!(sidecar.materials[0].ior, 1.8);

    // Headless: the sidecar as is, and once more with another seed to measure the noise.
    let bin = env!("CARGO_BIN_EXE_refract");
    let again = dir.join("again.exr");
    let other = dir.join("other-seed.exr");
    for (out, extra) in [(&again, vec![]), (&other, vec!["--seed", "7"])] {
        let st = Command::new(bin)
            .args(["render", "--quiet", "--settings"])
            .arg(&json)
            .arg("--out")
            .arg(out)
            .args(extra)
            .status()
            .unwrap();
        assert!(st.success());
    }
    let (m_view, a) = mean_and_pixels(&exr);
    let (m_again, _) = mean_and_pixels(&again);
    let (m_other, b) = mean_and_pixels(&other);
    assert_eq!(a.len(), 64 * 64);
    // σ of one image's mean, from two independent renders (pixels are independent):
    // Var(mean_a − mean_b) = 2σ² = Var_pixels(a − b) / N.
    let n = a.len() as f64;
    let d: Vec<f64> = a.iter().zip(&b).map(|(x, y)| x - y).collect();
    let dm = d.iter().sum::<f64>() / n;
    let var = d.iter().map(|x| (x - dm).powi(2)).sum::<f64>() / (n - 1.0);
    let sigma = (var / n / 2.0).sqrt();
    assert!(sigma > 0.0);
    // Same seed: the same image (the RNG is counter-based), so well within 4σ.
    assert!(
        (m_view - m_again).abs() < 4.0 * sigma,
        "viewer {m_view} vs headless {m_again}, σ {sigma}"
    );
    // Another seed: the same mean within noise (4σ·√2 for a difference of two).
    assert!(
        (m_view - m_other).abs() < 4.0 * sigma * 2f64.sqrt(),
        "viewer {m_view} vs other seed {m_other}, σ {sigma}"
    );
}

#[test]
fn reset_to_defaults_forgets_edits() {
    let mut h = harness(small_app());
    h.state_mut().selected = Some(GLASS);
    h.step();
    h.get_by_label("diamond").click();
    h.step();
    h.step();
    assert_eq!(h.state().settings.materials.len(), 1);
    h.get_by_label("Reset to defaults").click();
    h.step();
    h.step();
    assert!(h.state().settings.materials.is_empty());
    assert_eq!(h.state().scene.materials[GLASS].ior, 1.5);
}

/// `refract ARGS` in a plain Xvfb server; it must exit cleanly.
fn run_window_under_xvfb(test: &str, args: &[&str]) -> Option<xvfb::WindowRun> {
    let run = xvfb::run_under_xvfb(test, args, &xvfb::Setup::default())?;
    assert!(
        run.status.success(),
        "refract {args:?} failed: {}\n{}",
        run.status,
        run.log
    );
    Some(run)
}

/// The real window under Xvfb: `refract view --frames 120` must show a non-black image and exit
/// cleanly (auto device: the CPU backend on a software adapter).
#[test]
fn real_window_under_xvfb_is_not_black() {
    let test = "real_window_under_xvfb_is_not_black";
    let args = ["view", "--frames", "120", "--exit-after", "90s"];
    let Some(xvfb::WindowRun {
        log, best, shots, ..
    }) = run_window_under_xvfb(test, &args)
    else {
        return;
    };
    assert!(log.contains("120 frames"), "no frame summary:\n{log}");
    assert!(shots > 0, "no screenshot could be taken");
    assert!(
        best > 20.0,
        "the window looked black (best mean brightness {best:.1}/255 over {shots} screenshots)\n{log}"
    );
}

/// The same with `--device gpu`: the GPU backend renders on eframe's device (lavapipe here),
/// the frame summary names it, and the image is not black.
#[test]
fn gpu_window_under_xvfb_is_not_black() {
    let test = "gpu_window_under_xvfb_is_not_black";
    if let Err(e) = refract::gpu::GpuContext::new() {
        assert!(
            std::env::var_os("REFRACT_REQUIRE_GPU").is_none(),
            "{test}: no GPU adapter although REFRACT_REQUIRE_GPU is set ({e:#})"
        );
        eprintln!("SKIP {test}: no GPU adapter ({e:#})");
        return;
    }
    let args = [
        "view",
        "--device",
        "gpu",
        // lavapipe: ~1.5 s per frame at 256×256 here, one sample per pixel per batch; the
        // viewer now renders the window's viewport (~470×390 at scale 0.5), ~3× the work
        "--frames",
        "10",
        "--exit-after",
        "100s",
    ];
    let Some(xvfb::WindowRun {
        log, best, shots, ..
    }) = run_window_under_xvfb(test, &args)
    else {
        return;
    };
    eprintln!("{log}");
    // At least 10 frames: with --exit-after the viewer also waits for the first sample (the
    // pipelines compile in the background meanwhile), so the count may be higher.
    let frames = log
        .split(" frames in ")
        .next()
        .and_then(|head| head.rsplit(' ').next())
        .and_then(|n| n.parse::<u64>().ok());
    assert!(
        frames.is_some_and(|n| n >= 10),
        "no frame summary with ≥ 10 frames:\n{log}"
    );
    assert!(
        !log.contains(" 0 spp "),
        "closed before the first sample:\n{log}"
    );
    assert!(
        log.contains("render: GPU"),
        "the frame summary does not name the GPU backend:\n{log}"
    );
    assert!(shots > 0, "no screenshot could be taken");
    assert!(
        best > 20.0,
        "the window looked black (best mean brightness {best:.1}/255 over {shots} screenshots)\n{log}"
    );
}

/// The Environment group: a typed `.hdr` path + Load lights the scene with it (the rendered
/// image changes), strength and rotation edits reach the scene, a bad path is an error that
/// keeps the current lighting.
#[test]
fn environment_panel_loads_an_image_and_edits_it() {
    let sky = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/sun-sky.hdr");
    let mut h = harness(small_app());
    step_until(&mut h, "first samples", |a| a.backend().spp() >= 1);
    h.get_by_label_contains("No environment image");
    h.state_mut().env_path = sky.display().to_string();
    h.step();
    h.get_by_label("Load").click();
    h.step();
    h.step();
    assert!(
        h.state().messages.error.is_none(),
        "{:?}",
        h.state().messages.error
    );
    let env = h
        .state()
        .scene
        .env_map
        .clone()
        .expect("the scene has the image");
    assert_eq!((env.map.width, env.strength, env.rotation), (512, 1.0, 0.0));
    h.get_by_label_contains("sun-sky.hdr (512×256)");
    step_until(&mut h, "samples of the lit scene", |a| {
        a.backend().spp() >= 2
    });
    // Strength and rotation, as the sliders push them.
    h.state_mut().push(refract::app::Edit::Environment(
        refract::app::EnvEdit::Adjust {
            strength: 0.5,
            rotation: 45.0,
        },
    ));
    h.step();
    let env = h.state().scene.env_map.clone().expect("still lit");
    assert_eq!((env.strength, env.rotation), (0.5, 45.0));
    // A missing file: an error naming it, the image stays.
    h.state_mut().env_path = "/nonexistent/sky.hdr".into();
    h.step();
    h.get_by_label("Load").click();
    h.step();
    h.step();
    let err = h.state().messages.error.clone().expect("an error is shown");
    assert!(err.contains("/nonexistent/sky.hdr"), "{err}");
    assert_eq!(
        h.state().scene.env_map.as_ref().map(|e| e.strength),
        Some(0.5)
    );
    let spp = h.state().backend().spp();
    step_until(&mut h, "rendering to go on", |a| a.backend().spp() > spp);
}

/// Selecting a material shows it without changing it (issue 17, part 6): values outside the
/// sliders' ranges — IOR 4.5, V_d 0.5 (below the glTF clamp, possible from a sidecar or an
/// API edit), an absorption distance of 1000 m and a colour component of 0 — survive frames
/// of the open material panel, and a slider edit then writes exactly the edited value.
#[test]
fn selecting_a_material_never_changes_it() {
    let mut app = small_app();
    let mut m = app.scene.materials[GLASS].clone();
    m.ior = 4.5;
    m.abbe = Some(0.5);
    m.attenuation_distance = 1000.0;
    m.attenuation_color = glam::Vec3::new(0.0, 0.5, 1.0);
    app.set_material(GLASS, m.clone());
    let mut h = harness(app);
    h.state_mut().selected = Some(GLASS);
    for _ in 0..5 {
        h.step();
    }
    let shown = &h.state().scene.materials[GLASS];
    assert_eq!(
        (
            shown.ior,
            shown.abbe,
            shown.attenuation_distance,
            shown.attenuation_color
        ),
        (m.ior, m.abbe, m.attenuation_distance, m.attenuation_color),
        "looking changed the material"
    );
    h.get_by_role_and_label(Role::Slider, "IOR")
        .set_value_accesskit(3.7);
    h.step();
    h.step();
    let edited = &h.state().scene.materials[GLASS];
    assert_eq!(edited.ior, 3.7, "IOR 3.7 is inside the widened 1–4 range");
    assert_eq!(edited.abbe, m.abbe, "the untouched Abbe number is kept");
}

/// With "Fit viewport" (the default) the viewer renders the image area's physical pixels ×
/// render scale, HiDPI aware; a resize renders the new size and restarts accumulation.
#[test]
fn renders_at_the_viewport_size_in_physical_pixels() {
    let mut app = ViewerApp::open(DEFAULT_SCENE).expect("default scene opens");
    app.settings.render.render_scale = 0.1;
    app.options_changed();
    assert!(
        app.settings.render.fit_viewport,
        "fit viewport is the default"
    );
    let mut h = Harness::builder()
        .with_size(egui::vec2(1000.0, 1600.0))
        .with_pixels_per_point(2.0)
        .build_ui_state(|ui, app: &mut ViewerApp| app.show(ui), app);
    h.step();
    h.step();
    let (vw, vh) = h.state().settings.viewport.expect("viewport measured");
    // The central area: the window less the side panel, in physical pixels (2 per point).
    assert!(
        vw > 600 && vw < 2000 && vh > 2400 && vh <= 3200,
        "viewport {vw}x{vh}"
    );
    let res = h.state().settings.resolution(&h.state().scene);
    let want = (
        (vw as f32 * 0.1).round() as u32,
        (vh as f32 * 0.1).round() as u32,
    );
    assert_eq!(res, want, "rendered size for a {vw}x{vh} viewport");
    step_until(&mut h, "4 spp", |a| a.backend().spp() >= 4);
    let generation = h.state().backend().generation();
    h.set_size(egui::vec2(1400.0, 1600.0));
    h.step();
    h.step();
    assert_eq!(
        h.state().settings.viewport,
        Some((vw, vh)),
        "a new size waits until it has held for the settle time"
    );
    std::thread::sleep(refract::app::VIEWPORT_SETTLE);
    h.step();
    let (vw2, _) = h.state().settings.viewport.expect("viewport measured");
    assert!(
        vw2 >= vw + 700,
        "the viewport grew by 400 points: {vw} → {vw2}"
    );
    let res2 = h.state().settings.resolution(&h.state().scene);
    assert_eq!(res2.0, (vw2 as f32 * 0.1).round() as u32);
    assert!(
        h.state().backend().generation() > generation,
        "a resize restarts accumulation"
    );
    step_until(&mut h, "an image of the new size", |a| {
        a.backend()
            .read_image()
            .is_some_and(|img| img.spp >= 1 && (img.width, img.height) == res2)
    });
}

#[test]
fn view_selector_switches_to_the_layer_views_and_back() {
    let mut h = harness(small_app());
    step_until(&mut h, "beauty samples", |a| a.backend().spp() >= 2);
    let beauty = h.state().backend().read_image().expect("image").pixels;
    let mut last = beauty.clone();
    for label in ["TIR heat", "path classes", "depth heat"] {
        h.get_by_label(label).click();
        h.step();
        step_until(&mut h, label, |a| {
            a.backend().read_image().is_some_and(|p| p.spp >= 2)
        });
        let img = h.state().backend().read_image().expect("view").pixels;
        assert_ne!(img, beauty, "{label} looks like the beauty image");
        assert_ne!(img, last, "{label} looks like the previous view");
        last = img;
    }
    // The depth heat: most camera rays meet the box, the deepest pixel is white.
    let lit = last.iter().filter(|p| p.max_element() > 0.0).count();
    assert!(
        lit * 2 > last.len(),
        "{lit} of {} pixels meet a surface",
        last.len()
    );
    assert!(last.contains(&glam::Vec3::ONE));
    h.get_by_label("path classes").click();
    h.step();
    h.step();
    h.get_by_label("class LDE");
    h.get_by_label("class rest");
    h.get_by_label("beauty").click();
    h.step();
    step_until(&mut h, "beauty again", |a| {
        a.backend().read_image().is_some_and(|p| p.spp >= 2)
    });
    let again = h.state().backend().read_image().expect("image").pixels;
    assert_eq!(again.len(), beauty.len());
    assert!(h.query_by_label("class LDE").is_none(), "legend left on");
}

#[test]
fn light_line_choice_sets_the_spectrum_and_restarts_accumulation() {
    use refract::scene::edits::LightSpectrum;
    let mut h = harness(small_app());
    step_until(&mut h, "a few samples", |a| a.backend().spp() >= 2);
    let gen0 = h.state().backend().generation();
    h.get_by_label("sodium D 589.3 nm").click();
    h.step();
    h.step();
    assert_eq!(
        h.state().settings.light.spectrum,
        LightSpectrum::Line(589.3)
    );
    assert_eq!(h.state().scene.settings.light_line_nm, Some(589.3));
    assert!(
        h.state().backend().generation() > gen0,
        "edit bumps the generation"
    );
    assert!(
        h.state().backend().spp() <= 1,
        "spp {} after choosing a line",
        h.state().backend().spp()
    );
    h.get_by_label_contains("line 589.3 nm: RGB");
    step_until(&mut h, "samples under the line", |a| a.backend().spp() >= 2);
    h.get_by_label("white").click();
    h.step();
    h.step();
    assert_eq!(h.state().settings.light.spectrum, LightSpectrum::White);
    assert_eq!(h.state().scene.settings.light_line_nm, None);
}

/// What the estimator panel shows for `auto` follows the scene at once: the default Cornell
/// box photon-maps its caustics; its main light grown 2.5× (6.25× the area, ~0.58 sr from
/// the casters) makes it path tracing in the next frame, not when the panel's memo expires.
#[test]
fn auto_follows_an_edit_of_the_light_size() {
    let mut h = harness(small_app());
    assert_eq!(h.state_mut().auto_choice().0.to_string(), "sppm");
    let mut light = h.state().settings.light.clone();
    light.size = 2.5;
    h.state_mut().push(refract::app::Edit::Light(light));
    h.step();
    assert_eq!(h.state_mut().auto_choice().0.to_string(), "path");
}

/// The polarisation views (issue 38) on builtin:brewster, whose camera sees the panel
/// reflected off the glass plate at Brewster's angle in the image's centre: that light is
/// fully polarised (s, horizontal), the directly seen diffuse floor is not. The degree view
/// shows the centre bright and unpolarised light black; the angle view shows the centre red
/// (0°, horizontal); each shows its legend.
#[test]
fn polarisation_views_show_the_brewster_reflection_polarised_horizontally() {
    use refract::cpu::polarized::view::dop_colour;
    let mut app = ViewerApp::open("builtin:brewster").expect("brewster opens");
    app.settings.render.render_scale = 0.125;
    app.settings.render.fit_viewport = false;
    app.options_changed();
    let mut h = harness(app);
    let centre = |img: &refract::app::backend::Accumulated| {
        let (w, hgt) = (img.width as usize, img.height as usize);
        let mut sum = glam::Vec3::ZERO;
        for dy in 0..2 {
            for dx in 0..2 {
                sum += img.pixels[(hgt / 2 - 1 + dy) * w + w / 2 - 1 + dx];
            }
        }
        sum / 4.0
    };
    h.get_by_label("polarisation degree").click();
    h.step();
    step_until(&mut h, "degree view", |a| {
        a.backend().read_image().is_some_and(|p| p.spp >= 8)
    });
    h.get_by_label("1 polarised");
    let img = h.state().backend().read_image().expect("view");
    let c = centre(&img);
    let full = refract::math::color::srgb_to_linear(dop_colour(0.9).y);
    assert!(
        c.y > full,
        "centre {c}: the Brewster reflection is not fully polarised"
    );
    let black = img.pixels.iter().filter(|p| p.max_element() < 0.01).count();
    assert!(
        black * 10 > img.pixels.len(),
        "{black} of {} pixels unpolarised: the diffuse floor should be",
        img.pixels.len()
    );
    h.get_by_label("polarisation angle").click();
    h.step();
    step_until(&mut h, "angle view", |a| {
        a.backend().read_image().is_some_and(|p| p.spp >= 8)
    });
    h.get_by_label("0° (horizontal)");
    let c = centre(&h.state().backend().read_image().expect("view"));
    assert!(
        c.x > 0.5 && c.x > 4.0 * c.y && c.x > 4.0 * c.z,
        "centre {c}: s-polarised reflection should be red (0°)"
    );
}
