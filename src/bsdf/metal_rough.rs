//! The glTF 2.0 metallic-roughness BRDF (glTF 2.0 spec, appendix B "BRDF Implementation"),
//! with the dielectric F0/F90 of `KHR_materials_specular` and `KHR_materials_ior`.
//!
//! ```text
//! spec(α)    = D(h) G2(wo, wi) / (4 |n·wo| |n·wi|)                         (GGX, appendix B.3.2)
//! w          = (1 − |wo·h|)⁵                                               (Schlick 1994)
//! metal      = spec · (base + (1 − base) w)                                (appendix B.3.5)
//! Fd         = f0 + (1 − f0) w,  f0 = min(((ior−1)/(ior+1))² · specular_color, 1)
//! dielectric = Wd · base/π + s · Fd · spec,  s = specular_factor
//!                                                    (appendix B.3.5, KHR_materials_specular)
//! f          = mix(dielectric, metal, metallic)
//! ```
//! **Deviation from the spec (energy):** appendix B weights the Lambert term by
//! Wd = 1 − s·max(Fd(|wo·h|)). With h the half vector of (wo, wi) that weight is ≈ 1 − F0 for
//! most diffuse directions, while the specular layer reflects ≈ F(cosθo): the literal formula
//! reflects more than it receives (measured: directional albedo 1.151 ± 0.001 for a white
//! dielectric, roughness 0.05, cosθo = 0.3; 1.045 at roughness 0.5). We use the coupled,
//! reciprocal matte weight of Kelemen & Szirmay-Kalos 2001 ("A Microfacet Based Coupled
//! Specular-Matte BRDF Model with Importance Sampling", §3) with Schlick F standing in for the
//! specular albedo: Wd = (1 − s F(μo)) (1 − s F(μi)) / (1 − s F̄), F̄ = 2∫F(μ) μ dμ =
//! f0 + (1 − f0)/21 (F = max-channel Schlick). Its cosine-weighted integral over wi is exactly
//! 1 − s F(μo), the smooth-limit specular albedo, so the total stays ≤ 1 (checked by the energy
//! test for every wo) and the smooth limit is exact; at normal incidence Wd ≈ 1 − F0 like the
//! spec's.
//! Heckbert classes: the Lambert term is D, both specular terms are G ([`MetalRough::eval_lobes`]).
//!
//! Sampling picks the GGX visible-normal lobe with probability p_s(wo) (an estimate of the
//! specular share from Schlick at cosθo) or the cosine lobe otherwise; pdf = the mixture
//! (one-sample MIS, Veach 1997 §9.2.4). The returned class label k ∈ {D, G} is then chosen with
//! probability q_k = Σ f_k / (Σ f_D + Σ f_G) (sums over the colour lanes, at the sampled
//! direction), drawn from the remapped `uc`, and the sample reports f = f_k / q_k, weight =
//! f·|cosθi|/pdf. Hence E[weight · 1{lobe = k}] = ∫ pdf q_k f_k/q_k |cos|/pdf = ∫ f_k |cos| per
//! colour channel and class, and summed over the label E[weight] = ∫ f |cos|. When the lobes
//! have proportional colours (e.g. white base colour) f_k/q_k = f exactly.

use super::fresnel::reflect;
use super::fresnel_polarized::{
    MuellerLanes, all, dielectric_mueller, half_vector, ideal_conductor_mueller,
};
use super::microfacet::Microfacet;
use super::{BsdfSample, BxDF, Event, Lobe, LobeValues, MicrofacetDistribution, TransportMode};
use crate::math::mueller::depolarizer;
use crate::math::{Color, sampling};
use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

/// glTF metallic-roughness BRDF at a surface point (textures already applied).
/// One-sided like [`super::Lambert`]: wo and wi must both have z > 0.
#[derive(Clone, Copy, Debug)]
pub struct MetalRough {
    pub base_color: Color,
    /// In [0, 1].
    pub metallic: f32,
    /// GGX α = roughness² (callers clamp it to ≥ `SMOOTH_ALPHA`: no delta lobe here).
    pub alpha: f32,
    /// IOR of the dielectric (KHR_materials_ior, default 1.5 → F0 = 0.04).
    pub ior: f32,
    /// KHR_materials_specular `specularFactor` (default 1).
    pub specular_factor: f32,
    /// KHR_materials_specular `specularColorFactor` (default white).
    pub specular_color: Color,
}

/// Σ of the colour lanes (w is 0 for RGB inputs, or a real wavelength in spectral mode).
#[inline]
fn lane_sum(c: Color) -> f32 {
    c.x + c.y + c.z + c.w
}

