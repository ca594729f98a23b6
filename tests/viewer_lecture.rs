//! Lecture mode and the Dispersion panel, driven through egui_kittest without a window.

use eframe::egui;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use refract::app::ViewerApp;
use refract::app::lecture::{DEMOS, LARGE_ZOOM};
use refract::app::panels::lobe::lobe_vertex;
use refract::cpu::inspect::VertexEvent;
use refract::cpu::inspect::lobe::lobe_slice;
use std::time::{Duration, Instant};

/// A viewer on `spec` rendering small images (fast on 2 cores).
fn app_on(spec: &str) -> ViewerApp {
    let mut app = ViewerApp::open(spec).expect("scene opens");
    app.settings.render.render_scale = 0.25;
    app.settings.render.fit_viewport = false;
    app.options_changed();
    app
}

fn harness(app: ViewerApp) -> Harness<'static, ViewerApp> {
    let mut h = Harness::builder()
        .with_size(egui::vec2(1280.0, 2400.0))
        .build_ui_state(|ui, app: &mut ViewerApp| app.show(ui), app);
    h.step();
    h
}

fn open_lecture_group(h: &mut Harness<'static, ViewerApp>) {
    h.get_by_label("Lecture").click();
    h.step();
    h.step();
}

#[test]
fn every_demo_button_opens_its_scene_set_up() {
    let mut h = harness(app_on("builtin:furnace"));
    open_lecture_group(&mut h);
    for demo in &DEMOS {
        h.get_by_label(demo.title).click();
        h.step();
        h.step();
        let app = h.state();
        assert_eq!(app.settings.scene, demo.scene, "{}", demo.key);
        assert_eq!(app.settings.render.paths, demo.filter, "{}", demo.key);
        assert_eq!(app.lecture_caption(), Some(demo.caption), "{}", demo.key);
        assert_eq!(
            app.inspector.enabled,
            demo.inspect.is_some(),
            "{}",
            demo.key
        );
        let selected = app.selected.map(|i| app.scene.materials[i].name.as_str());
        assert_eq!(selected, demo.select, "{}: selection", demo.key);
        assert_eq!(app.view, demo.view, "{}: view", demo.key);
        assert_eq!(app.polarizer, demo.polarizer, "{}: polarizer", demo.key);
        // The demo renders: a sample of the demo's own scene arrives.
        assert!(
            app.messages.error.is_none(),
            "{}: {:?}",
            demo.key,
            app.messages.error
        );
    }
    // Opening another scene by hand ends the demo's caption.
    h.state_mut()
        .push(refract::app::Edit::OpenScene("builtin:furnace".into()));
    h.step();
    h.step();
    assert_eq!(h.state().lecture_caption(), None);
}

#[test]
fn large_type_zooms_the_interface_and_back() {
    let mut h = harness(app_on("builtin:furnace"));
    assert_eq!(h.ctx.zoom_factor(), 1.0);
    open_lecture_group(&mut h);
    h.get_by_label("Large type").click();
    h.step();
    h.step();
    h.step();
    assert!(h.state().lecture.large_type);
    assert_eq!(h.ctx.zoom_factor(), LARGE_ZOOM);
    h.get_by_label("Large type").click();
    h.step();
    h.step();
    h.step();
    assert_eq!(h.ctx.zoom_factor(), 1.0);
}

/// The paths the TIR demo's inspector traces, in a viewer that renders at `fit` (the
/// viewport's portrait shape) or the scene's own 4:3.
fn tir_demo_events(fit: bool) -> Vec<VertexEvent> {
    let mut app = app_on("builtin:furnace");
    app.settings.render.fit_viewport = fit;
    app.options_changed();
    let mut h = harness(app);
    let tir = DEMOS.iter().position(|d| d.key == "tir").unwrap();
    h.state_mut().start_demo(tir);
    let start = Instant::now();
    while h.state().inspector.traced.is_none() || h.state().inspector.is_tracing() {
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "no trace (fit {fit}): film {:?} size {:?} viewport {:?}",
            h.state().inspector.film,
            h.state().settings.resolution(&h.state().scene),
            h.state().settings.viewport
        );
        std::thread::sleep(Duration::from_millis(20));
        h.step();
    }
    let (w, hgt) = h.state().settings.resolution(&h.state().scene);
    assert_eq!(fit, w * 3 != hgt * 4, "{w}x{hgt}");
    let traced = h.state().inspector.traced.clone().unwrap();
    traced
        .trace
        .paths
        .iter()
        .flat_map(|p| p.vertices.iter().map(|v| v.event))
        .collect()
}

