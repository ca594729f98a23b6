//! The Dispersion group: n(λ) of the selected glass with the Fraunhofer F, d and C lines and
//! its Abbe number, and, in the prism scene, the deviation each wavelength leaves the prism
//! with (Snell's law at both faces, `math::prism`) beside the render.

use crate::app::ViewerApp;
use crate::math::prism::{
    FRAUNHOFER_C, FRAUNHOFER_D, FRAUNHOFER_F, abbe_number, deviation, min_deviation_incidence,
};
use crate::math::spectrum::rgb_matching;
use crate::scene::Material;
use crate::scene::builtin::{PRISM_APEX_DEG, PRISM_DESIGN_N_D, PRISM_WALL_DISTANCE};
use eframe::egui::{self, Color32};
use egui_plot::{Line, Plot, PlotPoint, PlotPoints, Text, VLine};

/// Visible range drawn (nm).
const VISIBLE: (f32, f32) = (380.0, 780.0);
/// Wavelength steps of a curve.
const STEPS: usize = 80;

/// The glass whose dispersion is drawn: the selected material if it is a dispersive glass,
/// else the scene's first dispersive glass.
fn plotted(app: &ViewerApp) -> Option<&Material> {
    let mats = &app.scene.materials;
    let dispersive = |m: &&Material| m.is_transmissive() && m.abbe.is_some_and(|v| v > 0.0);
    app.selected
        .and_then(|i| mats.get(i))
        .filter(dispersive)
        .or_else(|| mats.iter().find(dispersive))
}

pub fn show(app: &mut ViewerApp, ui: &mut egui::Ui) {
    let Some(m) = plotted(app) else {
        ui.label(
            egui::RichText::new(
                "No dispersive glass in this scene: select a glass and give it an Abbe number \
                 in the Material panel.",
            )
            .weak(),
        );
        return;
    };
    let n = |l: f32| m.ior_at(l);
    ui.label(format!(
        "'{}': n_F = {:.4}, n_d = {:.4}, n_C = {:.4}, V_d = (n_d − 1)/(n_F − n_C) = {:.1}",
        m.name,
        n(FRAUNHOFER_F.1),
        n(FRAUNHOFER_D.1),
        n(FRAUNHOFER_C.1),
        abbe_number(n)
    ))
    .on_hover_text(
        "The Abbe number measures how little a glass disperses: crown glass ≈ 60, flint ≈ 30.",
    );
    curve_plot(ui, "n_lambda", "index of refraction n", &|l| {
        Some(n(l) as f64)
    });
    if app.settings.scene == "builtin:prism" {
        prism_deviation(ui, &n);
    }
}

/// A curve over the visible range, each segment in the colour of its wavelength, with the
/// Fraunhofer lines marked.
fn curve_plot(ui: &mut egui::Ui, id: &str, y_label: &str, f: &dyn Fn(f32) -> Option<f64>) {
    Plot::new(id)
        .height(150.0)
        .include_x(VISIBLE.0)
        .include_x(VISIBLE.1)
        .x_axis_label("wavelength λ (nm)")
        .y_axis_label(y_label)
        .allow_drag(false)
        .allow_zoom(false)
        .allow_scroll(false)
        .show(ui, |p| {
            let top = (0..=STEPS)
                .filter_map(|i| f(lerp(i as f32 / STEPS as f32)))
                .fold(f64::NEG_INFINITY, f64::max);
            for i in 0..STEPS {
                let l0 = lerp(i as f32 / STEPS as f32);
                let l1 = lerp((i + 1) as f32 / STEPS as f32);
                let (Some(y0), Some(y1)) = (f(l0), f(l1)) else {
                    continue;
                };
                let pts = vec![[l0 as f64, y0], [l1 as f64, y1]];
                p.line(
                    Line::new(format!("{id}-{i}"), PlotPoints::from(pts))
                        .color(wavelength_colour(0.5 * (l0 + l1)))
                        .width(3.0),
                );
            }
            for (name, l) in [FRAUNHOFER_F, FRAUNHOFER_D, FRAUNHOFER_C] {
                p.vline(
                    VLine::new(format!("{name} {l:.1} nm"), l as f64)
                        .color(wavelength_colour(l).gamma_multiply(0.7)),
                );
                if top.is_finite() {
                    let at = PlotPoint::new(l as f64 + 12.0, top);
                    p.text(Text::new(format!("{id}-{name}"), at, name).color(wavelength_colour(l)));
                }
            }
        });
}

fn lerp(t: f32) -> f32 {
    VISIBLE.0 + t * (VISIBLE.1 - VISIBLE.0)
}

/// The prism's deviation per wavelength at the scene's fixed beam (aimed at minimum deviation
/// for the design index), and how far apart F and C land on the wall.
fn prism_deviation(ui: &mut egui::Ui, n: &dyn Fn(f32) -> f32) {
    let apex = PRISM_APEX_DEG.to_radians();
    let Some(theta_i) = min_deviation_incidence(PRISM_DESIGN_N_D, apex) else {
        return;
    };
    let dev = |l: f32| deviation(n(l), apex, theta_i).map(|d| d.to_degrees() as f64);
    ui.label(format!(
        "Prism: {PRISM_APEX_DEG}° apex, beam at θ_i = {:.1}°; predicted deviation δ(λ) = θ_i + θ_e − A:",
        theta_i.to_degrees()
    ))
    .on_hover_text("Snell's law at both faces; blue (large n) is deviated most.");
    curve_plot(ui, "prism_deviation", "deviation δ (°)", &dev);
    match (dev(FRAUNHOFER_F.1), dev(FRAUNHOFER_C.1)) {
        (Some(f), Some(c)) => {
            let spread_mm = PRISM_WALL_DISTANCE as f64 * (f - c).to_radians() * 1e3;
            ui.label(format!(
                "δ_F − δ_C = {:.2}°: F and C land ≈ {spread_mm:.0} mm apart on the wall {PRISM_WALL_DISTANCE} m away",
                f - c
            ));
        }
        _ => {
            ui.label("Part of the spectrum is totally reflected inside the prism.");
        }
    }
}

/// Display colour of monochromatic light of `lambda_nm`: its linear sRGB, negative parts
/// clipped, scaled to the brightest channel, sRGB-encoded.
pub fn wavelength_colour(lambda_nm: f32) -> Color32 {
    let rgb = rgb_matching(lambda_nm).max(glam::Vec3::ZERO);
    let peak = rgb.max_element();
    if peak <= 0.0 {
        return Color32::GRAY;
    }
    let c = rgb / peak;
    let enc = |x: f32| (crate::math::color::linear_to_srgb(x) * 255.0).round() as u8;
    Color32::from_rgb(enc(c.x), enc(c.y), enc(c.z))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spectral_colours_run_from_blue_to_red() {
        let blue = wavelength_colour(450.0);
        let green = wavelength_colour(530.0);
        let red = wavelength_colour(650.0);
        assert!(blue.b() > blue.r() && blue.b() > blue.g(), "{blue:?}");
        assert!(green.g() > green.r() && green.g() > green.b(), "{green:?}");
        assert!(red.r() > red.g() && red.r() > red.b(), "{red:?}");
    }
}
