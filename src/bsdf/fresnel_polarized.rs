//! The Fresnel equations as amplitudes with phases, and the Mueller matrices of specular
//! reflection and refraction in the s/p basis (issue 38: polarised transport).
//!
//! Basis: s = the unit normal of the plane of incidence, the same vector for the incident,
//! reflected and transmitted beams; each beam's p vector is d × s (d its direction of
//! travel), so (s, p, d) is the right-handed Stokes frame of `math::mueller` with x = s.
//! In this basis the amplitude coefficients are Hecht's ("Optics" 5th ed. §4.6.2, eqs.
//! 4.34, 4.40; the "Verdet convention" Mitsuba 3 also uses):
//!   r_s = (cos θi − η cos θt) / (cos θi + η cos θt),
//!   r_p = (η cos θi − cos θt) / (η cos θi + cos θt),
//!   t_s = 1 + r_s,  t_p = (1 + r_p) / η,
//! with η = n_t/n_i complex for a conductor (η − ik, k ≥ 0: Born & Wolf §14.2). Beyond the
//! critical angle cos θt is imaginary; the root with Im ≤ 0 is the evanescent wave of this
//! sign convention (Clarke, "Stellar Polarimetry", App. A.2, as Mitsuba 3's
//! `fresnel_polarized`), which gives |r_s| = |r_p| = 1 and the relative phase
//! tan(δ/2) = cos θi √(sin²θi − η²) / sin²θi, δ = arg r_p − arg r_s (Born & Wolf §1.5.4).

use super::Event;
use crate::math::Color;
use crate::math::complex::Complex;
use crate::math::mueller::{from_jones_diagonal, normalized};
use glam::{Mat4, Vec3};

/// The polarised amplitudes at one interface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FresnelAmplitudes {
    pub r_s: Complex,
    pub r_p: Complex,
    /// cos θt (complex under total internal reflection or in a conductor).
    pub cos_t: Complex,
    /// n_t / n_i along the ray.
    pub eta_rel: Complex,
    /// |cos θi|.
    pub cos_i: f32,
}

/// The amplitudes for incidence cosine `cos_i` against the normal (negative: the light
/// arrives from inside, η' = 1/η) and relative IOR `eta` = n_inside / n_outside (complex
/// η − ik for a conductor, lit from outside only).
pub fn fresnel_amplitudes(cos_i: f32, eta: Complex) -> FresnelAmplitudes {
    let c = cos_i.clamp(-1.0, 1.0);
    let eta_rel = if c < 0.0 { eta.recip() } else { eta };
    let c = c.abs();
    // cos²θt = 1 − sin²θi / η'² (Snell).
    let sin2_t = Complex::real(1.0 - c * c) / (eta_rel * eta_rel);
    let mut cos_t = (Complex::ONE - sin2_t).sqrt();
    if cos_t.im > 0.0 {
        cos_t = cos_t.conj();
    }
    let ci = Complex::real(c);
    // r_s and r_p with their numerators multiplied out (cos²θt = 1 − sin²θi/η'²):
    // cos²θi − η'² cos²θt = 1 − η'² and η'² cos²θi − cos²θt = (η'² − 1)((η'² + 1) cos²θi − 1)/η'²,
    // which do not cancel as η' → 1 (an index-matched interface), where the differences of
    // nearly equal terms lose every digit in f32; 1 − η'² as (1 − η')(1 + η').
    let d_s = ci + eta_rel * cos_t;
    let d_p = eta_rel * ci + cos_t;
    let eta2 = eta_rel * eta_rel;
    let one_minus_eta2 = (Complex::ONE - eta_rel) * (Complex::ONE + eta_rel);
    let r_s = one_minus_eta2 / (d_s * d_s);
    let brewster = Complex::real(c * c) * (eta2 + Complex::ONE) - Complex::ONE;
    let r_p = -(one_minus_eta2 * brewster) / (eta2 * d_p * d_p);
    FresnelAmplitudes {
        r_s,
        r_p,
        cos_t,
        eta_rel,
        cos_i: c,
    }
}

/// The Mueller matrix of specular reflection at incidence cosine `cos_i` (sign as in
/// [`fresnel_amplitudes`]); its m₀₀ is the unpolarised reflectance (r_s² + r_p²)/2.
pub fn reflection_mueller(cos_i: f32, eta: Complex) -> Mat4 {
    let a = fresnel_amplitudes(cos_i, eta);
    from_jones_diagonal(a.r_s, a.r_p)
}

