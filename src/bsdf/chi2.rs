//! χ² goodness-of-fit test of a BSDF's `sample` against its `pdf`, in the style of pbrt-v4's
//! `chi2` BSDF tests and Mitsuba's `ChiSquareTest` (Pearson 1900 χ² test).
//!
//! The sphere of directions is binned in (cosθ, φ) (equal-area cells, dω = d(cosθ) dφ). N
//! directions drawn with `sample` (non-delta samples only) fill the histogram; the expected
//! count of each cell is N·∫∫ pdf dcosθ dφ, integrated with nested adaptive Simpson quadrature.
//! Cells with expected count < `min_expected` are pooled (pbrt-v4 `Chi2Test`), and the p-value
//! of the statistic is Q(dof/2, χ²/2). Callers running many cases compare p against a
//! Šidák-corrected level ([`sidak_alpha`]).
//!
//! Test infrastructure, public so integration tests can use it; not used while rendering.

use super::{BxDF, TransportMode};
use crate::math::rng::Sampler;
use glam::Vec3;
use std::f64::consts::PI;

/// Binning, sample count and tolerances of one χ² test.
#[derive(Clone, Copy, Debug)]
pub struct Chi2Config {
    /// Cells along cosθ ∈ [−1, 1] (an even count puts a cell boundary on the horizon).
    pub cos_bins: usize,
    /// Cells along φ ∈ [0, 2π).
    pub phi_bins: usize,
    pub samples: usize,
    pub seed: u32,
    /// Cells expected to hold fewer samples are pooled (5 is the textbook rule).
    pub min_expected: f64,
    /// Absolute error target of each cell's probability (adaptive Simpson).
    pub cell_tolerance: f64,
}

impl Default for Chi2Config {
    fn default() -> Self {
        Chi2Config {
            cos_bins: 64,
            phi_bins: 128,
            samples: 1_000_000,
            seed: 1,
            min_expected: 5.0,
            cell_tolerance: 1e-7,
        }
    }
}

/// Outcome of [`chi2_test`].
#[derive(Clone, Copy, Debug)]
pub struct Chi2Result {
    pub statistic: f64,
    pub dof: usize,
    pub p_value: f64,
    /// ∫ pdf over the sphere (numerical).
    pub pdf_integral: f64,
    /// Fraction of the N calls that returned a non-delta sample.
    pub success_fraction: f64,
    /// Samples that were delta (excluded from the histogram).
    pub delta_samples: usize,
    /// Samples that fell in cells whose integrated pdf is exactly 0.
    pub zero_expected_hits: usize,
    /// Samples with a non-finite or non-unit direction.
    pub invalid_samples: usize,
    pub samples: usize,
}

impl Chi2Result {
    /// Binomial standard deviation of `success_fraction`.
    pub fn success_sigma(&self) -> f64 {
        let p = self.success_fraction;
        (p * (1.0 - p) / self.samples as f64).sqrt()
    }
}

/// Per-test significance level for `n` tests at family-wise level `alpha`:
/// 1 − (1 − α)^{1/n}, Šidák 1967.
pub fn sidak_alpha(alpha: f64, n: usize) -> f64 {
    1.0 - (1.0 - alpha).powf(1.0 / n as f64)
}

#[inline]
fn cell_of(cfg: &Chi2Config, w: Vec3) -> usize {
    let c = (w.z as f64).clamp(-1.0, 1.0);
    let mut phi = (w.y as f64).atan2(w.x as f64);
    if phi < 0.0 {
        phi += 2.0 * PI;
    }
    let i = (((c + 1.0) * 0.5 * cfg.cos_bins as f64) as usize).min(cfg.cos_bins - 1);
    let j = ((phi / (2.0 * PI) * cfg.phi_bins as f64) as usize).min(cfg.phi_bins - 1);
    i * cfg.phi_bins + j
}

/// Direction with cosθ = c and azimuth φ.
#[inline]
fn direction(c: f64, phi: f64) -> Vec3 {
    let s = (1.0 - c * c).max(0.0).sqrt();
    Vec3::new((s * phi.cos()) as f32, (s * phi.sin()) as f32, c as f32)
}

