//! Spectral helpers for hero-wavelength rendering of dispersive scenes: the Abbe-number
//! dispersion model, hero wavelength sampling over [360, 830] nm, analytic CIE 1931 colour
//! matching functions, XYZ → linear sRGB, the Monte Carlo spectrum → RGB estimator and a
//! smooth RGB → spectrum uplift.
//!
//! Normalisation ("white stays white"): the RGB of a spectrum s(λ) is
//! `rgb = diag(1/W) · M · ∫ s(λ) cmf(λ) dλ`, with `M` the XYZ → linear sRGB matrix and
//! `W = M · ∫ cmf(λ) dλ` the linear sRGB of the equal-energy spectrum (illuminant E), both
//! integrals over [360, 830] nm. So a constant spectrum of value 1 maps to RGB (1, 1, 1)
//! exactly (a von Kries white balance from E to the sRGB white, done in linear sRGB), and
//! [`rgb_to_spectrum`] maps RGB (1, 1, 1) to the constant 1: white stays white both ways.

use glam::{Vec3, Vec4};

/// Shortest wavelength sampled (nm).
pub const LAMBDA_MIN: f32 = 360.0;
/// Longest wavelength sampled (nm).
pub const LAMBDA_MAX: f32 = 830.0;
/// Number of wavelengths a path carries (one hero plus three rotated companions).
pub const HERO_COUNT: usize = 4;

/// n(λ) from n_d and Abbe number V_d (docs/design.md; Cauchy-type fit through the Fraunhofer
/// d, F, C lines: 523655 = (486.1·656.3)²/(656.3²−486.1²)·…; KHR_materials_dispersion spec).
/// n(λ) = max(n_d + (n_d − 1)/V_d · (523655/λ² − 1.5168), 1), λ in nm.
#[inline]
pub fn cauchy_from_abbe(n_d: f32, abbe: f32, lambda_nm: f32) -> f32 {
    (n_d + (n_d - 1.0) / abbe * (ABBE_B_NM2 / (lambda_nm * lambda_nm) - ABBE_C)).max(1.0)
}

/// The Abbe model's B (nm²) in n(λ) = n_d + (n_d − 1)/V_d · (B/λ² − C).
pub const ABBE_B_NM2: f32 = 523_655.0;
/// The Abbe model's C = B/λ_d² (λ_d = 587.56 nm), so that n(λ_d) = n_d.
pub const ABBE_C: f32 = 1.5168;

/// Hero wavelength sampling: the hero is uniform in [360, 830] nm, the other three are
/// rotated from it by equal offsets of 470/4 nm with wrap-around, so each one is uniform too.
/// Wilkie et al. 2014, "Hero Wavelength Spectral Sampling" (CGF 33(4)), §4.
#[inline]
pub fn sample_hero_wavelengths(u: f32) -> [f32; HERO_COUNT] {
    let range = LAMBDA_MAX - LAMBDA_MIN;
    let hero = u.clamp(0.0, 1.0) * range;
    let step = range / HERO_COUNT as f32;
    let mut out = [0.0; HERO_COUNT];
    for (j, l) in out.iter_mut().enumerate() {
        // λ_j = λ_min + ((λ_h − λ_min + j·Δ/C) mod Δ). Wilkie et al. 2014, §4.
        *l = LAMBDA_MIN + (hero + j as f32 * step).rem_euclid(range);
    }
    out
}

/// Marginal pdf of each wavelength returned by [`sample_hero_wavelengths`]: 1/470 per nm
/// inside [360, 830], 0 outside. Wilkie et al. 2014, §4.
#[inline]
pub fn hero_wavelength_pdf(lambda_nm: f32) -> f32 {
    if (LAMBDA_MIN..=LAMBDA_MAX).contains(&lambda_nm) {
        1.0 / (LAMBDA_MAX - LAMBDA_MIN)
    } else {
        0.0
    }
}

/// Piecewise Gaussian with different widths left and right of the mean.
/// Wyman, Sloan & Shirley 2013, "Simple Analytic Approximations to the CIE XYZ Color
/// Matching Functions" (JCGT 2(2)), §2.
#[inline]
fn piecewise_gaussian(lambda: f32, mu: f32, sigma_left: f32, sigma_right: f32) -> f32 {
    let t = (lambda - mu) / if lambda < mu { sigma_left } else { sigma_right };
    (-0.5 * t * t).exp()
}

