//! Soak test of the whole viewer (issue 37, item 5): `ViewerApp` on the GPU backend, drawn by
//! egui_kittest's wgpu renderer on lavapipe (no window), driven through random edits of the
//! kinds its panels make — lecture demos, screenshots, scenes, materials, the path filter
//! (valid and not), estimator, depth, field of view, orbit, exposure, pause, restart and
//! reset — with frames of the UI between them. Every tenth edit the accumulation is read
//! back: no pixel may be NaN or infinite. Every screenshot is a PNG that decodes, an EXR and a
//! sidecar beside it, and no temporary file is left behind (they are written and renamed).
//! Every demo is opened first; then the same random edits run three times from the default
//! scene: the first pass waits after each edit until its kernel has compiled and rendered,
//! and the mean resident memory over the third pass must be at most 5 % above that over the
//! second — a leak per edit grows the third by a pass's worth. The backend runs the general
//! kernels only, so passes 2 and 3 compile nothing (asserted) and memory does not depend on
//! which pipelines a cache holds. (The backend alone: `viewer_soak.rs`.)
//!
//! `REFRACT_SOAK_APP_EDITS` sets the edits per pass (CI: 60; docs/testing.md has a longer
//! run). Its own test binary: resident memory is the process's, so no other test may share it.

mod common_scenes;
use common_scenes::{Rng, assert_passes_flat, gpu_context, rss_bytes, soak_scene, soak_scenes};

use eframe::egui;
use eframe::egui_wgpu;
use egui_kittest::Harness;
use refract::app::backend::GpuBackend;
use refract::app::lecture::DEMOS;
use refract::app::{Edit, ViewerApp};
use refract::render::Estimator;
use refract::render::settings::{DEFAULT_SCENE, ViewerSettings};
use refract::scene::Scene;
use refract::scene::edits::Orbit;
use std::path::Path;
use std::time::{Duration, Instant};

const FILTERS: [&str; 6] = ["", "LS+DE", "LDE", "L(D|G|S)*(G|S)E", "L(D", "LX*E"];
const ESTIMATORS: [Estimator; 4] = [
    Estimator::Auto,
    Estimator::Path,
    Estimator::LtPt,
    Estimator::Sppm,
];

type App = Harness<'static, ViewerApp>;

/// Specialisations the soak keeps compiled: more than the kernel families its edits reach
/// (3 estimators × filter × dispersion × nested media).
const FAMILIES_KEPT: usize = 48;

/// Draw frames until no kernel compiles and the current one has rendered (at most 60 s):
/// lavapipe compiles a pipeline's machine code at its first dispatch.
fn settle(h: &mut App) {
    let start = Instant::now();
    h.step();
    let busy = |h: &App| {
        let b = h.state().backend();
        b.compiling() || (b.spp() == 0 && b.is_rendering())
    };
    while busy(h) && start.elapsed() < Duration::from_secs(60) {
        std::thread::sleep(Duration::from_millis(5));
        h.step();
    }
}

/// What a pass saw: resident memory after each edit, accumulations checked, screenshots.
struct Pass {
    rss: Vec<u64>,
    checked: usize,
    screenshots: usize,
}

/// One pass of `edits` random edits from the default scene with its default settings and the
/// seed every pass uses; with `settle_each`, each edit waits until its kernel has compiled
/// and rendered.
fn pass(h: &mut App, edits: usize, settle_each: bool, shots: &Path) -> Pass {
    h.state_mut()
        .push(Edit::OpenScene(DEFAULT_SCENE.to_owned()));
    h.step();
    h.state_mut().push(Edit::ResetAll);
    h.step();
    let mut rng = Rng(0x050a_6a99);
    let mut p = Pass {
        rss: Vec::with_capacity(edits),
        checked: 0,
        screenshots: 0,
    };
    for i in 0..edits {
        p.screenshots += usize::from(edit(h, &mut rng, shots));
        h.step();
        h.step();
        if settle_each {
            settle(h);
        }
        if i % 10 == 9 {
            // A paused viewer adds no samples: continue so the check sees some.
            h.state_mut().push(Edit::Pause(false));
            h.step();
            p.checked += usize::from(check_accumulation(h, i));
        }
        p.rss.extend(rss_bytes());
    }
    p
}

