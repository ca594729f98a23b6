//! Degree and angle of polarisation as images (issue 38, `render --aov dop,aop`), from the
//! mean Stokes vector of each pixel (luminance of each component: I, Q, U and V are linear
//! in the light, so their luminances are the Stokes vector of the luminance).
//!
//! - Degree of polarisation √(Q² + U² + V²) / I through a sequential map: black (0,
//!   unpolarised) through purple, red and orange to pale yellow (1, fully polarised); five
//!   stops of matplotlib's "inferno" map (van der Walt & Smith 2015), linear between them.
//! - Angle of polarisation ½ atan2(U, Q) as hue, counted from the image's horizontal
//!   counter-clockwise: 0° red, 30° yellow, 60° green, 90° cyan, 120° blue, 150° magenta,
//!   180° red again (the angle is periodic in 180°); brightness min(1, 2·DoP), so
//!   unpolarised light is black and DoP ≥ 0.5 shows at full brightness.
//!
//! Pixels without light (I ≤ 0) are black in both. The images are display colours; they
//! are returned as linear RGB for `film::save_image`, which encodes PNGs as sRGB.

use crate::math::color::{luminance, srgb_to_linear};
use crate::math::mueller::{angle_of_polarization, degree_of_polarization};
use glam::{Vec3, Vec4};

/// The luminance Stokes vector of a pixel's mean (I, Q, U, V) RGB components.
#[inline]
pub fn luminance_stokes(c: [Vec3; 4]) -> Vec4 {
    Vec4::new(
        luminance(c[0]),
        luminance(c[1]),
        luminance(c[2]),
        luminance(c[3]),
    )
}

/// Five stops of "inferno" in sRGB display values, at 0, ¼, ½, ¾, 1.
const INFERNO: [[f32; 3]; 5] = [
    [0.001, 0.000, 0.014],
    [0.341, 0.062, 0.429],
    [0.735, 0.215, 0.330],
    [0.978, 0.557, 0.035],
    [0.988, 0.998, 0.645],
];

/// The sequential map at `t` ∈ [0, 1] (display sRGB).
pub fn dop_colour(t: f32) -> Vec3 {
    let x = t.clamp(0.0, 1.0) * 4.0;
    let i = (x.floor() as usize).min(3);
    let f = x - i as f32;
    Vec3::from(INFERNO[i]).lerp(Vec3::from(INFERNO[i + 1]), f)
}

/// The cyclic hue of an angle of polarisation `aop` (radians, period π) at brightness `v`
/// (display sRGB; HSV with full saturation).
pub fn aop_colour(aop: f32, v: f32) -> Vec3 {
    let h = (aop / std::f32::consts::PI).rem_euclid(1.0) * 6.0;
    let k = |n: f32| {
        let k = (n + h) % 6.0;
        1.0 - k.min(4.0 - k).clamp(0.0, 1.0)
    };
    Vec3::new(k(5.0), k(3.0), k(1.0)) * v.clamp(0.0, 1.0)
}

/// Linear RGB of a display colour.
#[inline]
fn linear(c: Vec3) -> Vec3 {
    Vec3::new(
        srgb_to_linear(c.x),
        srgb_to_linear(c.y),
        srgb_to_linear(c.z),
    )
}

/// Each pixel's mean Stokes vector (I, Q, U, V, linear RGB each) from a four-layer Stokes
/// film (`polarized::render`) over `spp` samples.
pub fn stokes_pixels(stokes: &crate::cpu::layers::LayerFilm, spp: u64) -> Vec<[Vec3; 4]> {
    let layers: Vec<Vec<Vec3>> = (0..4).map(|k| stokes.image(k, spp)).collect();
    (0..layers[0].len())
        .map(|i| std::array::from_fn(|k| layers[k][i]))
        .collect()
}

/// Degree of polarisation per pixel (0 without light).
pub fn dop_values(stokes: &[[Vec3; 4]]) -> Vec<f32> {
    stokes
        .iter()
        .map(|&c| degree_of_polarization(luminance_stokes(c)).min(1.0))
        .collect()
}

/// The false-colour degree-of-polarisation image (linear RGB).
pub fn dop_image(stokes: &[[Vec3; 4]]) -> Vec<Vec3> {
    stokes
        .iter()
        .map(|&c| {
            let s = luminance_stokes(c);
            if s.x <= 0.0 {
                Vec3::ZERO
            } else {
                linear(dop_colour(degree_of_polarization(s)))
            }
        })
        .collect()
}

/// The false-colour angle-of-polarisation image (linear RGB).
pub fn aop_image(stokes: &[[Vec3; 4]]) -> Vec<Vec3> {
    stokes
        .iter()
        .map(|&c| {
            let s = luminance_stokes(c);
            if s.x <= 0.0 {
                return Vec3::ZERO;
            }
            let dop = degree_of_polarization(s).min(1.0);
            linear(aop_colour(angle_of_polarization(s), 2.0 * dop))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::PI;

    #[test]
    fn aop_hue_is_periodic_in_pi_and_red_at_zero() {
        let a = aop_colour(0.0, 1.0);
        assert!((a - Vec3::X).abs().max_element() < 1e-6, "{a}");
        let b = aop_colour(PI, 1.0);
        assert!((a - b).abs().max_element() < 1e-5, "{b}");
        let g = aop_colour(PI / 3.0, 1.0);
        assert!((g - Vec3::Y).abs().max_element() < 1e-5, "{g}");
        assert_eq!(aop_colour(0.3, 0.0), Vec3::ZERO);
    }

    #[test]
    fn dop_map_ends() {
        assert!(dop_colour(0.0).max_element() < 0.02);
        assert!(dop_colour(1.0).min_element() > 0.6);
        assert_eq!(dop_colour(-1.0), dop_colour(0.0));
        // Horizontal linear light: DoP 1, AoP 0.
        let px = [Vec3::ONE, Vec3::ONE, Vec3::ZERO, Vec3::ZERO];
        assert_eq!(dop_values(&[px]), [1.0]);
    }
}
