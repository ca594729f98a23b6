//! Equirectangular environment images (`.hdr`, `.exr`): the texels, the direction ↔ image
//! mapping and the sampling distribution built once per image.
//!
//! Mapping: three.js's equirectangular convention (`equirectUv` in its shader chunks), so an
//! HDRI looks as in glTF viewers: direction d → u = atan2(d.z, d.x)/2π + 0.5,
//! v = asin(d.y)/π + 0.5, v = 1 at the image's top row. Internally the row coordinate
//! t = 1 − v = θ/π (θ the polar angle from +Y) is used, so row 0 is the zenith. The
//! environment may be rotated about +Y by `rotation` degrees (counter-clockwise seen from
//! above): the world direction d reads the image at R_y(−rotation)·d.

use crate::math::color::luminance;
use crate::math::distribution::Distribution2D;
use anyhow::{Context, bail};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;
use std::path::Path;
use std::sync::Arc;

/// The most texels an environment image may have (8192 × 2048; a clear error beyond,
/// checked before decoding).
pub const MAX_ENV_PIXELS: u64 = 8192 * 2048;

/// An equirectangular radiance image and its importance-sampling distribution.
#[derive(Debug, PartialEq)]
pub struct EnvMap {
    pub width: u32,
    pub height: u32,
    /// Linear RGB radiance, row-major, row 0 at the top (the zenith).
    pub texels: Vec<Vec3>,
    /// ∝ mean luminance over the texel × sinθ (PBR 4th ed. §12.5.2 `ImageInfiniteLight`;
    /// the mean of the interpolated image: `texel_means`).
    pub dist: Distribution2D,
    /// ∫ luminance dω over the sphere (of the interpolated image, from the texel means).
    pub lum_integral: f32,
    /// ∫ luminance² dω over the sphere: with `lum_integral`, how concentrated the light is
    /// (`scene::caustic_casters`).
    pub lum_sq_integral: f32,
    /// Where it came from (file name or generator), for logs and the viewer.
    pub name: String,
}

/// An environment image placed in a scene: the image, its strength and rotation.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvImage {
    pub map: Arc<EnvMap>,
    /// Radiance multiplier.
    pub strength: f32,
    /// Rotation about +Y in degrees.
    pub rotation: f32,
    /// Importance-sample the image (the default); false samples directions uniformly on the
    /// sphere (a debug switch for the benchmark's comparison).
    pub importance: bool,
}

impl EnvImage {
    pub fn new(map: Arc<EnvMap>, strength: f32, rotation: f32) -> EnvImage {
        EnvImage {
            map,
            strength,
            rotation,
            importance: true,
        }
    }
}

/// (u, t) ∈ [0,1]² of the image direction `d` (unit; t = 1 − v = θ/π). At the poles
/// (x = z = 0) u is 0.5 (atan2(0, 0) is implementation-defined in WGSL).
#[inline]
pub fn dir_to_uv(d: Vec3) -> Vec2 {
    let u = if d.x == 0.0 && d.z == 0.0 {
        0.5
    } else {
        d.z.atan2(d.x) * (0.5 / PI) + 0.5
    };
    let t = d.y.clamp(-1.0, 1.0).acos() / PI;
    Vec2::new(u, t)
}

/// The image direction of (u, t) (inverse of [`dir_to_uv`]).
#[inline]
pub fn uv_to_dir(uv: Vec2) -> Vec3 {
    let phi = (uv.x - 0.5) * 2.0 * PI;
    let theta = uv.y * PI;
    let s = theta.sin();
    Vec3::new(s * phi.cos(), theta.cos(), s * phi.sin())
}

/// Rotate `d` about +Y by the angle with cosine `c` and sine `s` (right-handed).
#[inline]
pub fn rotate_y(d: Vec3, c: f32, s: f32) -> Vec3 {
    Vec3::new(c * d.x + s * d.z, d.y, -s * d.x + c * d.z)
}

impl EnvMap {
    /// From linear RGB texels (row 0 at the top); non-finite or negative components become 0
    /// and are counted in the returned number.
    pub fn from_texels(
        width: u32,
        height: u32,
        mut texels: Vec<Vec3>,
        name: &str,
    ) -> (EnvMap, u64) {
        assert_eq!(texels.len() as u64, width as u64 * height as u64);
        let mut bad = 0u64;
        for t in &mut texels {
            if !(t.is_finite() && t.min_element() >= 0.0) {
                bad += 1;
                *t = Vec3::select(t.cmpge(Vec3::ZERO) & t.is_finite_mask(), *t, Vec3::ZERO);
            }
        }
        let lum: Vec<f32> = texels.iter().map(|t| luminance(*t).max(0.0)).collect();
        let filtered = texel_means(&lum, width as usize, height as usize);
        let func: Vec<f32> = filtered
            .iter()
            .enumerate()
            .map(|(i, l)| {
                let row = i / width as usize;
                l * (PI * (row as f32 + 0.5) / height as f32).sin()
            })
            .collect();
        let dist = Distribution2D::new(&func, width as usize, height as usize);
        let (lum_integral, lum_sq_integral) = lum_integrals(&filtered, width, height);
        let map = EnvMap {
            width,
            height,
            texels,
            dist,
            lum_integral,
            lum_sq_integral,
            name: name.to_string(),
        };
        (map, bad)
    }

