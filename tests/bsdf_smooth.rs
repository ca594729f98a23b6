//! Smooth BSDFs against analytic optics: Fresnel, Snell, reciprocity, energy and delta sample
//! weights for Lambert, the perfect mirror, the smooth dielectric and the thin dielectric.

use glam::{Vec2, Vec3};
use refract::bsdf::fresnel::{fresnel_dielectric, fresnel_dielectric_terms, refract};
use refract::bsdf::thin::thin_dielectric_reflectance;
use refract::bsdf::*;
use refract::math::rng::Sampler;
use refract::math::sampling::{UNIFORM_SPHERE_PDF, uniform_sphere};
use refract::math::{Color, rgb};
use refract::scene::material::{Material, MaterialKind};
use std::f32::consts::FRAC_PI_2;

const IORS: [f32; 5] = [1.0001, 1.33, 1.5, 2.42, 4.0];

/// IORs and their inverses (the same interfaces seen from inside).
fn iors_and_inverses() -> Vec<f32> {
    IORS.iter().flat_map(|&n| [n, 1.0 / n]).collect()
}

/// Direction at polar angle `theta` and azimuth `phi` on the upper (+z) side.
fn dir(theta: f32, phi: f32) -> Vec3 {
    Vec3::new(
        theta.sin() * phi.cos(),
        theta.sin() * phi.sin(),
        theta.cos(),
    )
}

/// Incidence angles from near-normal to near-grazing.
fn angles() -> impl Iterator<Item = f32> {
    (0..=40).map(|i| (i as f32 + 0.01) / 41.0 * FRAC_PI_2)
}

fn sin_theta(w: Vec3) -> f32 {
    (w.x * w.x + w.y * w.y).sqrt()
}

/// Spacing of f32 values at `x` (one ulp).
fn ulp(x: f32) -> f32 {
    let a = x.abs();
    f32::from_bits(a.to_bits() + 1) - a
}

/// Error in `g(x)` caused by one f32 rounding of its input: |g'(x)|·ulp(x), with g' from a
/// central difference (h = 1e-4, kept inside [0, 1] or [−1, 0] for cosines).
fn input_rounding_error(g: impl Fn(f32) -> f32, x: f32) -> f32 {
    let h = 1e-4f32;
    let (lo, hi) = if x >= 0.0 {
        ((x - h).max(0.0), (x + h).min(1.0))
    } else {
        ((x - h).max(-1.0), (x + h).min(0.0))
    };
    ((g(hi) - g(lo)) / (hi - lo)).abs() * ulp(x)
}

// ---------------------------------------------------------------- Fresnel

#[test]
fn fresnel_normal_incidence() {
    for n in [1.33f32, 1.5, 2.42] {
        let want = ((n - 1.0) / (n + 1.0)).powi(2);
        let from_out = fresnel_dielectric(1.0, n);
        let from_in = fresnel_dielectric(-1.0, n);
        assert!(
            (from_out - want).abs() < 1e-6,
            "n={n}: {from_out} vs {want}"
        );
        assert!(
            (from_in - want).abs() < 1e-6,
            "n={n} inside: {from_in} vs {want}"
        );
    }
}

#[test]
fn fresnel_brewster_angle_kills_r_parallel() {
    // |r∥| < 1e-6 + 2·|∂r∥/∂cosθ|·ulp(cosθ): the f32 Brewster cosine itself is rounded, and
    // from inside a dense medium (η' = 1/n) r∥ is steep (measured: n = 4 from inside gives
    // r∥ = 3.8e-6, exactly one input ulp × slope). r∥ must also change sign across θB.
    let mut worst_ratio = 0.0f32;
    for n in [1.33f32, 1.5, 2.42, 4.0] {
        // Outside → inside: tan θB = n; inside → outside: tan θB = 1/n (cosines negative).
        for (theta_b, sign) in [(n.atan(), 1.0f32), ((1.0 / n).atan(), -1.0)] {
            let c = sign * theta_b.cos();
            let r_par = |c: f32| fresnel_dielectric_terms(c, n).r_par;
            let tol = 1e-6 + 2.0 * input_rounding_error(r_par, c);
            let t = fresnel_dielectric_terms(c, n);
            assert!(
                t.r_par.abs() < tol,
                "n={n} side {sign}: r∥ = {} (tol {tol})",
                t.r_par
            );
            assert!(t.r_perp.abs() > 0.05, "n={n}: r⊥ = {}", t.r_perp);
            let before = r_par(sign * (theta_b - 1e-3).cos());
            let after = r_par(sign * (theta_b + 1e-3).cos());
            assert!(before * after < 0.0, "n={n} side {sign}: no sign change");
            worst_ratio = worst_ratio.max(t.r_par.abs() / tol);
        }
    }
    println!("Brewster: worst |r∥|/tol = {worst_ratio}");
}