/// Schlick weight (1 − c)⁵, Schlick 1994, "An Inexpensive BRDF Model", eq. 15.
#[inline]
fn schlick_weight(cos: f32) -> f32 {
    let m = (1.0 - cos.abs()).clamp(0.0, 1.0);
    let m2 = m * m;
    m2 * m2 * m
}

impl MetalRough {
    /// Defaults of the glTF spec for everything but base colour, metallic and α.
    pub fn new(base_color: Color, metallic: f32, alpha: f32) -> Self {
        MetalRough {
            base_color,
            metallic,
            alpha,
            ior: 1.5,
            specular_factor: 1.0,
            specular_color: Color::ONE,
        }
    }

    #[inline]
    fn mf(&self) -> Microfacet {
        Microfacet::new(MicrofacetDistribution::Ggx, self.alpha)
    }

    /// Dielectric F0 = min(((ior − 1)/(ior + 1))² · specular_color, 1), KHR_materials_specular
    /// (glTF spec appendix B.3.4 for the ior → F0 rule).
    #[inline]
    pub fn dielectric_f0(&self) -> Color {
        let r = (self.ior - 1.0) / (self.ior + 1.0);
        (self.specular_color * (r * r)).min(Color::ONE)
    }

    /// Schlick-Fresnel of the dielectric layer Fd = f0 + (1 − f0) w (per lane).
    #[inline]
    fn fresnel_dielectric_layer(&self, w: f32) -> Color {
        let f0 = self.dielectric_f0();
        f0 + (Color::ONE - f0) * w
    }

    /// 1 − s·F(μ) with the max-channel dielectric Schlick F (module docs).
    #[inline]
    fn matte_weight(&self, mu: f32) -> f32 {
        let f0 = self.dielectric_f0().max_element();
        let f = f0 + (1.0 - f0) * schlick_weight(mu);
        (1.0 - self.specular_factor * f).max(0.0)
    }

    /// 1 − s·F̄, F̄ = 2∫₀¹ F(μ) μ dμ = f0 + (1 − f0)/21 (2∫(1−μ)⁵μ dμ = 2·B(2, 6) = 1/21).
    #[inline]
    fn matte_norm(&self) -> f32 {
        let f0 = self.dielectric_f0().max_element();
        (1.0 - self.specular_factor * (f0 + (1.0 - f0) / 21.0)).max(1e-6)
    }

    /// Schlick-Fresnel of the metal, F0 = base colour (glTF appendix B.3.5 `conductor_fresnel`).
    #[inline]
    fn fresnel_metal(&self, w: f32) -> Color {
        self.base_color + (Color::ONE - self.base_color) * w
    }

    /// f split into the diffuse (D) and specular (G) Heckbert classes.
    #[inline]
    pub fn eval_lobes(&self, wo: Vec3, wi: Vec3) -> LobeValues {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return LobeValues::default();
        }
        let h = wo + wi;
        let len2 = h.length_squared();
        if len2 <= 0.0 {
            return LobeValues::default();
        }
        let h = h / len2.sqrt();
        let mf = self.mf();
        // Specular microfacet BRDF D G2/(4 cos cos), glTF appendix B.3.2 (height-correlated V).
        let spec = mf.d(h) * mf.g2(wo, wi) / (4.0 * wo.z * wi.z);
        let w = schlick_weight(wo.dot(h));
        let fd = self.fresnel_dielectric_layer(w);
        let s = self.specular_factor;
        let m = self.metallic;
        // Coupled matte weight (module docs; Kelemen & Szirmay-Kalos 2001 §3).
        let diffuse_weight = self.matte_weight(wo.z) * self.matte_weight(wi.z) / self.matte_norm();
        let d = self.base_color * ((1.0 - m) * diffuse_weight * FRAC_1_PI);
        let g = (self.fresnel_metal(w) * m + fd * ((1.0 - m) * s)) * spec;
        LobeValues { d, g }
    }

    /// Probability of sampling the specular lobe: the specular and diffuse shares estimated
    /// with Schlick at cosθo (glTF appendix B.3.5 weights), clamped to [0.1, 0.9] when both
    /// are present.
    #[inline]
    fn spec_probability(&self, wo: Vec3) -> f32 {
        let w = schlick_weight(wo.z);
        let fd = self.fresnel_dielectric_layer(w).max_element() * self.specular_factor;
        let m = self.metallic;
        let spec = m * self.fresnel_metal(w).max_element() + (1.0 - m) * fd;
        let diff = (1.0 - m) * (1.0 - fd).max(0.0) * self.base_color.max_element();
        if diff <= 0.0 {
            1.0
        } else if spec <= 0.0 {
            0.0
        } else {
            (spec / (spec + diff)).clamp(0.1, 0.9)
        }
    }

    /// Mixture pdf p_s · D_wo(h)/(4 wo·h) + (1 − p_s) · cosθi/π (Walter 2007 eq. 14;
    /// PBR 4th ed. §A.5.3).
    #[inline]
    fn pdf_inner(&self, wo: Vec3, wi: Vec3, p_spec: f32) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let h = wo + wi;
        let len2 = h.length_squared();
        let pdf_spec = if len2 > 0.0 {
            let h = h / len2.sqrt();
            let dot = wo.dot(h);
            if dot > 0.0 {
                self.mf().pdf_visible(wo, h) / (4.0 * dot)
            } else {
                0.0
            }
        } else {
            0.0
        };
        p_spec * pdf_spec + (1.0 - p_spec) * sampling::cosine_hemisphere_pdf(wi.z)
    }
}

