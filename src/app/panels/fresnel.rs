//! Fresnel plot: reflectance against angle of incidence for the selected glass, entering
//! (air → glass) and leaving (glass → air), with Brewster and critical angles marked; for a
//! selected tabulated metal (`extras.conductor`) the exact conductor F(θ) per RGB channel with
//! Schlick's approximation (F0 = F(0°)) dashed for comparison.

use crate::app::ViewerApp;
use crate::bsdf::Metal;
use crate::bsdf::fresnel::{
    FresnelTerms, fresnel_conductor, fresnel_dielectric_terms, fresnel_schlick,
};
use crate::cpu::inspect::PixelTrace;
use eframe::egui::{self, Color32};
use egui_plot::{Line, LineStyle, Plot, PlotPoints, PlotUi, VLine};

/// Brewster angle (r_p = 0) for light going from index n₁ into n₂: tanθ_B = n₂/n₁ (Hecht §8.6).
pub fn brewster_deg(n1: f32, n2: f32) -> f32 {
    (n2 / n1).atan().to_degrees()
}

/// Critical angle for total internal reflection going from n₁ into n₂ < n₁: sinθ_c = n₂/n₁
/// (Hecht §4.7); None when n₂ ≥ n₁.
pub fn critical_deg(n1: f32, n2: f32) -> Option<f32> {
    (n2 < n1).then(|| (n2 / n1).asin().to_degrees())
}

/// The glass the plot describes: the selected material if it transmits, else the first
/// transmissive material of the scene. (index, IOR)
fn plotted_glass(app: &ViewerApp) -> Option<(usize, f32)> {
    let mats = &app.scene.materials;
    app.selected
        .filter(|&i| mats.get(i).is_some_and(|m| m.is_transmissive()))
        .or_else(|| mats.iter().position(|m| m.is_transmissive()))
        .map(|i| (i, mats[i].ior))
}

/// The selected material's tabulated metal, if it is a conductor.
fn plotted_metal(app: &ViewerApp) -> Option<(usize, Metal)> {
    let i = app.selected?;
    let m = app.scene.materials.get(i)?;
    m.conductor.filter(|_| m.is_metal_kind()).map(|c| (i, c))
}

pub fn show(app: &mut ViewerApp, ui: &mut egui::Ui) {
    if let Some((idx, metal)) = plotted_metal(app) {
        let name = &app.scene.materials[idx].name;
        conductor_show(ui, name, metal);
        return;
    }
    let Some((idx, n)) = plotted_glass(app) else {
        ui.label(
            egui::RichText::new(
                "No glass in this scene: select a material and set its type to glass.",
            )
            .weak(),
        );
        return;
    };
    let name = &app.scene.materials[idx].name;
    let eta = n.max(1e-3);
    ui.label(format!("'{name}', n = {eta:.3} (outside n = 1)"))
        .on_hover_text(
            "Fresnel equations: the fraction of light reflected depends on angle and polarisation.",
        );
    let cursor = app
        .inspector
        .traced
        .as_ref()
        .and_then(|t| inspected_angle(&t.trace, app.inspector.highlight, name));
    fresnel_plot(ui, eta, cursor);
    if let Some((deg, leaving)) = cursor {
        let side = if leaving { "leaving" } else { "entering" };
        ui.label(format!("inspected point: θ = {deg:.2}° ({side})"))
            .on_hover_text(
                "The angle of incidence at the first vertex on this glass of the inspected \
                 path (Alt+click a pixel): the white line on the plot.",
            );
    }
    angle_notes(ui, eta);
}

/// The angle of incidence (degrees) at the first vertex on material `name` of the inspected
/// path (the highlighted one, else the first), and whether the light there leaves the glass
/// (arrives from the denser side).
pub fn inspected_angle(
    trace: &PixelTrace,
    highlight: Option<usize>,
    name: &str,
) -> Option<(f64, bool)> {
    let path = trace.paths.get(highlight.unwrap_or(0))?;
    let v = path
        .vertices
        .iter()
        .skip(1)
        .find(|v| v.material == name && v.cos_i.is_some())?;
    let deg = v.cos_i?.clamp(0.0, 1.0).acos().to_degrees() as f64;
    Some((deg, v.eta_i > v.eta_t))
}

/// Blue for light entering the glass, orange for light leaving it.
const BLUE: Color32 = Color32::from_rgb(90, 160, 255);
const ORANGE: Color32 = Color32::from_rgb(255, 150, 60);

/// F, r_p² and r_s² against the angle of incidence, entering and leaving glass of index `eta`,
/// with the Brewster and critical angles marked, and the inspected point's angle (`cursor`).
fn fresnel_plot(ui: &mut egui::Ui, eta: f32, cursor: Option<(f64, bool)>) {
    Plot::new("fresnel")
        .height(190.0)
        .include_x(0.0)
        .include_x(90.0)
        .include_y(0.0)
        .include_y(1.0)
        .x_axis_label("angle of incidence θ (°)")
        .y_axis_label("reflectance")
        .allow_drag(false)
        .allow_zoom(false)
        .allow_scroll(false)
        .show(ui, |p| {
            reflectance_lines(p, eta);
            angle_lines(p, eta);
            if let Some((deg, _)) = cursor {
                p.vline(
                    VLine::new("inspected point", deg)
                        .color(Color32::WHITE)
                        .width(1.5),
                );
            }
        });
}

