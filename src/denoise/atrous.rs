//! The CPU twin of `src/denoise/denoise.wgsl`: demodulate by albedo and estimate each pixel's
//! noise variance from its guide-similar 7×7 neighbourhood ([`prepare`]), run the à-trous
//! levels with steps 1, 2, 4, … ([`level`]), re-multiply by albedo ([`finish`]). The
//! spatial variance estimate is SVGF's fallback for a short history (Schied et al. 2017
//! §4.3): with no temporal reprojection, it is the estimate there always is.

use super::weights::{GAUSS3, KERNEL, luma, w_depth, w_luma, w_normal, w_specular};
use super::{DenoiseParams, Guides};
use glam::{Vec3, Vec4};

/// The smallest albedo divided by (black texels would otherwise blow irradiance up).
pub const MIN_ALBEDO: f32 = 0.01;
/// Radius of the variance estimate's neighbourhood (7×7).
const VAR_RADIUS: i32 = 3;

/// The denoised image of `img` (linear radiance, row-major, the guides' size). `variance`:
/// each pixel's variance of the mean luminance when the renderer measured it
/// ([`half_variance`]); `None` estimates it from the pixel's neighbourhood.
pub fn denoise(
    img: &[Vec3],
    variance: Option<&[f32]>,
    guides: &Guides,
    p: &DenoiseParams,
) -> Vec<Vec3> {
    assert_eq!(
        img.len(),
        guides.albedo.len(),
        "image and guides differ in size"
    );
    let grad = depth_gradient(guides);
    let mut state = prepare(img, variance, guides, &grad, p);
    for i in 0..p.iterations {
        state = level(&state, guides, &grad, 1 << i, p);
    }
    finish(&state, guides)
}

/// Per pixel, how much depth changes to the next pixel (the smaller one-sided difference
/// per axis, so a silhouette does not count; the larger of the two axes).
pub fn depth_gradient(g: &Guides) -> Vec<f32> {
    let (w, h) = (g.width as i32, g.height as i32);
    let z = |x: i32, y: i32| g.depth[(y.clamp(0, h - 1) * w + x.clamp(0, w - 1)) as usize];
    let mut out = Vec::with_capacity(g.depth.len());
    for y in 0..h {
        for x in 0..w {
            let c = z(x, y);
            let dx = (z(x + 1, y) - c).abs().min((c - z(x - 1, y)).abs());
            let dy = (z(x, y + 1) - c).abs().min((c - z(x, y - 1)).abs());
            out.push(dx.max(dy));
        }
    }
    out
}

/// Per pixel, the variance of the mean luminance of an image made of two independent halves:
/// `first` the mean of its first `k` of `n` samples, `full` the mean of all `n`. The second
/// half's mean is (n·full − k·first)/(n − k); E[(a − b)²] = σ²·n/(k(n − k)), Var(full) = σ²/n.
pub fn half_variance(first: &[Vec3], full: &[Vec3], k: u64, n: u64) -> Vec<f32> {
    assert!(0 < k && k < n, "halves need 0 < k < n samples");
    let (k, n) = (k as f32, n as f32);
    first
        .iter()
        .zip(full)
        .map(|(a, f)| {
            let b = (n * *f - k * *a) / (n - k);
            let d = luma(*a - b);
            d * d * k * (n - k) / (n * n)
        })
        .collect()
}

/// The irradiance of `img`: radiance / albedo (black albedo clamped to [`MIN_ALBEDO`]).
fn demodulate(img: &[Vec3], g: &Guides) -> Vec<Vec3> {
    img.iter()
        .zip(&g.albedo)
        .map(|(c, a)| *c / a.max(Vec3::splat(MIN_ALBEDO)))
        .collect()
}

/// Irradiance (radiance / albedo) in xyz and its estimated variance in w: the guide-weighted
/// 7×7 mean of the measured variance (in irradiance units), or without one, the weighted
/// variance of the neighbourhood's luminance.
pub fn prepare(
    img: &[Vec3],
    variance: Option<&[f32]>,
    g: &Guides,
    grad: &[f32],
    p: &DenoiseParams,
) -> Vec<Vec4> {
    let irr = demodulate(img, g);
    let measured: Option<Vec<f32>> = variance.map(|v| {
        v.iter()
            .zip(&g.albedo)
            .map(|(v, a)| v / luma(a.max(Vec3::splat(MIN_ALBEDO))).powi(2))
            .collect()
    });
    let (w, h) = (g.width as i32, g.height as i32);
    let mut out = Vec::with_capacity(irr.len());
    for y in 0..h {
        for x in 0..w {
            let ip = (y * w + x) as usize;
            let var = pixel_variance(&irr, measured.as_deref(), (g, grad), (x, y), p);
            out.push(irr[ip].extend(var));
        }
    }
    out
}

