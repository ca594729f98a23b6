//! A thin film on a dielectric or a metal, smooth or rough (glTF `KHR_materials_iridescence`):
//! the base BSDF with its Fresnel term replaced by the film's reflectance
//! (Belcour & Barla 2017, "A Practical Extension to Microfacet Theory for the Modeling of
//! Varying Iridescence", §3: the film changes F only — D, G and the sampling stay).
//!
//! The film's reflectance is coloured, so where the base picks reflection or transmission by F
//! (dielectrics) it now picks by the mean over the path's lanes P, and each lane is weighted by
//! F_c/P or (1 − F_c)/(1 − P): unbiased per lane, R_c + T_c = 1 per lane (no absorption in the
//! film). Spectral paths evaluate the exact Airy reflectance at their four wavelengths, RGB paths
//! Belcour & Barla's analytic integral ([`ThinFilm::rgb`]).
//!
//! Approximations (glTF's, stated): the film's index is relative to the outside medium (exact
//! in air); a thin-walled sheet has the film on both faces (a sheet of index 1 is a free-standing
//! film: a soap bubble); a metal of the scene contract (reflectance = base colour F₀) becomes a
//! substrate of real index η = (1 + √F₀)/(1 − √F₀) under the film, as the glTF extension's
//! reference implementation does; `factor` blends the base's own Fresnel term and the film's.

use super::fresnel::{fresnel_dielectric, fresnel_dielectric_terms};
use super::fresnel_polarized::MuellerLanes;
use super::rough_dielectric::FacetFresnel;
use super::thin_film::ThinFilm;
use super::{
    Bsdf, BsdfSample, BxDF, ComplexIor, Event, Lobe, MicrofacetDistribution, RoughConductor,
    RoughDielectric, RoughFresnelConductor, SmoothConductor, SmoothDielectric, ThinDielectric,
    TransportMode, effectively_smooth,
};
use crate::math::Color;
use crate::math::complex::Complex;
use glam::{Vec2, Vec3};

/// What the film lies on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FilmBase {
    /// A solid dielectric of relative index `eta` (inside / outside).
    Dielectric { eta: f32 },
    /// A thin-walled sheet of index `eta` (no bending); 1 is a free-standing film.
    Sheet { eta: f32 },
    /// A conductor of complex index per lane; `tint` (the base colour) multiplies.
    Conductor { ior: ComplexIor, tint: Color },
    /// A metal of the scene contract: reflectance F₀ per lane.
    Reflectance { f0: Color },
}

/// A base BSDF under a thin film.
#[derive(Clone, Copy, Debug)]
pub struct Iridescent {
    pub film: ThinFilm,
    /// glTF `iridescenceFactor` ∈ [0, 1]: F = F_base + factor · (F_film − F_base).
    pub factor: f32,
    pub base: FilmBase,
    /// Microfacet α (below `SMOOTH_ALPHA`: a smooth, delta interface) and distribution.
    pub alpha: f32,
    pub dist: MicrofacetDistribution,
    /// The path's four wavelengths (spectral), or `None` (RGB).
    pub lambdas: Option<[f32; 4]>,
}

/// The largest F₀ turned into an index (F₀ = 1 would be an infinite one).
pub const MAX_F0: f32 = 0.999;

impl Iridescent {
    /// `base` under `film`: the dielectrics and metals take the film, the other BSDFs (Lambert,
    /// glTF metal-rough) stay as they are.
    pub fn over(base: Bsdf, film: ThinFilm, factor: f32) -> Bsdf {
        let (base, alpha, dist) = match base {
            Bsdf::SmoothDielectric(b) => (FilmBase::Dielectric { eta: b.eta }, 0.0, <_>::default()),
            Bsdf::RoughDielectric(b) => (FilmBase::Dielectric { eta: b.eta }, b.alpha, b.dist),
            Bsdf::ThinDielectric(b) => (FilmBase::Sheet { eta: b.eta }, 0.0, <_>::default()),
            Bsdf::Mirror(b) => (
                FilmBase::Reflectance { f0: b.reflectance },
                0.0,
                <_>::default(),
            ),
            Bsdf::RoughConductor(b) => {
                (FilmBase::Reflectance { f0: b.reflectance }, b.alpha, b.dist)
            }
            Bsdf::SmoothConductor(b) => {
                let base = FilmBase::Conductor {
                    ior: b.ior,
                    tint: b.tint,
                };
                (base, 0.0, <_>::default())
            }
            Bsdf::RoughFresnelConductor(b) => {
                let base = FilmBase::Conductor {
                    ior: b.ior,
                    tint: b.lobe.reflectance,
                };
                (base, b.lobe.alpha, b.lobe.dist)
            }
            other => return other,
        };
        Bsdf::Iridescent(Iridescent {
            film,
            factor: factor.clamp(0.0, 1.0),
            base,
            alpha,
            dist,
            lambdas: None,
        })
    }