/// One reflectance term `f` against the angle of incidence, 0°–90°, for light entering or
/// (`leaving`) glass of index `eta`.
fn dielectric_curve(eta: f32, leaving: bool, f: fn(&FresnelTerms) -> f32) -> Vec<[f64; 2]> {
    const STEPS: usize = 180;
    (0..=STEPS)
        .map(|i| {
            let deg = 90.0 * i as f32 / STEPS as f32;
            let c = deg.to_radians().cos();
            let t = fresnel_dielectric_terms(if leaving { -c } else { c }, eta);
            [deg as f64, f(&t) as f64]
        })
        .collect()
}

/// The F (solid), r_p² (dashed) and r_s² (dotted) curves, entering in blue and leaving in
/// orange.
fn reflectance_lines(p: &mut PlotUi<'_>, eta: f32) {
    let par = |t: &FresnelTerms| t.r_par * t.r_par;
    let perp = |t: &FresnelTerms| t.r_perp * t.r_perp;
    let unpol = |t: &FresnelTerms| t.f;
    for (leaving, colour, side) in [(false, BLUE, "entering"), (true, ORANGE, "leaving")] {
        let line = |label: &str, f: fn(&FresnelTerms) -> f32| {
            Line::new(
                format!("{label} {side}"),
                PlotPoints::from(dielectric_curve(eta, leaving, f)),
            )
            .color(colour)
        };
        p.line(line("F", unpol).width(2.0));
        p.line(line("r_p²", par).style(LineStyle::dashed_dense()));
        p.line(line("r_s²", perp).style(LineStyle::dotted_dense()));
    }
}

/// Vertical markers at the Brewster angles (entering, leaving) and the critical angle.
fn angle_lines(p: &mut PlotUi<'_>, eta: f32) {
    p.vline(
        VLine::new("Brewster (entering)", brewster_deg(1.0, eta)).color(BLUE.gamma_multiply(0.6)),
    );
    p.vline(
        VLine::new("Brewster (leaving)", brewster_deg(eta, 1.0)).color(ORANGE.gamma_multiply(0.6)),
    );
    if let Some(c) = critical_deg(eta, 1.0) {
        p.vline(
            VLine::new("critical angle", c)
                .color(Color32::from_rgb(230, 80, 80))
                .width(2.0),
        );
    }
}

/// The legend, R₀ and the Brewster and critical angles of glass of index `eta` in words.
fn angle_notes(ui: &mut egui::Ui, eta: f32) {
    let brewster_in = brewster_deg(1.0, eta);
    let brewster_out = brewster_deg(eta, 1.0);
    ui.horizontal_wrapped(|ui| {
        ui.colored_label(BLUE, "blue: entering (air to glass)");
        ui.colored_label(ORANGE, "orange: leaving (glass to air)");
    });
    ui.label(
        "solid: F = (r_p² + r_s²)/2 · dashed: r_p² (parallel, p) · dotted: r_s² (perpendicular, s)",
    )
    .on_hover_text(
        "p- and s-polarised light reflect differently; unpolarised light reflects their average.",
    );
    let r0 = ((eta - 1.0) / (eta + 1.0)).powi(2);
    ui.label(format!(
        "normal incidence R₀ = ((n−1)/(n+1))² = {:.2} %",
        100.0 * r0
    ))
    .on_hover_text("At 0° both polarisations reflect the same fraction.");
    ui.label(format!("Brewster angle: {brewster_in:.1}° entering, {brewster_out:.1}° leaving"))
        .on_hover_text("At tanθ_B = n₂/n₁ the parallel polarisation is not reflected at all (r_p = 0): polarising filters use this.");
    match critical_deg(eta, 1.0) {
        Some(c) => ui.label(format!("critical angle (leaving): {c:.1}° — total internal reflection beyond"))
            .on_hover_text("Leaving a denser medium, beyond sinθ_c = 1/n no refracted ray exists and all light is reflected."),
        None => ui.label("no critical angle (n = 1: index-matched, no reflection)"),
    };
}

/// A plotted curve: (angle in degrees, reflectance) points.
pub type Curve = Vec<[f64; 2]>;

/// Plot samples of the conductor curves (every half degree).
const CONDUCTOR_STEPS: usize = 180;

/// Per RGB channel: (exact conductor F(θ), Schlick with F0 = F(0°)) as (degrees, F) points,
/// for the metal's RGB η, k (the values an RGB render uses, `Metal::rgb`).
pub fn conductor_curves(metal: Metal) -> [(Curve, Curve); 3] {
    let (eta, k) = metal.rgb();
    std::array::from_fn(|c| {
        let f0 = fresnel_conductor(1.0, eta[c], k[c]);
        let mut exact = Vec::with_capacity(CONDUCTOR_STEPS + 1);
        let mut schlick = Vec::with_capacity(CONDUCTOR_STEPS + 1);
        for i in 0..=CONDUCTOR_STEPS {
            let deg = 90.0 * i as f32 / CONDUCTOR_STEPS as f32;
            let cos = deg.to_radians().cos();
            exact.push([deg as f64, fresnel_conductor(cos, eta[c], k[c]) as f64]);
            schlick.push([deg as f64, fresnel_schlick(f0, cos) as f64]);
        }
        (exact, schlick)
    })
}

