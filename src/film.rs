//! The film: f64 accumulation of pixel samples with a NaN firewall, and image output.

use glam::Vec3;
use std::path::Path;

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
        if sample_is_valid(v) {
            px[0] += v.x as f64;
            px[1] += v.y as f64;
            px[2] += v.z as f64;
            true
        } else {
            false
        }
    }

    /// Add a spectral-mode sample: a single-wavelength estimate converted to RGB can be
    /// legitimately outside the sRGB gamut (a negative channel), so only non-finite samples
    /// are dropped here; per-pixel means converge to the in-gamut colour.
    #[inline]
    pub fn add_signed_to(px: &mut [f64; 3], v: Vec3) -> bool {
        if v.is_finite() {
            px[0] += v.x as f64;
            px[1] += v.y as f64;
            px[2] += v.z as f64;
            true
        } else {
            false
        }
    }

    /// Add light-tracing splats (already divided by nothing; `scale` applied here).
    pub fn add_splat(&mut self, x: u32, y: u32, v: Vec3) -> bool {
        if x >= self.width || y >= self.height {
            return false;
        }
        let i = (y * self.width + x) as usize;
        Film::add_to(&mut self.sum[i], v)
    }

    /// Mean radiance of pixel (x, y).
    pub fn pixel(&self, x: u32, y: u32) -> Vec3 {
        let s = self.sum[(y * self.width + x) as usize];
        let n = self.spp.max(1) as f64;
        Vec3::new((s[0] / n) as f32, (s[1] / n) as f32, (s[2] / n) as f32)
    }

    /// Mean radiance image, row-major, top row first.
    pub fn image(&self) -> Vec<Vec3> {
        let n = self.spp.max(1) as f64;
        self.sum
            .iter()
            .map(|s| Vec3::new((s[0] / n) as f32, (s[1] / n) as f32, (s[2] / n) as f32))
            .collect()
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

/// Linear → sRGB transfer (IEC 61966-2-1).
#[inline]
pub fn linear_to_srgb(x: f32) -> f32 {
    if x <= 0.003_130_8 {
        12.92 * x.max(0.0)
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    }
}

/// sRGB → linear transfer (IEC 61966-2-1).
#[inline]
pub fn srgb_to_linear(x: f32) -> f32 {
    if x <= 0.040_45 {
        x / 12.92
    } else {
        ((x + 0.055) / 1.055).powf(2.4)
    }
}

/// Tone mapping for display and PNG output.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ToneMap {
    /// Exposure then clamp (what a physically based comparison wants).
    #[default]
    Clamp,
    /// Reinhard x/(1+x) on each channel.
    Reinhard,
    /// ACES filmic fit (Narkowicz 2015).
    Aces,
}

impl ToneMap {
    #[inline]
    pub fn apply(self, x: f32) -> f32 {
        match self {
            ToneMap::Clamp => x.clamp(0.0, 1.0),
            ToneMap::Reinhard => (x / (1.0 + x)).clamp(0.0, 1.0),
            // Narkowicz 2015, "ACES Filmic Tone Mapping Curve".
            ToneMap::Aces => {
                ((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14)).clamp(0.0, 1.0)
            }
        }
    }
}

/// 8-bit sRGB pixels (RGBA) of a linear image after exposure (in stops) and tone mapping.
pub fn to_srgb8(img: &[Vec3], exposure: f32, tone: ToneMap) -> Vec<u8> {
    let scale = 2f32.powf(exposure);
    let mut out = Vec::with_capacity(img.len() * 4);
    for p in img {
        for c in [p.x, p.y, p.z] {
            let v = linear_to_srgb(tone.apply(c * scale));
            out.push((v * 255.0 + 0.5).clamp(0.0, 255.0) as u8);
        }
        out.push(255);
    }
    out
}

/// Check that `path` names a format we can write (call before rendering).
pub fn check_output_path(path: &Path) -> anyhow::Result<()> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
        .unwrap_or_default();
    anyhow::ensure!(
        ext == "exr" || ext == "png",
        "unsupported output format '{}': use .exr (linear) or .png (sRGB)",
        path.display()
    );
    Ok(())
}

/// Write `img` (linear radiance) to `path`: `.exr` = linear float RGB, `.png` = tone-mapped sRGB.
pub fn save_image(
    path: &Path,
    width: u32,
    height: u32,
    img: &[Vec3],
    exposure: f32,
    tone: ToneMap,
) -> anyhow::Result<()> {
    use anyhow::Context;
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
        .unwrap_or_default();
    if let Some(dir) = path.parent()
        && !dir.as_os_str().is_empty()
    {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("cannot create folder '{}'", dir.display()))?;
    }
    match ext.as_str() {
        "exr" => {
            let data: Vec<f32> = img.iter().flat_map(|p| [p.x, p.y, p.z]).collect();
            let buf = image::Rgb32FImage::from_raw(width, height, data)
                .context("image buffer size does not match its dimensions")?;
            image::DynamicImage::ImageRgb32F(buf)
                .save_with_format(path, image::ImageFormat::OpenExr)
                .with_context(|| format!("cannot write '{}'", path.display()))?;
        }
        "png" => {
            let data = to_srgb8(img, exposure, tone);
            let buf = image::RgbaImage::from_raw(width, height, data)
                .context("image buffer size does not match its dimensions")?;
            buf.save_with_format(path, image::ImageFormat::Png)
                .with_context(|| format!("cannot write '{}'", path.display()))?;
        }
        _ => anyhow::bail!(
            "unsupported output format '{}': use .exr (linear) or .png (sRGB)",
            path.display()
        ),
    }
    Ok(())
}

/// Read a linear RGB EXR back (used by tests and `bench`).
pub fn load_exr(path: &Path) -> anyhow::Result<(u32, u32, Vec<Vec3>)> {
    use anyhow::Context;
    let img = image::open(path)
        .with_context(|| format!("cannot read '{}'", path.display()))?
        .into_rgb32f();
    let (w, h) = img.dimensions();
    let px = img.pixels().map(|p| Vec3::new(p[0], p[1], p[2])).collect();
    Ok((w, h, px))
}
