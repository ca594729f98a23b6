//! Bidirectional scattering distribution functions in a local shading frame (z = shading normal).
//!
//! Conventions (docs/design.md): `wo` and `wi` both point away from the surface; `eval` returns f
//! without the cosine; `pdf` is w.r.t. solid angle of `wi`; `sample` receives its random numbers
//! as arguments and returns the weight f·|cos θi|/pdf directly. Delta lobes: `eval` and `pdf`
//! return 0 and `sample` returns the weight (1 for a perfect mirror of reflectance 1).
//! `eta` = IOR(inside) / IOR(outside); outside is the side the normal points to (z > 0).
//! In [`TransportMode::Radiance`] refraction scales by 1/eta_rel² (eta_rel = n_t/n_i along the
//! sampled direction of light flow); in [`TransportMode::Importance`] it does not
//! (Veach 1997, §5.2).

pub mod chi2;
pub mod complex_conductor;
pub mod conductor;
pub mod dielectric;
pub mod diffuse;
pub mod family;
pub mod family_wgsl;
pub mod fresnel;
pub mod fresnel_polarized;
pub mod glossy;
pub mod iridescent;
pub mod metal_ior;
pub mod metal_rough;
pub mod microfacet;
pub mod polarized;
pub mod rough_dielectric;
pub mod rough_thin;
pub mod thin;
pub mod thin_film;

use crate::math::Color;
use glam::{Vec2, Vec3};

pub use complex_conductor::{ComplexIor, RoughFresnelConductor, SmoothConductor};
pub use conductor::Mirror;
pub use dielectric::SmoothDielectric;
pub use diffuse::Lambert;
pub use family::{Bsdf, BsdfParts};
pub use fresnel_polarized::MuellerLanes;
pub use glossy::RoughConductor;
pub use iridescent::{FilmBase, Iridescent};
pub use metal_ior::Metal;
pub use metal_rough::MetalRough;
pub use microfacet::Microfacet;
pub use rough_dielectric::RoughDielectric;
pub use rough_thin::RoughThinDielectric;
pub use thin::ThinDielectric;
pub use thin_film::ThinFilm;

/// Which quantity a path carries: radiance (camera paths) or importance (light paths).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TransportMode {
    Radiance,
    Importance,
}

/// Whether the sampled direction is on the same side as `wo` or the other.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Event {
    Reflect,
    Transmit,
}

/// Heckbert event class of a scattering lobe: diffuse, glossy, specular.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Lobe {
    D,
    G,
    S,
}

/// Microfacet normal distribution ("roughness type").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum MicrofacetDistribution {
    /// Trowbridge–Reitz / GGX (Walter et al. 2007).
    #[default]
    Ggx,
    /// Beckmann–Spizzichino (Walter et al. 2007).
    Beckmann,
}

/// α below this is treated as perfectly smooth (docs/design.md).
pub const SMOOTH_ALPHA: f32 = 1e-3;

/// glTF convention: α = roughness².
#[inline]
pub fn roughness_to_alpha(roughness: f32) -> f32 {
    let r = roughness.clamp(0.0, 1.0);
    r * r
}

/// α < 1e-3 → treat as smooth (delta) lobe.
#[inline]
pub fn effectively_smooth(alpha: f32) -> bool {
    alpha < SMOOTH_ALPHA
}

/// One sampled scattering direction.
#[derive(Clone, Copy, Debug)]
pub struct BsdfSample {
    /// Sampled direction (local frame, unit length, pointing away from the surface).
    pub wi: Vec3,
    /// BSDF value f(wo, wi) (0 for delta lobes). For multi-class BSDFs (MetalRough) the value
    /// of the labelled class divided by the label's probability, f_k / q_k, so that
    /// weight = f·|cos|/pdf still holds and E[f] over the label is f(wo, wi).
    pub f: Color,
    /// f·|cos θi| / pdf (for delta lobes the weight directly).
    pub weight: Color,
    /// Solid-angle pdf (for delta lobes: the discrete probability of choosing the lobe).
    pub pdf: f32,
    pub is_delta: bool,
    pub event: Event,
    /// Heckbert class of this sample. For multi-lobe BSDFs the label is chosen so that
    /// E[weight · 1{lobe = k}] = ∫ f_k |cos| for each class k (filtered images sum up).
    pub lobe: Lobe,
    /// Relative IOR n_t/n_i crossed by this sample (1 for reflection).
    pub eta_rel: f32,
}

