//! The side panel: one group per concern, every control with a one-sentence physics tooltip.

pub mod camera;
pub mod dispersion;
pub mod environment;
pub mod film;
pub mod fresnel;
pub mod inspect;
pub mod lecture;
pub mod light;
pub mod lobe;
pub mod material;
pub mod rendering;
pub mod scene;

use super::ViewerApp;
use eframe::egui::{self, Color32, RichText};

/// Draw every group of the side panel.
pub fn side_panel(app: &mut ViewerApp, ui: &mut egui::Ui) {
    messages(app, ui);
    group(ui, "Lecture", false, |ui| lecture::show(app, ui));
    group(ui, "Scene", true, |ui| scene::show(app, ui));
    group(ui, "Material", true, |ui| material::show(app, ui));
    group(ui, "Fresnel", true, |ui| fresnel::show(app, ui));
    let dispersive = app.scene.materials.iter().any(|m| m.abbe.is_some());
    group(ui, "Dispersion", dispersive, |ui| dispersion::show(app, ui));
    group(ui, "Light", true, |ui| light::show(app, ui));
    group(ui, "Environment", true, |ui| environment::show(app, ui));
    group(ui, "Camera", false, |ui| camera::show(app, ui));
    group(ui, "Rendering", true, |ui| rendering::show(app, ui));
}

fn group(ui: &mut egui::Ui, title: &str, open: bool, add: impl FnOnce(&mut egui::Ui)) {
    egui::CollapsingHeader::new(RichText::new(title).strong())
        .default_open(open)
        .show(ui, add);
}

/// Errors (red) and notes (grey) at the top of the panel, each with a dismiss button.
fn messages(app: &mut ViewerApp, ui: &mut egui::Ui) {
    if let Some(e) = app.messages.error.clone() {
        egui::Frame::new()
            .fill(Color32::from_rgb(80, 20, 20))
            .inner_margin(6.0)
            .corner_radius(4.0)
            .show(ui, |ui| {
                ui.horizontal_top(|ui| {
                    if ui.small_button("×").on_hover_text("Dismiss").clicked() {
                        app.messages.error = None;
                    }
                    ui.add(
                        egui::Label::new(
                            RichText::new(format!("Error: {e}")).color(Color32::WHITE),
                        )
                        .wrap(),
                    );
                });
            });
    }
    if let Some(i) = app.messages.info.clone() {
        ui.horizontal_top(|ui| {
            if ui.small_button("×").on_hover_text("Dismiss").clicked() {
                app.messages.info = None;
            }
            ui.add(egui::Label::new(RichText::new(i).weak()).wrap());
        });
    }
}
