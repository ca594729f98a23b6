//! Lambertian reflection.

use super::fresnel_polarized::{MuellerLanes, all};
use super::{BsdfSample, BxDF, Event, Lobe, TransportMode};
use crate::math::mueller::depolarizer;
use crate::math::{Color, sampling};
use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

/// Lambert: f = ρ/π on the side of `wo`. Lambert 1760; PBR 4th ed. §9.2.
/// One-sided in the local frame: wo and wi must be in the same hemisphere (the integrator
/// flips the frame for double-sided materials).
#[derive(Clone, Copy, Debug)]
pub struct Lambert {
    pub albedo: Color,
    /// Teaching switch (`Material::uniform_sampling`, the importance-sampling lecture demo):
    /// sample directions uniformly over the hemisphere (pdf 1/2π, weight 2ρ cosθ) instead of
    /// cosine-weighted. The same f, so the same image in the mean; only the variance differs.
    pub uniform: bool,
}

impl Lambert {
    /// Cosine-weighted Lambert (the default sampling).
    pub fn new(albedo: Color) -> Lambert {
        Lambert {
            albedo,
            uniform: false,
        }
    }

    fn sample_pdf(&self, cos_theta: f32) -> f32 {
        if self.uniform {
            sampling::UNIFORM_HEMISPHERE_PDF
        } else {
            sampling::cosine_hemisphere_pdf(cos_theta)
        }
    }
}

impl BxDF for Lambert {
    #[inline]
    fn can_transmit(&self) -> bool {
        false
    }

    /// The depolariser.
    fn mueller(&self, _wo: Vec3, _wi: Vec3, _event: Event, _lobe: Lobe) -> MuellerLanes {
        all(depolarizer())
    }

    #[inline]
    fn map_colors(self, f: impl Fn(Color) -> Color) -> Self {
        Lambert {
            albedo: f(self.albedo),
            ..self
        }
    }

    #[inline]
    fn eval(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> Color {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Color::ZERO;
        }
        self.albedo * FRAC_1_PI
    }

    #[inline]
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        self.sample_pdf(wi.z)
    }

    /// Cosine-weighted sampling: weight = ρ. PBR 4th ed. §9.2. Uniform (teaching): weight =
    /// f cosθ / (1/2π) = 2ρ cosθ, PBR 4th ed. §13.2 (the estimator with the poorer pdf).
    #[inline]
    fn sample(&self, wo: Vec3, _uc: f32, u2: Vec2, _mode: TransportMode) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let wi = if self.uniform {
            sampling::uniform_hemisphere(u2)
        } else {
            sampling::cosine_hemisphere(u2)
        };
        let pdf = self.sample_pdf(wi.z);
        if pdf <= 0.0 {
            return None;
        }
        let f = self.albedo * FRAC_1_PI;
        let weight = if self.uniform {
            f * (wi.z / pdf)
        } else {
            self.albedo
        };
        Some(BsdfSample::new(
            wi,
            f,
            weight,
            pdf,
            Event::Reflect,
            Lobe::D,
            1.0,
        ))
    }
}
