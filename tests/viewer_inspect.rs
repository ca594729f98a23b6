//! The viewer's Inspect mode driven through egui_kittest: Alt+click (or a click with the
//! toggle on) a pixel of the image and the side panel lists the traced paths and their
//! vertices.

use eframe::egui;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use refract::app::ViewerApp;
use refract::cpu::inspect::VertexEvent;
use std::time::{Duration, Instant};

fn harness(spec: &str) -> Harness<'static, ViewerApp> {
    let mut app = ViewerApp::open(spec).expect("scene opens");
    app.settings.render.render_scale = 0.125;
    // A fixed image size: with Fit viewport the inspector's panel appearing shrinks the
    // viewport, restarts accumulation at the new size and re-traces, closing the open paths
    // while the test clicks them.
    app.settings.render.fit_viewport = false;
    app.options_changed();
    let mut h = Harness::builder()
        .with_size(egui::vec2(1280.0, 2400.0))
        .build_ui_state(|ui, app: &mut ViewerApp| app.show(ui), app);
    h.step();
    h
}

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

/// Press and release the primary button at film point (sx, sy) of the drawn image.
fn click_image(
    h: &mut Harness<'static, ViewerApp>,
    (sx, sy): (f32, f32),
    modifiers: egui::Modifiers,
) {
    let rect = h.state().inspector.image_rect.expect("the image was drawn");
    let pos = rect.min + egui::vec2(sx * rect.width(), sy * rect.height());
    h.event(egui::Event::PointerMoved(pos));
    h.step();
    for pressed in [true, false] {
        h.event_modifiers(
            egui::Event::PointerButton {
                pos,
                button: egui::PointerButton::Primary,
                pressed,
                modifiers,
            },
            modifiers,
        );
        h.step();
    }
}

/// The film point of the glass sphere's centre in the default scene.
fn sphere_film(app: &ViewerApp) -> (f32, f32) {
    let cam = app.scene.camera;
    cam.to_film(glam::Vec3::new(0.35, 0.35, 0.3), 1.0)
        .expect("in front")
}

#[test]
fn alt_click_lists_the_paths_through_the_pixel() {
    let mut h = harness("builtin:cornell-glass");
    assert!(
        h.query_by_label_contains("Path inspector").is_none(),
        "no panel before a click"
    );
    let film = sphere_film(h.state());
    click_image(&mut h, film, egui::Modifiers::ALT);
    assert!(
        h.state().inspector.film.is_some(),
        "Alt+click did not inspect"
    );
    assert_eq!(
        h.state().selected,
        None,
        "Alt+click inspects instead of selecting"
    );
    step_until(&mut h, "the trace", |a| a.inspector.traced.is_some());
    h.step();
    let traced = h.state().inspector.traced.clone().expect("traced");
    assert_eq!(traced.trace.paths.len(), 32);
    // The sphere's pixel: some path refracts into the glass.
    let refracts = traced
        .trace
        .paths
        .iter()
        .flat_map(|p| &p.vertices)
        .any(|v| v.event == VertexEvent::Refract);
    assert!(refracts, "no refraction through the sphere's pixel");
    h.get_by_label("Path inspector");
    h.get_by_label_contains("32 paths");
    let first = &traced.trace.paths[0];
    h.get_by_label_contains(&format!("path 0: {}", first.heckbert));
    h.get_by_label_contains("path 31: ");
    // Path 0 is open: its vertex rows, with the glass and its IORs.
    assert!(
        !h.query_all_by_label("camera")
            .collect::<Vec<_>>()
            .is_empty(),
        "no camera vertex row"
    );
    assert!(
        !h.query_all_by_label("refract")
            .collect::<Vec<_>>()
            .is_empty()
            || !first
                .vertices
                .iter()
                .any(|v| v.event == VertexEvent::Refract)
    );
    assert_eq!(
        h.query_all_by_label("η_i, η_t").count(),
        1,
        "one open vertex table"
    );
    // Open another path: its table appears too.
    h.get_by_label_contains("path 1: ").click();
    h.step();
    h.step();
    assert_eq!(h.query_all_by_label("η_i, η_t").count(), 2, "path 1 opened");
}

#[test]
fn the_toggle_makes_a_plain_click_inspect_and_edits_retrace() {
    let mut h = harness("builtin:glass-slab");
    h.get_by_label("Inspect paths (Alt+click)").click();
    h.step();
    assert!(h.state().inspector.enabled);
    click_image(&mut h, (0.6, 0.5), egui::Modifiers::NONE);
    step_until(&mut h, "the trace", |a| a.inspector.traced.is_some());
    let first = h.state().inspector.traced.clone().expect("traced");
    let (w, hh) = first.size;
    assert_eq!(
        first.trace.pixel,
        [(0.6 * w as f32) as u32, (0.5 * hh as f32) as u32]
    );
    // A new seed restarts rendering and re-traces the same pixel with other samples.
    let mut render = h.state().settings.render.clone();
    render.seed = 9;
    h.state_mut().push(refract::app::Edit::Render(render));
    h.step();
    step_until(&mut h, "the re-trace", |a| {
        a.inspector
            .traced
            .as_ref()
            .is_some_and(|t| t.trace.seed == 9)
    });
    // Closing the panel stops inspecting.
    h.get_by_label("×").click();
    h.step();
    h.step();
    assert!(h.state().inspector.film.is_none());
    assert!(h.query_by_label("Path inspector").is_none());
}