    /// Radiance at (u, t), interpolated bilinearly between texel centres at
    /// ((i + ½)/W, (j + ½)/H) as Mitsuba 3's `envmap` and three.js filter: periodic in u,
    /// clamped to the edge rows in t. See [`bilinear`].
    #[inline]
    pub fn lookup_uv(&self, uv: Vec2) -> Vec3 {
        let ((x0, x1, fx), (y0, y1, fy)) = bilinear(uv, self.width, self.height);
        let w = self.width as usize;
        let row = |y: usize| self.texels[y * w + x0] * (1.0 - fx) + self.texels[y * w + x1] * fx;
        row(y0) * (1.0 - fy) + row(y1) * fy
    }

    /// ∫ luminance dω over the sphere.
    pub fn luminance_integral(&self) -> f32 {
        self.lum_integral
    }

    /// Decode `bytes` of a `.hdr` or `.exr` file (`what` names it in errors), refusing images
    /// above [`MAX_ENV_PIXELS`] before decoding. Returns the map and warnings.
    pub fn decode(bytes: &[u8], ext: &str, what: &str) -> anyhow::Result<(EnvMap, Vec<String>)> {
        let format = match ext.to_ascii_lowercase().as_str() {
            "hdr" => image::ImageFormat::Hdr,
            "exr" => image::ImageFormat::OpenExr,
            other => bail!("{what}: environment images must be .hdr or .exr, not '.{other}'"),
        };
        let reader = image::ImageReader::with_format(std::io::Cursor::new(bytes), format);
        let (w, h) = reader
            .into_dimensions()
            .with_context(|| format!("{what}: cannot read the image header"))?;
        let pixels = w as u64 * h as u64;
        if pixels == 0 || pixels > MAX_ENV_PIXELS {
            bail!(
                "{what} is {w}×{h} = {pixels} pixels: environment images may have 1..={MAX_ENV_PIXELS} \
                 (8192×2048); downscale it"
            );
        }
        let img = image::load_from_memory_with_format(bytes, format)
            .with_context(|| format!("{what}: cannot decode the image"))?
            .into_rgb32f();
        let texels: Vec<Vec3> = img.pixels().map(|p| Vec3::from_array(p.0)).collect();
        let (map, bad) = EnvMap::from_texels(w, h, texels, what);
        let mut warnings = Vec::new();
        if bad > 0 {
            warnings.push(format!(
                "{what}: {bad} texel(s) with NaN, infinite or negative values were set to 0"
            ));
        }
        Ok((map, warnings))
    }

    /// Load a `.hdr`/`.exr` file given on the command line or in the viewer (a regular file
    /// of at most 4 GiB, the loader's default file budget).
    pub fn load_file(path: &Path) -> anyhow::Result<(EnvMap, Vec<String>)> {
        let what = format!("environment image '{}'", path.display());
        let bytes = crate::files::read_regular_file(
            path,
            crate::files::DEFAULT_MAX_FILE_BYTES,
            "environment image",
        )
        .map_err(anyhow::Error::msg)?;
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
        let (mut map, warnings) = EnvMap::decode(&bytes, ext, &what)?;
        map.name = path.display().to_string();
        Ok((map, warnings))
    }

    /// Write the map as a Radiance `.hdr` (RGBE) file.
    pub fn write_hdr(&self, path: &Path) -> anyhow::Result<()> {
        let file = std::fs::File::create(path)
            .with_context(|| format!("cannot create '{}'", path.display()))?;
        let enc = image::codecs::hdr::HdrEncoder::new(std::io::BufWriter::new(file));
        let px: Vec<image::Rgb<f32>> = self
            .texels
            .iter()
            .map(|t| image::Rgb(t.to_array()))
            .collect();
        enc.encode(&px, self.width as usize, self.height as usize)
            .with_context(|| format!("cannot write '{}'", path.display()))
    }
}

