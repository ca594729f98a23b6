//! Dielectric Fresnel equations, Snell refraction and mirror reflection in the local frame
//! (z = normal). `eta` is always IOR(inside) / IOR(outside), the side the normal points to
//! being "outside"; a direction with z < 0 is inside.

use crate::math::Color;
use glam::Vec3;

/// Both polarised amplitude coefficients and the unpolarised reflectance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FresnelTerms {
    /// Amplitude reflection coefficient for light polarised parallel to the plane of incidence.
    pub r_par: f32,
    /// Amplitude reflection coefficient for light polarised perpendicular to it.
    pub r_perp: f32,
    /// Unpolarised reflectance F = (r∥² + r⊥²) / 2 (1 under total internal reflection).
    pub f: f32,
    /// |cos θt| of the transmitted direction (0 under TIR).
    pub cos_t: f32,
    /// Relative IOR along the ray (eta if cos_i > 0, 1/eta otherwise).
    pub eta_rel: f32,
}

/// cos²θt of the refracted direction for |cos θi| = `cos_i` and relative IOR `eta_rel`:
/// cos²θt = 1 − sin²θi/η'² = (cos²θi + (η' − 1)(η' + 1)) / η'² (Snell, PBR 4th ed. §9.3.2),
/// written without the cancellation of 1 − sin²θi (grazing angles, η' ≈ 1): exact for η' = 1.
/// TIR when the result is ≤ 0 (sin²θt ≥ 1): Fresnel and `refract` share this one test.
#[inline]
pub fn cos2_transmitted(cos_i: f32, eta_rel: f32) -> f32 {
    (cos_i * cos_i + (eta_rel - 1.0) * (eta_rel + 1.0)) / (eta_rel * eta_rel)
}

/// Exact unpolarised dielectric Fresnel with r∥ and r⊥.
/// Hecht, "Optics" 5th ed. §4.6.2 (Fresnel equations); PBR 4th ed. §9.3.5 (`FrDielectric`).
/// `cos_i` is the signed cosine of the incident direction with the normal; negative means the
/// ray arrives from inside, then the relative IOR is 1/eta. TIR when sin²θt ≥ 1 (the same test
/// `refract` uses).
#[inline]
pub fn fresnel_dielectric_terms(cos_i: f32, eta: f32) -> FresnelTerms {
    let mut cos_i = cos_i.clamp(-1.0, 1.0);
    let mut eta_rel = eta;
    if cos_i < 0.0 {
        eta_rel = 1.0 / eta;
        cos_i = -cos_i;
    }
    let cos2_t = cos2_transmitted(cos_i, eta_rel);
    if cos2_t <= 0.0 {
        return FresnelTerms {
            r_par: 1.0,
            r_perp: 1.0,
            f: 1.0,
            cos_t: 0.0,
            eta_rel,
        };
    }
    let cos_t = cos2_t.sqrt();
    let r_par = (eta_rel * cos_i - cos_t) / (eta_rel * cos_i + cos_t);
    let r_perp = (cos_i - eta_rel * cos_t) / (cos_i + eta_rel * cos_t);
    FresnelTerms {
        r_par,
        r_perp,
        f: 0.5 * (r_par * r_par + r_perp * r_perp),
        cos_t,
        eta_rel,
    }
}

/// Unpolarised dielectric reflectance F(cos_i, eta). See [`fresnel_dielectric_terms`].
#[inline]
pub fn fresnel_dielectric(cos_i: f32, eta: f32) -> f32 {
    fresnel_dielectric_terms(cos_i, eta).f
}

/// Mirror reflection of `wo` about the normal `n`. PBR 4th ed. §9.3.1.
#[inline]
pub fn reflect(wo: Vec3, n: Vec3) -> Vec3 {
    -wo + 2.0 * wo.dot(n) * n
}

