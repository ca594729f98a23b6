//! Glossy mirror: microfacet reflection with constant reflectance (the scene contract's
//! "metallic 1, roughness > 0" material; no Fresnel tint).

use super::fresnel::reflect;
use super::fresnel_polarized::{MuellerLanes, all, ideal_conductor_mueller};
use super::microfacet::Microfacet;
use super::{BsdfSample, BxDF, Event, Lobe, MicrofacetDistribution, TransportMode};
use crate::math::Color;
use glam::{Vec2, Vec3};

/// Rough conductor with constant reflectance R:
/// f = R D(m) G2(wo, wi) / (4 cosθo cosθi), m = normalize(wo + wi)
/// (Walter et al. 2007 eq. 20 with F ≡ R; Heitz 2014 height-correlated G2).
/// One-sided like [`super::Lambert`]: wo and wi must both have z > 0.
#[derive(Clone, Copy, Debug)]
pub struct RoughConductor {
    pub reflectance: Color,
    pub alpha: f32,
    pub dist: MicrofacetDistribution,
}

impl RoughConductor {
    #[inline]
    pub(super) fn mf(&self) -> Microfacet {
        Microfacet::new(self.dist, self.alpha)
    }

    /// Scalar D G2/(4 cos cos) and pdf, shared by eval/pdf/sample so they agree exactly.
    /// Also the lobe of [`super::RoughFresnelConductor`].
    #[inline]
    pub(super) fn eval_pdf(&self, wo: Vec3, wi: Vec3) -> (f32, f32) {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return (0.0, 0.0);
        }
        let h = wo + wi;
        let len2 = h.length_squared();
        if len2 <= 0.0 {
            return (0.0, 0.0);
        }
        let m = h / len2.sqrt();
        let dot_o = wo.dot(m);
        if dot_o <= 0.0 {
            return (0.0, 0.0);
        }
        let mf = self.mf();
        let d = mf.d(m);
        // Walter 2007 eq. 20 (F = 1 here; the reflectance multiplies outside).
        let f = d * mf.g2(wo, wi) / (4.0 * wo.z * wi.z);
        // Visible-normal pdf × reflection Jacobian 1/(4 wo·m), Walter 2007 eq. 14.
        let pdf = mf.pdf_visible(wo, m) / (4.0 * dot_o);
        (f, pdf)
    }
}

impl RoughConductor {
    /// The lobe's sample: a visible normal m (Heitz 2018), wo reflected about it, and the
    /// scalar D G2/(4 cos cos) and pdf there; None where wi leaves the upper hemisphere or
    /// the numbers are not finite. Shared by every reflecting microfacet lobe (this one, the
    /// tabulated metal's, a filmed metal's), which multiply their own F.
    #[inline]
    pub(super) fn sample_reflection(&self, wo: Vec3, u2: Vec2) -> Option<(Vec3, f32, f32)> {
        if wo.z <= 0.0 || !wo.is_finite() {
            return None;
        }
        let m = self.mf().sample_visible(wo, u2);
        if wo.dot(m) <= 0.0 {
            return None;
        }
        let wi = reflect(wo, m);
        if wi.z <= 0.0 {
            return None;
        }
        let (f, pdf) = self.eval_pdf(wo, wi);
        if pdf.is_nan() || pdf <= 0.0 || !f.is_finite() || !pdf.is_finite() {
            return None;
        }
        Some((wi, f, pdf))
    }
}

impl BxDF for RoughConductor {
    #[inline]
    fn can_transmit(&self) -> bool {
        false
    }

    /// The ideal conductor (r_s = −1, r_p = 1); the reflectance is the scalar part.
    fn mueller(&self, _wo: Vec3, _wi: Vec3, _event: Event, _lobe: Lobe) -> MuellerLanes {
        all(ideal_conductor_mueller())
    }

    #[inline]
    fn map_colors(self, f: impl Fn(Color) -> Color) -> Self {
        RoughConductor {
            reflectance: f(self.reflectance),
            ..self
        }
    }

    #[inline]
    fn distribution(&self) -> Option<MicrofacetDistribution> {
        Some(self.dist)
    }

    #[inline]
    fn eval(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> Color {
        self.reflectance * self.eval_pdf(wo, wi).0
    }

    #[inline]
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.eval_pdf(wo, wi).1
    }

    /// Visible-normal sampling + mirror reflection about m (Heitz 2018); the weight is
    /// R G2/G1(wo) analytically, computed here as f·cos/pdf from the same numbers.
    #[inline]
    fn sample(&self, wo: Vec3, _uc: f32, u2: Vec2, _mode: TransportMode) -> Option<BsdfSample> {
        let (wi, f, pdf) = self.sample_reflection(wo, u2)?;
        let f = self.reflectance * f;
        Some(BsdfSample::new(
            wi,
            f,
            f * (wi.z / pdf),
            pdf,
            Event::Reflect,
            Lobe::G,
            1.0,
        ))
    }
}
