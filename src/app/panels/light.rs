//! Light group: emission scale and colour, size and placement of the main area light,
//! environment brightness.

use crate::app::{Edit, ViewerApp};
use crate::math::color::{blackbody_rgb, luminance};
use crate::math::prism::SODIUM_D_NM;
use crate::scene::edits::{LightEdit, LightSpectrum, MainLight};
use eframe::egui::{self, Slider, SliderClamping};
use glam::Vec3;

pub fn show(app: &mut ViewerApp, ui: &mut egui::Ui) {
    let main = MainLight::find(&app.base);
    let mut light = app.settings.light.clone();
    let l = &mut light;
    intensity_slider(ui, l);
    colour_controls(ui, l);
    spectrum_controls(ui, l, app.base.settings.light_line_nm);
    match &main {
        Some(m) => main_light_controls(ui, l, m, &app.base.materials[m.material].name),
        None => {
            ui.label(egui::RichText::new("No area light in this scene.").weak());
        }
    }
    if app.base.env_map.is_some() {
        ui.label(egui::RichText::new("Environment: an image (see Environment).").weak());
    } else {
        environment_slider(ui, l, app.base.environment);
    }
    if l.intensity.is_nan() {
        l.intensity = 1.0;
    }
    if light != app.settings.light {
        app.push(Edit::Light(light));
    }
}

/// The scale on every light's radiance.
fn intensity_slider(ui: &mut egui::Ui, l: &mut LightEdit) {
    ui.add(
        Slider::new(&mut l.intensity, 0.0..=20.0)
            .text("Intensity ×")
            .logarithmic(true)
            .clamping(SliderClamping::Always),
    )
    .on_hover_text("Scales the radiance of every light; the image scales linearly with it (light transport is linear).");
}

/// Light colour: a linear RGB factor or a black-body temperature.
fn colour_controls(ui: &mut egui::Ui, l: &mut LightEdit) {
    let mut use_temp = l.temperature_k.is_some();
    ui.horizontal(|ui| {
        ui.label("Colour");
        ui.radio_value(&mut use_temp, false, "RGB")
            .on_hover_text("Tint the lights with a linear RGB colour.");
        ui.radio_value(&mut use_temp, true, "temperature")
            .on_hover_text("The colour of a black body at this temperature (Planck's law): candles ≈ 1900 K, daylight ≈ 6500 K.");
    });
    if use_temp {
        let mut t = l.temperature_k.unwrap_or(6500.0);
        ui.add(
            Slider::new(&mut t, 1700.0..=12000.0)
                .text("K")
                .clamping(SliderClamping::Always),
        )
        .on_hover_text("Hotter black bodies shift their emission towards blue, cooler ones towards red (Wien's law).");
        l.temperature_k = Some(if t.is_finite() { t } else { 6500.0 });
        let c = blackbody_rgb(t);
        ui.label(format!(
            "RGB ≈ ({:.2}, {:.2}, {:.2}) at luminance 1",
            c.x, c.y, c.z
        ));
    } else {
        l.temperature_k = None;
        ui.horizontal(|ui| {
            ui.color_edit_button_rgb(&mut l.color)
                .on_hover_text("Linear RGB factor on every light's emission.");
            ui.label("Light colour");
        });
        for c in &mut l.color {
            if !c.is_finite() {
                *c = 1.0;
            }
        }
    }
}

