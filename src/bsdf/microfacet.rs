//! Microfacet normal distributions (GGX / Trowbridge–Reitz and Beckmann), the Smith
//! masking-shadowing functions and visible-normal sampling, isotropic α.
//!
//! All directions are in the local shading frame (z = macro normal). Microfacet normals `m`
//! always lie in the upper hemisphere (m.z > 0). The visible-normal functions take the
//! direction `wo` on the upper side: callers whose `wo` is below (inside a dielectric) pass
//! `wo` mirrored through the surface (−wo), which by symmetry of the isotropic distributions
//! gives the visible normals seen from below (Walter et al. 2007, §5.3 "sampling").
//!
//! Visible-normal sampling:
//! - GGX: Heitz 2018, "Sampling the GGX Distribution of Visible Normals", JCGT 7(4), §2–4
//!   (stretch, sample the projected hemisphere disk, unstretch).
//! - Beckmann: the same stretch (Heitz & d'Eon 2014, "Importance Sampling Microfacet-Based
//!   BSDFs using the Distribution of Visible Normals", EGSR, §4) around an α = 1 slope sampler.
//!   For a unit-roughness Beckmann surface seen at polar angle θ the visible slopes (x, y) are
//!   independent: y ~ N(0, ½) and x has density ∝ (1 − x tanθ) e^{−x²} on x < cotθ, with CDF
//!   C(x) = [erfc(−x) + tanθ/√π · e^{−x²}] / [erfc(−cotθ) + tanθ/√π · e^{−cot²θ}].
//!   We invert C numerically with safeguarded Newton–bisection in x (Jakob 2014, "An Improved
//!   Visible Normal Sampling Routine for the Beckmann Distribution", replaces the original
//!   approximate inversion by such a numerical one); y = erfinv(2u − 1). Both are exact up to
//!   the f32 tolerance of the solve (|ΔC| ≤ 1e-6).

use super::MicrofacetDistribution;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// 1/√π.
const INV_SQRT_PI: f32 = 0.564_189_6;

/// A microfacet normal distribution with isotropic roughness α.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Microfacet {
    pub dist: MicrofacetDistribution,
    pub alpha: f32,
}

impl Microfacet {
    /// α is clamped to ≥ 1e-4 (below the smooth threshold callers use delta lobes anyway).
    #[inline]
    pub fn new(dist: MicrofacetDistribution, alpha: f32) -> Self {
        Microfacet {
            dist,
            alpha: alpha.max(1e-4),
        }
    }

    /// Normal distribution D(m) for a unit vector m (0 for m.z ≤ 0).
    #[inline]
    pub fn d(&self, m: Vec3) -> f32 {
        if m.z <= 0.0 {
            return 0.0;
        }
        let a2 = self.alpha * self.alpha;
        let xy2 = m.x * m.x + m.y * m.y;
        let z2 = m.z * m.z;
        match self.dist {
            MicrofacetDistribution::Ggx => {
                // D = 1/(π α² cos⁴θ (1 + tan²θ/α²)²), Walter et al. 2007 eq. 33, with
                // cos²θ (1 + tan²θ/α²) = z² + (x² + y²)/α² (accurate for tiny α).
                let t = xy2 / a2 + z2;
                1.0 / (PI * a2 * t * t)
            }
            MicrofacetDistribution::Beckmann => {
                // D = exp(−tan²θ/α²)/(π α² cos⁴θ), Walter et al. 2007 eq. 25.
                let tan2 = xy2 / z2;
                (-tan2 / a2).exp() / (PI * a2 * z2 * z2)
            }
        }
    }

    /// Smith Λ(w) (depends on |w.z| only through tanθ).
    #[inline]
    pub fn lambda(&self, w: Vec3) -> f32 {
        let xy2 = w.x * w.x + w.y * w.y;
        let z2 = w.z * w.z;
        if xy2 <= 0.0 {
            return 0.0;
        }
        if z2 <= 0.0 {
            return f32::INFINITY;
        }
        let a2_tan2 = self.alpha * self.alpha * xy2 / z2;
        match self.dist {
            MicrofacetDistribution::Ggx => {
                // Λ = (−1 + √(1 + α² tan²θ))/2, Heitz 2014 (JCGT 3(2)), Smith Λ of the GGX distribution.
                0.5 * ((1.0 + a2_tan2).sqrt() - 1.0)
            }
            MicrofacetDistribution::Beckmann => {
                // Λ = (erf(a) − 1)/2 + e^{−a²}/(2a√π), a = 1/(α tanθ);
                // Heitz 2014 (JCGT 3(2)), Smith Λ of the Beckmann distribution.
                let a = 1.0 / a2_tan2.sqrt();
                0.5 * (-erfc(a) + (-a * a).exp() * INV_SQRT_PI / a)
            }
        }
    }

