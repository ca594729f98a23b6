//! Smooth dielectric interface: exact Fresnel, Snell refraction, total internal reflection.

use super::Lobe;
use super::fresnel::{FresnelTerms, fresnel_dielectric_terms};
use super::fresnel_polarized::{MuellerLanes, all, dielectric_mueller};
use super::{BsdfSample, BxDF, Event, TransportMode};
use crate::math::Color;
use glam::Mat4;
use glam::{Vec2, Vec3};

/// Smooth dielectric boundary with relative IOR `eta` = n_inside / n_outside.
/// Reflect with probability F, refract with 1 − F (PBR 4th ed. §9.5.1, `DielectricBxDF`
/// specular case). Both lobes are delta; the sample weight is 1 for reflection and
/// 1/eta_rel² (radiance) or 1 (importance) for refraction. eta = 1 passes straight through.
#[derive(Clone, Copy, Debug)]
pub struct SmoothDielectric {
    pub eta: f32,
}

impl BxDF for SmoothDielectric {
    #[inline]
    fn can_transmit(&self) -> bool {
        true
    }

    /// Fresnel reflection or refraction at the normal; no interface at η = 1.
    fn mueller(&self, _wo: Vec3, wi: Vec3, event: Event, _lobe: Lobe) -> MuellerLanes {
        if self.eta == 1.0 {
            return all(Mat4::IDENTITY);
        }
        all(dielectric_mueller(wi.z, self.eta, event))
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
    fn sample(&self, wo: Vec3, uc: f32, _u2: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        if self.eta == 1.0 {
            return Some(BsdfSample::index_matched(wo));
        }
        let fr = fresnel_dielectric_terms(wo.z, self.eta);
        // TIR (F = 1) must reflect even for uc = 1.0 (the same sin²θt ≥ 1 test decides both).
        if uc < fr.f || fr.f >= 1.0 {
            // Specular reflection (includes TIR, where F = 1).
            return Some(BsdfSample::delta(
                Vec3::new(-wo.x, -wo.y, wo.z),
                Color::ONE,
                fr.f,
                Event::Reflect,
                1.0,
            ));
        }
        let (wi, scale) = refraction(wo, &fr, mode);
        Some(BsdfSample::delta(
            wi,
            Color::splat(scale),
            1.0 - fr.f,
            Event::Transmit,
            fr.eta_rel,
        ))
    }
}

/// The refracted direction of `wo` through a smooth interface whose Fresnel terms at wo's
/// cosine are `fr` (no TIR), and the crossing's radiance scale. Snell's law with the normal
/// flipped to the side of wo: wt = −wo/η' + (cosθi/η' − cosθt) n, PBR 4th ed. eq. (9.19);
/// radiance compresses by 1/η'² entering a denser medium, importance does not (Veach 1997,
/// §5.2). Shared with the filmed dielectric (`iridescent`).
#[inline]
pub(super) fn refraction(wo: Vec3, fr: &FresnelTerms, mode: TransportMode) -> (Vec3, f32) {
    let eta_rel = fr.eta_rel;
    let sign = wo.z.signum();
    let wi = Vec3::new(-wo.x / eta_rel, -wo.y / eta_rel, -sign * fr.cos_t).normalize();
    let scale = match mode {
        TransportMode::Radiance => 1.0 / (eta_rel * eta_rel),
        TransportMode::Importance => 1.0,
    };
    (wi, scale)
}