impl BxDF for MetalRough {
    #[inline]
    fn can_transmit(&self) -> bool {
        false
    }

    /// The diffuse lobe depolarises. Schlick's F of the specular lobe has no phases: its
    /// polarisation is dielectric reflection at the material's IOR at the half vector,
    /// blended towards the ideal conductor by `metallic` (docs/polarization.md).
    fn mueller(&self, wo: Vec3, wi: Vec3, _event: Event, lobe: Lobe) -> MuellerLanes {
        match (lobe, half_vector(wo, wi, Event::Reflect, 1.0)) {
            (Lobe::G, Some(m)) => {
                let d = dielectric_mueller(wi.dot(m), self.ior, Event::Reflect);
                all(d * (1.0 - self.metallic) + ideal_conductor_mueller() * self.metallic)
            }
            _ => all(depolarizer()),
        }
    }

    #[inline]
    fn map_colors(self, f: impl Fn(Color) -> Color) -> Self {
        MetalRough {
            base_color: f(self.base_color),
            specular_color: f(self.specular_color),
            ..self
        }
    }

    /// Its specular lobe is GGX (glTF 2.0 appendix B).
    #[inline]
    fn distribution(&self) -> Option<MicrofacetDistribution> {
        Some(MicrofacetDistribution::Ggx)
    }

    #[inline]
    fn eval(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> Color {
        let l = self.eval_lobes(wo, wi);
        l.d + l.g
    }

    #[inline]
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.pdf_inner(wo, wi, self.spec_probability(wo))
    }

    /// See the module docs for the lobe choice and the stochastic class label.
    #[inline]
    fn sample(&self, wo: Vec3, uc: f32, u2: Vec2, _mode: TransportMode) -> Option<BsdfSample> {
        if wo.z <= 0.0 || !wo.is_finite() {
            return None;
        }
        let p_spec = self.spec_probability(wo);
        let (wi, u_label) = if uc < p_spec {
            let h = self.mf().sample_visible(wo, u2);
            if wo.dot(h) <= 0.0 {
                return None;
            }
            (reflect(wo, h), uc / p_spec)
        } else {
            (
                sampling::cosine_hemisphere(u2),
                (uc - p_spec) / (1.0 - p_spec),
            )
        };
        if wi.z <= 0.0 {
            return None;
        }
        let pdf = self.pdf_inner(wo, wi, p_spec);
        if pdf.is_nan() || pdf <= 0.0 || !pdf.is_finite() {
            return None;
        }
        let lobes = self.eval_lobes(wo, wi);
        let (sd, sg) = (lane_sum(lobes.d), lane_sum(lobes.g));
        // Class label with probability q_k ∝ Σ f_k; the reported f = f_k/q_k (module docs).
        let pick_g = if sd <= 0.0 {
            true
        } else if sg <= 0.0 {
            false
        } else {
            u_label * (sd + sg) < sg
        };
        let (f, lobe) = if pick_g {
            let q = if sg > 0.0 { sg / (sd + sg) } else { 1.0 };
            (lobes.g / q, Lobe::G)
        } else {
            (lobes.d * ((sd + sg) / sd), Lobe::D)
        };
        if !f.is_finite() {
            return None;
        }
        Some(BsdfSample::new(
            wi,
            f,
            f * (wi.z / pdf),
            pdf,
            Event::Reflect,
            lobe,
            1.0,
        ))
    }
}