/// The lecture demos whose scenes the soak edits (`common_scenes::soak_scene`), found once.
fn soak_demos() -> &'static [usize] {
    static DEMO_INDICES: std::sync::OnceLock<Vec<usize>> = std::sync::OnceLock::new();
    DEMO_INDICES.get_or_init(|| {
        (0..DEMOS.len())
            .filter(|&i| soak_scene(DEMOS[i].scene))
            .collect()
    })
}

/// One random edit of the kinds the viewer's panels make; returns true for a screenshot.
fn edit(h: &mut App, rng: &mut Rng, shots: &Path) -> bool {
    let app = h.state_mut();
    match rng.below(10) {
        0 => {
            let demos = soak_demos();
            app.start_demo(demos[rng.below(demos.len())]);
        }
        1 => {
            // Before the first sample of an edit lands there is nothing to save: a clear
            // refusal, no files.
            let empty = app.backend().spp() == 0;
            match app.save_screenshot() {
                Ok(saved) => {
                    check_screenshot(&saved.png, &saved.exr, &saved.json, shots);
                    return true;
                }
                Err(e) => assert!(
                    empty && format!("{e}").contains("nothing rendered yet"),
                    "screenshot with {} spp: {e:#}",
                    app.backend().spp()
                ),
            }
        }
        2 if rng.below(3) == 0 => {
            let names = soak_scenes();
            let name = names[rng.below(names.len())];
            app.push(Edit::OpenScene(format!("builtin:{name}")));
        }
        2 | 3 => {
            let index = rng.below(app.scene.materials.len());
            let mut m = app.scene.materials[index].clone();
            m.ior = 1.0 + 1.42 * rng.unit();
            m.roughness = rng.unit();
            app.push(Edit::Material {
                index,
                material: Box::new(m),
            });
        }
        4 => {
            let text = FILTERS[rng.below(FILTERS.len())].to_owned();
            app.filter_text = text.clone();
            app.push(Edit::PathFilter(text));
        }
        5 => {
            let mut r = app.settings.render.clone();
            r.estimator = ESTIMATORS[rng.below(ESTIMATORS.len())];
            r.max_depth = Some(1 + rng.below(12) as u32);
            app.push(Edit::Render(r));
        }
        6 => app.push(Edit::FieldOfView(20.0 + 70.0 * rng.unit())),
        7 => {
            let mut o = Orbit::from_camera(&app.scene.camera, glam::Vec3::ZERO, 2.0);
            o.yaw_deg += 30.0 * (rng.unit() - 0.5);
            o.pitch_deg = (o.pitch_deg + 20.0 * (rng.unit() - 0.5)).clamp(-80.0, 80.0);
            app.push(Edit::Orbit(o));
        }
        8 => {
            let mut d = app.settings.display;
            d.exposure = 4.0 * (rng.unit() - 0.5);
            app.push(Edit::Display(d));
        }
        _ => match rng.below(4) {
            0 => app.push(Edit::Pause(true)),
            1 => app.push(Edit::Pause(false)),
            2 => app.push(Edit::Restart),
            _ => app.push(Edit::ResetAll),
        },
    }
    false
}

/// The screenshot triple exists, the PNG decodes, and nothing half-written is left in `dir`.
fn check_screenshot(png: &Path, exr: &Path, json: &Path, dir: &Path) {
    let img = image::open(png).unwrap_or_else(|e| panic!("{}: {e}", png.display()));
    assert!(img.width() > 0 && img.height() > 0);
    for p in [exr, json] {
        let len = std::fs::metadata(p).map(|m| m.len()).unwrap_or(0);
        assert!(len > 0, "{} missing or empty", p.display());
    }
    for entry in std::fs::read_dir(dir).unwrap() {
        let name = entry.unwrap().file_name().to_string_lossy().into_owned();
        assert!(
            name.ends_with(".png") || name.ends_with(".exr") || name.ends_with(".json"),
            "a temporary file is left: {name}"
        );
    }
}