#[test]
fn fresnel_critical_angle_from_inside() {
    for n in [1.0001f32, 1.33, 1.5, 2.42, 4.0] {
        let theta_c = (1.0 / n).asin();
        let above = -(theta_c + 1e-4).cos();
        let below = -(theta_c - 1e-4).cos();
        assert_eq!(fresnel_dielectric(above, n), 1.0, "n={n} just above θc");
        let f_below = fresnel_dielectric(below, n);
        assert!(f_below < 1.0, "n={n} just below θc: F = {f_below}");
        // Fresnel and refraction agree on TIR (same sin²θt ≥ 1 test).
        let w_above = dir(theta_c + 1e-4, 0.3);
        let w_below = dir(theta_c - 1e-4, 0.3);
        assert!(refract(w_above, Vec3::Z, 1.0 / n).is_none(), "n={n}");
        assert!(refract(w_below, Vec3::Z, 1.0 / n).is_some(), "n={n}");
    }
}

#[test]
fn fresnel_is_symmetric_under_refraction() {
    // F(cosθi, η) = F(cosθt, 1/η) = F(−cosθt, η) for the refracted angle θt, to
    // 1e-6 + 4·|∂F/∂cosθt|·ulp(cosθt): cosθt is an f32 result, and F seen from inside near the
    // critical angle is steep (grazing entry into n = 4 glass: one ulp of cosθt moves F by
    // 1.2e-4; a float64 model of the same formula confirms this is rounding, not a bug).
    let mut worst_ratio = 0.0f32;
    let mut worst_abs = 0.0f32;
    for eta in iors_and_inverses() {
        for theta in angles() {
            let t = fresnel_dielectric_terms(theta.cos(), eta);
            if t.f >= 1.0 {
                continue; // TIR: no refracted angle.
            }
            let back = fresnel_dielectric(t.cos_t, 1.0 / eta);
            let back_signed = fresnel_dielectric(-t.cos_t, eta);
            let tol =
                1e-6 + 4.0 * input_rounding_error(|c| fresnel_dielectric(c, 1.0 / eta), t.cos_t);
            let err = (back - t.f).abs().max((back_signed - t.f).abs());
            assert!(err < tol, "η={eta} θ={theta}: |ΔF| = {err} (tol {tol})");
            worst_ratio = worst_ratio.max(err / tol);
            worst_abs = worst_abs.max(err);
        }
    }
    println!("Fresnel symmetry: worst |ΔF| = {worst_abs}, worst |ΔF|/tol = {worst_ratio}");
}

#[test]
fn index_matched_interface_is_invisible() {
    for theta in angles() {
        for sign in [1.0f32, -1.0] {
            let cos = sign * theta.cos();
            // Exactly 0: cos²θt = cos²θi + (η−1)(η+1) is exact at η = 1.
            assert_eq!(fresnel_dielectric(cos, 1.0), 0.0, "cos={cos}");
            let wo = dir(theta, 1.1) * Vec3::new(1.0, 1.0, sign);
            let s = SmoothDielectric { eta: 1.0 }
                .sample(wo, 0.0, Vec2::ZERO, TransportMode::Radiance)
                .expect("index-matched sample");
            assert_eq!(s.event, Event::Transmit);
            assert!((s.wi + wo).length() < 1e-6, "wi {} wo {}", s.wi, wo);
            assert_eq!(s.weight.x, 1.0);
            let wt =
                refract(wo * Vec3::new(1.0, 1.0, sign), Vec3::Z, 1.0).expect("no TIR at η = 1");
            assert!((wt + wo * Vec3::new(1.0, 1.0, sign)).length() < 1e-6);
        }
    }
}

