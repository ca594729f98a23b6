//! The path inspector's controls (in the Rendering group) and its side panel: every traced path
//! through the inspected pixel with its Heckbert string and contribution, and per vertex the
//! class, event, material, η_i → η_t, θ_i, θ_t, Fresnel F and throughput.

use crate::app::ViewerApp;
use crate::app::inspect_overlay::{BLOCKED, CONNECTION, LEGEND, event_color};
use crate::cpu::inspect::{PathRecord, VertexRecord};
use eframe::egui::{self, RichText, Slider};

/// The Inspect toggle and the number of paths.
pub fn controls(app: &mut ViewerApp, ui: &mut egui::Ui) {
    let ins = &mut app.inspector;
    ui.checkbox(&mut ins.enabled, "Inspect paths (Alt+click)")
        .on_hover_text(
            "Click a pixel to trace camera paths through it with the CPU path tracer: each \
             vertex's event, angles, IORs and Fresnel term, drawn over the image.",
        );
    let mut n = ins.paths;
    ui.add(Slider::new(&mut n, 1..=256).text("Paths per pixel"))
        .on_hover_text("How many camera paths the inspector traces through the pixel.");
    if n != ins.paths {
        ins.paths = n;
        if let Some(f) = ins.film {
            ins.request(f);
        }
    }
    if ins.film.is_some() && ui.button("Clear inspected pixel").clicked() {
        ins.clear();
    }
}

/// The right-hand panel listing the traced paths (shown while a pixel is inspected; added
/// before the central viewport, as egui wants side panels).
pub fn side(app: &mut ViewerApp, ui: &mut egui::Ui) {
    if app.inspector.film.is_none() {
        return;
    }
    egui::Panel::right("path-inspector")
        .default_size(470.0)
        .resizable(true)
        .show(ui, |ui| {
            ui.horizontal(|ui| {
                ui.heading("Path inspector");
                if ui
                    .small_button("×")
                    .on_hover_text("Stop inspecting")
                    .clicked()
                {
                    app.inspector.clear();
                }
            });
            egui::ScrollArea::vertical().show(ui, |ui| contents(app, ui));
        });
}

fn contents(app: &mut ViewerApp, ui: &mut egui::Ui) {
    let ins = &mut app.inspector;
    if let Some(e) = &ins.error {
        ui.colored_label(egui::Color32::from_rgb(255, 110, 110), e);
    }
    let Some(traced) = &ins.traced else {
        ui.label("tracing…");
        return;
    };
    let t = &traced.trace;
    ui.label(format!(
        "pixel ({}, {}) of {}×{} · {} paths · mean {} · seed {}{}",
        t.pixel[0],
        t.pixel[1],
        t.width,
        t.height,
        t.paths.len(),
        rgb(t.mean),
        t.seed,
        if ins.is_tracing() {
            " · re-tracing…"
        } else {
            ""
        }
    ));
    ui.label(
        RichText::new(
            "The CPU path tracer's own samples (those of `refract trace`): the mean is the \
             pixel at this many spp. Hover a path to highlight it.",
        )
        .weak(),
    );
    super::lobe::show(ui, &t.paths, &mut ins.lobe_path, &mut ins.lobe_vertex);
    ui.separator();
    legend(ui);
    let mut hovered = None;
    for (i, p) in t.paths.iter().enumerate() {
        let header = egui::CollapsingHeader::new(path_title(i, p))
            .id_salt(("inspect-path", i))
            .default_open(i == 0)
            .show(ui, |ui| path_details(ui, i, p));
        if header.header_response.hovered() {
            hovered = Some(i);
        }
    }
    ins.highlight = hovered;
}

/// What the colours of the overlay mean.
fn legend(ui: &mut egui::Ui) {
    ui.horizontal_wrapped(|ui| {
        for (label, event) in LEGEND {
            ui.label(RichText::new(format!("— {label}")).color(event_color(event)));
        }
        ui.label(RichText::new("- - light connection").color(CONNECTION));
        ui.label(RichText::new("- - blocked").color(BLOCKED));
    });
}

fn path_title(i: usize, p: &PathRecord) -> String {
    format!(
        "path {i}: {}  = {}  ({})",
        p.heckbert,
        rgb(p.contribution),
        p.end.as_str()
    )
}

fn path_details(ui: &mut egui::Ui, i: usize, p: &PathRecord) {
    egui::Grid::new(("inspect-vertices", i))
        .striped(true)
        .spacing(egui::vec2(10.0, 2.0))
        .show(ui, |ui| {
            for h in [
                "#",
                "class",
                "event",
                "material",
                "η_i, η_t",
                "θ_i",
                "θ_t",
                "F",
                "throughput",
            ] {
                ui.label(RichText::new(h).strong());
            }
            ui.end_row();
            for (k, v) in p.vertices.iter().enumerate() {
                vertex_row(ui, k, v);
            }
        });
    for c in &p.connections {
        ui.label(format!(
            "- - light connection from #{}: {}  {}{}",
            c.from,
            c.heckbert,
            rgb(c.contribution),
            if c.occluded { "  (blocked)" } else { "" }
        ));
    }
}

fn vertex_row(ui: &mut egui::Ui, k: usize, v: &VertexRecord) {
    let deg = |c: Option<f32>| {
        c.map_or("—".to_owned(), |c| {
            format!("{:.2}°", c.clamp(0.0, 1.0).acos().to_degrees())
        })
    };
    ui.label(k.to_string());
    ui.label(v.class.as_char().to_string());
    let event = format!("{:?}", v.event).to_lowercase();
    ui.label(RichText::new(event).color(event_color(v.event)));
    ui.label(&v.material);
    ui.label(format!("{:.3}, {:.3}", v.eta_i, v.eta_t));
    ui.label(deg(v.cos_i));
    ui.label(deg(v.cos_t));
    ui.label(v.fresnel.map_or("—".to_owned(), |f| format!("{f:.4}")));
    ui.label(rgb(v.throughput));
    ui.end_row();
}

fn rgb(c: [f32; 3]) -> String {
    format!("({:.2}, {:.2}, {:.2})", c[0], c[1], c[2])
}
