//! Material group: the material of the selected object (click it in the viewport).

use crate::app::{Edit, ViewerApp};
use crate::bsdf::MicrofacetDistribution;
use crate::scene::{Material, MaterialKind};
use eframe::egui::{self, Slider, SliderClamping};

/// Refractive indices at the sodium d line (587.6 nm).
pub const IOR_PRESETS: &[(&str, f32)] = &[
    ("vacuum", 1.0),
    ("water", 1.333),
    ("ice", 1.31),
    ("olive oil", 1.47),
    ("crown glass", 1.52),
    ("flint glass", 1.62),
    ("sapphire", 1.77),
    ("diamond", 2.42),
];

/// The IOR slider's range (diamond is 2.42, germanium in the infrared ≈ 4). Values outside
/// it — from a file, say — are shown and kept as they are: every control here writes back
/// only what the user changed, never a clamped copy of what they only looked at.
pub const IOR_RANGE: std::ops::RangeInclusive<f32> = 1.0..=4.0;

/// The Abbe-number slider's range (V_d 1 disperses wildly, 100 hardly at all).
pub const ABBE_RANGE: std::ops::RangeInclusive<f32> = 1.0..=100.0;

fn kind_label(k: MaterialKind) -> &'static str {
    match k {
        MaterialKind::Diffuse => "diffuse",
        MaterialKind::Mirror => "mirror",
        MaterialKind::GlossyMetal => "glossy metal",
        MaterialKind::Glass => "glass",
        MaterialKind::ThinGlass => "thin glass (sheet)",
        MaterialKind::MetalRough => "glTF metal-rough",
    }
}

fn kind_tip(k: MaterialKind) -> &'static str {
    match k {
        MaterialKind::Diffuse => {
            "Lambertian: scatters light equally in all directions, radiance independent of view."
        }
        MaterialKind::Mirror => {
            "Perfect specular reflection: the angle of reflection equals the angle of incidence."
        }
        MaterialKind::GlossyMetal => {
            "Rough metal: microfacets spread the mirror reflection into a lobe whose width grows with roughness."
        }
        MaterialKind::Glass => {
            "Solid dielectric: Fresnel splits light into a reflected and a refracted part, Snell's law bends the latter."
        }
        MaterialKind::ThinGlass => {
            "Thin sheet with two interfaces: reflects like glass but passes light straight through without bending."
        }
        MaterialKind::MetalRough => {
            "glTF's metallic-roughness model: a Fresnel-weighted GGX layer over a diffuse base."
        }
    }
}

/// Roughness type shown in the UI.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Rough {
    Smooth,
    Ggx,
    Beckmann,
}

pub fn show(app: &mut ViewerApp, ui: &mut egui::Ui) {
    // Selection list (click in the viewport selects too).
    let names: Vec<String> = app
        .scene
        .materials
        .iter()
        .enumerate()
        .map(|(i, m)| {
            if m.name.is_empty() {
                format!("#{i}")
            } else {
                format!("#{i} {}", m.name)
            }
        })
        .collect();
    let mut sel = app.selected;
    egui::ComboBox::from_label("Object")
        .selected_text(
            sel.and_then(|i| names.get(i).cloned())
                .unwrap_or_else(|| "click an object".into()),
        )
        .show_ui(ui, |ui| {
            for (i, n) in names.iter().enumerate() {
                ui.selectable_value(&mut sel, Some(i), n);
            }
        })
        .response
        .on_hover_text("The material being edited; click an object in the image to select it.");
    app.selected = sel;
    let Some(idx) = app.selected.filter(|&i| i < app.scene.materials.len()) else {
        ui.label(egui::RichText::new("Click an object in the image to edit its material.").weak());
        return;
    };
    let mut m = app.scene.materials[idx].clone();
    edit_material(ui, &mut m);
    if m != app.scene.materials[idx] {
        app.push(Edit::Material {
            index: idx,
            material: Box::new(m),
        });
    }
}