/// CIE 1931 2° colour-matching functions (x̄, ȳ, z̄) at `lambda_nm`, multi-lobe analytic fit.
/// Wyman, Sloan & Shirley 2013 (JCGT 2(2)), §2, multi-lobe fit.
#[inline]
pub fn cie_xyz_cmf(lambda_nm: f32) -> Vec3 {
    let l = lambda_nm;
    // x̄: three lobes (one negative). Wyman et al. 2013, §2.
    let x = 1.056 * piecewise_gaussian(l, 599.8, 37.9, 31.0)
        + 0.362 * piecewise_gaussian(l, 442.0, 16.0, 26.7)
        - 0.065 * piecewise_gaussian(l, 501.1, 20.4, 26.2);
    // ȳ: two lobes. Wyman et al. 2013, §2.
    let y = 0.821 * piecewise_gaussian(l, 568.8, 46.9, 40.5)
        + 0.286 * piecewise_gaussian(l, 530.9, 16.3, 31.1);
    // z̄: two lobes. Wyman et al. 2013, §2.
    let z = 1.217 * piecewise_gaussian(l, 437.0, 11.8, 36.0)
        + 0.681 * piecewise_gaussian(l, 459.0, 26.0, 13.8);
    Vec3::new(x, y, z)
}

/// ∫ cmf(λ) dλ over [360, 830] nm of [`cie_xyz_cmf`] (midpoint rule, 0.005 nm steps, f64;
/// checked by `tests/spectrum.rs`). Used to normalise the spectrum → RGB estimator.
pub const CIE_CMF_INTEGRAL: Vec3 = Vec3::new(106.765_82, 106.922_07, 106.875);

/// CIE XYZ → linear sRGB (Rec.709 primaries, D65 white).
/// IEC 61966-2-1:1999, §5.2 (matrix with 4-decimal coefficients).
#[inline]
pub fn xyz_to_linear_srgb(xyz: Vec3) -> Vec3 {
    Vec3::new(
        3.2406 * xyz.x - 1.5372 * xyz.y - 0.4986 * xyz.z,
        -0.9689 * xyz.x + 1.8758 * xyz.y + 0.0415 * xyz.z,
        0.0557 * xyz.x - 0.2040 * xyz.y + 1.0570 * xyz.z,
    )
}

/// White-balanced linear sRGB matching functions r̄(λ) = diag(1/W) · M · cmf(λ) with
/// W = M · ∫ cmf (module docs), so that ∫ r̄(λ) dλ over [360, 830] = (1, 1, 1).
/// Von Kries-style white balance in linear sRGB (Fairchild, "Color Appearance Models",
/// 3rd ed., §9.1) applied to IEC 61966-2-1 §5.2.
#[inline]
pub fn rgb_matching(lambda_nm: f32) -> Vec3 {
    let white = xyz_to_linear_srgb(CIE_CMF_INTEGRAL);
    xyz_to_linear_srgb(cie_xyz_cmf(lambda_nm)) / white
}

/// Monte Carlo estimate of the linear sRGB of a spectrum from its values at four sampled
/// wavelengths: (1/4) Σ_i values_i · r̄(λ_i) / pdf(λ_i). Unbiased for the white-balanced RGB
/// of the module docs; a constant spectrum 1 gives (1, 1, 1) in expectation.
/// PBR 4th ed. §4.6.5 (Monte Carlo tristimulus estimate from sampled wavelengths);
/// Wilkie et al. 2014, §4.
#[inline]
pub fn spectrum_sample_to_rgb(lambda: [f32; HERO_COUNT], values: Vec4) -> Vec3 {
    let v = values.to_array();
    let mut sum = Vec3::ZERO;
    for (l, value) in lambda.iter().zip(v) {
        let pdf = hero_wavelength_pdf(*l);
        if pdf > 0.0 {
            sum += value * rgb_matching(*l) / pdf;
        }
    }
    sum / HERO_COUNT as f32
}

/// Centre (nm) of the blue → green transition of the uplift basis.
pub const UPLIFT_BLUE_EDGE_NM: f32 = 488.0;
/// Half-width (nm) of the blue → green transition.
pub const UPLIFT_BLUE_HALF_WIDTH_NM: f32 = 48.0;
/// Centre (nm) of the green → red transition.
pub const UPLIFT_RED_EDGE_NM: f32 = 589.5;
/// Half-width (nm) of the green → red transition.
pub const UPLIFT_RED_HALF_WIDTH_NM: f32 = 15.25;

/// C² step from 0 at x ≤ −1 to 1 at x ≥ 1: 6t⁵ − 15t⁴ + 10t³ with t = (x + 1)/2.
/// Perlin 2002, "Improving Noise" (SIGGRAPH), §2 (the quintic fade curve).
#[inline]
fn smoother_step(x: f32) -> f32 {
    let t = (0.5 * (x + 1.0)).clamp(0.0, 1.0);
    t * t * t * (t * (6.0 * t - 15.0) + 10.0)
}