// ---------------------------------------------------------------- Snell

#[test]
fn snell_law_with_refract() {
    // sinθi = η' sinθt to 2e-6, |wt| = 1 to 1e-6, wt on the far side, in the plane of incidence.
    let mut worst = 0.0f32;
    for eta in iors_and_inverses() {
        for theta in angles() {
            let wi = dir(theta, 0.7);
            let Some(wt) = refract(wi, Vec3::Z, eta) else {
                assert!(
                    theta.sin() >= eta * 0.999_99,
                    "unexpected TIR η={eta} θ={theta}"
                );
                assert_eq!(fresnel_dielectric(wi.z, eta), 1.0);
                continue;
            };
            assert!(wt.z < 0.0);
            assert!((wt.length() - 1.0).abs() < 1e-6, "|wt| = {}", wt.length());
            // Opposite azimuth: wt.xy is a negative multiple of wi.xy.
            assert!((wt.x * wi.y - wt.y * wi.x).abs() < 1e-6 && wt.x * wi.x <= 0.0);
            worst = worst.max((theta.sin() - eta * sin_theta(wt)).abs());
        }
    }
    assert!(worst < 2e-6, "worst Snell residual {worst}");
}

#[test]
fn snell_law_with_smooth_dielectric_sample() {
    // Same checks through SmoothDielectric::sample with uc ≥ F (forces refraction), for wo
    // on both sides: eta_rel reported = η (outside) or 1/η (inside).
    let mut worst = 0.0f32;
    for eta in iors_and_inverses() {
        for theta in angles() {
            for side in [1.0f32, -1.0] {
                let wo = dir(theta, 2.1) * Vec3::new(1.0, 1.0, side);
                let f = fresnel_dielectric(wo.z, eta);
                let uc = f + 0.5 * (1.0 - f);
                let s = SmoothDielectric { eta }
                    .sample(wo, uc, Vec2::ZERO, TransportMode::Radiance)
                    .expect("sample");
                if f >= 1.0 {
                    assert_eq!(s.event, Event::Reflect, "TIR must reflect");
                    continue;
                }
                let eta_rel = if side > 0.0 { eta } else { 1.0 / eta };
                assert_eq!(s.event, Event::Transmit);
                assert_eq!(s.eta_rel, eta_rel);
                assert!(s.wi.z * side < 0.0, "wi must cross the surface");
                assert!((s.wi.length() - 1.0).abs() < 1e-6);
                assert!((s.wi.x * wo.y - s.wi.y * wo.x).abs() < 1e-6 && s.wi.x * wo.x <= 0.0);
                worst = worst.max((sin_theta(wo) - eta_rel * sin_theta(s.wi)).abs());
            }
        }
    }
    assert!(worst < 2e-6, "worst Snell residual {worst}");
}

// ---------------------------------------------------------------- reciprocity

#[test]
fn lambert_is_reciprocal() {
    let b = Lambert::new(rgb(0.9, 0.5, 0.1));
    let mut s = Sampler::new(1, 0, 11);
    for _ in 0..10_000 {
        let mut wo = uniform_sphere(s.next2());
        let mut wi = uniform_sphere(s.next2());
        wo.z = wo.z.abs();
        wi.z = wi.z.abs();
        let a = b.eval(wo, wi, TransportMode::Radiance);
        let c = b.eval(wi, wo, TransportMode::Radiance);
        assert_eq!(a, c, "wo {wo} wi {wi}");
        assert!((b.pdf(wo, wi) - wi.z / std::f32::consts::PI).abs() < 1e-6);
    }
}

