//! Environment group: load an equirectangular `.hdr`/`.exr` image (path + Load, or drop the
//! file on the window) and set its strength and rotation about +Y.

use crate::app::{Edit, EnvEdit, ViewerApp};
use eframe::egui::{self, Slider, SliderClamping};

pub fn show(app: &mut ViewerApp, ui: &mut egui::Ui) {
    ui.horizontal(|ui| {
        ui.add(
            egui::TextEdit::singleline(&mut app.env_path)
                .hint_text("path/to/sky.hdr")
                .desired_width(170.0),
        )
        .on_hover_text("An equirectangular .hdr or .exr image (three.js/glTF-viewer mapping).");
        if ui
            .button("Load")
            .on_hover_text(
                "Light the scene with this image; on failure the current lighting stays.",
            )
            .clicked()
        {
            app.push(Edit::Environment(EnvEdit::Load(
                app.env_path.trim().to_owned(),
            )));
        }
    });
    let Some(img) = app.base.env_map.as_ref() else {
        ui.label(egui::RichText::new("No environment image (drop a .hdr/.exr here).").weak());
        return;
    };
    ui.label(format!(
        "{} ({}×{})",
        img.map.name, img.map.width, img.map.height
    ));
    let (mut strength, mut rotation) = (img.strength, img.rotation);
    ui.add(
        Slider::new(&mut strength, 0.0..=20.0)
            .text("Strength")
            .logarithmic(true)
            .clamping(SliderClamping::Always),
    )
    .on_hover_text("Radiance multiplier of the environment image.");
    ui.add(
        Slider::new(&mut rotation, -180.0..=180.0)
            .text("Rotation °")
            .clamping(SliderClamping::Always),
    )
    .on_hover_text("Turns the environment about the vertical (+Y) axis.");
    if strength != img.strength || rotation != img.rotation {
        app.push(Edit::Environment(EnvEdit::Adjust { strength, rotation }));
    }
}