/// The two texels and the weight of the second along each axis for a bilinear lookup at
/// (u, t): ((x₀, x₁, fx), (y₀, y₁, fy)), texel i's centre at (i + ½)/W, x wrapping around
/// (the image is periodic in longitude), y clamped to the first and last rows (the poles).
/// A coordinate outside [−2, 2] (or NaN) reads as 0, as in the GPU twin.
#[inline]
pub fn bilinear(uv: Vec2, width: u32, height: u32) -> ((usize, usize, f32), (usize, usize, f32)) {
    let axis = |c: f32, n: u32, wrap: bool| {
        let x = if c.abs() <= 2.0 {
            c.clamp(-1.0, 2.0)
        } else {
            0.0
        } * n as f32
            - 0.5;
        let f = x.floor();
        let i = f as i64;
        let (i0, i1) = if wrap {
            (i.rem_euclid(n as i64), (i + 1).rem_euclid(n as i64))
        } else {
            (i.clamp(0, n as i64 - 1), (i + 1).clamp(0, n as i64 - 1))
        };
        (i0 as usize, i1 as usize, x - f)
    };
    (axis(uv.x, width, true), axis(uv.y, height, false))
}

/// The mean of the bilinearly interpolated image over each texel's footprint: the texel
/// filtered with the separable kernel [1, 6, 1]/8 (∫ of the tent over the box), wrapping in
/// x and clamping in y like [`bilinear`]. The sampling distribution is built from these
/// means, so its density is positive wherever the interpolated radiance is (a texel whose
/// footprint the tent of a bright neighbour reaches gets that neighbour's weight), which
/// keeps importance sampling and MIS unbiased (PBR 3rd ed. §14.2.4 builds
/// `InfiniteAreaLight`'s distribution from filtered lookups of the map for the same reason).
fn texel_means(lum: &[f32], w: usize, h: usize) -> Vec<f32> {
    let at = |x: usize, y: usize| lum[y * w + x];
    let mut rows = vec![0.0f32; w * h];
    for y in 0..h {
        for x in 0..w {
            let (l, r) = ((x + w - 1) % w, (x + 1) % w);
            rows[y * w + x] = (at(l, y) + 6.0 * at(x, y) + at(r, y)) / 8.0;
        }
    }
    let mut out = vec![0.0f32; w * h];
    for y in 0..h {
        let (u, d) = (y.saturating_sub(1), (y + 1).min(h - 1));
        for x in 0..w {
            out[y * w + x] = (rows[u * w + x] + 6.0 * rows[y * w + x] + rows[d * w + x]) / 8.0;
        }
    }
    out
}

/// Σ luminance × texel solid angle, a row's texels spanning (2π/W)(cos θ₀ − cos θ₁), from
/// the texels' mean luminances ([`texel_means`]): ∫ luminance dω and (approximately, the
/// mean's square standing for the mean square) ∫ luminance² dω over the sphere.
fn lum_integrals(lum: &[f32], width: u32, height: u32) -> (f32, f32) {
    let (mut sum, mut sum_sq) = (0.0f64, 0.0f64);
    for (row, texels) in lum.chunks(width as usize).enumerate() {
        let t0 = row as f64 / height as f64 * std::f64::consts::PI;
        let t1 = (row + 1) as f64 / height as f64 * std::f64::consts::PI;
        let omega = 2.0 * std::f64::consts::PI / width as f64 * (t0.cos() - t1.cos());
        for &l in texels {
            let lum = l as f64;
            sum += lum * omega;
            sum_sq += lum * lum * omega;
        }
    }
    (sum as f32, sum_sq as f32)
}

/// Replace or adjust the environment image of `scene` from the command line or the viewer:
/// `file` loads a new image (strength 1, rotation 0 unless given); `strength`/`rotation`
/// adjust the scene's own image. Returns the loader's warnings.
pub fn override_environment(
    scene: &mut super::Scene,
    file: Option<&Path>,
    strength: Option<f32>,
    rotation: Option<f32>,
) -> anyhow::Result<Vec<String>> {
    let mut warnings = Vec::new();
    if let Some(f) = file {
        let (map, w) = EnvMap::load_file(f).context("--env")?;
        warnings = w;
        scene.env_map = Some(EnvImage::new(Arc::new(map), 1.0, 0.0));
    }
    if strength.is_none() && rotation.is_none() {
        return Ok(warnings);
    }
    let Some(img) = scene.env_map.as_mut() else {
        bail!(
            "--env-strength/--env-rotation need an environment image (--env FILE, or the \
             scene's extras.environment.uri)"
        );
    };
    if let Some(s) = strength {
        if !(s.is_finite() && s >= 0.0) {
            bail!("--env-strength must be a finite number ≥ 0, got {s}");
        }
        img.strength = s;
    }
    if let Some(r) = rotation {
        if !r.is_finite() {
            bail!("--env-rotation must be a finite number of degrees, got {r}");
        }
        img.rotation = r;
    }
    Ok(warnings)
}