/// Delta "mass" of a sampled event: weight · probability = ∫ f |cos θi| over the delta.
fn mass(s: &BsdfSample) -> f32 {
    s.weight.x * s.pdf
}

#[test]
fn dielectric_transmission_obeys_adjoint_and_generalised_reciprocity() {
    // For a refraction from side A (wo) to side B (wi) with η' = n_B/n_A = eta_rel:
    //  (a) weight_radiance · η'² = weight_importance = 1;
    //  (b) the event probabilities agree both ways: p(A→B) = p(B→A) = 1 − F;
    //  (c) generalised reciprocity f(wo,wi)/n_A² = f(wi,wo)/n_B² (Veach 1997, eq. 5.14) in
    //      delta form: m_R(A→B)·η'_AB² = m_R(B→A)·η'_BA² (both = T), m = weight·pdf;
    //  (d) the reverse sample from wi refracts back to wo.
    // (a) to 2e-6 relative; (b), (c) to 2e-6 + 4·|∂F/∂cosθ|·ulp(cos θ_B) (wi is rounded to
    // f32 and F seen from B is steep near its critical angle); (d) 1e-5 + 4 propagated ulps.
    for eta in iors_and_inverses() {
        for theta in angles() {
            for side in [1.0f32, -1.0] {
                let wo = dir(theta, 0.4) * Vec3::new(1.0, 1.0, side);
                let b = SmoothDielectric { eta };
                let f = fresnel_dielectric(wo.z, eta);
                if f >= 1.0 {
                    continue;
                }
                let uc = f + 0.5 * (1.0 - f);
                let rad = b
                    .sample(wo, uc, Vec2::ZERO, TransportMode::Radiance)
                    .unwrap();
                let imp = b
                    .sample(wo, uc, Vec2::ZERO, TransportMode::Importance)
                    .unwrap();
                let e = rad.eta_rel;
                assert!((rad.weight.x * e * e - imp.weight.x).abs() < 2e-6 * imp.weight.x);
                assert_eq!(imp.weight.x, 1.0);
                let fb = fresnel_dielectric(rad.wi.z, eta);
                let ucb = fb + 0.5 * (1.0 - fb);
                let back = b
                    .sample(rad.wi, ucb, Vec2::ZERO, TransportMode::Radiance)
                    .unwrap();
                assert_eq!(back.event, Event::Transmit);
                // wi is an f32 result; F seen from B can be steep (near its critical angle).
                let tol =
                    2e-6 + 4.0 * input_rounding_error(|c| fresnel_dielectric(c, eta), rad.wi.z);
                assert!(
                    (back.pdf - rad.pdf).abs() < tol,
                    "p(A→B) ≠ p(B→A), tol {tol}"
                );
                let eb = back.eta_rel;
                assert!((eb * e - 1.0).abs() < 1e-6);
                let lhs = mass(&rad) * e * e;
                let rhs = mass(&back) * eb * eb;
                assert!(
                    (lhs - rhs).abs() < 2e-6 * lhs + tol,
                    "η={eta} θ={theta}: {lhs} vs {rhs}"
                );
                assert!((lhs - (1.0 - f)).abs() < 2e-6, "mass·η'² = T");
                // Back from B, dcosθ_A/dcosθ_B = cosθ_B/(η_BA'² cosθ_A): one ulp of wi.z can
                // move wo.z by up to ~2e-5 (grazing exit from n = 4), so allow 4 such ulps.
                let dir_tol = 1e-5 + 4.0 * (rad.wi.z / (eb * eb * wo.z)).abs() * ulp(rad.wi.z);
                assert!(
                    (back.wi - wo).length() < dir_tol,
                    "reverse path {} vs {wo}",
                    back.wi
                );
            }
        }
    }
}

// ---------------------------------------------------------------- energy

