// spectrum.wgsl — twin of src/math/spectrum.rs: hero wavelength sampling, the Abbe-number
// dispersion model, analytic CIE 1931 matching functions, XYZ → linear sRGB, the Monte Carlo
// spectrum → RGB estimator and the smooth RGB → spectrum uplift. Only reached when the scene
// has a dispersive material (HAS_SPECTRAL in integrator.wgsl).

// LAMBDA_MIN, LAMBDA_MAX, HERO_COUNT, the UPLIFT_* edges, CIE_CMF_INTEGRAL (∫ cmf(λ) dλ over
// [360, 830] nm) and the Abbe model's ABBE_B_NM2, ABBE_C come from the prelude
// (gpu::prelude, from math::spectrum).

// n(λ) = max(n_d + (n_d − 1)/V_d · (523655/λ² − 1.5168), 1), λ in nm.
fn cauchy_from_abbe(n_d: f32, abbe: f32, lambda_nm: f32) -> f32 {
    return max(n_d + (n_d - 1.0) / abbe * (ABBE_B_NM2 / (lambda_nm * lambda_nm) - ABBE_C), 1.0);
}

// Rust's f32::rem_euclid (x % m is exact fmod there; here x ∈ [0, 2m) so one subtraction is
// the exact result).
fn rem_euclid_f32(x: f32, m: f32) -> f32 {
    var r = x;
    if r >= m {
        r = r - m;
    }
    if r < 0.0 {
        r = r + m;
    }
    return r;
}

// Hero wavelength sampling: the hero is uniform in [360, 830] nm, the other three are
// rotated from it by equal offsets of 470/4 nm with wrap-around, so each one is uniform too.
// Wilkie et al. 2014, "Hero Wavelength Spectral Sampling" (CGF 33(4)), §4.
fn sample_hero_wavelengths(u: f32) -> vec4<f32> {
    let range = LAMBDA_MAX - LAMBDA_MIN;
    let hero = clamp(u, 0.0, 1.0) * range;
    let step = range / f32(HERO_COUNT);
    var out = vec4<f32>(0.0);
    for (var j = 0u; j < HERO_COUNT; j++) {
        // λ_j = λ_min + ((λ_h − λ_min + j·Δ/C) mod Δ). Wilkie et al. 2014, §4.
        out[j] = LAMBDA_MIN + rem_euclid_f32(hero + f32(j) * step, range);
    }
    return out;
}

// Marginal pdf of each wavelength returned by [`sample_hero_wavelengths`]: 1/470 per nm
// inside [360, 830], 0 outside. Wilkie et al. 2014, §4.
fn hero_wavelength_pdf(lambda_nm: f32) -> f32 {
    if lambda_nm >= LAMBDA_MIN && lambda_nm <= LAMBDA_MAX {
        return 1.0 / (LAMBDA_MAX - LAMBDA_MIN);
    }
    return 0.0;
}

// Piecewise Gaussian with different widths left and right of the mean.
// Wyman, Sloan & Shirley 2013, "Simple Analytic Approximations to the CIE XYZ Color
// Matching Functions" (JCGT 2(2)), §2.
fn piecewise_gaussian(lambda: f32, mu: f32, sigma_left: f32, sigma_right: f32) -> f32 {
    var sigma = sigma_right;
    if lambda < mu {
        sigma = sigma_left;
    }
    let t = (lambda - mu) / sigma;
    return exp(-0.5 * t * t);
}

// CIE 1931 2° colour-matching functions (x̄, ȳ, z̄) at `lambda_nm`, multi-lobe analytic fit.
// Wyman, Sloan & Shirley 2013 (JCGT 2(2)), §2, multi-lobe fit.
fn cie_xyz_cmf(lambda_nm: f32) -> vec3<f32> {
    let l = lambda_nm;
    let x = 1.056 * piecewise_gaussian(l, 599.8, 37.9, 31.0)
        + 0.362 * piecewise_gaussian(l, 442.0, 16.0, 26.7)
        - 0.065 * piecewise_gaussian(l, 501.1, 20.4, 26.2);
    let y = 0.821 * piecewise_gaussian(l, 568.8, 46.9, 40.5)
        + 0.286 * piecewise_gaussian(l, 530.9, 16.3, 31.1);
    let z = 1.217 * piecewise_gaussian(l, 437.0, 11.8, 36.0)
        + 0.681 * piecewise_gaussian(l, 459.0, 26.0, 13.8);
    return vec3<f32>(x, y, z);
}

