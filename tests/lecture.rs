//! The lecture's demos (issue 40): every demo opens in the viewer and renders a non-black
//! image, its caption names its concept, the clicker walks through all of them in order and
//! back; the importance-sampling switch keeps the mean and costs variance; Snell's window
//! has the angular radius asin(1/1.33); the lens focuses blue nearer than red as n(λ) and
//! the thick-lens equation predict.

mod common_scenes;
use common_scenes::*;
use eframe::egui;
use egui_kittest::Harness;
use glam::Vec3;
use refract::app::ViewerApp;
use refract::app::lecture::DEMOS;
use refract::bvh::Bvh;
use refract::cpu::Renderer;
use refract::render::{Estimator, RenderOptions};
use refract::scene::Scene;
use refract::scene::builtin::optics::{
    LENS_APERTURE, LENS_EDGE, LENS_R, WATER_IOR, convex_lens, snell_window,
};

/// The mean of a small, cheap render of `scene` (CPU path tracing).
fn small_mean(scene: &Scene) -> f64 {
    let mut s = scene.clone();
    s.settings.width = 32;
    s.settings.height = 24;
    let r = Renderer::new(s).expect("valid");
    let opts = RenderOptions::from_scene(&r.scene);
    let (film, _) = r.render(&opts, 4, None, |_| {});
    let img = film.image();
    img.iter()
        .map(|p| (p.x + p.y + p.z) as f64 / 3.0)
        .sum::<f64>()
        / img.len() as f64
}

#[test]
fn every_demo_renders_and_its_caption_names_its_concept() {
    for d in &DEMOS {
        assert!(
            d.caption.to_lowercase().contains(&d.concept.to_lowercase()),
            "{}: caption does not name '{}'",
            d.key,
            d.concept
        );
        let s = Scene::load(d.scene).expect("demo scene");
        let m = small_mean(&s);
        assert!(m.is_finite() && m > 1e-3, "{}: image mean {m}", d.key);
    }
}

#[test]
fn the_clicker_walks_through_every_demo_in_order_and_back() {
    let mut app = ViewerApp::open("builtin:furnace").expect("opens");
    app.settings.render.render_scale = 0.1;
    app.settings.render.fit_viewport = false;
    app.options_changed();
    let mut h = Harness::builder()
        .with_size(egui::vec2(1280.0, 900.0))
        .build_ui_state(|ui, app: &mut ViewerApp| app.show(ui), app);
    h.step();
    let press = |h: &mut Harness<'static, ViewerApp>, key| {
        h.key_press(key);
        h.step();
        h.step();
    };
    for (k, d) in DEMOS.iter().enumerate() {
        press(&mut h, egui::Key::PageDown);
        let app = h.state();
        assert_eq!(app.settings.scene, d.scene, "forward {k}");
        assert_eq!(app.lecture_position(), Some((k + 1, DEMOS.len())));
        assert_eq!(app.lecture_caption(), Some(d.caption));
        assert!(
            app.messages.error.is_none(),
            "{}: {:?}",
            d.key,
            app.messages.error
        );
    }
    // Past the last the clicker stays; back down to the first, then Home / End.
    press(&mut h, egui::Key::PageDown);
    assert_eq!(
        h.state().lecture_position(),
        Some((DEMOS.len(), DEMOS.len()))
    );
    for k in (0..DEMOS.len() - 1).rev() {
        press(&mut h, egui::Key::ArrowLeft);
        assert_eq!(h.state().settings.scene, DEMOS[k].scene, "back {k}");
        assert_eq!(h.state().lecture_position(), Some((k + 1, DEMOS.len())));
    }
    press(&mut h, egui::Key::End);
    assert_eq!(
        h.state().lecture_position(),
        Some((DEMOS.len(), DEMOS.len()))
    );
    press(&mut h, egui::Key::Home);
    assert_eq!(h.state().lecture_position(), Some((1, DEMOS.len())));
}

#[test]
fn the_energy_switch_makes_the_white_sphere_glow_and_back() {
    let mut app = ViewerApp::open("builtin:furnace").expect("opens");
    let k = DEMOS.iter().position(|d| d.key == "energy").unwrap();
    app.start_demo(k);
    let (t, on) = app.lecture_toggle().expect("the energy demo has a switch");
    assert!(!on);
    app.set_lecture_toggle(true);
    let white = app
        .scene
        .materials
        .iter()
        .find(|m| m.name == t.material)
        .unwrap();
    assert_eq!(white.base_color, Vec3::splat(std::f32::consts::PI));
    assert!(
        small_mean(&app.scene) > 1.1 * small_mean(&app.base),
        "no glow"
    );
    app.set_lecture_toggle(false);
    assert_eq!(app.lecture_toggle().map(|x| x.1), Some(false));
}

/// The importance scene with both spheres sampled `uniform`ly or cosine-weighted.
fn importance_with(uniform: bool) -> Scene {
    let mut s = Scene::load("builtin:importance").expect("scene");
    for m in &mut s.materials {
        m.uniform_sampling = uniform && m.name != "floor";
    }
    s.settings.width = 64;
    s.settings.height = 48;
    s.settings.max_depth = 4;
    s
}

