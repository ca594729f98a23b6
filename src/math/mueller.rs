//! Stokes vectors and Mueller matrices (Collett, "Polarized Light", 2nd ed., ch. 4–5;
//! Wilkie & Weidlich 2012, "Polarised Light in Computer Graphics", SIGGRAPH Asia course).
//!
//! A Stokes vector S = (I, Q, U, V) (a `Vec4`) describes light travelling along a
//! direction d with respect to a reference vector x ⊥ d; with y = d × x the frame (x, y, d)
//! is right-handed, so the light is seen by an observer looking back into the beam with x
//! to the right and y up. For a field E = (Eₓ, E_y) in that frame
//!   I = |Eₓ|² + |E_y|²,  Q = |Eₓ|² − |E_y|²,  U = 2 Re(Eₓ E_y*),  V = −2 Im(Eₓ E_y*),
//! so linear polarisation at angle χ from x towards y has (Q, U) = I (cos 2χ, sin 2χ).
//! A Mueller matrix (a `Mat4`, glam column-major; build it from rows with [`from_rows`])
//! maps an input Stokes vector, in its input frame, to the output one in the output frame.

use super::complex::Complex;
use glam::{Mat4, Vec4};

/// A Mueller matrix written row by row.
#[inline]
pub fn from_rows(r: [[f32; 4]; 4]) -> Mat4 {
    Mat4::from_cols_array_2d(&r).transpose()
}

/// Unpolarised light of intensity `i`.
#[inline]
pub fn unpolarized(i: f32) -> Vec4 {
    Vec4::new(i, 0.0, 0.0, 0.0)
}