    #[inline]
    pub fn is_smooth(&self) -> bool {
        effectively_smooth(self.alpha)
    }

    /// Lanes in use: four wavelengths, or R, G, B.
    #[inline]
    fn lanes(&self) -> usize {
        if self.lambdas.is_some() { 4 } else { 3 }
    }

    /// The mean over the lanes in use (the probability a coloured F selects with).
    #[inline]
    fn mean(&self, c: Color) -> f32 {
        let n = self.lanes();
        c.to_array()[..n].iter().sum::<f32>() / n as f32
    }

    /// The substrate's complex index in lane `i`.
    #[inline]
    fn substrate(&self, i: usize) -> Complex {
        match self.base {
            FilmBase::Dielectric { eta } | FilmBase::Sheet { eta } => Complex::real(eta),
            FilmBase::Conductor { ior, .. } => Complex::new(ior.eta[i], ior.k[i]),
            FilmBase::Reflectance { f0 } => {
                let s = f0[i].clamp(0.0, MAX_F0).sqrt();
                Complex::real((1.0 + s) / (1.0 - s))
            }
        }
    }

    /// The base's own Fresnel term at the outside cosine `cos1` (what `factor` < 1 keeps).
    #[inline]
    fn base_fresnel(&self, cos1: f32) -> Color {
        match self.base {
            FilmBase::Dielectric { eta } | FilmBase::Sheet { eta } => {
                Color::splat(fresnel_dielectric(cos1, eta))
            }
            FilmBase::Conductor { ior, .. } => ior.fresnel(cos1),
            FilmBase::Reflectance { f0 } => f0,
        }
    }

    /// The film's reflectance per lane at the outside incidence cosine `cos1` ∈ [0, 1],
    /// blended with the base's by `factor`. Lanes not in use (w in RGB) are 0.
    pub fn reflectance(&self, cos1: f32) -> Color {
        let mut r = [0.0f32; 4];
        match self.lambdas {
            Some(l) => {
                for (i, ri) in r.iter_mut().enumerate() {
                    *ri = self.film.airy(cos1, self.substrate(i), l[i]);
                }
            }
            None if matches!(
                self.base,
                FilmBase::Dielectric { .. } | FilmBase::Sheet { .. }
            ) =>
            {
                r[..3].copy_from_slice(&self.film.rgb(cos1, self.substrate(0)).to_array());
            }
            None => {
                for (i, ri) in r.iter_mut().enumerate().take(3) {
                    *ri = self.film.rgb(cos1, self.substrate(i))[i];
                }
            }
        }
        let film = Color::from_array(r);
        let base = self.base_fresnel(cos1);
        base + (film - base) * self.factor
    }

    /// The reflectance seen from the side of the signed cosine `cos` of a dielectric base:
    /// from inside, at the outside cosine of the Snell pair (a lossless stack reflects the same
    /// from both sides); 1 under total internal reflection.
    fn reflectance_signed(&self, cos: f32, eta: f32) -> Color {
        if cos >= 0.0 {
            return self.reflectance(cos.min(1.0));
        }
        let sin2_out = (1.0 - cos * cos).max(0.0) * eta * eta;
        if sin2_out >= 1.0 {
            return Color::ONE;
        }
        self.reflectance((1.0 - sin2_out).sqrt())
    }

    /// A sheet's reflectance: the free-standing film for index 1, else both faces filmed with
    /// every inter-reflection summed, R' = R + T²R/(1 − R²) (as `thin::ThinDielectric`).
    fn sheet_reflectance(&self, cos: f32, eta: f32) -> Color {
        let r = self.reflectance(cos.abs().min(1.0));
        if eta == 1.0 {
            return r;
        }
        let t = Color::ONE - r;
        let denom = (Color::ONE - r * r).max(Color::splat(1e-7));
        (r + t * t * r / denom).min(Color::ONE)
    }

    /// The reflection weight tint (a conductor's base colour; 1 otherwise).
    #[inline]
    fn tint(&self) -> Color {
        match self.base {
            FilmBase::Conductor { tint, .. } => tint,
            _ => Color::ONE,
        }
    }

    fn rough_dielectric(&self, eta: f32) -> RoughDielectric {
        RoughDielectric {
            eta,
            alpha: self.alpha,
            dist: self.dist,
        }
    }

