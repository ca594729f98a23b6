//! Dielectric Fresnel equations, Snell refraction and mirror reflection in the local frame
//! (z = normal). `eta` is always IOR(inside) / IOR(outside), the side the normal points to
//! being "outside"; a direction with z < 0 is inside.

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
