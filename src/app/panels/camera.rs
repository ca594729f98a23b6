//! Camera group: field of view, orbit parameters, reset.

use crate::app::{Edit, ViewerApp};
use crate::scene::edits::Orbit;
use eframe::egui::{self, Slider, SliderClamping};

pub fn show(app: &mut ViewerApp, ui: &mut egui::Ui) {
    ui.label(
        egui::RichText::new("Drag: orbit · right/middle drag: pan · scroll: zoom · R: reset")
            .weak(),
    );
    field_of_view(app, ui);
    orbit(app, ui);
    if ui
        .button("Reset view")
        .on_hover_text("Back to the scene's own camera and field of view.")
        .clicked()
    {
        app.push(Edit::ResetCamera);
    }
}

/// The vertical field-of-view slider (degrees).
fn field_of_view(app: &mut ViewerApp, ui: &mut egui::Ui) {
    let mut fov = app.scene.camera.yfov.to_degrees();
    if ui
        .add(
            Slider::new(&mut fov, 10.0..=120.0)
                .text("Field of view °")
                .clamping(SliderClamping::Always),
        )
        .on_hover_text("Full vertical angle a pinhole camera sees: small values zoom in like a telephoto lens.")
        .changed()
        && fov.is_finite()
    {
        app.push(Edit::FieldOfView(fov));
    }
}

/// Distance, yaw and pitch of the orbit camera; an edit is sanitised against the current orbit.
fn orbit(app: &mut ViewerApp, ui: &mut egui::Ui) {
    let mut o = app.orbit;
    let mut changed = ui
        .add(
            egui::DragValue::new(&mut o.distance)
                .speed(0.01)
                .range(0.001..=1e5)
                .prefix("distance "),
        )
        .on_hover_text(
            "Distance from the camera to the orbit pivot (scroll in the image to change it).",
        )
        .changed();
    ui.horizontal(|ui| changed |= yaw_pitch(ui, &mut o));
    if changed {
        let fallback = app.orbit;
        o.sanitize(&fallback);
        app.push(Edit::Orbit(o));
    }
}

/// The yaw and pitch drag values, side by side; true when either changed.
fn yaw_pitch(ui: &mut egui::Ui, o: &mut Orbit) -> bool {
    let mut changed = ui
        .add(
            egui::DragValue::new(&mut o.yaw_deg)
                .speed(0.5)
                .suffix("° yaw"),
        )
        .on_hover_text("Rotation of the camera around the vertical axis through the pivot.")
        .changed();
    changed |= ui
        .add(
            egui::DragValue::new(&mut o.pitch_deg)
                .speed(0.5)
                .range(-89.0..=89.0)
                .suffix("° pitch"),
        )
        .on_hover_text("Height of the camera above the pivot, as an angle.")
        .changed();
    changed
}