    fn rough_lobe(&self) -> RoughConductor {
        RoughConductor {
            reflectance: Color::ONE,
            alpha: self.alpha,
            dist: self.dist,
        }
    }
}

/// The film as the rough dielectric's Fresnel term (`rough_dielectric::FacetFresnel`).
struct FilmFresnel<'a>(&'a Iridescent, f32);

impl FacetFresnel for FilmFresnel<'_> {
    #[inline]
    fn select(&self, cos: f32) -> f32 {
        self.0.mean(self.0.reflectance_signed(cos, self.1))
    }
    #[inline]
    fn lanes(&self, cos: f32, reflect: bool) -> Color {
        let r = self.0.reflectance_signed(cos, self.1);
        let p = self.0.mean(r);
        if reflect {
            if p > 0.0 { r / p } else { Color::ZERO }
        } else if p < 1.0 {
            (Color::ONE - r) / (1.0 - p)
        } else {
            Color::ZERO
        }
    }
}

impl BxDF for Iridescent {
    #[inline]
    fn can_transmit(&self) -> bool {
        matches!(
            self.base,
            FilmBase::Dielectric { .. } | FilmBase::Sheet { .. }
        )
    }

    /// Its base's matrix ([`film_base`]).
    fn mueller(&self, wo: Vec3, wi: Vec3, event: Event, lobe: Lobe) -> MuellerLanes {
        film_base(self).mueller(wo, wi, event, lobe)
    }

    /// Colours to the path's lanes.
    fn map_colors(self, f: impl Fn(Color) -> Color) -> Self {
        let base = match self.base {
            FilmBase::Conductor { ior, tint } => FilmBase::Conductor { ior, tint: f(tint) },
            FilmBase::Reflectance { f0 } => FilmBase::Reflectance { f0: f(f0) },
            other => other,
        };
        Iridescent { base, ..self }
    }

    /// The path's wavelengths: exact Airy per lane, a tabulated metal's η, k at them.
    fn at_wavelengths(self, lambdas: [f32; 4]) -> Self {
        let base = match self.base {
            FilmBase::Conductor { ior, tint } => FilmBase::Conductor {
                ior: ior.at_wavelengths(lambdas),
                tint,
            },
            other => other,
        };
        Iridescent {
            base,
            lambdas: Some(lambdas),
            ..self
        }
    }

    #[inline]
    fn distribution(&self) -> Option<MicrofacetDistribution> {
        (!self.is_smooth()).then_some(self.dist)
    }

    fn eval(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> Color {
        if self.is_smooth() {
            return Color::ZERO;
        }
        match self.base {
            FilmBase::Dielectric { eta } => {
                let fresnel = FilmFresnel(self, eta);
                self.rough_dielectric(eta)
                    .eval_pdf_with(wo, wi, mode, &fresnel)
                    .0
            }
            FilmBase::Sheet { .. } => Color::ZERO,
            _ => self.rough_conductor(wo, wi).0,
        }
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if self.is_smooth() {
            return 0.0;
        }
        match self.base {
            FilmBase::Dielectric { eta } => {
                let fresnel = FilmFresnel(self, eta);
                let mode = TransportMode::Radiance;
                self.rough_dielectric(eta)
                    .eval_pdf_with(wo, wi, mode, &fresnel)
                    .1
            }
            FilmBase::Sheet { .. } => 0.0,
            _ => self.rough_lobe().eval_pdf(wo, wi).1,
        }
    }

    fn sample(&self, wo: Vec3, uc: f32, u2: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        match self.base {
            FilmBase::Dielectric { eta } if self.is_smooth() => {
                self.sample_smooth(wo, uc, mode, eta)
            }
            FilmBase::Dielectric { eta } => {
                let fresnel = FilmFresnel(self, eta);
                self.rough_dielectric(eta)
                    .sample_with(wo, uc, u2, mode, &fresnel)
            }
            FilmBase::Sheet { eta } => self.sample_sheet(wo, uc, eta),
            _ if self.is_smooth() => {
                if wo.z <= 0.0 {
                    return None;
                }
                let weight = self.tint() * self.reflectance(wo.z.min(1.0));
                let wi = Vec3::new(-wo.x, -wo.y, wo.z);
                Some(BsdfSample::delta(wi, weight, 1.0, Event::Reflect, 1.0))
            }
            _ => self.sample_rough_conductor(wo, u2),
        }
    }
}

impl Iridescent {
    /// Smooth filmed dielectric: reflect with P = mean F_c (weight F/P), refract by Snell with
    /// 1 − P (weight (1 − F)/(1 − P), radiance scaled by 1/η'²) — `SmoothDielectric` with a
    /// coloured F.
    fn sample_smooth(
        &self,
        wo: Vec3,
        uc: f32,
        mode: TransportMode,
        eta: f32,
    ) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let fr = fresnel_dielectric_terms(wo.z, eta);
        let r = if fr.f >= 1.0 {
            Color::ONE
        } else {
            self.reflectance_signed(wo.z, eta)
        };
        let p = self.mean(r);
        if uc < p || fr.f >= 1.0 {
            let wi = Vec3::new(-wo.x, -wo.y, wo.z);
            return Some(BsdfSample::delta(wi, r / p, p, Event::Reflect, 1.0));
        }
        let (wi, scale) = super::dielectric::refraction(wo, &fr, mode);
        let weight = (Color::ONE - r) / (1.0 - p) * scale;
        Some(BsdfSample::delta(
            wi,
            weight,
            1.0 - p,
            Event::Transmit,
            fr.eta_rel,
        ))
    }