#[test]
fn the_tir_demo_inspects_paths_that_are_totally_reflected() {
    // The demo inspects a scene point, so a viewport of another shape sees the same paths.
    for fit in [false, true] {
        let events = tir_demo_events(fit);
        assert!(events.contains(&VertexEvent::Tir), "fit {fit}: {events:?}");
        assert!(
            events.contains(&VertexEvent::Refract),
            "fit {fit}: {events:?}"
        );
    }
}

/// Step `h` until the inspector has finished tracing.
fn until_traced(h: &mut Harness<'static, ViewerApp>) {
    let start = Instant::now();
    while h.state().inspector.traced.is_none() || h.state().inspector.is_tracing() {
        assert!(start.elapsed() < Duration::from_secs(60), "no trace");
        std::thread::sleep(Duration::from_millis(20));
        h.step();
    }
    h.step();
}

#[test]
fn the_brdf_types_demo_draws_the_lobe_of_the_inspected_sphere() {
    let mut h = harness(app_on("builtin:furnace"));
    let demo = DEMOS.iter().position(|d| d.key == "brdf-types").unwrap();
    h.state_mut().start_demo(demo);
    until_traced(&mut h);
    // The demo inspects the glossy sphere: its first vertex scatters with a continuous lobe
    // (no delta spike) peaked on the far side of the normal from the camera ray.
    let traced = h.state().inspector.traced.clone().unwrap();
    let (k, rec) = lobe_vertex(&traced.trace.paths[0], 1).expect("the path scatters");
    assert_eq!(traced.trace.paths[0].vertices[k].material, "glossy");
    let s = lobe_slice(&rec);
    assert!(s.spikes.is_empty() && s.continuous_albedo > 0.5, "{s:?}");
    let peak = s
        .density
        .iter()
        .fold((0.0, 0.0), |a, p| if p.1 > a.1 { *p } else { a });
    assert!(peak.0 < 0.0, "peak at {} rad", peak.0);
    let label = format!("#{k} 'glossy'");
    assert!(
        h.query_by_label_contains(&label).is_some(),
        "the panel names the vertex ({label})"
    );
    // Choosing the mirror sphere's path shows a spike instead: re-inspect a mirror point.
    let mirror = glam::Vec3::new(0.9, 0.35 + 0.35 * 0.5, 0.35 * 0.866);
    let size = h.state().settings.resolution(&h.state().scene);
    let film = h
        .state()
        .scene
        .camera
        .to_film(mirror, size.0 as f32 / size.1 as f32)
        .unwrap();
    h.state_mut().lecture.inspect_point = None;
    h.state_mut().inspector.clear();
    h.state_mut().inspector.request(film);
    until_traced(&mut h);
    let traced = h.state().inspector.traced.clone().unwrap();
    let (k, rec) = lobe_vertex(&traced.trace.paths[0], 1).expect("the path scatters");
    assert_eq!(traced.trace.paths[0].vertices[k].material, "mirror");
    let s = lobe_slice(&rec);
    assert_eq!(s.spikes.len(), 1, "{s:?}");
    assert!((s.spikes[0].fraction - 0.95).abs() < 1e-3, "{s:?}");
    assert!(h.query_by_label_contains("reflected spike 0.950").is_some());
}

#[test]
fn dispersion_panel_shows_the_prism_glass_and_its_deviation() {
    let mut h = harness(app_on("builtin:prism"));
    h.step();
    // n_d 1.5168, V_d 20 (the prism's glass): the panel recomputes V_d from n_F, n_d, n_C.
    h.get_by_label_contains("'dispersive-glass': n_F = ");
    h.get_by_label_contains("V_d = (n_d − 1)/(n_F − n_C) = 20.0");
    h.get_by_label_contains("Prism: 60° apex, beam at θ_i = 49.3°");
    h.get_by_label_contains("F and C land ≈");
}

#[test]
fn dispersion_panel_says_when_there_is_no_dispersive_glass() {
    let mut h = harness(app_on("builtin:cornell-glass"));
    h.get_by_label("Dispersion").click();
    h.step();
    h.step();
    h.get_by_label_contains("No dispersive glass in this scene");
}

