//! The colour lanes a path carries: RGB, or four hero wavelengths in scenes with a dispersive
//! material (Wilkie et al. 2014, "Hero Wavelength Spectral Sampling").

use crate::math::{Color, rgb3, spectrum};
use glam::Vec3;

/// Colour representation of one path: RGB, or four hero wavelengths (dispersive scenes).
#[derive(Clone, Copy, Debug)]
pub struct Spectral {
    pub lambdas: Option<[f32; 4]>,
}

impl Spectral {
    /// RGB lanes (no hero wavelengths).
    pub const RGB: Spectral = Spectral { lambdas: None };

    /// RGB lanes, or hero wavelengths drawn from `u` when `spectral`.
    #[inline]
    pub fn new(spectral: bool, u: impl FnOnce() -> f32) -> Spectral {
        Spectral {
            lambdas: spectral.then(|| spectrum::sample_hero_wavelengths(u())),
        }
    }

    /// RGB parameter → the path's colour lanes (smooth uplift in spectral mode).
    #[inline]
    pub fn c(&self, rgb: Vec3) -> Color {
        match self.lambdas {
            Some(l) => spectrum::rgb_to_spectrum4(rgb, l),
            None => rgb3(rgb),
        }
    }

    /// The path's estimate in linear RGB.
    #[inline]
    pub fn to_rgb(&self, c: Color) -> Vec3 {
        match self.lambdas {
            Some(l) => spectrum::spectrum_sample_to_rgb(l, c),
            None => c.truncate(),
        }
    }
}

/// Keep only the hero lane after a dispersive event (Wilkie et al. 2014, §4.2): the other
/// wavelengths cannot follow the hero's refracted direction.
#[inline]
pub fn collapse_lanes(c: Color) -> Color {
    Color::new(c.x, 0.0, 0.0, 0.0)
}

/// A full path's estimate once some vertex collapsed it: the hero lane stands for all four
/// wavelengths (×4, exact in floating point, applied once per path).
#[inline]
pub fn finish_collapsed(c: Color, collapsed: bool) -> Color {
    if collapsed {
        Color::new(4.0 * c.x, 0.0, 0.0, 0.0)
    } else {
        c
    }
}