/// The material controls; edits `m` in place with sanitised values.
fn edit_material(ui: &mut egui::Ui, m: &mut Material) {
    if m.is_emissive() {
        ui.label(
            egui::RichText::new("This object emits light: edit its emission in the Light group.")
                .weak(),
        );
    }
    let before = m.kind;
    kind_combo(ui, m);
    if m.kind != before {
        fit_fields_to_kind(m, before);
    }
    if m.kind == MaterialKind::ThinGlass
        && ui
            .button("Make solid glass")
            .on_hover_text(
                "Blender exports glass as a thin sheet; a solid bends light by Snell's law.",
            )
            .clicked()
    {
        m.kind = MaterialKind::Glass;
    }
    let transmissive = m.is_transmissive();
    if transmissive {
        ior_controls(ui, m);
    }
    if matches!(
        m.kind,
        MaterialKind::GlossyMetal
            | MaterialKind::Glass
            | MaterialKind::ThinGlass
            | MaterialKind::MetalRough
    ) {
        roughness_controls(ui, m);
    }
    if transmissive {
        dispersion_controls(ui, m);
    }
    base_color_control(ui, m);
    if m.kind == MaterialKind::Glass {
        absorption_controls(ui, m);
    }
    super::film::film_controls(ui, m);
}

/// The material type: the four kinds a user picks from, plus thin glass and the glTF
/// metallic-roughness material when the material already is one.
fn kind_combo(ui: &mut egui::Ui, m: &mut Material) {
    egui::ComboBox::from_label("Type")
        .selected_text(kind_label(m.kind))
        .show_ui(ui, |ui| {
            let mut kinds = vec![
                MaterialKind::Diffuse,
                MaterialKind::Mirror,
                MaterialKind::GlossyMetal,
                MaterialKind::Glass,
            ];
            for k in [MaterialKind::ThinGlass, MaterialKind::MetalRough] {
                if m.kind == k {
                    kinds.push(k);
                }
            }
            for k in kinds {
                ui.selectable_value(&mut m.kind, k, kind_label(k))
                    .on_hover_text(kind_tip(k));
            }
        })
        .response
        .on_hover_text(kind_tip(m.kind));
}

/// After a change of kind from `before`: the glTF fields made consistent with the new kind
/// (the scene contract), so that an export reloads as the same material.
fn fit_fields_to_kind(m: &mut Material, before: MaterialKind) {
    match m.kind {
        MaterialKind::Diffuse => {
            m.metallic = 0.0;
            m.roughness = 1.0;
        }
        MaterialKind::Mirror => {
            m.metallic = 1.0;
            m.roughness = 0.0;
        }
        MaterialKind::GlossyMetal => {
            m.metallic = 1.0;
            if m.roughness <= 0.0 || m.roughness >= 1.0 {
                m.roughness = 0.3;
            }
        }
        MaterialKind::Glass | MaterialKind::ThinGlass => {
            m.metallic = 0.0;
            if before != MaterialKind::Glass && before != MaterialKind::ThinGlass {
                m.roughness = 0.0;
                m.base_color = glam::Vec3::ONE;
            }
        }
        MaterialKind::MetalRough => {}
    }
}

/// The base colour picker, its tooltip saying what the colour means for the kind; the value
/// kept finite and in [0, 1].
fn base_color_control(ui: &mut egui::Ui, m: &mut Material) {
    let mut c = m.base_color.to_array();
    let mut changed = false;
    ui.horizontal(|ui| {
        changed = ui.color_edit_button_rgb(&mut c).on_hover_text(match m.kind {
            MaterialKind::Diffuse => "Albedo: the fraction of light reflected at each wavelength band (linear RGB).",
            MaterialKind::Glass | MaterialKind::ThinGlass => "Transmission tint at the surface (white for clear glass; use absorption for coloured solids).",
            _ => "Reflectance: the fraction of light the surface reflects (linear RGB).",
        }).changed();
        ui.label("Base colour");
    });
    if changed && c.iter().all(|v| v.is_finite()) {
        m.base_color = glam::Vec3::from_array(c).clamp(glam::Vec3::ZERO, glam::Vec3::ONE);
    }
}