impl BsdfSample {
    /// A sample of a non-delta lobe: value f, direction wi, solid-angle pdf, weight f|cos θi|/pdf,
    /// event, Heckbert lobe and relative IOR (pbrt-v4 `BSDFSample(f, wi, pdf, flags, eta)`).
    #[inline]
    pub fn new(
        wi: Vec3,
        f: Color,
        weight: Color,
        pdf: f32,
        event: Event,
        lobe: Lobe,
        eta_rel: f32,
    ) -> BsdfSample {
        BsdfSample {
            wi,
            f,
            weight,
            pdf,
            is_delta: false,
            event,
            lobe,
            eta_rel,
        }
    }

    /// A sample of a delta lobe (specular, [`Lobe::S`]): f is not a function value (0), `pdf` is
    /// the lobe's selection probability and `weight` the throughput factor (pbrt-v4
    /// `BSDFSample` with `BxDFFlags::Specular`).
    #[inline]
    pub fn delta(wi: Vec3, weight: Color, pdf: f32, event: Event, eta_rel: f32) -> BsdfSample {
        BsdfSample {
            wi,
            f: Color::ZERO,
            weight,
            pdf,
            is_delta: true,
            event,
            lobe: Lobe::S,
            eta_rel,
        }
    }

    /// An index-matched interface (η = 1): no interface at all, the sample passes straight
    /// through with weight 1.
    #[inline]
    pub fn index_matched(wo: Vec3) -> BsdfSample {
        BsdfSample::delta(-wo, Color::ONE, 1.0, Event::Transmit, 1.0)
    }
}

/// Per-class BSDF values (for the Heckbert path filter on next-event estimation).
#[derive(Clone, Copy, Debug, Default)]
pub struct LobeValues {
    pub d: Color,
    pub g: Color,
}

/// The interface every BSDF implements (see the module docs for conventions).
/// Besides scattering, each variant says in its own file whether it can transmit, how it
/// polarises ([`BxDF::mueller`]) and, where it has them, its colours, its wavelength-dependent
/// parameters and its microfacet distribution; [`Bsdf`] dispatches (generated from the
/// table, `bsdf::family`).
pub trait BxDF {
    fn eval(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> Color;
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32;
    fn sample(&self, wo: Vec3, uc: f32, u2: Vec2, mode: TransportMode) -> Option<BsdfSample>;

    /// True if some lobe transmits (the sampled direction may cross the surface).
    fn can_transmit(&self) -> bool;

    /// The normalised Mueller matrix of the event (wo, wi) in class `lobe` (local frame,
    /// wi = the light's incoming direction, wo = where it leaves to; `bsdf::polarized`).
    fn mueller(&self, wo: Vec3, wi: Vec3, event: Event, lobe: Lobe) -> MuellerLanes;

    /// Apply `f` to every colour parameter (RGB → the path's spectral lanes).
    #[inline]
    fn map_colors(self, _f: impl Fn(Color) -> Color) -> Self
    where
        Self: Sized,
    {
        self
    }

    /// Spectral mode: re-evaluate wavelength-dependent parameters (a conductor's tabulated
    /// η, k) at the path's four wavelengths.
    #[inline]
    fn at_wavelengths(self, _lambdas: [f32; 4]) -> Self
    where
        Self: Sized,
    {
        self
    }

    /// The microfacet distribution of a rough lobe (a scene feature: the kernel compiles it in).
    #[inline]
    fn distribution(&self) -> Option<MicrofacetDistribution> {
        None
    }
}

impl Bsdf {
    /// f(wo, wi) split by Heckbert class (delta lobes contribute nothing).
    #[inline]
    pub fn eval_lobes(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> LobeValues {
        if let Bsdf::MetalRough(b) = self {
            return b.eval_lobes(wo, wi);
        }
        let f = self.eval(wo, wi, mode);
        match self.class() {
            Lobe::D => LobeValues {
                d: f,
                g: Color::ZERO,
            },
            _ => LobeValues {
                d: Color::ZERO,
                g: f,
            },
        }
    }
}
