//! Rough dielectric interface: microfacet reflection and refraction
//! (Walter, Marschner, Li, Torrance 2007, "Microfacet Models for Refraction through Rough
//! Surfaces", EGSR).

use super::fresnel::{fresnel_dielectric, fresnel_dielectric_terms, reflect, refract};
use super::fresnel_polarized::{MuellerLanes, all, dielectric_mueller, half_vector};
use super::microfacet::Microfacet;
use super::{BsdfSample, BxDF, Event, Lobe, MicrofacetDistribution, TransportMode};
use crate::math::Color;
use crate::math::mueller::depolarizer;
use glam::Mat4;
use glam::{Vec2, Vec3};

/// Rough dielectric boundary with relative IOR `eta` = n_inside / n_outside (outside: z > 0).
///
/// - Exact unpolarised Fresnel at the microfacet, reflection/transmission chosen by F(wo·m);
///   total internal reflection on microfacets when coming from inside (relative IOR 1/eta).
/// - Height-correlated Smith G2, visible-normal sampling from the side `wo` is on.
/// - Radiance mode carries the 1/eta'² factor of refraction (eta' = n(wi side)/n(wo side)),
///   importance mode does not; then f_importance(wo, wi) = f_radiance(wi, wo) (Veach 1997
///   §5.3.2, adjoint BSDF).
/// - eta = 1 has no interface: `sample` passes straight through (a delta event), eval/pdf are 0.
#[derive(Clone, Copy, Debug)]
pub struct RoughDielectric {
    pub eta: f32,
    pub alpha: f32,
    pub dist: MicrofacetDistribution,
}

impl RoughDielectric {
    #[inline]
    fn mf(&self) -> Microfacet {
        Microfacet::new(self.dist, self.alpha)
    }

    /// f(wo, wi) and pdf(wo, wi) with the Fresnel term of `fresnel`, computed together so that
    /// `eval`, `pdf` and `sample` agree exactly. The scalar f is computed with the reflection
    /// probability P of `fresnel` in place of F, then multiplied by its lane factors (1 for
    /// the plain interface, whose f is the same in every channel).
    #[inline]
    pub(super) fn eval_pdf_with(
        &self,
        wo: Vec3,
        wi: Vec3,
        mode: TransportMode,
        fresnel: &impl FacetFresnel,
    ) -> (Color, f32) {
        let (cos_o, cos_i) = (wo.z, wi.z);
        if cos_o == 0.0 || cos_i == 0.0 || self.eta == 1.0 {
            return (Color::ZERO, 0.0);
        }
        let reflect = cos_o * cos_i > 0.0;
        let Some(m) = self.half_vector(wo, wi, reflect) else {
            return (Color::ZERO, 0.0);
        };
        let dot_o = wo.dot(m);
        let dot_i = wi.dot(m);
        // Back-facing microfacets contribute nothing: each direction must be on the same side of
        // m as of the macro normal (Walter 2007 §5, the χ⁺ terms of eqs. 20–21).
        if dot_o * cos_o <= 0.0 || dot_i * cos_i <= 0.0 {
            return (Color::ZERO, 0.0);
        }
        let mf = self.mf();
        let d = mf.d(m);
        if d <= 0.0 {
            return (Color::ZERO, 0.0);
        }
        // Visible normals of the side wo is on (wo mirrored to the upper hemisphere).
        let wo_up = if cos_o > 0.0 { wo } else { -wo };
        let cos_f = Self::facet_cosine(reflect, cos_o, (dot_o, dot_i));
        let facet = Facet {
            cos: (cos_o, cos_i),
            dot: (dot_o, dot_i),
            pdf_m: mf.pdf_visible(wo_up, m),
            g: mf.g2(wo, wi),
            d,
            fr: fresnel.select(cos_f),
        };
        let (f, pdf) = if reflect {
            facet.reflection()
        } else {
            self.transmission(&facet, mode)
        };
        (Color::splat(f) * fresnel.lanes(cos_f, reflect), pdf)
    }

    /// The microfacet normal of the pair (wo, wi): the generalised half vector
    /// m ∝ n_o wo + n_i wi, Walter 2007 eq. 16 (eq. 13 for reflection), face-forwarded to the
    /// outside (m.z > 0); `None` when it is degenerate. Built in a canonical order (outside
    /// direction + eta · inside direction) so that swapping wo and wi gives a bit-identical m:
    /// reciprocity then holds to rounding even at grazing microfacets.
    #[inline(always)]
    fn half_vector(&self, wo: Vec3, wi: Vec3, reflect: bool) -> Option<Vec3> {
        let h = if reflect {
            wo + wi
        } else if wo.z > 0.0 {
            wo + wi * self.eta
        } else {
            wi + wo * self.eta
        };
        let len2 = h.length_squared();
        if len2 <= 0.0 || !len2.is_finite() {
            return None;
        }
        let m = h / len2.sqrt();
        Some(if m.z < 0.0 { -m } else { m })
    }