/// Largest |exact − Schlick| over the plotted angles, and the angle (°) where it occurs.
pub fn schlick_worst(exact: &[[f64; 2]], schlick: &[[f64; 2]]) -> (f64, f64) {
    exact
        .iter()
        .zip(schlick)
        .map(|(e, s)| ((e[1] - s[1]).abs(), e[0]))
        .fold((0.0, 0.0), |a, b| if b.0 > a.0 { b } else { a })
}

/// The conductor mode: exact F(θ) per channel (solid) and Schlick (dashed), ticks in degrees.
fn conductor_show(ui: &mut egui::Ui, name: &str, metal: Metal) {
    let (eta, k) = metal.rgb();
    ui.label(format!(
        "'{name}': conductor {} (outside n = 1)",
        metal.symbol()
    ))
    .on_hover_text("Tabulated spectral n, k (Mitsuba 3's data), projected to linear sRGB per channel as an RGB render uses them.");
    let curves = conductor_curves(metal);
    let channels = [
        ("R", Color32::from_rgb(240, 80, 70)),
        ("G", Color32::from_rgb(80, 200, 90)),
        ("B", Color32::from_rgb(90, 140, 255)),
    ];
    Plot::new("fresnel-conductor")
        .height(190.0)
        .include_x(0.0)
        .include_x(90.0)
        .include_y(0.0)
        .include_y(1.0)
        .x_axis_label("angle of incidence θ (°)")
        .y_axis_label("reflectance")
        .x_axis_formatter(|m, _| format!("{:.0}°", m.value))
        .allow_drag(false)
        .allow_zoom(false)
        .allow_scroll(false)
        .show(ui, |p| {
            for ((exact, schlick), (ch, colour)) in curves.iter().zip(channels) {
                p.line(
                    Line::new(format!("F {ch}"), PlotPoints::from(exact.clone()))
                        .color(colour)
                        .width(2.0),
                );
                p.line(
                    Line::new(format!("Schlick {ch}"), PlotPoints::from(schlick.clone()))
                        .color(colour)
                        .style(LineStyle::dashed_dense()),
                );
            }
        });
    ui.label("solid: exact conductor Fresnel F(θ) · dashed: Schlick F0 + (1 − F0)(1 − cosθ)⁵, F0 = F(0°)")
        .on_hover_text("Schlick's approximation misses the dip a metal's reflectance has near grazing incidence.");
    for (c, ((exact, schlick), (ch, colour))) in curves.iter().zip(channels).enumerate() {
        let (worst, at) = schlick_worst(exact, schlick);
        ui.colored_label(
            colour,
            format!(
                "{ch}: η = {:.3}, k = {:.3}, F0 = {:.3}; Schlick off by up to {worst:.3} at {at:.0}°",
                eta[c], k[c], exact[0][1]
            ),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn conductor_curves_start_at_f0_and_end_at_one() {
        for metal in Metal::ALL {
            let (eta, k) = metal.rgb();
            for (c, (exact, schlick)) in conductor_curves(metal).iter().enumerate() {
                let f0 = (((eta[c] - 1.0).powi(2) + k[c] * k[c])
                    / ((eta[c] + 1.0).powi(2) + k[c] * k[c])) as f64;
                assert!((exact[0][1] - f0).abs() < 1e-6 && (schlick[0][1] - f0).abs() < 1e-6);
                let last = exact.len() - 1;
                assert_eq!((exact[last][0], schlick[last][0]), (90.0, 90.0));
                assert!(exact[last][1] > 0.999 && schlick[last][1] > 0.999);
                // Schlick is an approximation: it differs somewhere in between, but not wildly.
                let (worst, at) = schlick_worst(exact, schlick);
                assert!(
                    worst > 1e-3 && worst < 0.25,
                    "{metal:?} {c}: {worst} at {at}°"
                );
            }
        }
    }

    #[test]
    fn angles_match_the_textbook_for_crown_glass() {
        assert!((brewster_deg(1.0, 1.5) - 56.31).abs() < 0.01);
        assert!((critical_deg(1.5, 1.0).unwrap() - 41.81).abs() < 0.01);
        assert!(critical_deg(1.0, 1.5).is_none());
        // r∥ vanishes at Brewster's angle, entering and leaving.
        for (cos_sign, b) in [
            (1.0, brewster_deg(1.0, 1.5)),
            (-1.0, brewster_deg(1.5, 1.0)),
        ] {
            let t = fresnel_dielectric_terms(cos_sign * b.to_radians().cos(), 1.5);
            assert!(t.r_par.abs() < 1e-4, "{t:?}");
        }
    }
}