/// Opening a demo prepares its neighbours in the background (`lecture::Ahead`): the scenes
/// of the demos before and after it arrive at the backend (`Backend::prepare_for`; the GPU
/// compiles their general kernels ahead, tests/gpu_general_kernel.rs) without the UI
/// thread waiting for them.
#[test]
fn opening_a_demo_prepares_the_next_and_the_previous() {
    let mut h = harness(app_on("builtin:furnace"));
    let k = DEMOS.iter().position(|d| d.key == "snell").unwrap();
    h.state_mut().start_demo(k);
    let start = Instant::now();
    while h.state().lecture.ahead.prepared < 2 {
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "neighbours not prepared: {}",
            h.state().lecture.ahead.prepared
        );
        std::thread::sleep(Duration::from_millis(20));
        h.step();
    }
    assert_eq!(
        h.state().lecture.ahead.prepared,
        2,
        "next and previous, once"
    );
}

/// The thin-film demo selects the soap bubble; its Material group shows the film's sliders,
/// and unticking the film removes it from the material (an edit the renderer receives).
#[test]
fn the_thin_film_demo_shows_the_film_controls_of_the_bubble() {
    let mut h = harness(app_on("builtin:furnace"));
    open_lecture_group(&mut h);
    h.get_by_label("Thin-film interference").click();
    h.step();
    h.step();
    let bubble = |h: &Harness<'static, ViewerApp>| {
        let app = h.state();
        let i = app.selected.expect("a selection");
        assert_eq!(app.scene.materials[i].name, "soap-bubble");
        app.scene.materials[i].iridescence
    };
    let film = bubble(&h).expect("the bubble has a film");
    assert_eq!(film.ior, refract::scene::builtin::thin_film::SOAP_FILM_IOR);
    for label in ["Film thickness (nm)", "Film IOR"] {
        assert!(h.query_all_by_label_contains(label).count() > 0, "{label}");
    }
    h.get_by_label("Thin film (iridescence)").click();
    h.step();
    h.step();
    assert_eq!(bubble(&h), None, "unticked: no film");
    assert!(
        h.state().messages.error.is_none(),
        "{:?}",
        h.state().messages.error
    );
}

/// The mean of the 2×2 pixels at the image's centre once `spp` samples of a generation
/// other than `not` have landed, and that generation.
fn centre_after(h: &mut Harness<'static, ViewerApp>, spp: u64, not: u64) -> (glam::Vec3, u64) {
    let start = Instant::now();
    while !h
        .state()
        .backend()
        .read_image()
        .is_some_and(|p| p.spp >= spp && p.generation != not)
    {
        assert!(start.elapsed() < Duration::from_secs(60), "no {spp} spp");
        std::thread::sleep(Duration::from_millis(20));
        h.step();
    }
    let img = h.state().backend().read_image().expect("image");
    let (w, hgt) = (img.width as usize, img.height as usize);
    let at = |x: usize, y: usize| img.pixels[y * w + x];
    let (x, y) = (w / 2 - 1, hgt / 2 - 1);
    let c = (at(x, y) + at(x + 1, y) + at(x, y + 1) + at(x + 1, y + 1)) / 4.0;
    (c, img.generation)
}

/// The Brewster demo (issue 38): it inspects the plate's centre, which the Fresnel plot's
/// cursor shows at Brewster's angle, and looks through a vertical polariser, which removes
/// the panel's reflection there; turned to horizontal, the filter passes it (r⊥² ≈ 0.148 of
/// the panel's radiance 6).
#[test]
fn the_brewster_demo_removes_the_reflection_until_the_filter_turns() {
    let mut h = harness(app_on("builtin:furnace"));
    let demo = DEMOS.iter().position(|d| d.key == "brewster").unwrap();
    h.state_mut().start_demo(demo);
    until_traced(&mut h);
    let traced = h.state().inspector.traced.clone().unwrap();
    let (deg, leaving) = refract::app::panels::fresnel::inspected_angle(
        &traced.trace,
        h.state().inspector.highlight,
        "glass-plate",
    )
    .expect("the inspected path meets the plate");
    let brewster = 1.5f64.atan().to_degrees();
    assert!(
        !leaving && (deg - brewster).abs() < 1.0,
        "inspected θ = {deg:.2}°, Brewster {brewster:.2}°"
    );
    assert_eq!(h.state().polarizer, Some(90.0));
    let (blocked, generation) = centre_after(&mut h, 16, u64::MAX);
    h.state_mut().set_polarizer(Some(0.0));
    h.step();
    let (passed, _) = centre_after(&mut h, 16, generation);
    let lum = |c: glam::Vec3| c.dot(glam::Vec3::new(0.2126, 0.7152, 0.0722));
    assert!(
        lum(passed) > 0.5 && lum(blocked) < 0.02 * lum(passed),
        "reflection through the filter at 90° {blocked}, at 0° {passed}"
    );
}