    /// The cosine Fresnel is evaluated at, a symmetric argument: the mean cosine for
    /// reflection (wo·m = wi·m analytically) and the outside direction's cosine for
    /// transmission (T(θ_outside) = T(θ_inside) for a Snell pair), so f(wo, wi) and f(wi, wo)
    /// share it.
    #[inline(always)]
    fn facet_cosine(reflect: bool, cos_o: f32, (dot_o, dot_i): (f32, f32)) -> f32 {
        if reflect {
            0.5 * (dot_o + dot_i)
        } else if cos_o > 0.0 {
            dot_o
        } else {
            dot_i
        }
    }

    /// f and pdf of refraction through the facet (wo and wi on opposite sides).
    #[inline(always)]
    fn transmission(&self, facet: &Facet, mode: TransportMode) -> (f32, f32) {
        let Facet {
            cos: (cos_o, cos_i),
            dot: (dot_o, dot_i),
            pdf_m,
            g,
            d,
            fr,
        } = *facet;
        // eta' = n(wi side) / n(wo side).
        let etap = if cos_o > 0.0 {
            self.eta
        } else {
            1.0 / self.eta
        };
        // (wo·m + eta' wi·m)², from the canonical (outside + eta · inside) sum.
        let denom = if cos_o > 0.0 {
            dot_o + self.eta * dot_i
        } else {
            (dot_i + self.eta * dot_o) / self.eta
        };
        let denom2 = denom * denom;
        // f_t = |wi·m||wo·m| / (|wi·n||wo·n|) · n_o² (1 − F) G D / (n_i wi·m + n_o wo·m)²,
        // Walter 2007 eq. 21 (wo = Walter's o, wi = i), divided through by n_o².
        let f_rad = (dot_i * dot_o).abs() * (1.0 - fr) * g * d / ((cos_i * cos_o).abs() * denom2);
        // Radiance mode keeps the 1/eta'² (Walter's n_o²); importance mode removes it
        // (Veach 1997 §5.2, non-symmetric BSDF due to refraction).
        let f = match mode {
            TransportMode::Radiance => f_rad,
            TransportMode::Importance => f_rad * etap * etap,
        };
        // dω_m/dω_i = eta'² |wi·m| / (wo·m + eta' wi·m)², Walter 2007 eq. 17.
        let pdf = pdf_m * (1.0 - fr) * etap * etap * dot_i.abs() / denom2;
        (f, pdf)
    }
}

/// The Fresnel term at a microfacet as the rough dielectric uses it: the probability of
/// reflection P (which also weights the pdf) and, per colour lane, the factor that turns
/// f computed with P into f with the lane's own reflectance F_c: F_c/P for reflection and
/// (1 − F_c)/(1 − P) for transmission (a film's coloured Fresnel, `bsdf::iridescent`).
pub(super) trait FacetFresnel {
    /// P at the cosine `cos` (signed as `fresnel_dielectric`'s: negative from inside).
    fn select(&self, cos: f32) -> f32;
    /// The lane factors at `cos` for the event (reflection or transmission).
    fn lanes(&self, cos: f32, reflect: bool) -> Color;
}

/// The interface's own exact dielectric Fresnel term: the same in every lane.
struct PlainFresnel(f32);

impl FacetFresnel for PlainFresnel {
    #[inline(always)]
    fn select(&self, cos: f32) -> f32 {
        fresnel_dielectric(cos, self.0)
    }
    #[inline(always)]
    fn lanes(&self, _cos: f32, _reflect: bool) -> Color {
        Color::ONE
    }
}

/// What `eval_pdf_with` knows of one microfacet m between wo and wi.
#[derive(Clone, Copy)]
struct Facet {
    /// (wo·n, wi·n).
    cos: (f32, f32),
    /// (wo·m, wi·m).
    dot: (f32, f32),
    /// Density of m among the visible normals of wo's side.
    pdf_m: f32,
    /// Smith G2(wo, wi) and D(m).
    g: f32,
    d: f32,
    /// Fresnel reflectance at m.
    fr: f32,
}

