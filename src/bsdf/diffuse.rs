//! Lambertian reflection.

use super::{BsdfSample, BxDF, Event, Lobe, TransportMode};
use crate::math::{Color, sampling};
use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

/// Lambert: f = ρ/π on the side of `wo`. Lambert 1760; PBR 4th ed. §9.2.
/// One-sided in the local frame: wo and wi must be in the same hemisphere (the integrator
/// flips the frame for double-sided materials).
#[derive(Clone, Copy, Debug)]
pub struct Lambert {
    pub albedo: Color,
}

impl BxDF for Lambert {
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
        sampling::cosine_hemisphere_pdf(wi.z)
    }

    /// Cosine-weighted sampling: weight = ρ. PBR 4th ed. §9.2.
    #[inline]
    fn sample(&self, wo: Vec3, _uc: f32, u2: Vec2, _mode: TransportMode) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let wi = sampling::cosine_hemisphere(u2);
        let pdf = sampling::cosine_hemisphere_pdf(wi.z);
        if pdf <= 0.0 {
            return None;
        }
        Some(BsdfSample::new(
            wi,
            self.albedo * FRAC_1_PI,
            self.albedo,
            pdf,
            Event::Reflect,
            Lobe::D,
            1.0,
        ))
    }
}