#[test]
fn uniform_and_cosine_sampling_agree_in_the_mean_and_cosine_has_less_variance() {
    let uni = Renderer::new(importance_with(true)).expect("valid");
    let cos = Renderer::new(importance_with(false)).expect("valid");
    let a = cpu_block_runs(&uni, Estimator::Path, 16, None, 10, 12);
    let b = cpu_block_runs(&cos, Estimator::Path, 16, None, 10, 12);
    assert_blocks_agree("uniform vs cosine", &a, &b);
    let var = |runs: &[Vec<f64>]| -> f64 { (0..runs[0].len()).map(|k| run_stats(runs, k).1).sum() };
    let (va, vb) = (var(&a), var(&b));
    eprintln!("summed block variance: uniform {va:.3e}, cosine {vb:.3e}");
    assert!(vb < va, "cosine-weighted is not less noisy: {vb} vs {va}");
}

#[test]
fn snells_window_has_the_critical_angle_as_its_radius() {
    let mut s = snell_window();
    for m in &mut s.materials {
        if m.name.starts_with("sand") {
            m.base_color = Vec3::ZERO; // outside the window: TIR of black
        }
    }
    let n = 129u32;
    (s.settings.width, s.settings.height) = (n, n);
    let yfov = s.camera.yfov;
    let r = Renderer::new(s).expect("valid");
    let mut opts = RenderOptions::from_scene(&r.scene);
    opts.estimator = Estimator::Path;
    let (film, _) = r.render(&opts, 16, None, |_| {});
    let img = film.image();
    let lum = |x: u32, y: u32| {
        let p = img[(y * n + x) as usize];
        p.x + p.y + p.z
    };
    // The sky at the zenith (not the peak: the sun is thousands of times brighter).
    let zenith = lum(n / 2, n / 2);
    assert!(zenith > 0.0, "the window is dark");
    let f = 0.5 * n as f32 / (0.5 * yfov).tan();
    let want = f * (1.0 / WATER_IOR).asin().tan();
    let c = n / 2; // the centre pixel's centre lies on the axis (odd size)
    // Along the four half-axes: the last pixel (centre at distance d + 0.5 … ) still lit.
    let radii = [(1i32, 0i32), (-1, 0), (0, 1), (0, -1)].map(|(dx, dy)| {
        (0..c as i32)
            .filter(|&d| {
                let (x, y) = ((c as i32 + dx * d) as u32, (c as i32 + dy * d) as u32);
                lum(x, y) > 1e-3 * zenith
            })
            .max()
            .unwrap_or(0) as f32
    });
    for got in radii {
        assert!(
            (got - want).abs() <= 1.0,
            "window radius {got} px, asin(1/{WATER_IOR}) gives {want:.2} px"
        );
    }
}

/// Snell's law in vector form (PBR 4th ed. §9.3): `d` refracted at normal `n` (facing `d`'s
/// origin side) with relative index `eta` = n_i / n_t; None at TIR.
fn refract_dir(d: Vec3, n: Vec3, eta: f32) -> Option<Vec3> {
    let cos_i = -d.dot(n);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    (sin2_t < 1.0).then(|| eta * d + (eta * cos_i - (1.0 - sin2_t).sqrt()) * n)
}

/// Where a ray parallel to the axis at height `h` crosses the axis behind the lens of
/// [`convex_lens`] at wavelength `lambda` (traced through the scene's own mesh and normals).
fn axis_crossing(scene: &Scene, bvh: &Bvh, h: f32, lambda: f32) -> f32 {
    let n = scene.materials[0].ior_at(lambda);
    let (mut o, mut d) = (Vec3::new(-1.0, h, 0.0), Vec3::X);
    for eta in [1.0 / n, n] {
        let hit = bvh
            .intersect(o, d, f32::INFINITY)
            .expect("the ray meets the lens");
        assert_eq!(scene.mesh.tri_material[hit.tri as usize], 0, "not the lens");
        let [a, b, c] =
            scene.mesh.indices[hit.tri as usize].map(|i| scene.mesh.normals[i as usize]);
        let mut nrm = ((1.0 - hit.b1 - hit.b2) * a + hit.b1 * b + hit.b2 * c).normalize();
        if nrm.dot(d) > 0.0 {
            nrm = -nrm;
        }
        o += hit.t * d;
        d = refract_dir(d, nrm, eta).expect("no TIR near the axis");
        o += 1e-4 * d;
    }
    o.x - o.y / d.y * d.x
}

#[test]
fn the_lens_focuses_blue_nearer_than_red_as_the_lensmaker_equation_predicts() {
    let scene = convex_lens();
    let bvh = Bvh::build(&scene.mesh);
    let sag = LENS_R - (LENS_R * LENS_R - LENS_APERTURE * LENS_APERTURE).sqrt();
    let thick = LENS_EDGE + 2.0 * sag;
    let focus = |lambda: f32| {
        let got = axis_crossing(&scene, &bvh, 0.01, lambda);
        // Thick lens, R₁ = R, R₂ = −R (Hecht, Optics §6.2): 1/f = (n−1)(2/R − (n−1)d/(nR²)),
        // back focal length f(1 − (n−1)d/(nR)) from the back vertex at x = d/2.
        let n = scene.materials[0].ior_at(lambda);
        let inv_f = (n - 1.0) * (2.0 / LENS_R - (n - 1.0) * thick / (n * LENS_R * LENS_R));
        let want = 0.5 * thick + (1.0 - (n - 1.0) * thick / (n * LENS_R)) / inv_f;
        eprintln!("λ {lambda} nm: n {n:.4}, focus {got:.4} m, thick lens {want:.4} m");
        assert!(
            (got - want).abs() < 0.01 * want,
            "{lambda} nm: {got} vs {want}"
        );
        got
    };
    let (blue, red) = (focus(450.0), focus(650.0));
    assert!(
        blue < red,
        "blue focus {blue} is not nearer the lens than red {red}"
    );
}