fn ior_controls(ui: &mut egui::Ui, m: &mut Material) {
    let mut ior = m.ior;
    let r = ui.add(
        Slider::new(&mut ior, IOR_RANGE)
            .text("IOR")
            .clamping(SliderClamping::Edits)
            .max_decimals(3),
    )
    .on_hover_text("Index of refraction n: light is c/n slower inside, so it bends by Snell's law n₁ sinθ₁ = n₂ sinθ₂.");
    // Only an edit is written back; the edit validates it once (`app::edit`, a typed "NaN"
    // is refused there with a message and never reaches a renderer).
    if r.changed() {
        m.ior = ior;
    }
    ui.horizontal_wrapped(|ui| {
        for (name, n) in IOR_PRESETS {
            if ui
                .small_button(*name)
                .on_hover_text(format!("n = {n}: {}", preset_tip(name)))
                .clicked()
            {
                m.ior = *n;
            }
        }
    });
}

fn preset_tip(name: &str) -> &'static str {
    match name {
        "vacuum" => "index-matched with the air around it, so the object becomes invisible.",
        "water" => "why a straw looks bent at the surface of a glass of water.",
        "ice" => "slightly lower than water, so ice refracts a little less.",
        "olive oil" => "close to glass: a glass rod in oil nearly disappears.",
        "crown glass" => "ordinary window and lens glass, low dispersion.",
        "flint glass" => "lead glass: higher index and stronger dispersion than crown glass.",
        "sapphire" => "a crystal with a high index, used for scratch-proof windows.",
        "diamond" => {
            "a very high index: a small critical angle traps light by total internal reflection."
        }
        _ => "",
    }
}

fn roughness_controls(ui: &mut egui::Ui, m: &mut Material) {
    let mut r = if m.roughness <= 0.0 {
        Rough::Smooth
    } else {
        match m.distribution {
            MicrofacetDistribution::Ggx => Rough::Ggx,
            MicrofacetDistribution::Beckmann => Rough::Beckmann,
        }
    };
    let before = r;
    ui.horizontal(|ui| {
        ui.label("Roughness type");
        ui.radio_value(&mut r, Rough::Smooth, "smooth")
            .on_hover_text("A perfectly flat interface: one reflected and one refracted direction (delta lobes).");
        ui.radio_value(&mut r, Rough::Ggx, "GGX")
            .on_hover_text("Trowbridge–Reitz microfacets: long tails, so highlights keep a soft glow.");
        ui.radio_value(&mut r, Rough::Beckmann, "Beckmann")
            .on_hover_text("Gaussian-like microfacet slopes: shorter tails than GGX at the same roughness.");
    });
    if r != before {
        match r {
            Rough::Smooth => m.roughness = 0.0,
            Rough::Ggx | Rough::Beckmann => {
                m.distribution = if r == Rough::Ggx {
                    MicrofacetDistribution::Ggx
                } else {
                    MicrofacetDistribution::Beckmann
                };
                if m.roughness <= 0.0 {
                    m.roughness = 0.2;
                }
            }
        }
    }
    if r != Rough::Smooth {
        let mut rough = m.roughness;
        let resp = ui.add(
            Slider::new(&mut rough, 0.01..=1.0)
                .text("Roughness")
                .clamping(SliderClamping::Edits),
        )
        .on_hover_text("Perceptual roughness r; the microfacet slope spread is α = r², so highlights blur as r grows.");
        if resp.changed() && rough.is_finite() {
            m.roughness = rough.clamp(0.0, 1.0);
        }
    }
}