/// The change of reference frame: a Stokes vector given with respect to x, re-expressed
/// with respect to x' = cos θ x + sin θ y (x turned by θ counter-clockwise about the
/// direction of travel, seen looking into the beam). Linear polarisation at χ in the old
/// frame is at χ − θ in the new one (Collett ch. 5 eq. 43, the "rotator").
#[inline]
pub fn rotator(theta: f32) -> Mat4 {
    let (s, c) = (2.0 * theta).sin_cos();
    from_rows([
        [1.0, 0.0, 0.0, 0.0],
        [0.0, c, s, 0.0],
        [0.0, -s, c, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ])
}

/// An ideal linear polariser whose transmission axis is at `angle` from the frame's x
/// towards y (Collett ch. 5 eq. 13 at angle 0, turned by [`rotator`]: R(−α) P₀ R(α)).
pub fn linear_polarizer(angle: f32) -> Mat4 {
    let p0 = from_rows([
        [0.5, 0.5, 0.0, 0.0],
        [0.5, 0.5, 0.0, 0.0],
        [0.0; 4],
        [0.0; 4],
    ]);
    rotator(-angle) * p0 * rotator(angle)
}

/// The ideal depolariser: keeps the intensity, forgets the polarisation (a Lambertian
/// surface; Wilkie & Weidlich 2012 §4).
#[inline]
pub fn depolarizer() -> Mat4 {
    from_rows([[1.0, 0.0, 0.0, 0.0], [0.0; 4], [0.0; 4], [0.0; 4]])
}

/// The Mueller matrix of the diagonal Jones matrix diag(a, b) (Eₓ' = a Eₓ, E_y' = b E_y):
/// with c = a b*,
///   [ (|a|²+|b|²)/2  (|a|²−|b|²)/2  0     0    ]
///   [ (|a|²−|b|²)/2  (|a|²+|b|²)/2  0     0    ]
///   [ 0              0              Re c  Im c ]
///   [ 0              0             −Im c  Re c ]
/// (Azzam & Bashara, "Ellipsometry and Polarized Light", §2.11; with the V sign above). A
/// Fresnel interface is such a matrix in its s/p basis (x = s), with a = r_s, b = r_p.
pub fn from_jones_diagonal(a: Complex, b: Complex) -> Mat4 {
    let (aa, bb) = (a.norm2(), b.norm2());
    let c = a * b.conj();
    let (p, m) = (0.5 * (aa + bb), 0.5 * (aa - bb));
    from_rows([
        [p, m, 0.0, 0.0],
        [m, p, 0.0, 0.0],
        [0.0, 0.0, c.re, c.im],
        [0.0, 0.0, -c.im, c.re],
    ])
}

/// `m` / m₀₀ (the polarising part of an event whose intensity the scalar walk already
/// carries); the depolariser when m₀₀ is 0 or not finite.
#[inline]
pub fn normalized(m: Mat4) -> Mat4 {
    let m00 = m.x_axis.x;
    if m00 > 0.0 && m00.is_finite() {
        m * (1.0 / m00)
    } else {
        depolarizer()
    }
}

/// Degree of polarisation √(Q² + U² + V²) / I (0 for I ≤ 0).
#[inline]
pub fn degree_of_polarization(s: Vec4) -> f32 {
    if s.x <= 0.0 {
        return 0.0;
    }
    (s.y * s.y + s.z * s.z + s.w * s.w).sqrt() / s.x
}

/// Angle of (linear) polarisation ½ atan2(U, Q), in (−π/2, π/2], from the frame's x.
#[inline]
pub fn angle_of_polarization(s: Vec4) -> f32 {
    0.5 * s.z.atan2(s.y)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::{FRAC_PI_2, PI};

    fn close(a: Mat4, b: Mat4, tol: f32) -> bool {
        a.to_cols_array()
            .iter()
            .zip(b.to_cols_array())
            .all(|(x, y)| (x - y).abs() <= tol)
    }

    #[test]
    fn rotation_by_zero_is_identity_and_by_pi_acts_as_identity() {
        assert!(close(rotator(0.0), Mat4::IDENTITY, 0.0));
        assert!(close(rotator(PI), Mat4::IDENTITY, 1e-6));
        // By π/2 the frame's x and y swap: horizontal light becomes vertical.
        let s = rotator(FRAC_PI_2) * Vec4::new(1.0, 1.0, 0.0, 0.0);
        assert!(
            (s - Vec4::new(1.0, -1.0, 0.0, 0.0)).abs().max_element() < 1e-6,
            "{s}"
        );
        // Rotations compose: R(a) R(b) = R(a + b).
        assert!(close(rotator(0.3) * rotator(0.5), rotator(0.8), 1e-6));
    }

    #[test]
    fn malus_law_through_two_polarizers() {
        let i0 = 3.0;
        let first = linear_polarizer(0.2) * unpolarized(2.0 * i0);
        assert!((first.x - i0).abs() < 1e-6);
        for k in 0..=36 {
            let theta = k as f32 * PI / 36.0;
            let out = linear_polarizer(0.2 + theta) * first;
            let want = i0 * theta.cos().powi(2);
            assert!(
                (out.x - want).abs() < 1e-5,
                "θ {theta}: {} vs {want}",
                out.x
            );
            // What leaves a polariser is fully polarised along its axis.
            if out.x > 1e-3 {
                assert!((degree_of_polarization(out) - 1.0).abs() < 1e-4);
                let aop = angle_of_polarization(out);
                let d = (aop - (0.2 + theta)).rem_euclid(PI);
                assert!(d.min(PI - d) < 1e-3, "AoP {aop} vs {}", 0.2 + theta);
            }
        }
    }

    #[test]
    fn jones_diagonal_of_a_polarizer_and_a_retarder() {
        // diag(1, 0): the polariser at 0°.
        let p = from_jones_diagonal(Complex::ONE, Complex::ZERO);
        assert!(close(p, linear_polarizer(0.0), 1e-6));
        // diag(1, i): a quarter-wave retarder turns +45° linear into circular light.
        let q = from_jones_diagonal(Complex::ONE, Complex::new(0.0, 1.0));
        let s = q * Vec4::new(1.0, 0.0, 1.0, 0.0);
        assert!((s.x - 1.0).abs() < 1e-6 && s.y.abs() < 1e-6 && s.z.abs() < 1e-6);
        assert!((s.w.abs() - 1.0).abs() < 1e-6, "{s}");
    }

    #[test]
    fn normalized_has_unit_m00_and_falls_back_to_the_depolarizer() {
        let m = from_jones_diagonal(Complex::real(-0.4), Complex::real(0.1));
        assert!((normalized(m).x_axis.x - 1.0).abs() < 1e-6);
        assert_eq!(normalized(Mat4::ZERO), depolarizer());
    }
}
