//! The core glTF factors of a material: base colour, metallic and roughness, and emission
//! (`emissiveFactor` × `KHR_materials_emissive_strength`).

use super::clamp01;
use crate::gltf_io::load::Loader;
use glam::Vec3;
use gltf::json;

/// The largest emitted radiance a material may have (far above any real light; beyond ~1e36
/// the light distribution's power sums overflow f32).
const MAX_EMISSION: f32 = 1e20;

impl Loader<'_> {
    /// Base colour, metallic and roughness factors (invalid ones replaced, with a warning).
    pub(super) fn pbr_factors(
        &mut self,
        pbr: &json::material::PbrMetallicRoughness,
        name: &str,
    ) -> (Vec3, f32, f32) {
        let bc = pbr.base_color_factor.0;
        let mut base_color = Vec3::new(bc[0], bc[1], bc[2]);
        if !(base_color.is_finite() && base_color.min_element() >= 0.0) {
            self.warnings.push(format!(
                "material '{name}': invalid baseColorFactor; using white"
            ));
            base_color = Vec3::ONE;
        } else if base_color.max_element() > 1.0 {
            // An albedo above 1 reflects more light than arrives (glTF: factors in [0, 1]).
            self.warnings.push(format!(
                "material '{name}': baseColorFactor {base_color} has a component above 1 (an \
                 albedo above 1 creates energy); clamped to [0, 1]"
            ));
            base_color = base_color.min(Vec3::ONE);
        }
        let metallic = clamp01(
            pbr.metallic_factor.0,
            name,
            "metallicFactor",
            &mut self.warnings,
        );
        let roughness = clamp01(
            pbr.roughness_factor.0,
            name,
            "roughnessFactor",
            &mut self.warnings,
        );
        (base_color, metallic, roughness)
    }

    /// `emissiveFactor` × `KHR_materials_emissive_strength` (zero when invalid).
    pub(super) fn emission(
        &mut self,
        m: &json::Material,
        ext: Option<&json::extensions::material::Material>,
        name: &str,
        i: usize,
    ) -> anyhow::Result<Vec3> {
        let strength = ext
            .and_then(|e| e.emissive_strength.as_ref())
            .map(|s| s.emissive_strength.0)
            .unwrap_or(1.0);
        let mut emission = Vec3::from(m.emissive_factor.0) * strength;
        if !(emission.is_finite() && emission.min_element() >= 0.0) {
            self.warnings.push(format!(
                "material '{name}': emissiveFactor × emissiveStrength = {emission} is negative \
                 or not finite; emission ignored"
            ));
            emission = Vec3::ZERO;
        }
        // Radiance this large overflows f32 in the light's power (π·L·A) and the image: the
        // light would silently render black.
        anyhow::ensure!(
            emission.max_element() <= MAX_EMISSION,
            "material {i} ('{name}'): emission {} (/materials/{i}/emissiveFactor × \
             KHR_materials_emissive_strength) is above {MAX_EMISSION:e}, where f32 light \
             power overflows",
            emission.max_element()
        );
        Ok(emission)
    }
}
