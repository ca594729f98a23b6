//! The BSDF lobe at an inspected vertex, drawn in the plane of incidence (the lecture's
//! "three BRDF types" picture): the camera ray arrives as a beam, the continuous lobe
//! f·|cos θ_i| is a polar curve (a circle for a diffuse surface, a lobe around the mirror
//! direction for a glossy one) and delta lobes are spikes as long as the energy they carry.

use crate::cpu::inspect::lobe::{LobeSlice, lobe_slice};
use crate::cpu::inspect::{PathRecord, ScatterRecord};
use eframe::egui::{self, Color32, RichText};
use egui_plot::{Arrows, Line, LineStyle, Plot, PlotPoints, PlotUi};

const LOBE: Color32 = Color32::from_rgb(90, 200, 120);
const SPIKE: Color32 = Color32::from_rgb(255, 200, 70);
const RAY: Color32 = Color32::from_rgb(230, 230, 230);

/// The first scattering vertex of `path` at or after `from` (vertex 0 is the camera).
pub fn lobe_vertex(path: &PathRecord, from: usize) -> Option<(usize, ScatterRecord)> {
    path.vertices
        .iter()
        .enumerate()
        .skip(from.max(1))
        .find_map(|(k, v)| v.scatter.map(|s| (k, s)))
}

/// The lobe section of the inspector: path `i`, its first scattering vertex at or after
/// `k` (both chosen with drag values, clamped to what was traced).
pub fn show(ui: &mut egui::Ui, paths: &[PathRecord], i: &mut usize, k: &mut usize) {
    if paths.is_empty() {
        return;
    }
    ui.horizontal(|ui| {
        ui.label(RichText::new("BSDF lobe: path").strong());
        ui.add(egui::DragValue::new(i).range(0..=paths.len() - 1));
        *i = (*i).min(paths.len() - 1);
        let last = paths[*i].vertices.len().saturating_sub(1).max(1);
        ui.label(RichText::new("vertex").strong());
        ui.add(egui::DragValue::new(k).range(1..=last));
    });
    let path = &paths[*i];
    let Some((at, rec)) = lobe_vertex(path, *k) else {
        ui.label(RichText::new("This path does not scatter at or after that vertex.").weak());
        return;
    };
    let slice = lobe_slice(&rec);
    ui.label(summary(at, &path.vertices[at].material, &slice))
        .on_hover_text(
            "The camera ray taken as a beam of light: where its energy goes. The green curve is \
             f(wo, wi)·|cos θ_i| in the plane of incidence, scaled to its peak; yellow spikes \
             are delta lobes (a mirror, smooth glass), as long as the fraction they carry.",
        );
    Plot::new("bsdf-lobe")
        .height(200.0)
        .data_aspect(1.0)
        .include_x(-1.3)
        .include_x(1.3)
        .include_y(-1.2)
        .include_y(1.2)
        .show_axes(false)
        .show_grid(false)
        .allow_drag(false)
        .allow_zoom(false)
        .allow_scroll(false)
        .show(ui, |p| draw(p, &slice));
}

/// θ_i, the material and where the energy goes, in words.
fn summary(at: usize, material: &str, s: &LobeSlice) -> String {
    let mut parts = vec![format!(
        "#{at} '{material}', θ_i = {:.1}°",
        s.incident.to_degrees()
    )];
    if s.continuous_albedo > 0.0 {
        parts.push(format!("lobe {:.3}", s.continuous_albedo));
    }
    for k in &s.spikes {
        let what = if k.transmit { "refracted" } else { "reflected" };
        parts.push(format!("{what} spike {:.3}", k.fraction));
    }
    parts.push(format!("scattered {:.3} of the energy", s.albedo()));
    parts.join(" · ")
}

/// A plot point at angle `t` from the normal and radius `r`: the incoming side (t > 0) on
/// the left, as textbooks draw it.
fn polar(t: f32, r: f32) -> [f64; 2] {
    [(-t.sin() * r) as f64, (t.cos() * r) as f64]
}

fn draw(p: &mut PlotUi<'_>, s: &LobeSlice) {
    let grey = Color32::from_gray(120);
    p.line(Line::new("surface", PlotPoints::from(vec![[-1.3, 0.0], [1.3, 0.0]])).color(grey));
    p.line(
        Line::new("normal", PlotPoints::from(vec![[0.0, 0.0], [0.0, 1.2]]))
            .color(grey)
            .style(LineStyle::dashed_dense()),
    );
    p.arrows(
        Arrows::new(
            "camera ray",
            PlotPoints::from(vec![polar(s.incident, 1.25)]),
            PlotPoints::from(vec![[0.0, 0.0]]),
        )
        .color(RAY),
    );
    let peak = s.peak();
    if peak > 0.0 {
        let mut pts: Vec<[f64; 2]> = s.density.iter().map(|&(t, v)| polar(t, v / peak)).collect();
        pts.push(pts[0]);
        p.line(
            Line::new("f·|cos θ_i|", PlotPoints::from(pts))
                .color(LOBE)
                .width(2.0),
        );
    }
    for k in &s.spikes {
        p.arrows(
            Arrows::new(
                if k.transmit { "refracted" } else { "reflected" },
                PlotPoints::from(vec![[0.0, 0.0]]),
                PlotPoints::from(vec![polar(k.angle, k.fraction.clamp(0.02, 1.0))]),
            )
            .color(SPIKE),
        );
    }
}
