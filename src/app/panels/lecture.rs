//! The Lecture group: one button per demonstration and large type.

use crate::app::ViewerApp;
use crate::app::lecture::DEMOS;
use eframe::egui;

pub fn show(app: &mut ViewerApp, ui: &mut egui::Ui) {
    ui.horizontal_wrapped(|ui| {
        for (i, demo) in DEMOS.iter().enumerate() {
            let on = app.lecture_caption().is_some() && app.lecture.active == Some(i);
            if ui
                .selectable_label(on, demo.title)
                .on_hover_text(demo.caption)
                .clicked()
            {
                app.start_demo(i);
            }
        }
    });
    if let Some((k, n)) = app.lecture_position() {
        ui.label(format!(
            "{k} / {n} — PageDown/PageUp or the arrow keys step (a clicker)"
        ));
    }
    if let Some((toggle, on)) = app.lecture_toggle() {
        let mut want = on;
        if ui.checkbox(&mut want, toggle.label).changed() {
            app.set_lecture_toggle(want);
        }
    }
    ui.checkbox(&mut app.lecture.large_type, "Large type")
        .on_hover_text("Zoom the whole interface for the back of the lecture hall.");
}
