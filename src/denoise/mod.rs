//! The live view's denoiser (off by default): an edge-avoiding à-trous wavelet filter
//! (Dammertz, Sewtz, Hanika & Lensch 2010, "Edge-avoiding À-Trous wavelet transform for fast
//! global illumination filtering") guided by first-hit albedo, normal and depth, with
//! variance-guided luminance weights (Schied et al. 2017, "Spatiotemporal variance-guided
//! filtering", the spatial part). The filter works on irradiance: radiance divided by the
//! guide's albedo, re-multiplied at the end, so texture and colour edges stay sharp.
//!
//! It reads the mean image and the guides and returns a new image: it never writes to the
//! accumulation film nor to the unbiased output. [`atrous`] is the CPU twin of the WGSL
//! filter (`src/denoise/denoise.wgsl`, run by [`gpu`]); both compute the same thing in f32.

pub mod atrous;
pub mod badge;
pub mod gpu;
pub mod guides;
pub mod weights;

pub use atrous::{denoise, half_variance};
pub use guides::{Guides, render_guides};

/// The filter's parameters (the defaults are those measured in `examples/denoise_relmse.rs`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DenoiseParams {
    /// À-trous iterations: the footprint is 4·(2^n − 1) + 1 pixels wide.
    pub iterations: u32,
    /// Luminance tolerance in standard deviations of the pixel's estimated noise.
    pub sigma_l: f32,
    /// Normal exponent: weight = max(0, n_p·n_q)^sigma_n.
    pub sigma_n: f32,
    /// Depth tolerance in multiples of the local depth gradient times the pixel distance.
    pub sigma_z: f32,
}

impl Default for DenoiseParams {
    fn default() -> Self {
        DenoiseParams {
            iterations: 5,
            sigma_l: 4.0,
            sigma_n: 8.0,
            sigma_z: 1.0,
        }
    }
}
