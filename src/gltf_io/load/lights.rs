//! `KHR_lights_punctual` nodes → punctual lights.

use super::Loader;
use crate::scene::PunctualLight;
use glam::{Mat4, Vec3};
use gltf::json::extensions::scene::khr_lights_punctual::{Light, Type as LT};
use gltf::json::validation::Checked;

impl Loader<'_> {
    /// The light `li` on node `ni`: invalid values are skipped with a warning, except an
    /// intensity that overflows f32 (an error, as an overflowing emissive material is).
    pub(super) fn light_node(&mut self, ni: usize, li: usize, world: Mat4) -> anyhow::Result<()> {
        let light = self
            .root
            .extensions
            .as_ref()
            .and_then(|e| e.khr_lights_punctual.as_ref())
            .and_then(|l| l.lights.get(li));
        let Some(light) = light else {
            self.warnings.push(format!(
                "node {ni}: KHR_lights_punctual light {li} does not exist (index out of range)"
            ));
            return Ok(());
        };
        let Some(intensity) = self.light_intensity(li, light)? else {
            return Ok(());
        };
        if light.range.is_some() {
            self.warnings.once("light-range", || {
                "KHR_lights_punctual 'range' is ignored (lights fall off with inverse square)"
                    .into()
            });
        }
        let Some((position, direction)) = self.light_placement(ni, li, light, world) else {
            return Ok(());
        };
        if let Some(l) = self.punctual_light(li, light, position, direction, intensity) {
            self.lights.push(l);
        }
        Ok(())
    }

    /// Colour × intensity of light `li`: an error when it overflows f32 light power, None
    /// (with a warning) when it is not finite and non-negative.
    fn light_intensity(&mut self, li: usize, light: &Light) -> anyhow::Result<Option<Vec3>> {
        let color = Vec3::from(light.color);
        let intensity = color * light.intensity;
        // As for emissive materials: beyond 1e20 the light's power (4π·I) overflows f32.
        anyhow::ensure!(
            !intensity.to_array().iter().any(|c| c.abs() > 1e20),
            "light {li} (/extensions/KHR_lights_punctual/lights/{li}): colour × intensity \
             is above 1e20, where f32 light power overflows (intensity {}, colour {color})",
            light.intensity
        );
        if !intensity.is_finite() || intensity.min_element() < 0.0 {
            self.warnings.push(format!(
                "light {li}: colour × intensity must be finite and non-negative; ignored"
            ));
            return Ok(None);
        }
        Ok(Some(intensity))
    }

    /// The world position and direction (−Z) of light `li` on node `ni`; None (with a
    /// warning) when a light that needs a direction has a degenerate one.
    fn light_placement(
        &mut self,
        ni: usize,
        li: usize,
        light: &Light,
        world: Mat4,
    ) -> Option<(Vec3, Vec3)> {
        let position = world.transform_point3(Vec3::ZERO);
        let direction = world.transform_vector3(Vec3::NEG_Z).normalize_or_zero();
        let needs_dir = !matches!(light.type_, Checked::Valid(LT::Point));
        if needs_dir && direction == Vec3::ZERO {
            self.warnings.push(format!(
                "light {li}: node {ni} has a degenerate rotation; ignored"
            ));
            return None;
        }
        Some((position, direction))
    }

    /// The scene light for glTF light `li` of its type; None (with a warning) for an unknown
    /// type.
    fn punctual_light(
        &mut self,
        li: usize,
        light: &Light,
        position: Vec3,
        direction: Vec3,
        intensity: Vec3,
    ) -> Option<PunctualLight> {
        let l = match light.type_ {
            Checked::Valid(LT::Point) => PunctualLight::Point {
                position,
                intensity,
            },
            Checked::Valid(LT::Directional) => PunctualLight::Directional {
                direction,
                irradiance: intensity,
            },
            Checked::Valid(LT::Spot) => {
                let (inner, outer) = light
                    .spot
                    .as_ref()
                    .map(|s| (s.inner_cone_angle, s.outer_cone_angle))
                    .unwrap_or((0.0, std::f32::consts::FRAC_PI_4));
                let (inner, outer) = self.spot_cone(li, inner, outer);
                PunctualLight::Spot {
                    position,
                    direction,
                    intensity,
                    cos_inner: inner.cos(),
                    cos_outer: outer.cos(),
                }
            }
            Checked::Invalid => {
                self.warnings
                    .push(format!("light {li}: unknown light type; ignored"));
                return None;
            }
        };
        Some(l)
    }

    /// KHR_lights_punctual: 0 ≤ innerConeAngle < outerConeAngle ≤ π/2; anything else is
    /// clamped into that order with a warning.
    fn spot_cone(&mut self, li: usize, inner: f32, outer: f32) -> (f32, f32) {
        let half_pi = std::f32::consts::FRAC_PI_2;
        let o = if outer.is_nan() {
            half_pi / 2.0
        } else {
            outer.clamp(0.0, half_pi)
        };
        let i = if inner.is_nan() {
            0.0
        } else {
            inner.clamp(0.0, o)
        };
        if (i, o) != (inner, outer) || inner >= outer {
            self.warnings.push(format!(
                "light {li}: spot cone angles inner {inner}, outer {outer} are not \
                 0 ≤ inner < outer ≤ π/2; using inner {i}, outer {o}"
            ));
        }
        (i, o)
    }
}