/// Step the UI until the accumulation has samples (a new kernel may be compiling) and check
/// every pixel is finite; false if none arrived in time (paused, or still compiling).
fn check_accumulation(h: &mut App, i: usize) -> bool {
    let start = Instant::now();
    while h.state().backend().spp() == 0 && start.elapsed() < Duration::from_secs(30) {
        h.step();
        std::thread::sleep(Duration::from_millis(2));
    }
    let Some(img) = h.state().backend().read_image() else {
        return false;
    };
    let bad = img.pixels.iter().filter(|p| !p.is_finite()).count();
    assert_eq!(
        bad, 0,
        "edit {i}: {bad} non-finite pixels after {} spp",
        img.spp
    );
    img.spp > 0
}

#[test]
fn the_viewer_takes_random_edits_demos_and_screenshots_without_poison_or_leak() {
    if gpu_context("the_viewer_takes_random_edits_demos_and_screenshots").is_none() {
        return;
    }
    let edits: usize = std::env::var("REFRACT_SOAK_APP_EDITS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(60);
    let shots = std::env::temp_dir().join(format!("refract-soak-app-{}", std::process::id()));
    std::fs::create_dir_all(&shots).unwrap();
    let rs = egui_kittest::wgpu::create_render_state(
        refract::app::wgpu_configuration().wgpu_setup,
        egui_wgpu::RendererOptions::PREDICTABLE,
    );
    let mut backend = GpuBackend::from_render_state(&rs, None).expect("GPU backend");
    // The general kernels only, all kept (as tests/viewer_soak.rs): after the first pass the
    // edits compile nothing, so resident memory measures what the viewer allocates, not which
    // of lavapipe's pipelines the cache holds.
    backend.set_general_kernel(true);
    backend.set_pipeline_capacity(FAMILIES_KEPT);
    let base = Scene::load(DEFAULT_SCENE).unwrap();
    let mut settings = ViewerSettings::for_scene(DEFAULT_SCENE);
    settings.render.render_scale = 0.125;
    settings.render.fit_viewport = false;
    let mut app = ViewerApp::with_backend(base, settings, Box::new(backend)).unwrap();
    app.screenshot_dir = shots.clone();
    let mut h = Harness::builder()
        .with_size(egui::vec2(1024.0, 768.0))
        .renderer(egui_kittest::wgpu::WgpuTestRenderer::from_render_state(rs))
        .build_ui_state(|ui, app: &mut ViewerApp| app.show(ui), app);
    h.step();
    // Every demo once (its scene, filter and kernels), then pass 1 compiles and runs every
    // kernel the edits reach (waiting after each edit); passes 2 and 3 repeat the same edits
    // at full speed. A leak grows pass 3 over pass 2.
    let start = Instant::now();
    for i in 0..DEMOS.len() {
        h.state_mut().start_demo(i);
        h.step();
        h.step();
    }
    let first = pass(&mut h, edits, true, &shots);
    let warm = h.state().backend().pipeline_stats();
    eprintln!(
        "pass 1: {:.0} s, (pipelines compiled, specialisations cached) {warm:?}",
        start.elapsed().as_secs_f64()
    );
    let second = pass(&mut h, edits, false, &shots);
    let third = pass(&mut h, edits, false, &shots);
    let after = h.state().backend().pipeline_stats();
    eprintln!(
        "passes 2 and 3: {:.0} s in all, {after:?}",
        start.elapsed().as_secs_f64()
    );
    let files = std::fs::read_dir(&shots).unwrap().count();
    std::fs::remove_dir_all(&shots).ok();
    let screenshots = first.screenshots + second.screenshots + third.screenshots;
    let checked = first.checked + second.checked + third.checked;
    eprintln!("3 × {edits} edits: {screenshots} screenshots, {checked} accumulations checked");
    assert!(screenshots > 0, "no screenshot taken");
    assert_eq!(files, 3 * screenshots, "each screenshot writes three files");
    assert!(
        checked > 3 * edits / 20,
        "only {checked} accumulations read back"
    );
    assert_passes_flat(warm, after, &second.rss, &third.rss, edits);
}