#[test]
fn lambert_albedo_monte_carlo() {
    // Uniform-sphere estimate of ∫ f cos dωi (independent of the BSDF's own sampler) for 16
    // directions; |estimate − ρ| < 4σ each (σ from the sample variance, 20k samples), and the
    // sampler's weight is exactly ρ.
    for albedo in [1.0f32, 0.5] {
        let b = Lambert::new(Color::splat(albedo));
        let mut s = Sampler::new(5, 0, 99);
        for k in 0..16 {
            let wo = dir(k as f32 / 16.0 * 1.5, 0.2 * k as f32);
            let n = 20_000;
            let (mut m, mut m2) = (0.0f64, 0.0f64);
            for _ in 0..n {
                let wi = uniform_sphere(s.next2());
                let v = (b.eval(wo, wi, TransportMode::Radiance).x * wi.z.abs()
                    / UNIFORM_SPHERE_PDF) as f64;
                m += v;
                m2 += v * v;
            }
            m /= n as f64;
            let sigma = ((m2 / n as f64 - m * m) / n as f64).sqrt();
            assert!(m <= 1.0 + 3.0 * sigma, "energy gain: {m} ± {sigma}");
            assert!(
                (m - albedo as f64).abs() < 4.0 * sigma,
                "{m} ± {sigma} vs {albedo}"
            );
            let smp = b
                .sample(wo, s.next(), s.next2(), TransportMode::Radiance)
                .unwrap();
            assert_eq!(smp.weight.x, albedo);
            let cos_pdf = smp.f.x * smp.wi.z / smp.pdf;
            assert!((cos_pdf - albedo).abs() < 1e-5, "f·cos/pdf = {cos_pdf}");
        }
    }
}

#[test]
fn mirror_and_dielectric_albedo() {
    let mirror = Mirror {
        reflectance: rgb(1.0, 0.7, 0.2),
    };
    for theta in angles() {
        let wo = dir(theta, 0.9);
        let s = mirror
            .sample(wo, 0.3, Vec2::ZERO, TransportMode::Radiance)
            .unwrap();
        assert!(s.weight.max_element() <= 1.0);
        assert_eq!(s.weight, mirror.reflectance);
    }
    // Smooth dielectric: mean weight over 20k uc (fixed seed), per direction.
    // Importance mode (flux): exactly 1. Radiance mode from outside: F + (1−F)/η² ≤ 1 within
    // 3σ of the analytic value; from inside it is F + (1−F)·η² > 1, the η² radiance gain on
    // exit (not an energy gain), also checked within 3σ.
    for eta in IORS {
        let b = SmoothDielectric { eta };
        let mut rng = Sampler::new(17, 0, 5);
        for theta in angles() {
            for side in [1.0f32, -1.0] {
                let wo = dir(theta, 0.1) * Vec3::new(1.0, 1.0, side);
                let n = 20_000;
                let (mut mr, mut mr2, mut mi) = (0.0f64, 0.0f64, 0.0f64);
                for _ in 0..n {
                    let uc = rng.next();
                    let r = b
                        .sample(wo, uc, Vec2::ZERO, TransportMode::Radiance)
                        .unwrap();
                    let i = b
                        .sample(wo, uc, Vec2::ZERO, TransportMode::Importance)
                        .unwrap();
                    mr += r.weight.x as f64;
                    mr2 += (r.weight.x as f64).powi(2);
                    mi += i.weight.x as f64;
                }
                mr /= n as f64;
                mi /= n as f64;
                assert_eq!(mi, 1.0, "importance-mode albedo");
                // Clamp: a constant weight (F ≈ 0) gives a rounding-negative variance.
                let sigma = ((mr2 / n as f64 - mr * mr).max(0.0) / n as f64).sqrt();
                let f = fresnel_dielectric(wo.z, eta) as f64;
                let e = if side > 0.0 {
                    eta as f64
                } else {
                    1.0 / eta as f64
                };
                let want = f + (1.0 - f) / (e * e);
                assert!(
                    (mr - want).abs() <= 3.0 * sigma + 1e-6,
                    "η={eta} θ={theta} side {side}: {mr} ± {sigma} vs {want}"
                );
                if side > 0.0 {
                    assert!(mr <= 1.0 + 3.0 * sigma, "radiance albedo {mr} > 1");
                }
            }
        }
    }
}

