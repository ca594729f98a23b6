//! Thin-walled dielectric: a glass sheet with two parallel interfaces and no bending.

use super::Lobe;
use super::fresnel::fresnel_dielectric;
use super::fresnel_polarized::{MuellerLanes, all, dielectric_mueller, transmission_mueller};
use super::{BsdfSample, BxDF, Event, TransportMode};
use crate::math::Color;
use crate::math::mueller::normalized;
use glam::{Mat4, Vec2, Vec3};

/// Reflectance R' of a thin sheet with two parallel smooth interfaces, summing every internal
/// bounce: R' = R + T²R/(1 − R²), T = 1 − R, where R is the exact dielectric Fresnel
/// reflectance of one interface (R = 1 under TIR stays 1).
/// PBR 4th ed. §9.5 (pbrt-v4 `ThinDielectricBxDF`); Mitsuba 3 `thindielectric`.
#[inline]
pub fn thin_dielectric_reflectance(abs_cos_i: f32, eta: f32) -> f32 {
    // Both faces see the same outside medium, so the Fresnel term uses |cos θ| and eta as is.
    let r = fresnel_dielectric(abs_cos_i.abs(), eta);
    if r >= 1.0 {
        return 1.0;
    }
    let t = 1.0 - r;
    // Geometric series of the inter-reflections: R + T²R Σ R^(2k). PBR 4th ed. §9.5.
    (r + t * t * r / (1.0 - r * r)).min(1.0)
}

/// A sheet's normalised Mueller matrix at the incidence cosine `c`: one interface's
/// reflection, or transmission through both interfaces (the inner reflections' polarisation
/// is neglected). Also the rough sheet's, at its facet (`bsdf::rough_thin`).
pub fn sheet_mueller(c: f32, eta: f32, event: Event) -> Mat4 {
    match event {
        Event::Reflect => dielectric_mueller(c, eta, event),
        Event::Transmit => {
            let t = transmission_mueller(c, eta);
            normalized(t * t)
        }
    }
}

/// Thin-walled dielectric sheet (glTF transmission without `KHR_materials_volume`).
/// Reflect with probability R' (weight 1), pass straight through (wi = −wo) with 1 − R'
/// (weight 1). The ray enters and leaves the sheet, so there is no η² radiance scaling in
/// either transport mode. Both lobes are delta and of Heckbert class S. Works for `wo` on
/// either side: the sheet is symmetric.
/// PBR 4th ed. §9.5 (pbrt-v4 `ThinDielectricBxDF`); Mitsuba 3 `thindielectric`.
#[derive(Clone, Copy, Debug)]
pub struct ThinDielectric {
    pub eta: f32,
}

impl ThinDielectric {
    /// R' for an incident direction `wo` (local frame, either side).
    #[inline]
    pub fn reflectance(&self, wo: Vec3) -> f32 {
        thin_dielectric_reflectance(wo.z.abs(), self.eta)
    }
}

impl BxDF for ThinDielectric {
    #[inline]
    fn can_transmit(&self) -> bool {
        true
    }

    /// One interface's reflection; transmission through both interfaces (the inner
    /// reflections' polarisation is neglected).
    fn mueller(&self, _wo: Vec3, wi: Vec3, event: Event, _lobe: Lobe) -> MuellerLanes {
        all(sheet_mueller(wi.z.abs(), self.eta, event))
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
    fn sample(&self, wo: Vec3, uc: f32, _u2: Vec2, _mode: TransportMode) -> Option<BsdfSample> {
        if wo.z == 0.0 || !wo.z.is_finite() {
            return None;
        }
        let r = self.reflectance(wo);
        // R' = 1 (TIR at the first face) must reflect even for uc = 1.0.
        if uc < r || r >= 1.0 {
            // Specular reflection about the normal. PBR 4th ed. §9.3.1.
            return Some(BsdfSample::delta(
                Vec3::new(-wo.x, -wo.y, wo.z),
                Color::ONE,
                r,
                Event::Reflect,
                1.0,
            ));
        }
        // Straight pass-through: the two refractions cancel. PBR 4th ed. §9.5.
        Some(BsdfSample::delta(
            -wo,
            Color::ONE,
            1.0 - r,
            Event::Transmit,
            1.0,
        ))
    }
}
