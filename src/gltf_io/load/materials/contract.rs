//! The scene contract's material kind decision and its rules on a converted material.

use crate::gltf_io::load::{GLASS_TRANSMISSION_THRESHOLD, Loader};
use crate::scene::{Material, MaterialKind};
use glam::Vec3;

impl Loader<'_> {
    /// The contract's material kind from transmission, volume thickness and the
    /// metallic-roughness factors or texture.
    pub(super) fn material_kind(
        &mut self,
        name: &str,
        transmission: f32,
        thickness: f32,
        (metallic, roughness): (f32, f32),
        has_mr_tex: bool,
    ) -> MaterialKind {
        let eps = 1e-6;
        if transmission >= GLASS_TRANSMISSION_THRESHOLD {
            if thickness > 0.0 {
                MaterialKind::Glass
            } else {
                self.warnings.once("thin-glass", || {
                    format!(
                        "material '{name}' is thin-walled glass (transmission without KHR_materials_volume, as Blender exports glass): rendered as a thin sheet; switch it to solid glass in the viewer if the object is a solid"
                    )
                });
                MaterialKind::ThinGlass
            }
        } else {
            if transmission > 0.0 {
                self.warnings.push(format!(
                    "material '{name}': partial transmission {transmission} (< {GLASS_TRANSMISSION_THRESHOLD}) is ignored; treated as opaque"
                ));
            }
            if has_mr_tex {
                MaterialKind::MetalRough
            } else if (metallic - 1.0).abs() <= eps && roughness <= eps {
                MaterialKind::Mirror
            } else if (metallic - 1.0).abs() <= eps {
                MaterialKind::GlossyMetal
            } else if metallic <= eps && (roughness - 1.0).abs() <= eps && transmission == 0.0 {
                MaterialKind::Diffuse
            } else {
                MaterialKind::MetalRough
            }
        }
    }
}

/// The scene contract's rules on a converted material: `extras.conductor` needs a metal (an
/// error naming the material); an emitter's surface is otherwise black (its textures
/// dropped).
pub(super) fn enforce_contract(mat: &mut Material) -> anyhow::Result<()> {
    if mat.conductor.is_some() && !mat.is_metal_kind() {
        anyhow::bail!(
            "material '{}': extras.conductor needs a metallic material (metallicFactor 1, no metallic-roughness texture, no transmission)",
            mat.name
        );
    }
    if mat.is_emissive() {
        mat.kind = MaterialKind::Diffuse;
        mat.base_color = Vec3::ZERO;
        mat.base_color_texture = None;
        mat.metallic_roughness_texture = None;
        mat.normal_texture = None;
        mat.transmission_texture = None;
    }
    Ok(())
}
