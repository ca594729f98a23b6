//! Material overrides by index: [`MaterialEdit`] (its checks and how it is written into a
//! material) and [`apply_materials`], which applies a list of them to a scene.

use crate::bsdf::MicrofacetDistribution;
use crate::scene::{Material, MaterialKind, Scene};
use glam::Vec3;
use serde::{Deserialize, Serialize};

/// Overrides of one material's editable fields (emission is edited through [`LightEdit`](super::LightEdit)).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MaterialEdit {
    pub index: usize,
    /// The material's name when edited (a mismatch on apply gives a warning).
    pub name: String,
    pub kind: MaterialKind,
    pub base_color: [f32; 3],
    pub metallic: f32,
    pub roughness: f32,
    pub distribution: MicrofacetDistribution,
    pub ior: f32,
    /// Abbe number; None = no dispersion.
    pub abbe: Option<f32>,
    pub attenuation_color: [f32; 3],
    /// None = no absorption (infinite distance; JSON has no infinity).
    pub attenuation_distance: Option<f32>,
}

impl MaterialEdit {
    pub fn from_material(index: usize, m: &Material) -> MaterialEdit {
        MaterialEdit {
            index,
            name: m.name.clone(),
            kind: m.kind,
            base_color: m.base_color.to_array(),
            metallic: m.metallic,
            roughness: m.roughness,
            distribution: m.distribution,
            ior: m.ior,
            abbe: m.abbe,
            attenuation_color: m.attenuation_color.to_array(),
            attenuation_distance: m
                .attenuation_distance
                .is_finite()
                .then_some(m.attenuation_distance),
        }
    }

    /// Refuse values that break energy conservation or the arithmetic, naming the field:
    /// IOR finite in 1e-3..=1e3 (the bound keeps η and 1/η far from f32 overflow; any real
    /// material is 1..4), base and absorption colour components finite in 0..=1 (an albedo
    /// above 1 creates energy), metallic and roughness in 0..=1, a positive absorption
    /// distance and an Abbe number ≥ 1. `refract render --settings` calls it on every sidecar edit.
    pub fn check(&self) -> anyhow::Result<()> {
        use anyhow::ensure;
        let unit = |c: [f32; 3]| c.iter().all(|v| (0.0..=1.0).contains(v));
        ensure!(
            (1e-3..=1e3).contains(&self.ior),
            "ior {} is out of range (finite, 1e-3..=1e3)",
            self.ior
        );
        ensure!(
            unit(self.base_color),
            "base_color {:?} is out of range (each component in 0..=1: an albedo above 1 \
             creates energy)",
            self.base_color
        );
        ensure!(
            unit(self.attenuation_color),
            "attenuation_color {:?} is out of range (each component in 0..=1)",
            self.attenuation_color
        );
        for (key, v) in [("metallic", self.metallic), ("roughness", self.roughness)] {
            ensure!(
                (0.0..=1.0).contains(&v),
                "{key} {v} is out of range (0..=1)"
            );
        }
        if let Some(v) = self.attenuation_distance {
            ensure!(
                v.is_finite() && v > 0.0,
                "attenuation_distance {v} must be finite and > 0"
            );
        }
        if let Some(v) = self.abbe {
            // As the glTF loader clamps dispersion: V_d ≥ 1 keeps the Cauchy fit positive.
            ensure!(v.is_finite() && v >= 1.0, "abbe {v} must be finite and ≥ 1");
        }
        Ok(())
    }

    /// Write the overrides into `m` (emission and textures are left alone).
    pub fn apply_to(&self, m: &mut Material) {
        m.kind = self.kind;
        m.base_color = Vec3::from_array(self.base_color);
        m.metallic = self.metallic;
        m.roughness = self.roughness;
        m.distribution = self.distribution;
        m.ior = self.ior;
        m.abbe = self.abbe;
        m.attenuation_color = Vec3::from_array(self.attenuation_color);
        m.attenuation_distance = self.attenuation_distance.unwrap_or(f32::INFINITY);
    }
}

/// Write material overrides into `scene`; an edit that does not fit (no such material, a
/// value [`MaterialEdit::check`] refuses, or an invalid result) is skipped with a warning.
pub fn apply_materials(edits: &[MaterialEdit], scene: &mut Scene, warnings: &mut Vec<String>) {
    for e in edits {
        match scene.materials.get_mut(e.index) {
            Some(m) => {
                if m.name != e.name {
                    warnings.push(format!(
                        "material {} is '{}' here but '{}' in the settings; applied anyway",
                        e.index, m.name, e.name
                    ));
                }
                if let Err(err) = e.check() {
                    warnings.push(format!("material edit {} skipped: {err}", e.index));
                    continue;
                }
                let before = m.clone();
                e.apply_to(m);
                if let Err(err) = m.validate() {
                    warnings.push(format!("material edit skipped: {err}"));
                    *m = before;
                }
            }
            None => warnings.push(format!(
                "the scene has no material {} ('{}'); edit skipped",
                e.index, e.name
            )),
        }
    }
}