    /// Smith masking G1(w) = 1/(1 + Λ(w)), Heitz 2014 (JCGT 3(2)), Smith masking function.
    #[inline]
    pub fn g1(&self, w: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(w))
    }

    /// Height-correlated masking-shadowing G2 = 1/(1 + Λ(wo) + Λ(wi)),
    /// Heitz 2014 (JCGT 3(2)), height-correlated Smith masking-shadowing.
    #[inline]
    pub fn g2(&self, wo: Vec3, wi: Vec3) -> f32 {
        // (Λo + Λi) summed first: symmetric in its arguments to the last bit.
        1.0 / (1.0 + (self.lambda(wo) + self.lambda(wi)))
    }

    /// Distribution of visible normals D_wo(m) = G1(wo) max(0, wo·m) D(m) / |wo.z|
    /// (Heitz 2018, JCGT 7(4), eq. 1). `wo` must be on the upper side (wo.z > 0).
    #[inline]
    pub fn pdf_visible(&self, wo: Vec3, m: Vec3) -> f32 {
        let dot = wo.dot(m);
        if wo.z <= 0.0 || dot <= 0.0 {
            return 0.0;
        }
        self.g1(wo) * dot * self.d(m) / wo.z
    }

    /// Sample a microfacet normal from D_wo (see the module docs for the methods).
    /// `wo` must be on the upper side (wo.z > 0). The result has m.z ≥ 0.
    #[inline]
    pub fn sample_visible(&self, wo: Vec3, u: Vec2) -> Vec3 {
        match self.dist {
            MicrofacetDistribution::Ggx => self.sample_visible_ggx(wo, u),
            MicrofacetDistribution::Beckmann => self.sample_visible_beckmann(wo, u),
        }
    }

    /// Heitz 2018 (JCGT 7(4)), listing 1: stretch → sample the visible hemisphere disk with
    /// the foreshortened half warped (§4.2) → unstretch.
    #[inline]
    fn sample_visible_ggx(&self, wo: Vec3, u: Vec2) -> Vec3 {
        let a = self.alpha;
        // Stretch the view direction to the α = 1 configuration (Heitz 2018 §4.1).
        let vh = Vec3::new(a * wo.x, a * wo.y, wo.z).normalize();
        // Orthonormal basis around vh (Heitz 2018 §4.2, T1 ⟂ z).
        let lensq = vh.x * vh.x + vh.y * vh.y;
        let t1 = if lensq > 0.0 {
            Vec3::new(-vh.y, vh.x, 0.0) / lensq.sqrt()
        } else {
            Vec3::X
        };
        let t2 = vh.cross(t1);
        // Uniform point on the unit disk (polar map), then squash the half hidden behind the
        // hemisphere's projection: t2 ← (1 − s)√(1 − t1²) + s t2, s = (1 + vh.z)/2 (§4.2).
        let r = u.x.sqrt();
        let phi = 2.0 * PI * u.y;
        let p1 = r * phi.cos();
        let mut p2 = r * phi.sin();
        let s = 0.5 * (1.0 + vh.z);
        p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * p2;
        // Reproject onto the hemisphere and unstretch (§4.3).
        let nh = p1 * t1 + p2 * t2 + (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt() * vh;
        Vec3::new(a * nh.x, a * nh.y, nh.z.max(0.0)).normalize()
    }

    /// Stretched Beckmann visible-normal sampling (Heitz & d'Eon 2014 §4, Alg. 1 structure)
    /// with the α = 1 slope sampler [`beckmann_visible_slopes`].
    #[inline]
    fn sample_visible_beckmann(&self, wo: Vec3, u: Vec2) -> Vec3 {
        let a = self.alpha;
        // 1. Stretch wo (Heitz 2014, JCGT 3(2): shape-invariant distributions stretch with α).
        let ws = Vec3::new(a * wo.x, a * wo.y, wo.z).normalize();
        let sin_t = (ws.x * ws.x + ws.y * ws.y).sqrt();
        let (cos_p, sin_p) = if sin_t > 1e-7 {
            (ws.x / sin_t, ws.y / sin_t)
        } else {
            (1.0, 0.0)
        };
        // 2. Visible slopes of the unit-roughness surface for incidence angle θ (φ = 0).
        let (sx, sy) = beckmann_visible_slopes(ws.z, sin_t, u);
        // 3. Rotate to φ and 4. unstretch the slopes.
        let rx = (cos_p * sx - sin_p * sy) * a;
        let ry = (sin_p * sx + cos_p * sy) * a;
        // 5. Slope → normal: m ∝ (−x̃, −ỹ, 1) (Heitz 2014, JCGT 3(2), slope space).
        Vec3::new(-rx, -ry, 1.0).normalize()
    }
}

