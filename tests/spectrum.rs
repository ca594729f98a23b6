//! Spectral maths: Abbe dispersion, hero wavelength sampling, CIE → sRGB normalisation and the
//! RGB → spectrum uplift round trip.

use glam::{Vec3, Vec4};
use refract::math::rng::Sampler;
use refract::math::spectrum::*;

/// Fine deterministic quadrature: midpoint rule over [360, 830] nm with `n` steps, in f64.
fn integrate_rgb(n: usize, s: impl Fn(f32) -> f32) -> [f64; 3] {
    let h = (LAMBDA_MAX - LAMBDA_MIN) as f64 / n as f64;
    let mut acc = [0.0f64; 3];
    for i in 0..n {
        let l = (LAMBDA_MIN as f64 + (i as f64 + 0.5) * h) as f32;
        let w = rgb_matching(l) * s(l);
        acc[0] += w.x as f64 * h;
        acc[1] += w.y as f64 * h;
        acc[2] += w.z as f64 * h;
    }
    acc
}

/// Steps of the fine quadrature.
const FINE: usize = 94_000; // 0.005 nm steps

#[test]
fn abbe_model_reproduces_nd_and_vd() {
    for (n_d, v_d) in [(1.5168f32, 64.17f32), (1.62, 36.4)] {
        let n_f = cauchy_from_abbe(n_d, v_d, 486.1);
        let n_dd = cauchy_from_abbe(n_d, v_d, 587.6);
        let n_c = cauchy_from_abbe(n_d, v_d, 656.3);
        let v = (n_dd - 1.0) / (n_f - n_c);
        assert!(
            ((n_dd - n_d) / n_d).abs() < 1e-3,
            "n_d: got {n_dd}, want {n_d}"
        );
        assert!(((v - v_d) / v_d).abs() < 1e-3, "V_d: got {v}, want {v_d}");
        // Normal dispersion: n_F > n_d > n_C.
        assert!(n_f > n_dd && n_dd > n_c);
    }
}

#[test]
fn cmf_integral_constant_matches_quadrature() {
    let n = FINE;
    let h = (LAMBDA_MAX - LAMBDA_MIN) as f64 / n as f64;
    let mut acc = [0.0f64; 3];
    for i in 0..n {
        let l = (LAMBDA_MIN as f64 + (i as f64 + 0.5) * h) as f32;
        let c = cie_xyz_cmf(l);
        acc[0] += c.x as f64 * h;
        acc[1] += c.y as f64 * h;
        acc[2] += c.z as f64 * h;
    }
    let k = CIE_CMF_INTEGRAL;
    for (got, want) in acc.iter().zip([k.x, k.y, k.z]) {
        assert!(
            (got / want as f64 - 1.0).abs() < 1e-5,
            "∫cmf {got} vs {want}"
        );
    }
    // The fit is close to the CIE 1931 table: ∫ȳ ≈ 106.86 (1 nm table over 360..830).
    assert!((acc[1] - 106.86).abs() < 0.5, "∫ȳ = {}", acc[1]);
    // Peak of ȳ near 555 nm with value ≈ 1.
    let y555 = cie_xyz_cmf(555.0).y;
    assert!((y555 - 1.0).abs() < 0.02, "ȳ(555) = {y555}");
}

#[test]
fn xyz_to_srgb_maps_d65_to_white() {
    // D65 white point XYZ (Y = 1): x = 0.3127, y = 0.3290. IEC 61966-2-1.
    let (x, y) = (0.3127f32, 0.3290f32);
    let d65 = Vec3::new(x / y, 1.0, (1.0 - x - y) / y);
    let rgb = xyz_to_linear_srgb(d65);
    assert!((rgb - Vec3::ONE).abs().max_element() < 1e-3, "D65 → {rgb}");
}

#[test]
fn constant_spectrum_is_white_quadrature() {
    let rgb = integrate_rgb(FINE, |_| 1.0);
    for c in rgb {
        assert!((c - 1.0).abs() < 1e-3, "constant 1 → {rgb:?}");
    }
}

