//! The colour lanes a path carries: RGB, or four hero wavelengths in scenes with a dispersive
//! material (Wilkie et al. 2014, "Hero Wavelength Spectral Sampling"), or one wavelength in
//! every lane when the scene's light is a single spectral line (`RenderSettings::light_line_nm`).

use crate::math::{Color, rgb3, spectrum};
use glam::Vec3;

/// A scene-wide light line: every emitter radiates only at `nm`; `rgb` is the colour one unit
/// of lane value stands for (`spectrum::light_line_rgb`, computed once per render).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightLine {
    pub nm: f32,
    pub rgb: Vec3,
}

impl LightLine {
    /// The line at `nm` (checked by the caller: `spectrum::check_light_line`).
    pub fn new(nm: f32) -> LightLine {
        LightLine {
            nm,
            rgb: spectrum::light_line_rgb(nm),
        }
    }
}

/// Colour representation of one path: RGB, four hero wavelengths (dispersive scenes), or the
/// light line's wavelength in all four lanes.
#[derive(Clone, Copy, Debug)]
pub struct Spectral {
    pub lambdas: Option<[f32; 4]>,
    /// Set when the lanes all carry the light line's wavelength.
    pub line: Option<LightLine>,
}

impl Spectral {
    /// RGB lanes (no hero wavelengths).
    pub const RGB: Spectral = Spectral {
        lambdas: None,
        line: None,
    };

    /// RGB lanes, or hero wavelengths drawn from `u` when `spectral`, or — whatever
    /// `spectral` — the light line's wavelength in every lane when `line` is set (no
    /// wavelength is sampled then and `u` is not called: the walk's random numbers are those
    /// of an RGB render, so a grey scene renders the same path by path).
    #[inline]
    pub fn new(spectral: bool, line: Option<LightLine>, u: impl FnOnce() -> f32) -> Spectral {
        if let Some(l) = line {
            return Spectral {
                lambdas: Some([l.nm; 4]),
                line,
            };
        }
        Spectral {
            lambdas: spectral.then(|| spectrum::sample_hero_wavelengths(u())),
            line: None,
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
        if let Some(l) = self.line {
            // Four estimates of the same wavelength (one after a collapse, which put 4× the
            // hero in lane 0): their mean is the line's lane value.
            return (c.x + c.y + c.z + c.w) * 0.25 * l.rgb;
        }
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