#[test]
fn dielectric_reflect_plus_transmit_is_one() {
    // pdf(reflect) + pdf(transmit) = 1 to 1e-6, importance weights exactly 1.
    for eta in iors_and_inverses() {
        let b = SmoothDielectric { eta };
        for theta in angles() {
            for side in [1.0f32, -1.0] {
                let wo = dir(theta, 0.5) * Vec3::new(1.0, 1.0, side);
                let f = fresnel_dielectric(wo.z, eta);
                let r = b
                    .sample(wo, 0.0, Vec2::ZERO, TransportMode::Importance)
                    .unwrap();
                let t = b
                    .sample(
                        wo,
                        1.0 - f32::EPSILON,
                        Vec2::ZERO,
                        TransportMode::Importance,
                    )
                    .unwrap();
                assert_eq!(r.weight.x, 1.0);
                assert_eq!(t.weight.x, 1.0);
                if f >= 1.0 {
                    assert_eq!((r.event, t.event), (Event::Reflect, Event::Reflect));
                    assert_eq!(r.pdf, 1.0);
                    continue;
                }
                assert_eq!((r.event, t.event), (Event::Reflect, Event::Transmit));
                assert!((r.pdf + t.pdf - 1.0).abs() < 1e-6, "{} + {}", r.pdf, t.pdf);
            }
        }
    }
}

// ---------------------------------------------------------------- delta sample weights

#[test]
fn delta_sample_weights() {
    // Mirror: weight = reflectance, pdf 1, direction exact.
    let m = Mirror {
        reflectance: rgb(0.9, 0.5, 0.25),
    };
    let wo = dir(0.8, 1.3);
    let s = m
        .sample(wo, 0.5, Vec2::ZERO, TransportMode::Radiance)
        .unwrap();
    assert_eq!(s.weight, m.reflectance);
    assert_eq!(s.wi, Vec3::new(-wo.x, -wo.y, wo.z));
    assert!(s.is_delta && s.lobe == Lobe::S && s.pdf == 1.0);
    assert_eq!(m.eval(wo, s.wi, TransportMode::Radiance), Color::ZERO);
    assert_eq!(m.pdf(wo, s.wi), 0.0);

    // Dielectric: reflection weight 1 with probability F, transmission 1/η'² (radiance) or
    // 1 (importance) with 1 − F. The reflected fraction over 100k fixed-seed uc is within 4σ
    // (binomial) of F.
    for eta in [1.33f32, 1.5, 2.42] {
        let b = SmoothDielectric { eta };
        for (theta, side) in [(0.3f32, 1.0f32), (1.2, 1.0), (0.3, -1.0)] {
            let wo = dir(theta, 0.2) * Vec3::new(1.0, 1.0, side);
            let f = fresnel_dielectric(wo.z, eta);
            let e = if side > 0.0 { eta } else { 1.0 / eta };
            let mut rng = Sampler::new(2, 3, 4);
            let n = 100_000;
            let mut reflected = 0;
            for _ in 0..n {
                let uc = rng.next();
                let r = b
                    .sample(wo, uc, Vec2::ZERO, TransportMode::Radiance)
                    .unwrap();
                match r.event {
                    Event::Reflect => {
                        reflected += 1;
                        assert_eq!(r.weight.x, 1.0);
                        assert_eq!(r.pdf, f);
                        assert_eq!(r.wi, Vec3::new(-wo.x, -wo.y, wo.z));
                    }
                    Event::Transmit => {
                        assert!((r.weight.x - 1.0 / (e * e)).abs() < 1e-6 / (e * e));
                        assert!((r.pdf - (1.0 - f)).abs() < 1e-7);
                        let i = b
                            .sample(wo, uc, Vec2::ZERO, TransportMode::Importance)
                            .unwrap();
                        assert_eq!(i.weight.x, 1.0);
                    }
                }
                assert!(r.is_delta && r.lobe == Lobe::S);
            }
            let frac = reflected as f64 / n as f64;
            let sigma = (f as f64 * (1.0 - f as f64) / n as f64).sqrt();
            assert!(
                (frac - f as f64).abs() < 4.0 * sigma,
                "η={eta} θ={theta}: {frac} vs F={f} (σ={sigma})"
            );
        }
    }
}