/// The three smooth uplift basis spectra (red, green, blue) at `lambda_nm`: non-negative and
/// summing to 1 at every λ (a partition of unity). Blue falls and red rises with quintic steps
/// centred at 488 nm (±48) and 589.5 nm (±15.25); green is the rest. The edges were fitted
/// (minimax over the round-trip error of the six primaries and secondaries, measured 0.0255)
/// against [`rgb_matching`].
#[inline]
pub fn uplift_basis(lambda_nm: f32) -> Vec3 {
    let red = smoother_step((lambda_nm - UPLIFT_RED_EDGE_NM) / UPLIFT_RED_HALF_WIDTH_NM);
    let blue = 1.0 - smoother_step((lambda_nm - UPLIFT_BLUE_EDGE_NM) / UPLIFT_BLUE_HALF_WIDTH_NM);
    Vec3::new(red, (1.0 - red - blue).max(0.0), blue)
}

/// Smooth RGB → spectrum uplift for reflectances and emission:
/// s(λ) = r·b_r(λ) + g·b_g(λ) + b·b_b(λ) with the partition-of-unity basis of
/// [`uplift_basis`]. This is Smits' decomposition (white + secondary + primary) with
/// secondaries equal to sums of primaries and white = 1, which collapses to the linear form:
/// greys map to the constant exactly, rgb in [0, 1] stays in [0, 1], and emission scales
/// linearly. Smits 1999, "An RGB-to-Spectrum Conversion for Reflectances" (JGT 4(4)), §2.
#[inline]
pub fn rgb_to_spectrum(rgb: Vec3, lambda_nm: f32) -> f32 {
    let basis = uplift_basis(lambda_nm);
    // Written relative to green so that r = g = b gives exactly g (no rounding).
    let s = rgb.y + (rgb.x - rgb.y) * basis.x + (rgb.z - rgb.y) * basis.z;
    // A convex combination of r, g, b: clamp away f32 rounding only.
    s.clamp(rgb.min_element(), rgb.max_element())
}

/// [`rgb_to_spectrum`] at the four wavelengths of a path (spectral-mode `Color`).
#[inline]
pub fn rgb_to_spectrum4(rgb: Vec3, lambda: [f32; HERO_COUNT]) -> Vec4 {
    Vec4::new(
        rgb_to_spectrum(rgb, lambda[0]),
        rgb_to_spectrum(rgb, lambda[1]),
        rgb_to_spectrum(rgb, lambda[2]),
        rgb_to_spectrum(rgb, lambda[3]),
    )
}

/// Shortest wavelength a scene-wide light line may have (nm): the sampled range.
pub const LIGHT_LINE_MIN_NM: f32 = LAMBDA_MIN;
/// Longest wavelength a scene-wide light line may have (nm).
pub const LIGHT_LINE_MAX_NM: f32 = LAMBDA_MAX;

/// The wavelength of a light line read from `source` (a CLI flag, a glTF field …), or an
/// error naming it when it is not a finite number in [360, 830] nm.
pub fn check_light_line(nm: f32, source: &str) -> Result<f32, String> {
    if nm.is_finite() && (LIGHT_LINE_MIN_NM..=LIGHT_LINE_MAX_NM).contains(&nm) {
        Ok(nm)
    } else {
        Err(format!(
            "{source} is {nm}, but a light line must be a wavelength in {LIGHT_LINE_MIN_NM}..={LIGHT_LINE_MAX_NM} nm"
        ))
    }
}

/// The linear sRGB a unit lane value stands for when every emitter radiates one line at
/// `lambda_nm`: the white-balanced matching functions r̄(λ₀) of [`rgb_matching`] with the
/// negative part clipped (a monochromatic colour lies outside the sRGB gamut; clipping each
/// channel at 0 is the simplest projection onto it, and keeps the hue's dominant
/// channels), scaled so its luminance is 1, the luminance of RGB (1, 1, 1). A grey scene thus
/// keeps its brightness when its white light becomes a line; only the hue changes.
/// The estimator of such a line: L(λ) = L₀ δ(λ − λ₀), so sampling λ = λ₀ with probability 1
/// makes L/p the line's power (PBR 4th ed. §4.6.5 for the tristimulus integral; a delta
/// spectrum cannot be found by uniform wavelength sampling).
pub fn light_line_rgb(lambda_nm: f32) -> Vec3 {
    let c = rgb_matching(lambda_nm).max(Vec3::ZERO);
    let y = crate::math::color::luminance(c);
    if y > 0.0 { c / y } else { Vec3::ZERO }
}