/// The Mueller matrix of specular refraction through a dielectric (real `eta`) at incidence
/// cosine `cos_i`: the amplitude transmission of t_s, t_p scaled by the ratio of beam
/// cross-sections and impedances η cos θt / cos θi (Hecht eq. 4.61), so that m₀₀ is the
/// transmittance T = 1 − F (radiance's 1/η² is the scalar walk's). Zero under TIR.
pub fn transmission_mueller(cos_i: f32, eta: f32) -> Mat4 {
    let a = fresnel_amplitudes(cos_i, Complex::real(eta));
    if a.cos_t.im != 0.0 || a.cos_i == 0.0 {
        return Mat4::ZERO;
    }
    let eta_rel = a.eta_rel.re;
    let t_s = Complex::ONE + a.r_s;
    let t_p = (Complex::ONE + a.r_p) * (1.0 / eta_rel);
    from_jones_diagonal(t_s, t_p) * (eta_rel * a.cos_t.re / a.cos_i)
}

/// The ideal conductor (a perfect mirror): r_s = −1, r_p = 1 at every angle.
pub fn ideal_conductor_mueller() -> Mat4 {
    from_jones_diagonal(-Complex::ONE, Complex::ONE)
}

/// One Mueller matrix per colour lane (RGB channels or hero wavelengths).
pub type MuellerLanes = [Mat4; 4];

/// The same matrix in every lane.
#[inline]
pub fn all(m: Mat4) -> MuellerLanes {
    [m; 4]
}

/// The microfacet normal of (wo, wi), face-forwarded to the outside (z > 0): wo + wi for
/// reflection, n_o wo + n_i wi for refraction (Walter et al. 2007, eqs. 13 and 16) with
/// `eta` = n_inside / n_outside. `None` when degenerate.
pub fn half_vector(wo: Vec3, wi: Vec3, event: Event, eta: f32) -> Option<Vec3> {
    let h = match event {
        Event::Reflect => wo + wi,
        Event::Transmit if wo.z > 0.0 => wo + wi * eta,
        Event::Transmit => wi + wo * eta,
    };
    let m = h.try_normalize()?;
    Some(if m.z < 0.0 { -m } else { m })
}

/// Dielectric Fresnel at the incidence cosine `cos_i` of the light (signed: < 0 from inside),
/// normalised.
pub fn dielectric_mueller(cos_i: f32, eta: f32, event: Event) -> Mat4 {
    normalized(match event {
        Event::Reflect => reflection_mueller(cos_i, Complex::real(eta)),
        Event::Transmit => transmission_mueller(cos_i, eta),
    })
}

