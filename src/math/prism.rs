//! A ray through a prism in its principal section: Snell's law at both faces gives the
//! deviation δ(n) = θ_i + θ_e − A for apex angle A and incidence θ_i (Hecht, *Optics*, 5th ed.,
//! §5.5.1, eq. 5.52). With n(λ) this is the angle each wavelength leaves at: dispersion.

/// Fraunhofer lines: (name, wavelength in nm) of F (hydrogen, blue), d (helium, yellow) and
/// C (hydrogen, red), the lines the Abbe number V_d = (n_d − 1)/(n_F − n_C) is defined on.
pub const FRAUNHOFER_F: (&str, f32) = ("F", 486.13);
pub const FRAUNHOFER_D: (&str, f32) = ("d", 587.56);
pub const FRAUNHOFER_C: (&str, f32) = ("C", 656.27);

/// The sodium D line (the mean of D₁ and D₂), a classic monochromatic lamp.
pub const SODIUM_D_NM: f32 = 589.3;

/// Deviation (radians) of a ray meeting the first face at `theta_i` (radians from the
/// normal) through a prism of apex `apex` and index `n` (outside 1); None when the ray is
/// totally reflected at the second face. Hecht §5.5.1: sin θ₁' = sin θ_i / n,
/// θ₂ = A − θ₁', sin θ_e = n sin θ₂, δ = θ_i + θ_e − A.
pub fn deviation(n: f32, apex: f32, theta_i: f32) -> Option<f32> {
    let inside_1 = (theta_i.sin() / n).asin();
    let inside_2 = apex - inside_1;
    let sin_e = n * inside_2.sin();
    (sin_e.abs() <= 1.0).then(|| theta_i + sin_e.asin() - apex)
}

/// The incidence at which index `n` passes with minimum deviation (the symmetric path,
/// θ₁' = A/2): sin θ_i = n sin(A/2).
pub fn min_deviation_incidence(n: f32, apex: f32) -> Option<f32> {
    let s = n * (apex / 2.0).sin();
    (s <= 1.0).then(|| s.asin())
}

/// Abbe number of a dispersion curve n(λ): V_d = (n_d − 1)/(n_F − n_C).
pub fn abbe_number(n: impl Fn(f32) -> f32) -> f32 {
    let (f, d, c) = (n(FRAUNHOFER_F.1), n(FRAUNHOFER_D.1), n(FRAUNHOFER_C.1));
    (d - 1.0) / (f - c)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::spectrum::cauchy_from_abbe;

    const A: f32 = std::f32::consts::FRAC_PI_3;

    #[test]
    fn minimum_deviation_is_symmetric_and_minimal() {
        let n = 1.5168;
        let ti = min_deviation_incidence(n, A).unwrap();
        let d = deviation(n, A, ti).unwrap();
        // Symmetric path: δ_min = 2θ_i − A, and sin((A + δ_min)/2) = n sin(A/2).
        assert!((d - (2.0 * ti - A)).abs() < 1e-5, "{d}");
        assert!((((A + d) / 2.0).sin() - n * (A / 2.0).sin()).abs() < 1e-5);
        for dt in [-0.05f32, -0.01, 0.01, 0.05] {
            assert!(deviation(n, A, ti + dt).unwrap() > d, "not minimal at {dt}");
        }
    }

    #[test]
    fn blue_bends_more_than_red_and_tir_is_reported() {
        let (n_d, v) = (1.5168, 20.0);
        let ti = min_deviation_incidence(n_d, A).unwrap();
        let dev = |l: f32| deviation(cauchy_from_abbe(n_d, v, l), A, ti).unwrap();
        assert!(dev(FRAUNHOFER_F.1) > dev(FRAUNHOFER_D.1));
        assert!(dev(FRAUNHOFER_D.1) > dev(FRAUNHOFER_C.1));
        // Grazing exit: n sin(A − θ₁') > 1 at small incidence for dense glass.
        assert!(deviation(2.4, A, 0.1).is_none());
    }

    #[test]
    fn the_abbe_model_has_the_abbe_number_it_was_given() {
        for (n_d, v) in [(1.5168, 64.17), (1.5168, 20.0), (1.7, 4.0), (2.42, 55.0)] {
            let got = abbe_number(|l| cauchy_from_abbe(n_d, v, l));
            assert!((got - v).abs() / v < 2e-3, "n_d {n_d} V_d {v}: {got}");
            assert!((cauchy_from_abbe(n_d, v, FRAUNHOFER_D.1) - n_d).abs() < 1e-3);
        }
    }
}