fn dispersion_controls(ui: &mut egui::Ui, m: &mut Material) {
    let mut on = m.abbe.is_some();
    ui.checkbox(&mut on, "Dispersion")
        .on_hover_text("The index depends on wavelength, so white light splits into colours (rainbows, fire in diamonds).");
    if !on {
        m.abbe = None;
        return;
    }
    let Some(mut v) = m.abbe else {
        m.abbe = Some(40.0); // just switched on
        return;
    };
    let r = ui.add(
        Slider::new(&mut v, ABBE_RANGE)
            .text("Abbe number V_d")
            .clamping(SliderClamping::Edits)
            .logarithmic(true),
    )
    .on_hover_text("V_d = (n_d − 1)/(n_F − n_C): low values disperse strongly (flint ≈ 36), high values weakly (crown ≈ 59).");
    if r.changed() && v.is_finite() && v > 0.0 {
        m.abbe = Some(v);
    }
}

fn absorption_controls(ui: &mut egui::Ui, m: &mut Material) {
    let mut on = m.attenuation_distance.is_finite();
    ui.checkbox(&mut on, "Absorption")
        .on_hover_text("Beer–Lambert: light inside the solid decays as exp(−σ·d), so thick parts look more coloured.");
    if !on {
        m.attenuation_distance = f32::INFINITY;
        return;
    }
    let mut c = m.attenuation_color.to_array();
    let mut changed = false;
    ui.horizontal(|ui| {
        changed = ui
            .color_edit_button_rgb(&mut c)
            .on_hover_text(
                "The colour white light has after travelling the absorption distance inside.",
            )
            .changed();
        ui.label("Absorption colour");
    });
    if changed && c.iter().all(|v| v.is_finite()) {
        m.attenuation_color =
            glam::Vec3::from_array(c).clamp(glam::Vec3::splat(1e-4), glam::Vec3::ONE);
    }
    let mut d = if m.attenuation_distance.is_finite() {
        m.attenuation_distance
    } else {
        1.0
    };
    let r = ui
        .add(
            Slider::new(&mut d, 0.01..=100.0)
                .text("Distance (m)")
                .logarithmic(true)
                .clamping(SliderClamping::Edits),
        )
        .on_hover_text(
            "Path length inside after which light has the absorption colour; σ = −ln(colour)/distance.",
        );
    if (r.changed() || !m.attenuation_distance.is_finite()) && d.is_finite() && d > 0.0 {
        m.attenuation_distance = d;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn changed(mut m: Material, to: MaterialKind) -> Material {
        let before = m.kind;
        m.kind = to;
        fit_fields_to_kind(&mut m, before);
        m
    }

    #[test]
    fn a_change_of_kind_keeps_the_gltf_fields_consistent() {
        let rough_red = Material {
            kind: MaterialKind::Diffuse,
            base_color: glam::Vec3::new(0.8, 0.1, 0.1),
            roughness: 0.7,
            ..Material::default()
        };
        let glass = changed(rough_red.clone(), MaterialKind::Glass);
        assert_eq!((glass.metallic, glass.roughness), (0.0, 0.0));
        assert_eq!(
            glass.base_color,
            glam::Vec3::ONE,
            "clear glass from a diffuse"
        );
        // Glass to thin glass keeps the glass's own roughness and tint.
        let frosted = Material {
            roughness: 0.2,
            base_color: glam::Vec3::splat(0.9),
            ..glass
        };
        let thin = changed(frosted, MaterialKind::ThinGlass);
        assert_eq!(
            (thin.roughness, thin.base_color),
            (0.2, glam::Vec3::splat(0.9))
        );
        let mirror = changed(rough_red.clone(), MaterialKind::Mirror);
        assert_eq!((mirror.metallic, mirror.roughness), (1.0, 0.0));
        let metal = changed(mirror, MaterialKind::GlossyMetal);
        assert_eq!((metal.metallic, metal.roughness), (1.0, 0.3));
        let diffuse = changed(metal, MaterialKind::Diffuse);
        assert_eq!((diffuse.metallic, diffuse.roughness), (0.0, 1.0));
    }
}
