//! Material presets shared by the built-in scenes.

use crate::scene::{Material, MaterialKind};
use glam::Vec3;

/// Rough dielectric (solid, GGX).
pub fn rough_glass_material(name: &str, ior: f32, roughness: f32) -> Material {
    Material {
        roughness,
        ..Material::glass(name, ior)
    }
}

/// Glossy metal: microfacet reflection with reflectance `color`, α = roughness².
pub fn glossy_metal(name: &str, color: Vec3, roughness: f32) -> Material {
    Material {
        name: name.into(),
        kind: MaterialKind::GlossyMetal,
        base_color: color,
        metallic: 1.0,
        roughness,
        ..Default::default()
    }
}

/// glTF metallic-roughness dielectric ("plastic"): metallic 0.
pub fn plastic(name: &str, color: Vec3, roughness: f32) -> Material {
    Material {
        name: name.into(),
        kind: MaterialKind::MetalRough,
        base_color: color,
        metallic: 0.0,
        roughness,
        ..Default::default()
    }
}