/// Size, elevation and azimuth of the main area light `m` (material `name`).
fn main_light_controls(ui: &mut egui::Ui, l: &mut LightEdit, m: &MainLight, name: &str) {
    ui.label(format!("Main area light: '{name}'"));
    ui.add(
        Slider::new(&mut l.size, 0.1..=4.0)
            .text("Size ×")
            .logarithmic(true)
            .clamping(SliderClamping::Always),
    )
    .on_hover_text("Scales the light about its centre at constant radiance: bigger lights give more light and softer shadows.");
    let mut el = l.elevation_deg.unwrap_or(m.elevation_deg);
    let mut az = l.azimuth_deg.unwrap_or(m.azimuth_deg);
    let r1 = ui
        .add(Slider::new(&mut el, -90.0..=90.0).text("Elevation °").clamping(SliderClamping::Always))
        .on_hover_text("Height of the light seen from the scene centre; it keeps facing the centre, so shadows swing.");
    let r2 = ui
        .add(
            Slider::new(&mut az, -180.0..=180.0)
                .text("Azimuth °")
                .clamping(SliderClamping::Always),
        )
        .on_hover_text("Direction of the light around the vertical axis through the scene centre.");
    if r1.changed() && el.is_finite() {
        l.elevation_deg = Some(el);
        l.azimuth_deg.get_or_insert(m.azimuth_deg);
    }
    if r2.changed() && az.is_finite() {
        l.azimuth_deg = Some(az);
        l.elevation_deg.get_or_insert(m.elevation_deg);
    }
    if ui
        .button("Reset size and position")
        .on_hover_text("Put the main light back where the scene had it.")
        .clicked()
    {
        l.size = 1.0;
        l.elevation_deg = None;
        l.azimuth_deg = None;
    }
}

/// Radiance of the uniform environment (default: the luminance of the scene's own).
fn environment_slider(ui: &mut egui::Ui, l: &mut LightEdit, scene_environment: Vec3) {
    let mut env = l
        .environment
        .unwrap_or_else(|| luminance(scene_environment));
    if ui
        .add(
            Slider::new(&mut env, 0.0..=10.0)
                .text("Environment")
                .clamping(SliderClamping::Always),
        )
        .on_hover_text("Radiance of the uniform sky that escaping rays see; in a closed furnace every object should vanish into it.")
        .changed()
        && env.is_finite()
    {
        l.environment = Some(env.max(0.0));
    }
}

/// The line lights offered (name, wavelength in nm).
const LINES: [(&str, f32); 4] = [
    ("sodium D", SODIUM_D_NM),
    ("He-Ne", 632.8),
    ("green laser", 532.0),
    ("violet laser", 405.0),
];

/// The slider range of a custom line (nm): the visible range.
const CUSTOM_NM: std::ops::RangeInclusive<f32> = 380.0..=780.0;

/// Light spectrum: white, or one spectral line for every emitter (`RenderSettings::
/// light_line_nm`); `loaded` is the scene file's line, shown as the state when not edited.
fn spectrum_controls(ui: &mut egui::Ui, l: &mut LightEdit, loaded: Option<f32>) {
    let current = match l.spectrum {
        LightSpectrum::AsLoaded => loaded,
        LightSpectrum::White => None,
        LightSpectrum::Line(nm) => Some(nm),
    };
    let preset = current.and_then(|nm| LINES.iter().find(|(_, v)| *v == nm));
    ui.label("Spectrum").on_hover_text(
        "White light, or one spectral line for every light of the scene (area, point, environment): paths carry that wavelength only, so a dispersive prism sends one sharp beam deviated by n(λ).",
    );
    ui.horizontal_wrapped(|ui| {
        if ui.selectable_label(current.is_none(), "white").clicked() {
            l.spectrum = LightSpectrum::White;
        }
        for (name, nm) in LINES {
            if ui
                .selectable_label(current == Some(nm), format!("{name} {nm} nm"))
                .clicked()
            {
                l.spectrum = LightSpectrum::Line(nm);
            }
        }
        let custom = current.is_some() && preset.is_none();
        if ui.selectable_label(custom, "custom").clicked() && !custom {
            l.spectrum = LightSpectrum::Line(550.0);
        }
    });
    if let Some(nm) = current
        && preset.is_none()
    {
        let mut v = nm;
        ui.add(
            Slider::new(&mut v, CUSTOM_NM)
                .text("line nm")
                .clamping(SliderClamping::Always),
        )
        .on_hover_text("The wavelength every light emits at.");
        if v != nm {
            l.spectrum = LightSpectrum::Line(if v.is_finite() { v } else { 550.0 });
        }
    }
    if let Some(nm) = current {
        let c = crate::math::spectrum::light_line_rgb(nm);
        ui.label(format!(
            "line {nm:.1} nm: RGB ≈ ({:.2}, {:.2}, {:.2}) at luminance 1",
            c.x, c.y, c.z
        ));
    }
}