#[test]
fn hero_wavelengths_are_rotated_and_in_range() {
    let mut s = Sampler::new(3, 0, 42);
    for _ in 0..10_000 {
        let l = sample_hero_wavelengths(s.next());
        for (j, lj) in l.iter().enumerate() {
            assert!((LAMBDA_MIN..=LAMBDA_MAX).contains(lj), "λ{j} = {lj}");
            assert_eq!(hero_wavelength_pdf(*lj), 1.0 / 470.0);
        }
        // Consecutive companions are 117.5 nm apart modulo 470.
        for j in 1..4 {
            let d = (l[j] - l[0]).rem_euclid(470.0);
            let want = 117.5 * j as f32;
            assert!((d - want).abs() < 1e-3, "offset {j}: {d} vs {want}");
        }
    }
    assert_eq!(sample_hero_wavelengths(0.0), [360.0, 477.5, 595.0, 712.5]);
    assert_eq!(hero_wavelength_pdf(359.0), 0.0);
    assert_eq!(hero_wavelength_pdf(831.0), 0.0);
}

#[test]
fn constant_spectrum_is_white_hero_sampler() {
    // 1e6 hero samples of a constant spectrum 1; each channel's mean must be within 3σ of 1,
    // σ = sample standard deviation / √N.
    let n = 1_000_000u32;
    let mut sum = [0.0f64; 3];
    let mut sum2 = [0.0f64; 3];
    for i in 0..n {
        let u = Sampler::new(i, 0, 7).next();
        let l = sample_hero_wavelengths(u);
        let rgb = spectrum_sample_to_rgb(l, Vec4::ONE);
        for (k, v) in rgb.to_array().iter().enumerate() {
            sum[k] += *v as f64;
            sum2[k] += (*v as f64) * (*v as f64);
        }
    }
    for k in 0..3 {
        let mean = sum[k] / n as f64;
        let var = sum2[k] / n as f64 - mean * mean;
        let sigma = (var / n as f64).sqrt();
        assert!(
            (mean - 1.0).abs() < 3.0 * sigma,
            "channel {k}: mean {mean}, σ {sigma}"
        );
    }
}

#[test]
fn grey_uplift_is_exact_constant() {
    for g in [0.0f32, 0.18, 0.5, 1.0, 3.7] {
        for i in 0..=470 {
            let l = 360.0 + i as f32;
            assert_eq!(rgb_to_spectrum(Vec3::splat(g), l), g, "grey {g} at {l}");
        }
        let rgb = integrate_rgb(FINE, |l| rgb_to_spectrum(Vec3::splat(g), l));
        for c in rgb {
            assert!((c - g as f64).abs() < 1e-3, "grey {g} → {rgb:?}");
        }
    }
}

#[test]
fn uplift_stays_in_unit_interval_and_scales_linearly() {
    let steps = [0.0f32, 0.25, 0.5, 0.75, 1.0];
    for &r in &steps {
        for &g in &steps {
            for &b in &steps {
                let c = Vec3::new(r, g, b);
                for i in 0..=94 {
                    let l = 360.0 + 5.0 * i as f32;
                    let s = rgb_to_spectrum(c, l);
                    assert!((0.0..=1.0).contains(&s), "{c} at {l}: {s}");
                    let s10 = rgb_to_spectrum(10.0 * c, l);
                    assert!((s10 - 10.0 * s).abs() <= 1e-5 * (1.0 + s10), "{c} at {l}");
                }
            }
        }
    }
    for i in 0..=470 {
        let basis = uplift_basis(360.0 + i as f32);
        assert!(basis.min_element() >= 0.0);
        assert!((basis.element_sum() - 1.0).abs() < 1e-6);
    }
}

#[test]
fn primaries_round_trip_within_tolerance() {
    // Measured worst case 0.0255 (red's blue channel); asserted ≤ 0.03 absolute per channel.
    let cases = [
        Vec3::X,
        Vec3::Y,
        Vec3::Z,
        Vec3::new(0.0, 1.0, 1.0),
        Vec3::new(1.0, 0.0, 1.0),
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::new(0.8, 0.4, 0.1),
    ];
    let mut worst = 0.0f64;
    for c in cases {
        let rgb = integrate_rgb(FINE / 10, |l| rgb_to_spectrum(c, l));
        for (k, v) in rgb.iter().enumerate() {
            let err = (v - c[k] as f64).abs();
            worst = worst.max(err);
            assert!(err <= 0.03, "{c} → {rgb:?} (channel {k} off by {err})");
        }
    }
    println!("worst primary round-trip error {worst:.4}");
}