#[test]
fn total_internal_reflection_always_reflects() {
    for eta in [1.33f32, 1.5, 2.42, 4.0] {
        let b = SmoothDielectric { eta };
        let theta_c = (1.0 / eta).asin();
        for k in 1..=10 {
            let theta = theta_c + (FRAC_PI_2 - theta_c) * k as f32 / 10.5;
            let wo = -dir(theta, 0.6); // inside, heading out
            // uc = 1.0 included: an f32 sampler can round up to 1 (was a refraction bug).
            for uc in [0.0f32, 0.5, 0.999_999_9, 1.0] {
                let s = b
                    .sample(wo, uc, Vec2::ZERO, TransportMode::Radiance)
                    .unwrap();
                assert_eq!(s.event, Event::Reflect, "η={eta} θ={theta} uc={uc}");
                assert_eq!((s.pdf, s.weight.x), (1.0, 1.0));
                assert_eq!(s.wi, Vec3::new(-wo.x, -wo.y, wo.z));
            }
        }
    }
}

// ---------------------------------------------------------------- thin dielectric

#[test]
fn thin_dielectric_normal_incidence() {
    // R' = 2R/(1+R) at normal incidence; for n = 1.5: R = 0.04, R' = 0.076923…; slab
    // transmittance T' = (1−R)/(1+R) (docs/design.md "Testing"). Tolerance 1e-6.
    let b = ThinDielectric { eta: 1.5 };
    let r = 0.04f32;
    let rp = b.reflectance(Vec3::Z);
    assert!((rp - 2.0 * r / (1.0 + r)).abs() < 1e-6, "R' = {rp}");
    assert!((rp - 0.076_923_08).abs() < 1e-6, "R' = {rp}");
    assert!((1.0 - rp - (1.0 - r) / (1.0 + r)).abs() < 1e-6);
    assert_eq!(b.reflectance(-Vec3::Z), rp);
}

#[test]
fn thin_dielectric_matches_interreflection_series() {
    // R' = R + T²R Σ_k R^{2k} summed explicitly (200 terms), to 1e-6, at many angles.
    for eta in IORS {
        for theta in angles() {
            let c = theta.cos();
            let r = fresnel_dielectric(c, eta) as f64;
            let t = 1.0 - r;
            let mut series = r;
            let mut term = t * t * r;
            for _ in 0..200 {
                series += term;
                term *= r * r;
            }
            let got = thin_dielectric_reflectance(c, eta) as f64;
            assert!(
                (got - series).abs() < 1e-6,
                "η={eta} θ={theta}: {got} vs {series}"
            );
        }
    }
}

#[test]
fn thin_dielectric_sampling() {
    // R' + T' = 1 (pdfs, 1e-6); weights 1 in both modes (no η² scaling); pass-through exactly
    // −wo; reflection exactly mirrored; works from both sides.
    for eta in [1.0001f32, 1.33, 1.5, 2.42, 4.0, 1.0 / 1.5] {
        let b = ThinDielectric { eta };
        for theta in angles() {
            for side in [1.0f32, -1.0] {
                let wo = dir(theta, 1.7) * Vec3::new(1.0, 1.0, side);
                let rp = b.reflectance(wo);
                for mode in [TransportMode::Radiance, TransportMode::Importance] {
                    let r = b.sample(wo, 0.0, Vec2::ZERO, mode).unwrap();
                    let t = b.sample(wo, 1.0 - f32::EPSILON, Vec2::ZERO, mode).unwrap();
                    assert_eq!(r.event, Event::Reflect);
                    assert_eq!(r.wi, Vec3::new(-wo.x, -wo.y, wo.z));
                    assert_eq!(r.pdf, rp);
                    assert_eq!(r.weight.x, 1.0);
                    if rp >= 1.0 {
                        assert_eq!(t.event, Event::Reflect);
                        continue;
                    }
                    assert_eq!(t.event, Event::Transmit);
                    assert_eq!(t.wi, -wo, "pass-through must be exact");
                    assert_eq!((t.weight.x, t.eta_rel), (1.0, 1.0));
                    assert!((r.pdf + t.pdf - 1.0).abs() < 1e-6);
                    assert!(r.is_delta && t.is_delta && r.lobe == Lobe::S && t.lobe == Lobe::S);
                }
            }
        }
    }
    // Index-matched sheet: invisible.
    let s = ThinDielectric { eta: 1.0 }
        .sample(dir(0.4, 0.0), 0.0, Vec2::ZERO, TransportMode::Radiance)
        .unwrap();
    assert_eq!(s.event, Event::Transmit);
}

