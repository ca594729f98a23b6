//! The film: f64 accumulation of pixel samples with a NaN firewall ([`Film`]), tone mapping
//! for display ([`tonemap`]) and image files ([`image_io`]). Colour transfer functions live in
//! [`crate::math::color`].

pub mod atomic;
pub mod image_io;
pub mod tonemap;

pub use atomic::write_atomically;
pub use image_io::{check_output_path, load_exr, probe_writable, save_image};
pub use tonemap::{ToneMap, exposure_scale, to_srgb8};

use glam::Vec3;

/// The largest film we allocate (2 GiB: 89 M pixels, 8K fits): a clear error beyond, never
/// an allocation failure (the largest allowed side, 16384², would need 6.4 GB).
pub const MAX_FILM_BYTES: u64 = 2 << 30;

/// Accumulates radiance samples per pixel in f64 (f32 running sums drift by ~1% at 2²⁰ spp).
#[derive(Clone, Debug)]
pub struct Film {
    pub width: u32,
    pub height: u32,
    /// Per-pixel sum of accepted sample values.
    sum: Vec<[f64; 3]>,
    /// Samples per pixel taken so far (every pixel gets the same number).
    pub spp: u64,
    /// Samples dropped because they were non-finite or negative.
    pub dropped: u64,
}

/// A sample is accepted only if every component is finite and non-negative.
#[inline]
pub fn sample_is_valid(v: Vec3) -> bool {
    v.is_finite() && v.min_element() >= 0.0
}

impl Film {
    /// Bytes of the accumulation film of a `width` × `height` image (three f64 per pixel).
    pub fn bytes_for(width: u32, height: u32) -> u64 {
        width as u64 * height as u64 * 24
    }

    pub fn new(width: u32, height: u32) -> Film {
        Film {
            width,
            height,
            sum: vec![[0.0; 3]; (width as usize) * (height as usize)],
            spp: 0,
            dropped: 0,
        }
    }

    pub fn pixel_count(&self) -> usize {
        self.sum.len()
    }

    /// Mutable per-pixel sums (row-major) for parallel rendering.
    pub fn sums_mut(&mut self) -> &mut [[f64; 3]] {
        &mut self.sum
    }

    /// Add a sample to a row's pixel (the firewall: invalid samples are dropped and counted by
    /// the caller through the return value).
    #[inline]
    pub fn add_to(px: &mut [f64; 3], v: Vec3) -> bool {
        accumulate(px, v, sample_is_valid(v))
    }

    /// Add a spectral-mode sample: a single-wavelength estimate converted to RGB can be
    /// legitimately outside the sRGB gamut (a negative channel), so only non-finite samples
    /// are dropped here; per-pixel means converge to the in-gamut colour.
    #[inline]
    pub fn add_signed_to(px: &mut [f64; 3], v: Vec3) -> bool {
        accumulate(px, v, v.is_finite())
    }

    /// [`Film::add_signed_to`] for a spectral render (`signed`), else [`Film::add_to`].
    #[inline]
    pub fn add_sample_to(px: &mut [f64; 3], v: Vec3, signed: bool) -> bool {
        if signed {
            Film::add_signed_to(px, v)
        } else {
            Film::add_to(px, v)
        }
    }

    /// Add a light-tracing splat to pixel (x, y) (false when it lies outside the film or the
    /// firewall of [`Film::add_to`] drops it).
    pub fn add_splat(&mut self, x: u32, y: u32, v: Vec3) -> bool {
        if x >= self.width || y >= self.height {
            return false;
        }
        let i = (y * self.width + x) as usize;
        Film::add_to(&mut self.sum[i], v)
    }

    /// Mean radiance of pixel (x, y).
    pub fn pixel(&self, x: u32, y: u32) -> Vec3 {
        mean(self.sum[(y * self.width + x) as usize], self.spp)
    }

    /// Mean radiance image, row-major, top row first.
    pub fn image(&self) -> Vec<Vec3> {
        self.sum.iter().map(|&s| mean(s, self.spp)).collect()
    }

    /// Merge another film of the same size (sums, spp and drop counts add).
    pub fn merge(&mut self, other: &Film) {
        assert_eq!((self.width, self.height), (other.width, other.height));
        for (a, b) in self.sum.iter_mut().zip(&other.sum) {
            for k in 0..3 {
                a[k] += b[k];
            }
        }
        self.spp += other.spp;
        self.dropped += other.dropped;
    }
}

/// Add `v` to the pixel sum `px` when `accept`; returns `accept`.
#[inline]
fn accumulate(px: &mut [f64; 3], v: Vec3, accept: bool) -> bool {
    if accept {
        px[0] += v.x as f64;
        px[1] += v.y as f64;
        px[2] += v.z as f64;
    }
    accept
}

/// Mean of a pixel sum over `spp` samples (0 samples: the sum itself).
#[inline]
fn mean(s: [f64; 3], spp: u64) -> Vec3 {
    let n = spp.max(1) as f64;
    Vec3::new((s[0] / n) as f32, (s[1] / n) as f32, (s[2] / n) as f32)
}