/// Snell refraction of `wi` (pointing away from the surface) through a surface with normal `n`
/// (on the same side as `wi`) and relative IOR `eta_rel` = n_t / n_i.
/// Returns `None` under total internal reflection (sin²θt ≥ 1).
/// PBR 4th ed. §9.3.2 (`Refract`), Snell: n_i sinθi = n_t sinθt.
#[inline]
pub fn refract(wi: Vec3, n: Vec3, eta_rel: f32) -> Option<Vec3> {
    let cos_i = n.dot(wi);
    let cos2_t = cos2_transmitted(cos_i.min(1.0), eta_rel);
    if cos2_t <= 0.0 {
        return None;
    }
    let cos_t = cos2_t.sqrt();
    Some(-wi / eta_rel + (cos_i / eta_rel - cos_t) * n)
}

/// Schlick's approximation F0 + (1 − F0)(1 − cosθ)⁵. Schlick 1994, "An Inexpensive BRDF Model".
#[inline]
pub fn fresnel_schlick(f0: f32, cos_i: f32) -> f32 {
    let m = (1.0 - cos_i.abs()).clamp(0.0, 1.0);
    let m2 = m * m;
    f0 + (1.0 - f0) * m2 * m2 * m
}

/// Exact unpolarised Fresnel reflectance of a conductor with complex relative IOR η − ik
/// (η = n_metal/n_outside, k likewise) for incidence cosine `cos_i` (|cos_i| is used; a
/// conductor is lit from outside only):
///   a² + b² = √((η² − k² − sin²θ)² + 4η²k²),  a = √((a² + b² + η² − k² − sin²θ)/2),
///   R⊥ = (a² + b² + cos²θ − 2a cosθ) / (a² + b² + cos²θ + 2a cosθ),
///   R∥ = R⊥ (cos²θ (a² + b²) + sin⁴θ − 2a cosθ sin²θ) / (cos²θ (a² + b²) + sin⁴θ + 2a cosθ sin²θ),
///   F = (R⊥ + R∥) / 2.
/// Real-arithmetic form of PBR 4th ed. §9.3.6 (`FrComplex`), as in PBR 3rd ed. §8.2.1
/// (`FrConductor`) and Mitsuba 3 `fresnel_conductor`; Born & Wolf, "Principles of Optics",
/// §14.2. k = 0 gives the dielectric [`fresnel_dielectric`] (with F = 1 under TIR, a = 0).
#[inline]
pub fn fresnel_conductor(cos_i: f32, eta: f32, k: f32) -> f32 {
    let cos = cos_i.abs().min(1.0);
    let cos2 = cos * cos;
    let sin2 = 1.0 - cos2;
    let t1 = eta * eta - k * k - sin2;
    let a2b2 = (t1 * t1 + 4.0 * eta * eta * k * k).sqrt();
    let a = (0.5 * (a2b2 + t1)).max(0.0).sqrt();
    let t2 = 2.0 * a * cos;
    // The denominators vanish only in degenerate cases (η = k = 0 at normal incidence, η = 1,
    // k = 0 at grazing incidence); total reflection is reported there, as the limit of R⊥.
    let d1 = a2b2 + cos2 + t2;
    let rs = if d1 > 0.0 {
        (a2b2 + cos2 - t2) / d1
    } else {
        1.0
    };
    let t3 = a2b2 * cos2 + sin2 * sin2;
    let t4 = t2 * sin2;
    let d2 = t3 + t4;
    let rp = if d2 > 0.0 { rs * (t3 - t4) / d2 } else { rs };
    (0.5 * (rs + rp)).clamp(0.0, 1.0)
}

/// [`fresnel_conductor`] per colour lane (RGB channels or hero wavelengths).
#[inline]
pub fn fresnel_conductor_color(cos_i: f32, eta: Color, k: Color) -> Color {
    Color::new(
        fresnel_conductor(cos_i, eta.x, k.x),
        fresnel_conductor(cos_i, eta.y, k.y),
        fresnel_conductor(cos_i, eta.z, k.z),
        fresnel_conductor(cos_i, eta.w, k.w),
    )
}