impl Facet {
    /// f and pdf of reflection off the facet (wo and wi on the same side).
    #[inline(always)]
    fn reflection(&self) -> (f32, f32) {
        let ((cos_o, cos_i), (dot_o, _)) = (self.cos, self.dot);
        // f_r = F G D / (4 |wo·n| |wi·n|), Walter 2007 eq. 20.
        let f = self.fr * self.g * self.d / (4.0 * cos_o.abs() * cos_i.abs());
        // dω_m/dω_i = 1/(4 |wi·m|), Walter 2007 eq. 14 (|wi·m| = |wo·m| for reflection).
        let pdf = self.pdf_m * self.fr / (4.0 * dot_o.abs());
        (f, pdf)
    }
}

impl BxDF for RoughDielectric {
    #[inline]
    fn can_transmit(&self) -> bool {
        true
    }

    /// Fresnel reflection or refraction at the microfacet normal m, where wo, wi and m share
    /// the plane of incidence (Wilkie & Weidlich 2012, §5.3; Mitsuba 3's polarised
    /// `roughdielectric`); no interface at η = 1, the depolariser where m is degenerate.
    fn mueller(&self, wo: Vec3, wi: Vec3, event: Event, _lobe: Lobe) -> MuellerLanes {
        if self.eta == 1.0 {
            return all(Mat4::IDENTITY);
        }
        match half_vector(wo, wi, event, self.eta) {
            Some(m) => all(dielectric_mueller(wi.dot(m), self.eta, event)),
            None => all(depolarizer()),
        }
    }

    #[inline]
    fn distribution(&self) -> Option<MicrofacetDistribution> {
        Some(self.dist)
    }

    #[inline]
    fn eval(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> Color {
        self.eval_pdf_with(wo, wi, mode, &self.plain()).0
    }

    #[inline]
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.eval_pdf_with(wo, wi, TransportMode::Radiance, &self.plain())
            .1
    }

    #[inline]
    fn sample(&self, wo: Vec3, uc: f32, u2: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        self.sample_with(wo, uc, u2, mode, &self.plain())
    }
}

impl RoughDielectric {
    /// The interface's own Fresnel term.
    #[inline(always)]
    fn plain(&self) -> PlainFresnel {
        PlainFresnel(self.eta)
    }

    /// Sample a visible normal m from the side of `wo` (u2), then reflect with probability
    /// P(wo·m) of `fresnel` or refract (uc) (Walter 2007 §5.3; Heitz & d'Eon 2014 for
    /// visible normals).
    #[inline]
    pub(super) fn sample_with(
        &self,
        wo: Vec3,
        uc: f32,
        u2: Vec2,
        mode: TransportMode,
        fresnel: &impl FacetFresnel,
    ) -> Option<BsdfSample> {
        if wo.z == 0.0 || !wo.is_finite() {
            return None;
        }
        if self.eta == 1.0 {
            return Some(BsdfSample::index_matched(wo));
        }
        let side = wo.z.signum();
        let wo_up = wo * side;
        let m = self.mf().sample_visible(wo_up, u2);
        let dot_o = wo.dot(m);
        if dot_o * side <= 0.0 || m.z <= 0.0 {
            return None;
        }
        let fr = fresnel_dielectric_terms(dot_o, self.eta);
        // TIR (Snell's test, fr.f = 1) reflects whatever `fresnel` says.
        let p = if fr.f >= 1.0 {
            1.0
        } else {
            fresnel.select(dot_o)
        };
        let (wi, event, eta_rel) = if uc < p {
            // Microfacet mirror reflection (includes TIR where F = 1).
            (reflect(wo, m), Event::Reflect, 1.0)
        } else {
            // Snell refraction through the microfacet (normal on wo's side).
            let wi = refract(wo, m * side, fr.eta_rel)?;
            (wi.normalize(), Event::Transmit, fr.eta_rel)
        };
        let same_side = wi.z * wo.z > 0.0;
        if same_side != (event == Event::Reflect) || wi.z == 0.0 {
            return None;
        }
        let (f, pdf) = self.eval_pdf_with(wo, wi, mode, fresnel);
        if pdf.is_nan() || pdf <= 0.0 || !f.is_finite() || !pdf.is_finite() {
            return None;
        }
        Some(BsdfSample::new(
            wi,
            f,
            f * (wi.z.abs() / pdf),
            pdf,
            event,
            Lobe::G,
            eta_rel,
        ))
    }
}