/// The variance of pixel (x, y): the guide-weighted 7×7 mean of `measured` (never below the
/// pixel's own: a firefly is not diluted by its calm neighbours), or without it the weighted
/// variance of the neighbourhood's luminance.
fn pixel_variance(
    irr: &[Vec3],
    measured: Option<&[f32]>,
    (g, grad): (&Guides, &[f32]),
    (x, y): (i32, i32),
    p: &DenoiseParams,
) -> f32 {
    let (w, h) = (g.width as i32, g.height as i32);
    let ip = (y * w + x) as usize;
    let (mut sw, mut m1, mut m2, mut mv) = (0.0f32, 0.0f32, 0.0f32, 0.0f32);
    for dy in -VAR_RADIUS..=VAR_RADIUS {
        for dx in -VAR_RADIUS..=VAR_RADIUS {
            let (qx, qy) = (x + dx, y + dy);
            if qx < 0 || qy < 0 || qx >= w || qy >= h {
                continue;
            }
            let iq = (qy * w + qx) as usize;
            let dist = ((dx * dx + dy * dy) as f32).sqrt();
            let wt = if iq == ip {
                1.0
            } else {
                guide_weight(g, grad, ip, iq, dist, p)
            };
            let l = luma(irr[iq]);
            sw += wt;
            m1 += wt * l;
            m2 += wt * l * l;
            mv += wt * measured.map_or(0.0, |v| v[iq]);
        }
    }
    let (m1, m2) = (m1 / sw, m2 / sw);
    match measured {
        Some(v) => (mv / sw).max(v[ip]),
        None => (m2 - m1 * m1).max(0.0),
    }
}

/// The guides' part of a tap's weight: normal, depth and specular fraction.
#[inline]
fn guide_weight(
    g: &Guides,
    grad: &[f32],
    ip: usize,
    iq: usize,
    dist: f32,
    p: &DenoiseParams,
) -> f32 {
    let np = g.normal[ip].normalize_or_zero();
    let nq = g.normal[iq].normalize_or_zero();
    w_normal(np, nq, p.sigma_n)
        * w_depth(g.depth[ip], g.depth[iq], grad[ip], dist, p.sigma_z)
        * w_specular(g.specular[ip], g.specular[iq])
}

/// The variance at (x, y) smoothed by a 3×3 Gaussian (clamped at the border).
fn blurred_variance(s: &[Vec4], (w, h): (i32, i32), (x, y): (i32, i32)) -> f32 {
    let mut v = 0.0;
    for dy in -1..=1i32 {
        for dx in -1..=1i32 {
            let (qx, qy) = ((x + dx).clamp(0, w - 1), (y + dy).clamp(0, h - 1));
            v +=
                GAUSS3[(dx + 1) as usize] * GAUSS3[(dy + 1) as usize] * s[(qy * w + qx) as usize].w;
        }
    }
    v
}

/// One à-trous level with taps `step` pixels apart: the weighted mean of the irradiance and
/// the variance of that mean (Σ w² var / (Σ w)²).
pub fn level(s: &[Vec4], g: &Guides, grad: &[f32], step: i32, p: &DenoiseParams) -> Vec<Vec4> {
    let (w, h) = (g.width as i32, g.height as i32);
    let mut out = Vec::with_capacity(s.len());
    for y in 0..h {
        for x in 0..w {
            let ip = (y * w + x) as usize;
            let std_dev = blurred_variance(s, (w, h), (x, y)).max(0.0).sqrt();
            let lp = luma(s[ip].truncate());
            let (mut sw, mut sc, mut sv) = (0.0f32, Vec3::ZERO, 0.0f32);
            for ky in 0..5i32 {
                for kx in 0..5i32 {
                    let (dx, dy) = ((kx - 2) * step, (ky - 2) * step);
                    let (qx, qy) = (x + dx, y + dy);
                    if qx < 0 || qy < 0 || qx >= w || qy >= h {
                        continue;
                    }
                    let iq = (qy * w + qx) as usize;
                    let mut wt = KERNEL[kx as usize] * KERNEL[ky as usize];
                    if iq != ip {
                        let dist = ((dx * dx + dy * dy) as f32).sqrt();
                        let lq = luma(s[iq].truncate());
                        wt *= guide_weight(g, grad, ip, iq, dist, p)
                            * w_luma(lp, lq, std_dev, p.sigma_l);
                    }
                    sw += wt;
                    sc += wt * s[iq].truncate();
                    sv += wt * wt * s[iq].w;
                }
            }
            out.push((sc / sw).extend(sv / (sw * sw)));
        }
    }
    out
}

/// Radiance again: the filtered irradiance times the albedo.
pub fn finish(s: &[Vec4], g: &Guides) -> Vec<Vec3> {
    s.iter()
        .zip(&g.albedo)
        .map(|(v, a)| v.truncate() * a.max(Vec3::splat(MIN_ALBEDO)))
        .collect()
}