/// Histogram of `cfg.samples` calls to `sample` (random numbers from [`Sampler`] with the
/// sample index as the pixel): (counts per cell, non-delta successes, delta, invalid).
pub fn sample_histogram<B: BxDF + ?Sized>(
    bsdf: &B,
    wo: Vec3,
    mode: TransportMode,
    cfg: &Chi2Config,
) -> (Vec<f64>, usize, usize, usize) {
    let mut hist = vec![0.0f64; cfg.cos_bins * cfg.phi_bins];
    let (mut ok, mut delta, mut invalid) = (0usize, 0usize, 0usize);
    for i in 0..cfg.samples {
        let mut rng = Sampler::new(i as u32, 0, cfg.seed);
        let uc = rng.next();
        let u2 = rng.next2();
        let Some(s) = bsdf.sample(wo, uc, u2, mode) else {
            continue;
        };
        if s.is_delta {
            delta += 1;
            continue;
        }
        if !s.wi.is_finite() || (s.wi.length() - 1.0).abs() > 1e-3 {
            invalid += 1;
            continue;
        }
        ok += 1;
        hist[cell_of(cfg, s.wi)] += 1.0;
    }
    (hist, ok, delta, invalid)
}

/// Adaptive Simpson on [a, b] given f(a), f(m), f(b) and the whole-interval estimate
/// (Kuncir 1962; Lyness 1969 error estimate |S₂ − S₁|/15).
#[allow(clippy::too_many_arguments)]
fn simpson_rec(
    f: &mut dyn FnMut(f64) -> f64,
    a: f64,
    b: f64,
    fa: f64,
    fm: f64,
    fb: f64,
    whole: f64,
    eps: f64,
    depth: i32,
    min_depth: i32,
) -> f64 {
    let m = 0.5 * (a + b);
    let (lm, rm) = (0.5 * (a + m), 0.5 * (m + b));
    let (flm, frm) = (f(lm), f(rm));
    let left = (m - a) / 6.0 * (fa + 4.0 * flm + fm);
    let right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
    let delta = left + right - whole;
    if depth <= 0 || (min_depth <= 0 && delta.abs() <= 15.0 * eps) {
        return left + right + delta / 15.0;
    }
    simpson_rec(
        f,
        a,
        m,
        fa,
        flm,
        fm,
        left,
        0.5 * eps,
        depth - 1,
        min_depth - 1,
    ) + simpson_rec(
        f,
        m,
        b,
        fm,
        frm,
        fb,
        right,
        0.5 * eps,
        depth - 1,
        min_depth - 1,
    )
}

/// ∫_a^b f with absolute tolerance `eps` (adaptive Simpson, at most 2^max_depth intervals,
/// at least 2^min_depth).
pub fn adaptive_simpson(
    f: &mut dyn FnMut(f64) -> f64,
    a: f64,
    b: f64,
    eps: f64,
    max_depth: i32,
    min_depth: i32,
) -> f64 {
    let m = 0.5 * (a + b);
    let (fa, fm, fb) = (f(a), f(m), f(b));
    let whole = (b - a) / 6.0 * (fa + 4.0 * fm + fb);
    simpson_rec(f, a, b, fa, fm, fb, whole, eps, max_depth, min_depth)
}

/// Probability of every cell: ∫∫ pdf(wo, ω(cosθ, φ)) dcosθ dφ (nested adaptive Simpson).
pub fn integrate_pdf<B: BxDF + ?Sized>(bsdf: &B, wo: Vec3, cfg: &Chi2Config) -> Vec<f64> {
    let dc = 2.0 / cfg.cos_bins as f64;
    let dphi = 2.0 * PI / cfg.phi_bins as f64;
    let mut out = vec![0.0f64; cfg.cos_bins * cfg.phi_bins];
    for i in 0..cfg.cos_bins {
        let (c0, c1) = (-1.0 + i as f64 * dc, -1.0 + (i + 1) as f64 * dc);
        for j in 0..cfg.phi_bins {
            let (p0, p1) = (j as f64 * dphi, (j + 1) as f64 * dphi);
            let eps = cfg.cell_tolerance;
            let mut outer = |c: f64| {
                let mut inner = |phi: f64| bsdf.pdf(wo, direction(c, phi)) as f64;
                adaptive_simpson(&mut inner, p0, p1, eps / dc, 10, 1)
            };
            out[i * cfg.phi_bins + j] = adaptive_simpson(&mut outer, c0, c1, eps, 10, 1).max(0.0);
        }
    }
    out
}

