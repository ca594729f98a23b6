//! Low-level maths shared by every layer: frames, sampling warps, the counter-based RNG,
//! colour (sRGB, luminance, black body) and spectral helpers. Knows nothing about scenes, renderers or the UI.

pub mod color;
pub mod complex;
pub mod distribution;
pub mod fnv;
pub mod frame;
pub mod mueller;
pub mod prism;
pub mod rng;
pub mod sampling;
pub mod spectrum;

pub use frame::Frame;

/// Colour / spectral throughput type used everywhere.
///
/// In RGB mode lanes x, y, z are linear Rec.709 R, G, B and w is 0. In spectral mode
/// (scenes with dispersion) the four lanes are the values at the path's four hero-rotated
/// wavelengths (Wilkie et al. 2014, "Hero Wavelength Spectral Sampling").
pub type Color = glam::Vec4;

/// Build an RGB colour (w = 0).
#[inline]
pub fn rgb(r: f32, g: f32, b: f32) -> Color {
    Color::new(r, g, b, 0.0)
}

/// Build an RGB colour from a `Vec3` (w = 0).
#[inline]
pub fn rgb3(c: glam::Vec3) -> Color {
    c.extend(0.0)
}

/// Largest component of the first three lanes (RGB) or all four (spectral: w is 0 in RGB).
#[inline]
pub fn max_comp(c: Color) -> f32 {
    c.max_element()
}
