//! Conductors: the perfect mirror (delta lobe) with constant reflectance.

use super::Lobe;
use super::fresnel_polarized::{MuellerLanes, all, ideal_conductor_mueller};
use super::{BsdfSample, BxDF, Event, TransportMode};
use crate::math::Color;
use glam::{Vec2, Vec3};

/// Perfect mirror with constant reflectance R (no Fresnel tint, as the scene contract says).
/// f = R δ(wi − reflect(wo)) / |cos θi|; PBR 4th ed. §9.4 (specular reflection).
#[derive(Clone, Copy, Debug)]
pub struct Mirror {
    pub reflectance: Color,
}

impl BxDF for Mirror {
    #[inline]
    fn can_transmit(&self) -> bool {
        false
    }

    /// The ideal conductor (r_s = −1, r_p = 1); the tint is the scalar part.
    fn mueller(&self, _wo: Vec3, _wi: Vec3, _event: Event, _lobe: Lobe) -> MuellerLanes {
        all(ideal_conductor_mueller())
    }

    #[inline]
    fn map_colors(self, f: impl Fn(Color) -> Color) -> Self {
        Mirror {
            reflectance: f(self.reflectance),
        }
    }

    #[inline]
    fn eval(&self, _wo: Vec3, _wi: Vec3, _mode: TransportMode) -> Color {
        Color::ZERO
    }
    #[inline]
    fn pdf(&self, _wo: Vec3, _wi: Vec3) -> f32 {
        0.0
    }
    #[inline]
    fn sample(&self, wo: Vec3, _uc: f32, _u2: Vec2, _mode: TransportMode) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        Some(BsdfSample::delta(
            Vec3::new(-wo.x, -wo.y, wo.z),
            self.reflectance,
            1.0,
            Event::Reflect,
            1.0,
        ))
    }
}