/// Pearson χ² over cells with pooling of cells expected below `min_expected`
/// (pbrt-v4 `Chi2Test`): returns (statistic, dof, observed count in zero-expected cells).
pub fn chi2_statistic(observed: &[f64], expected: &[f64], min_expected: f64) -> (f64, usize, f64) {
    let mut idx: Vec<usize> = (0..expected.len()).collect();
    idx.sort_by(|&a, &b| expected[a].total_cmp(&expected[b]));
    let (mut pooled_obs, mut pooled_exp) = (0.0, 0.0);
    let (mut stat, mut cells, mut zero_hits) = (0.0, 0usize, 0.0);
    for &k in &idx {
        let (o, e) = (observed[k], expected[k]);
        if e <= 0.0 {
            zero_hits += o;
        } else if e < min_expected || (pooled_exp > 0.0 && pooled_exp < min_expected) {
            pooled_obs += o;
            pooled_exp += e;
        } else {
            stat += (o - e) * (o - e) / e;
            cells += 1;
        }
    }
    if pooled_exp > 0.0 {
        stat += (pooled_obs - pooled_exp) * (pooled_obs - pooled_exp) / pooled_exp;
        cells += 1;
    }
    (stat, cells.saturating_sub(1), zero_hits)
}

/// ln Γ(x) for x > 0, Lanczos approximation (g = 7, n = 9; Lanczos 1964, coefficients of
/// Godfrey), |error| < 1e-14.
pub fn ln_gamma(x: f64) -> f64 {
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        // Reflection Γ(x)Γ(1 − x) = π / sin(πx).
        return (PI / (PI * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let mut a = C[0];
    let t = x + 7.5;
    for (i, c) in C.iter().enumerate().skip(1) {
        a += c / (x + i as f64);
    }
    0.5 * (2.0 * PI).ln() + (x + 0.5) * t.ln() - t + a.ln()
}

/// Regularised upper incomplete gamma Q(a, x): series for x < a + 1, Lentz continued fraction
/// otherwise (Press et al., Numerical Recipes 3rd ed. §6.2).
pub fn gamma_q(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    let ln_pre = -x + a * x.ln() - ln_gamma(a);
    if x < a + 1.0 {
        // P(a, x) = e^{−x} x^a / Γ(a) Σ_n x^n / (a (a+1) … (a+n)).
        let (mut term, mut sum, mut ap) = (1.0 / a, 1.0 / a, a);
        for _ in 0..100_000 {
            ap += 1.0;
            term *= x / ap;
            sum += term;
            if term.abs() < sum.abs() * 1e-16 {
                break;
            }
        }
        (1.0 - sum * ln_pre.exp()).clamp(0.0, 1.0)
    } else {
        // Q(a, x) = e^{−x} x^a / Γ(a) · 1/(x + 1 − a − 1(1−a)/(x + 3 − a − …)).
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..100_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let del = d * c;
            h *= del;
            if (del - 1.0).abs() < 1e-16 {
                break;
            }
        }
        (ln_pre.exp() * h).clamp(0.0, 1.0)
    }
}

/// p-value of a χ² statistic with `dof` degrees of freedom: Q(dof/2, χ²/2).
pub fn chi2_p_value(statistic: f64, dof: usize) -> f64 {
    if dof == 0 {
        return 1.0;
    }
    gamma_q(0.5 * dof as f64, 0.5 * statistic)
}

/// Histogram `sample`, integrate `pdf`, and run the pooled χ² test (see the module docs).
pub fn chi2_test<B: BxDF + ?Sized>(
    bsdf: &B,
    wo: Vec3,
    mode: TransportMode,
    cfg: &Chi2Config,
) -> Chi2Result {
    let (hist, ok, delta, invalid) = sample_histogram(bsdf, wo, mode, cfg);
    let probs = integrate_pdf(bsdf, wo, cfg);
    let n = cfg.samples as f64;
    let expected: Vec<f64> = probs.iter().map(|p| p * n).collect();
    let (statistic, dof, zero_hits) = chi2_statistic(&hist, &expected, cfg.min_expected);
    Chi2Result {
        statistic,
        dof,
        p_value: chi2_p_value(statistic, dof),
        pdf_integral: probs.iter().sum(),
        success_fraction: ok as f64 / n,
        delta_samples: delta,
        zero_expected_hits: zero_hits as usize,
        invalid_samples: invalid,
        samples: cfg.samples,
    }
}