/// Visible slopes (x, y) of the α = 1 Beckmann surface seen from the direction
/// (sinθ, 0, cosθ): y ~ N(0, ½) by inversion; x by inverting
/// C(x) ∝ erfc(−x) + tanθ/√π e^{−x²} on (−∞, cotθ) (derivation in the module docs;
/// Heitz & d'Eon 2014 §4, Jakob 2014 §2) with Newton steps safeguarded by bisection.
#[inline]
fn beckmann_visible_slopes(cos_t: f32, sin_t: f32, u: Vec2) -> (f32, f32) {
    // y: Gaussian with variance ½ (the Beckmann slope marginal), y = erfinv(2u − 1).
    let y = erfinv((2.0 * u.y - 1.0).clamp(-0.999_999_9, 0.999_999_9));
    if sin_t <= 1e-6 * cos_t {
        // Normal incidence: x is the same Gaussian.
        let x = erfinv((2.0 * u.x - 1.0).clamp(-0.999_999_9, 0.999_999_9));
        return (x, y);
    }
    let tan_t = sin_t / cos_t;
    let cot_t = cos_t / sin_t;
    let k = tan_t * INV_SQRT_PI;
    // Unnormalised CDF and its normalisation Z = C̃(cotθ).
    let cdf = |x: f32| erfc(-x) + k * (-x * x).exp();
    let z = cdf(cot_t);
    let target = u.x * z;
    // Bracket: below −6 the CDF mass is < 1e-15 of Z for every θ.
    let mut lo = -6.0f32;
    let mut hi = cot_t.min(6.0);
    let mut x = erfinv((2.0 * u.x - 1.0).clamp(-0.999_999, 0.999_999));
    if !(x > lo && x < hi) {
        x = 0.5 * (lo + hi);
    }
    for _ in 0..40 {
        let g = cdf(x) - target;
        if g.abs() <= 1e-6 * z {
            break;
        }
        if g > 0.0 {
            hi = x;
        } else {
            lo = x;
        }
        // dC̃/dx = (2/√π) e^{−x²} (1 − x tanθ).
        let dg = 2.0 * INV_SQRT_PI * (-x * x).exp() * (1.0 - x * tan_t);
        let xn = x - g / dg;
        x = if xn > lo && xn < hi {
            xn
        } else {
            0.5 * (lo + hi)
        };
        if hi - lo < 1e-7 {
            break;
        }
    }
    (x, y)
}

/// Complementary error function, fractional error < 1.2e-7 everywhere.
/// Press et al., "Numerical Recipes in C" 2nd ed. §6.2 (`erfcc`, Chebyshev fit).
// Published coefficients kept verbatim (easier to check against the source).
#[allow(clippy::excessive_precision)]
#[inline]
pub fn erfc(x: f32) -> f32 {
    let z = x.abs();
    let t = 1.0 / (1.0 + 0.5 * z);
    let poly = -1.265_512_2
        + t * (1.000_023_7
            + t * (0.374_091_96
                + t * (0.096_784_18
                    + t * (-0.186_288_06
                        + t * (0.278_868_07
                            + t * (-1.135_203_98
                                + t * (1.488_515_87 + t * (-0.822_152_23 + t * 0.170_872_77))))))));
    let r = t * (-z * z + poly).exp();
    if x >= 0.0 { r } else { 2.0 - r }
}

/// Error function erf(x) = 1 − erfc(x) (see [`erfc`]).
#[inline]
pub fn erf(x: f32) -> f32 {
    1.0 - erfc(x)
}

/// Inverse error function for |x| < 1, single precision.
/// Giles 2010, "Approximating the erfinv function" (GPU Computing Gems Jade, ch. 10), Fig. 2.
// Published coefficients kept verbatim (easier to check against the source).
#[allow(clippy::excessive_precision)]
#[inline]
pub fn erfinv(x: f32) -> f32 {
    let w = -((1.0 - x) * (1.0 + x)).ln();
    let p = if w < 5.0 {
        let w = w - 2.5;
        let mut p = 2.810_226_36e-08;
        p = 3.432_739_39e-07 + p * w;
        p = -3.523_387_7e-06 + p * w;
        p = -4.391_506_54e-06 + p * w;
        p = 0.000_218_580_87 + p * w;
        p = -0.001_253_725_03 + p * w;
        p = -0.004_177_681_64 + p * w;
        p = 0.246_640_727 + p * w;
        1.501_409_41 + p * w
    } else {
        let w = w.sqrt() - 3.0;
        let mut p = -0.000_200_214_257;
        p = 0.000_100_950_558 + p * w;
        p = 0.001_349_343_22 + p * w;
        p = -0.003_673_428_44 + p * w;
        p = 0.005_739_507_73 + p * w;
        p = -0.007_622_461_3 + p * w;
        p = 0.009_438_870_47 + p * w;
        p = 1.001_674_06 + p * w;
        2.832_976_82 + p * w
    };
    p * x
}