#[test]
fn thin_glass_material_maps_to_thin_dielectric() {
    let mut m = Material::glass("sheet", 1.5);
    m.kind = MaterialKind::ThinGlass;
    let bsdf = m.bsdf(&[], Vec2::ZERO, 1.5);
    assert!(matches!(bsdf, Bsdf::ThinDielectric(ThinDielectric { eta }) if eta == 1.5));
    assert!(bsdf.is_delta());
    assert_eq!(bsdf.class(), Lobe::S);
    let s = bsdf
        .sample(Vec3::Z, 0.5, Vec2::ZERO, TransportMode::Radiance)
        .unwrap();
    assert_eq!((s.event, s.wi), (Event::Transmit, -Vec3::Z));
    // Solid glass still maps to the smooth (refracting) interface.
    let solid = Material::glass("solid", 1.5).bsdf(&[], Vec2::ZERO, 1.5);
    assert!(matches!(solid, Bsdf::SmoothDielectric(_)));
}

#[test]
fn smooth_conductor_reflects_with_the_conductor_fresnel() {
    // Delta reflection, Heckbert S, weight = tint × F(cosθo) per channel (in [0, 1] for a
    // white tint), nothing from below; the material maps to it (smooth) or the rough lobe.
    use refract::bsdf::fresnel::fresnel_conductor_color;
    for metal in Metal::ALL {
        let ior = ComplexIor::rgb(metal);
        let b = Bsdf::SmoothConductor(SmoothConductor {
            ior,
            tint: rgb(1.0, 0.5, 0.25),
        });
        assert!(b.is_delta() && b.class() == Lobe::S && !b.can_transmit());
        for c in [1.0f32, 0.7, 0.3, 0.05] {
            let wo = Vec3::new((1.0 - c * c).sqrt(), 0.0, c);
            let s = b
                .sample(wo, 0.5, Vec2::splat(0.5), TransportMode::Radiance)
                .unwrap();
            assert!(
                s.is_delta
                    && s.lobe == Lobe::S
                    && (s.wi - Vec3::new(-wo.x, 0.0, c)).length() < 1e-6
            );
            let f = fresnel_conductor_color(c, ior.eta, ior.k);
            let want = rgb(1.0, 0.5, 0.25) * f;
            assert!(
                (s.weight - want).abs().max_element() < 1e-6,
                "{metal:?} cos {c}: {:?}",
                s.weight
            );
            assert!(f.truncate().max_element() <= 1.0 && f.truncate().min_element() > 0.0);
            assert!(
                b.sample(-wo, 0.5, Vec2::splat(0.5), TransportMode::Radiance)
                    .is_none()
            );
        }
        let smooth = Material {
            conductor: Some(metal),
            ..Material::mirror("m", Vec3::ONE)
        };
        assert!(matches!(
            smooth.bsdf(&[], Vec2::ZERO, 1.5),
            Bsdf::SmoothConductor(_)
        ));
        let rough = Material {
            kind: MaterialKind::GlossyMetal,
            roughness: 0.3,
            ..smooth.clone()
        };
        match rough.bsdf(&[], Vec2::ZERO, 1.5) {
            Bsdf::RoughFresnelConductor(r) => assert!((r.lobe.alpha - 0.09).abs() < 1e-6),
            other => panic!("{other:?}"),
        }
    }
}
