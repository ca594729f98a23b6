//! Scene group: built-in picker, open a .glb/.gltf (path, dialog, drag-and-drop).

use crate::app::{Edit, ViewerApp};
use crate::scene::builtin;
use eframe::egui;

pub fn show(app: &mut ViewerApp, ui: &mut egui::Ui) {
    builtin_picker(app, ui);
    ui.horizontal(|ui| open_file(app, ui));
    ui.label(egui::RichText::new("Tip: drop a .glb/.gltf file on the window to open it.").weak());
    summary(app, ui);
}

/// The built-in scene combo box; choosing one queues opening it.
fn builtin_picker(app: &mut ViewerApp, ui: &mut egui::Ui) {
    let current = app.settings.scene.clone();
    let mut chosen = None;
    egui::ComboBox::from_label("Built-in scene")
        .selected_text(current.strip_prefix("builtin:").unwrap_or("(file)"))
        .show_ui(ui, |ui| {
            for name in builtin::NAMES {
                let spec = format!("builtin:{name}");
                if ui.selectable_label(current == spec, *name).clicked() {
                    chosen = Some(spec);
                }
            }
        })
        .response
        .on_hover_text(
            "Scenes built into refract; the Cornell box shows colour bleeding, caustics and refraction at once.",
        );
    if let Some(spec) = chosen {
        app.push(Edit::OpenScene(spec));
    }
}

/// The path field with its Open (or Enter) and Browse… buttons.
fn open_file(app: &mut ViewerApp, ui: &mut egui::Ui) {
    let edit = ui
        .add(
            egui::TextEdit::singleline(&mut app.open_path)
                .hint_text("path/to/scene.glb")
                .desired_width(170.0),
        )
        .on_hover_text(
            "A glTF 2.0 scene file; its materials follow the scene contract (meters, +Y up).",
        );
    let enter = edit.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
    if ui
        .button("Open")
        .on_hover_text("Load the scene at this path; if it fails the current scene stays.")
        .clicked()
        || enter
    {
        let p = app.open_path.clone();
        app.push(Edit::OpenScene(p));
    }
    if ui
        .button("Browse…")
        .on_hover_text("Pick a .glb/.gltf with the system file dialog (xdg-desktop-portal).")
        .clicked()
    {
        app.open_dialog();
    }
}

/// One line on the loaded scene: name, triangles, materials and lights.
fn summary(app: &ViewerApp, ui: &mut egui::Ui) {
    let s = &app.scene;
    ui.label(format!(
        "{}: {} triangles, {} materials, {} area-light triangles, {} punctual lights",
        s.name,
        s.mesh.triangle_count(),
        s.materials.len(),
        app.scene.emissive_triangles().len(),
        s.punctual_lights.len()
    ));
}
