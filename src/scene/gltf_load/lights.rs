//! `KHR_lights_punctual` nodes → punctual lights.

use super::Loader;
use crate::scene::PunctualLight;
use glam::{Mat4, Vec3};
use gltf::json;
use gltf::json::validation::Checked;

impl Loader<'_> {
    pub(super) fn light_node(&mut self, ni: usize, li: usize, world: Mat4) {
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
            return;
        };
        use json::extensions::scene::khr_lights_punctual::Type as LT;
        let color = Vec3::from(light.color);
        let intensity = color * light.intensity;
        if !intensity.is_finite() || intensity.min_element() < 0.0 {
            self.warnings.push(format!(
                "light {li}: colour × intensity must be finite and non-negative; ignored"
            ));
            return;
        }
        if light.range.is_some() {
            self.warnings.once("light-range", || {
                "KHR_lights_punctual 'range' is ignored (lights fall off with inverse square)"
                    .into()
            });
        }
        let position = world.transform_point3(Vec3::ZERO);
        let direction = world.transform_vector3(Vec3::NEG_Z).normalize_or_zero();
        let needs_dir = !matches!(light.type_, Checked::Valid(LT::Point));
        if needs_dir && direction == Vec3::ZERO {
            self.warnings.push(format!(
                "light {li}: node {ni} has a degenerate rotation; ignored"
            ));
            return;
        }
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
                let outer = outer.clamp(0.0, std::f32::consts::FRAC_PI_2);
                let inner = inner.clamp(0.0, outer);
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
                return;
            }
        };
        self.lights.push(l);
    }
}