#[cfg(test)]
mod conductor_tests {
    use super::*;

    /// PBR 4th ed. §9.3.6 `FrComplex` in f64 complex arithmetic (η + ik; the sign convention
    /// does not change |r|²): an independent reference for the real-arithmetic form.
    fn fr_complex(cos_i: f64, n: f64, k: f64) -> f64 {
        #[derive(Clone, Copy)]
        struct C(f64, f64);
        let mul = |a: C, b: C| C(a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0);
        let div = |a: C, b: C| {
            let d = b.0 * b.0 + b.1 * b.1;
            C((a.0 * b.0 + a.1 * b.1) / d, (a.1 * b.0 - a.0 * b.1) / d)
        };
        let sqrt = |a: C| {
            let r = (a.0 * a.0 + a.1 * a.1).sqrt();
            let re = (0.5 * (r + a.0)).max(0.0).sqrt();
            let im = (0.5 * (r - a.0)).max(0.0).sqrt().copysign(a.1);
            C(re, im)
        };
        let eta = C(n, k);
        let sin2_i = 1.0 - cos_i * cos_i;
        let sin2_t = div(C(sin2_i, 0.0), mul(eta, eta));
        let cos_t = sqrt(C(1.0 - sin2_t.0, -sin2_t.1));
        let ci = C(cos_i, 0.0);
        let sub = |a: C, b: C| C(a.0 - b.0, a.1 - b.1);
        let add = |a: C, b: C| C(a.0 + b.0, a.1 + b.1);
        let norm = |a: C| a.0 * a.0 + a.1 * a.1;
        let r_parl = div(sub(mul(eta, ci), cos_t), add(mul(eta, ci), cos_t));
        let r_perp = div(sub(ci, mul(eta, cos_t)), add(ci, mul(eta, cos_t)));
        0.5 * (norm(r_parl) + norm(r_perp))
    }

    const METALS: [(f32, f32); 5] = [
        (0.143, 3.983),
        (0.155, 4.828),
        (1.6575, 9.2238),
        (0.2, 2.45),
        (1.5, 0.3),
    ];

    #[test]
    fn zero_k_is_the_dielectric_fresnel() {
        for eta in [1.2f32, 1.5, 2.4, 0.8, 1.0 / 1.5] {
            for i in 0..=100 {
                let c = i as f32 / 100.0;
                let (fc, fd) = (fresnel_conductor(c, eta, 0.0), fresnel_dielectric(c, eta));
                assert!((fc - fd).abs() < 2e-5, "η {eta} cos {c}: {fc} vs {fd}");
            }
        }
    }

    #[test]
    fn normal_incidence_closed_form() {
        for (n, k) in METALS {
            let want = ((n - 1.0).powi(2) + k * k) / ((n + 1.0).powi(2) + k * k);
            let got = fresnel_conductor(1.0, n, k);
            assert!((got - want).abs() < 1e-6, "η {n} k {k}: {got} vs {want}");
        }
    }

    #[test]
    fn grazing_is_total_and_values_in_unit_interval() {
        for (n, k) in METALS {
            assert!((fresnel_conductor(0.0, n, k) - 1.0).abs() < 1e-6);
            assert!(fresnel_conductor(1e-4, n, k) > 0.99);
            for i in 0..=1000 {
                let c = i as f32 / 1000.0;
                let f = fresnel_conductor(c, n, k);
                assert!((0.0..=1.0).contains(&f), "η {n} k {k} cos {c}: {f}");
                let r = fr_complex(c as f64, n as f64, k as f64) as f32;
                assert!(
                    (f - r).abs() < 2e-5,
                    "η {n} k {k} cos {c}: {f} vs complex {r}"
                );
            }
        }
    }

    #[test]
    fn sign_of_cosine_does_not_matter() {
        assert_eq!(
            fresnel_conductor(-0.3, 0.2, 3.0),
            fresnel_conductor(0.3, 0.2, 3.0)
        );
    }
}
