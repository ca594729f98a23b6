//! Rough thin-walled dielectric: a glass sheet with two rough interfaces and no average
//! bending (glTF transmission without `KHR_materials_volume`, roughness above the smooth
//! threshold: frosted glass, a matte plastic film).
//!
//! The model is glTF's own (KHR_materials_transmission, "Transmission BTDF"): the microfacet
//! distribution applies to both faces, uncorrelated, so each pair of facets is a small prism
//! that blurs what passes through; the transmission lobe is the reflection lobe mirrored
//! through the surface plane, with the half vector H_T = normalize(wo + wi'), wi' = wi
//! reflected through the plane (the extension's H_T = normalize(V − 2(N·L)N + L)). Each lobe
//! takes its share of the sheet's Fresnel sum at the facet, R' = R + T²R/(1 − R²) and
//! T' = 1 − R' (PBR 4th ed. §9.5, the smooth sheet's `thin_dielectric_reflectance`), so
//!   f_r(wo, wi) = R'(wo·m) D(m) G2(wo, wi)  / (4 |cos θo| |cos θi|),  m = normalize(wo + wi),
//!   f_t(wo, wi) = T'(wo·m) D(m) G2(wo, wi') / (4 |cos θo| |cos θi|),  m = normalize(wo + wi'),
//! (Walter et al. 2007 eq. 20; Heitz 2014 height-correlated G2). Both are symmetric in wo and
//! wi (|wo·m| = |wi'·m|, D and Λ depend on |z| only), so the BSDF is reciprocal; R' + T' = 1
//! and G2 ≤ G1 keep it energy-conserving. The sheet enters and leaves the same medium: no η²
//! scaling in either transport mode. Like the smooth sheet it works for `wo` on either side.

use super::fresnel::reflect;
use super::fresnel_polarized::{MuellerLanes, all, half_vector};
use super::microfacet::Microfacet;
use super::thin::{sheet_mueller, thin_dielectric_reflectance};
use super::{BsdfSample, BxDF, Event, Lobe, MicrofacetDistribution, TransportMode};
use crate::math::Color;
use glam::{Vec2, Vec3};

/// A sheet of relative index `eta` with rough faces (α, distribution).
#[derive(Clone, Copy, Debug)]
pub struct RoughThinDielectric {
    pub eta: f32,
    pub alpha: f32,
    pub dist: MicrofacetDistribution,
}

/// `w` mirrored through the surface plane (z → −z).
#[inline]
fn through_plane(w: Vec3) -> Vec3 {
    Vec3::new(w.x, w.y, -w.z)
}

impl RoughThinDielectric {
    #[inline]
    fn mf(&self) -> Microfacet {
        Microfacet::new(self.dist, self.alpha)
    }

    /// Scalar f and pdf of (wo, wi), shared by eval, pdf and sample so that they agree. The
    /// sheet is symmetric, so both directions are turned to put `wo` above it.
    fn eval_pdf(&self, wo: Vec3, wi: Vec3) -> (f32, f32) {
        if wo.z == 0.0 || wi.z == 0.0 || !wo.is_finite() || !wi.is_finite() {
            return (0.0, 0.0);
        }
        let (wo, wi) = if wo.z < 0.0 { (-wo, -wi) } else { (wo, wi) };
        let transmit = wi.z < 0.0;
        // The reflection lobe's direction: wi itself, or for transmission its mirror image.
        let wr = if transmit { through_plane(wi) } else { wi };
        let Some(m) = (wo + wr).try_normalize() else {
            return (0.0, 0.0);
        };
        let dot_o = wo.dot(m);
        if dot_o <= 0.0 {
            return (0.0, 0.0);
        }
        // wo·m = wr·m exactly; their mean is the same number, bit for bit, when wo and wi
        // trade places (R' is steep near the critical angle of η < 1: reciprocity to the
        // last bit needs it).
        let r = thin_dielectric_reflectance(0.5 * (dot_o + wr.dot(m)), self.eta);
        let share = if transmit { 1.0 - r } else { r };
        let mf = self.mf();
        // Walter 2007 eq. 20 with F = the lobe's share of the sheet's Fresnel sum.
        let f = share * mf.d(m) * mf.g2(wo, wr) / (4.0 * wo.z * wr.z);
        // The lobe's probability × visible-normal pdf × reflection Jacobian 1/(4 wo·m)
        // (Walter 2007 eq. 14; Heitz 2018).
        let pdf = share * mf.pdf_visible(wo, m) / (4.0 * dot_o);
        (f, pdf)
    }
}

impl BxDF for RoughThinDielectric {
    #[inline]
    fn eval(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> Color {
        Color::splat(self.eval_pdf(wo, wi).0)
    }

    #[inline]
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.eval_pdf(wo, wi).1
    }

    /// A visible normal m (Heitz 2018), then reflect about it with probability R'(wo·m),
    /// else the reflection mirrored through the plane; the weight is G2/G1(wo), computed as
    /// f·|cos θi|/pdf from the same numbers as `eval`.
    fn sample(&self, wo: Vec3, uc: f32, u2: Vec2, _mode: TransportMode) -> Option<BsdfSample> {
        if wo.z == 0.0 || !wo.is_finite() {
            return None;
        }
        let side = wo.z.signum();
        let wo_up = wo * side;
        let m = self.mf().sample_visible(wo_up, u2);
        let dot_o = wo_up.dot(m);
        if dot_o <= 0.0 {
            return None;
        }
        let wr = reflect(wo_up, m);
        if wr.z <= 0.0 {
            return None;
        }
        let r = thin_dielectric_reflectance(dot_o, self.eta);
        let (wi_up, event) = if uc < r || r >= 1.0 {
            (wr, Event::Reflect)
        } else {
            (through_plane(wr), Event::Transmit)
        };
        let (f, pdf) = self.eval_pdf(wo_up, wi_up);
        if pdf.is_nan() || pdf <= 0.0 || !f.is_finite() || !pdf.is_finite() {
            return None;
        }
        let wi = wi_up * side;
        let f = Color::splat(f);
        Some(BsdfSample::new(
            wi,
            f,
            f * (wi.z.abs() / pdf),
            pdf,
            event,
            Lobe::G,
            1.0,
        ))
    }

    #[inline]
    fn can_transmit(&self) -> bool {
        true
    }

    /// As the smooth sheet (one interface's reflection, transmission through both) at the
    /// facet's incidence cosine |wo·m|, m the reflection lobe's half vector; the rotation
    /// between the facet's plane of incidence and the plane of (wo, wi) for transmission is
    /// neglected (docs/polarization.md).
    fn mueller(&self, wo: Vec3, wi: Vec3, event: Event, _lobe: Lobe) -> MuellerLanes {
        let wr = if wo.z * wi.z < 0.0 {
            through_plane(wi)
        } else {
            wi
        };
        let Some(m) = half_vector(wo, wr, Event::Reflect, 1.0) else {
            return all(crate::math::mueller::depolarizer());
        };
        all(sheet_mueller(wo.dot(m).abs(), self.eta, event))
    }

    #[inline]
    fn distribution(&self) -> Option<MicrofacetDistribution> {
        Some(self.dist)
    }
}