/// A conductor's reflection per lane at `cos_i` (η − ik per lane), normalised.
pub fn conductor_mueller(cos_i: f32, eta: Color, k: Color) -> MuellerLanes {
    std::array::from_fn(|l| normalized(reflection_mueller(cos_i, Complex::new(eta[l], -k[l]))))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::fresnel::{fresnel_conductor, fresnel_dielectric};
    use crate::math::mueller::degree_of_polarization;
    use glam::Vec4;

    /// Stokes vectors on a grid over the Poincaré sphere (fully polarised) plus unpolarised.
    fn stokes_probe() -> Vec<Vec4> {
        let mut v = vec![Vec4::new(1.0, 0.0, 0.0, 0.0)];
        for i in 0..12 {
            for j in 0..7 {
                let (az, el) = (
                    i as f32 * std::f32::consts::FRAC_PI_6,
                    -1.5 + j as f32 * 0.5,
                );
                v.push(Vec4::new(
                    1.0,
                    el.cos() * az.cos(),
                    el.cos() * az.sin(),
                    el.sin(),
                ));
            }
        }
        v
    }

    /// Physically realisable: no input gains polarisation beyond 1, intensity stays ≥ 0.
    fn assert_realizable(m: Mat4, what: &str) {
        let r0 = m.row(0);
        assert!(
            r0.x + 1e-6 >= (r0.y * r0.y + r0.z * r0.z + r0.w * r0.w).sqrt(),
            "{what}: m00 {} < |row 0| {r0}",
            r0.x
        );
        for s in stokes_probe() {
            let o = m * s;
            assert!(o.x >= -1e-6, "{what}: negative intensity {o} from {s}");
            if o.x > 1e-6 {
                let dop = degree_of_polarization(o);
                assert!(dop <= 1.0 + 1e-4, "{what}: DoP {dop} from {s}");
            }
        }
    }

    #[test]
    fn m00_is_the_unpolarized_fresnel() {
        for eta in [1.5f32, 1.33, 2.4, 1.0 / 1.5] {
            for i in -20..=20 {
                let c = i as f32 / 20.0;
                let r = reflection_mueller(c, Complex::real(eta));
                let f = fresnel_dielectric(c, eta);
                assert!((r.x_axis.x - f).abs() < 2e-5, "η {eta} cos {c}");
                let t = transmission_mueller(c, eta);
                if f < 1.0 && c != 0.0 {
                    assert!((t.x_axis.x - (1.0 - f)).abs() < 2e-5, "η {eta} cos {c}");
                }
                assert_realizable(r, "reflection");
                assert_realizable(t, "transmission");
            }
        }
        for (n, k) in [(0.143f32, 3.983f32), (1.6575, 9.2238), (0.2, 2.45)] {
            for i in 0..=20 {
                let c = i as f32 / 20.0;
                let r = reflection_mueller(c, Complex::new(n, -k));
                let f = fresnel_conductor(c, n, k);
                assert!((r.x_axis.x - f).abs() < 1e-4, "n {n} k {k} cos {c}");
                assert_realizable(r, "conductor");
            }
        }
        assert_realizable(ideal_conductor_mueller(), "ideal conductor");
    }

    #[test]
    fn brewster_reflection_is_purely_s() {
        let eta = 1.5f32;
        let theta_b = eta.atan();
        let a = fresnel_amplitudes(theta_b.cos(), Complex::real(eta));
        assert!(a.r_p.norm2() < 1e-12, "{a:?}");
        // The reflected light of unpolarised light is fully polarised, along s (Q > 0).
        let s = reflection_mueller(theta_b.cos(), Complex::real(eta)) * Vec4::X;
        assert!(
            (degree_of_polarization(s) - 1.0).abs() < 1e-4 && s.y > 0.0,
            "{s}"
        );
    }

    #[test]
    fn total_internal_reflection_keeps_intensity_and_shifts_phase() {
        let eta = 1.5f32; // glass; from inside η' = 1/1.5, critical angle 41.8°
        let n = 1.0 / eta;
        for deg in [42.0f32, 45.0, 50.0, 60.0, 70.0, 85.0] {
            let th = deg.to_radians();
            let a = fresnel_amplitudes(-th.cos(), Complex::real(eta));
            assert!((a.r_s.norm2() - 1.0).abs() < 1e-5 && (a.r_p.norm2() - 1.0).abs() < 1e-5);
            let m = reflection_mueller(-th.cos(), Complex::real(eta));
            assert!((m.x_axis.x - 1.0).abs() < 1e-5 && m.row(0).y.abs() < 1e-5);
            // Born & Wolf §1.5.4: tan(δ/2) = cos θ √(sin²θ − n²) / sin²θ.
            let s2 = th.sin() * th.sin();
            let want = 2.0 * (th.cos() * (s2 - n * n).sqrt() / s2).atan();
            let got = (a.r_p.arg() - a.r_s.arg()).rem_euclid(std::f32::consts::TAU);
            assert!((got - want).abs() < 1e-4, "{deg}°: δ {got} vs {want}");
            // The U–V block is the retarder of that phase.
            assert!((m.z_axis.z - want.cos()).abs() < 1e-4, "{deg}°");
            assert!((m.w_axis.z.abs() - want.sin()).abs() < 1e-4, "{deg}°");
            assert_realizable(m, "TIR");
        }
    }

    #[test]
    fn reflection_and_transmission_are_reciprocal() {
        // The normalised matrices do not depend on which side the light comes from (the
        // s/p ratio of t is symmetric for a Snell pair: reciprocity of the interface).
        for eta in [1.5f32, 1.33] {
            for i in 1..20 {
                let ci = i as f32 / 20.0;
                let ct = (1.0 - (1.0 - ci * ci) / (eta * eta)).sqrt();
                let a = transmission_mueller(ci, eta);
                let b = transmission_mueller(-ct, eta);
                let (na, nb) = (a * (1.0 / a.x_axis.x), b * (1.0 / b.x_axis.x));
                assert!(
                    na.abs_diff_eq(nb, 1e-4),
                    "η {eta} cos {ci}: {na:?} vs {nb:?}"
                );
                // Energy: T(θi) from outside equals T(θt) from inside.
                assert!((a.x_axis.x - b.x_axis.x).abs() < 1e-4);
            }
        }
    }
}