// CIE XYZ → linear sRGB (Rec.709 primaries, D65 white).
// IEC 61966-2-1:1999, §5.2 (matrix with 4-decimal coefficients).
fn xyz_to_linear_srgb(xyz: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(
        3.2406 * xyz.x - 1.5372 * xyz.y - 0.4986 * xyz.z,
        -0.9689 * xyz.x + 1.8758 * xyz.y + 0.0415 * xyz.z,
        0.0557 * xyz.x - 0.2040 * xyz.y + 1.0570 * xyz.z,
    );
}

// White-balanced linear sRGB matching functions r̄(λ) = diag(1/W) · M · cmf(λ) with
// W = M · ∫ cmf (module docs), so that ∫ r̄(λ) dλ over [360, 830] = (1, 1, 1).
// Von Kries-style white balance in linear sRGB (Fairchild, "Color Appearance Models",
// 3rd ed., §9.1) applied to IEC 61966-2-1 §5.2.
fn rgb_matching(lambda_nm: f32) -> vec3<f32> {
    let white = xyz_to_linear_srgb(CIE_CMF_INTEGRAL);
    return xyz_to_linear_srgb(cie_xyz_cmf(lambda_nm)) / white;
}

// Monte Carlo estimate of the linear sRGB of a spectrum from its values at four sampled
// wavelengths: (1/4) Σ_i values_i · r̄(λ_i) / pdf(λ_i).
// PBR 4th ed. §4.6.5 (Monte Carlo tristimulus estimate from sampled wavelengths);
// Wilkie et al. 2014, §4.
fn spectrum_sample_to_rgb(lambda: vec4<f32>, values: vec4<f32>) -> vec3<f32> {
    var sum = vec3<f32>(0.0);
    for (var j = 0u; j < HERO_COUNT; j++) {
        let pdf = hero_wavelength_pdf(lambda[j]);
        if pdf > 0.0 {
            sum += values[j] * rgb_matching(lambda[j]) / pdf;
        }
    }
    return sum / f32(HERO_COUNT);
}

// C² step from 0 at x ≤ −1 to 1 at x ≥ 1: 6t⁵ − 15t⁴ + 10t³ with t = (x + 1)/2.
// Perlin 2002, "Improving Noise" (SIGGRAPH), §2 (the quintic fade curve).
fn smoother_step(x: f32) -> f32 {
    let t = clamp(0.5 * (x + 1.0), 0.0, 1.0);
    return t * t * t * (t * (6.0 * t - 15.0) + 10.0);
}

// The three smooth uplift basis spectra (red, green, blue) at `lambda_nm`: non-negative and
// summing to 1 at every λ (a partition of unity).
fn uplift_basis(lambda_nm: f32) -> vec3<f32> {
    let red = smoother_step((lambda_nm - UPLIFT_RED_EDGE_NM) / UPLIFT_RED_HALF_WIDTH_NM);
    let blue = 1.0 - smoother_step((lambda_nm - UPLIFT_BLUE_EDGE_NM) / UPLIFT_BLUE_HALF_WIDTH_NM);
    return vec3<f32>(red, max(1.0 - red - blue, 0.0), blue);
}

// Smooth RGB → spectrum uplift for reflectances and emission:
// s(λ) = r·b_r(λ) + g·b_g(λ) + b·b_b(λ) with the partition-of-unity basis of
// [`uplift_basis`]. Smits 1999, "An RGB-to-Spectrum Conversion for Reflectances" (JGT 4(4)), §2.
fn rgb_to_spectrum(rgb: vec3<f32>, lambda_nm: f32) -> f32 {
    let basis = uplift_basis(lambda_nm);
    // Written relative to green so that r = g = b gives exactly g (no rounding).
    let s = rgb.y + (rgb.x - rgb.y) * basis.x + (rgb.z - rgb.y) * basis.z;
    // A convex combination of r, g, b: clamp away f32 rounding only.
    return clamp(s, min(min(rgb.x, rgb.y), rgb.z), max(max(rgb.x, rgb.y), rgb.z));
}

// [`rgb_to_spectrum`] at the four wavelengths of a path (spectral-mode `Color`).
fn rgb_to_spectrum4(rgb: vec3<f32>, lambda: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(
        rgb_to_spectrum(rgb, lambda.x),
        rgb_to_spectrum(rgb, lambda.y),
        rgb_to_spectrum(rgb, lambda.z),
        rgb_to_spectrum(rgb, lambda.w),
    );
}