    /// Filmed sheet: reflect with P = mean R'_c, pass straight through with 1 − P.
    fn sample_sheet(&self, wo: Vec3, uc: f32, eta: f32) -> Option<BsdfSample> {
        if wo.z == 0.0 || !wo.z.is_finite() {
            return None;
        }
        let r = self.sheet_reflectance(wo.z, eta);
        let p = self.mean(r);
        if uc < p || p >= 1.0 {
            let wi = Vec3::new(-wo.x, -wo.y, wo.z);
            return Some(BsdfSample::delta(wi, r / p, p, Event::Reflect, 1.0));
        }
        let weight = (Color::ONE - r) / (1.0 - p);
        Some(BsdfSample::delta(
            -wo,
            weight,
            1.0 - p,
            Event::Transmit,
            1.0,
        ))
    }

    /// Rough filmed metal: f = tint F_film(wo·m) D G2/(4 cos cos) and its pdf
    /// (`RoughFresnelConductor` with the film's F).
    fn rough_conductor(&self, wo: Vec3, wi: Vec3) -> (Color, f32) {
        let (f, pdf) = self.rough_lobe().eval_pdf(wo, wi);
        if f == 0.0 {
            return (Color::ZERO, pdf);
        }
        let h = (wo + wi).normalize_or_zero();
        let cos = wo.dot(h).clamp(0.0, 1.0);
        (self.tint() * self.reflectance(cos) * f, pdf)
    }

    /// The lobe's sample (`RoughConductor::sample_reflection`) with the film's F at the half
    /// vector, weight f·cos/pdf.
    fn sample_rough_conductor(&self, wo: Vec3, u2: Vec2) -> Option<BsdfSample> {
        let (wi, _, pdf) = self.rough_lobe().sample_reflection(wo, u2)?;
        let f = self.rough_conductor(wo, wi).0;
        if !f.is_finite() {
            return None;
        }
        let weight = f * (wi.z / pdf);
        Some(BsdfSample::new(
            wi,
            f,
            weight,
            pdf,
            Event::Reflect,
            Lobe::G,
            1.0,
        ))
    }
}

/// The BSDF a thin film lies on, whose Fresnel matrix stands for the film's: the film's
/// interference is an Airy sum per polarisation (Belcour & Barla 2017 sum s and p
/// separately), which this does not follow; its intensity is the scalar BSDF's.
fn film_base(b: &Iridescent) -> Bsdf {
    let smooth = effectively_smooth(b.alpha);
    let rough = |reflectance: Color| RoughConductor {
        reflectance,
        alpha: b.alpha,
        dist: b.dist,
    };
    match b.base {
        FilmBase::Dielectric { eta } if smooth => Bsdf::SmoothDielectric(SmoothDielectric { eta }),
        FilmBase::Dielectric { eta } => Bsdf::RoughDielectric(RoughDielectric {
            eta,
            alpha: b.alpha,
            dist: b.dist,
        }),
        FilmBase::Sheet { eta } => Bsdf::ThinDielectric(ThinDielectric { eta }),
        FilmBase::Conductor { ior, tint } if smooth => {
            Bsdf::SmoothConductor(SmoothConductor { ior, tint })
        }
        FilmBase::Conductor { ior, tint } => Bsdf::RoughFresnelConductor(RoughFresnelConductor {
            ior,
            lobe: rough(tint),
        }),
        FilmBase::Reflectance { f0 } => Bsdf::RoughConductor(rough(f0)),
    }
}
