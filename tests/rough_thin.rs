//! The rough thin-walled dielectric (`bsdf::RoughThinDielectric`, a frosted sheet): reciprocity,
//! energy, sampling against its pdf (χ²), its smooth limit against the smooth sheet's R', the
//! absence of η² scaling, and which materials become it. Its CPU/GPU twin is in tests/gpu.rs
//! (the BSDF probe's `BSDF_ROUGH_THIN_DIELECTRIC` cases).

use glam::{Vec2, Vec3};
use rayon::prelude::*;
use refract::bsdf::chi2::{self, Chi2Config};
use refract::bsdf::thin::thin_dielectric_reflectance;
use refract::bsdf::{
    Bsdf, BxDF, Event, MicrofacetDistribution, RoughThinDielectric, ThinDielectric, TransportMode,
};
use refract::math::rng::Sampler;
use refract::scene::{Features, Material, MaterialKind, Scene};

const GGX: MicrofacetDistribution = MicrofacetDistribution::Ggx;
const BECK: MicrofacetDistribution = MicrofacetDistribution::Beckmann;

fn sheet(eta: f32, alpha: f32, dist: MicrofacetDistribution) -> RoughThinDielectric {
    RoughThinDielectric { eta, alpha, dist }
}

/// A direction of cosθ = `c` (negative: below the sheet) at azimuth 0.7.
fn wo_at(c: f32) -> Vec3 {
    let s = (1.0 - c * c).max(0.0).sqrt();
    Vec3::new(s * 0.7f32.cos(), s * 0.7f32.sin(), c).normalize()
}

fn random_dir(rng: &mut Sampler) -> Vec3 {
    let z = 2.0 * rng.next() - 1.0;
    let phi = std::f32::consts::TAU * rng.next();
    let s = (1.0 - z * z).max(0.0).sqrt();
    Vec3::new(s * phi.cos(), s * phi.sin(), z)
}

/// f(wo, wi) = f(wi, wo) for random pairs on both sides (reflection and transmission), both
/// distributions, several roughnesses and indices (η < 1 included): the sheet enters and leaves
/// the same medium, so the BSDF itself is symmetric in either transport mode.
#[test]
fn reciprocal_in_both_modes() {
    let mut rng = Sampler::new(3, 0, 11);
    let mut worst = 0.0f32;
    for dist in [GGX, BECK] {
        for alpha in [0.02f32, 0.3, 1.0] {
            for eta in [1.33f32, 1.5, 2.4, 0.67] {
                let b = sheet(eta, alpha, dist);
                for _ in 0..2000 {
                    let (wo, wi) = (random_dir(&mut rng), random_dir(&mut rng));
                    for mode in [TransportMode::Radiance, TransportMode::Importance] {
                        let a = b.eval(wo, wi, mode).x;
                        let r = b.eval(wi, wo, mode).x;
                        let rel = (a - r).abs() / a.abs().max(r.abs()).max(1e-6);
                        worst = worst.max(rel);
                        assert!(rel <= 1e-6, "{dist:?} α={alpha} η={eta}: {a} vs {r}");
                    }
                    assert_eq!(
                        b.eval(wo, wi, TransportMode::Radiance),
                        b.eval(wo, wi, TransportMode::Importance),
                        "no η² scaling"
                    );
                }
            }
        }
    }
    println!("rough sheet: worst reciprocity error {worst:e}");
}

/// The mean and standard error of the sampling weight (the directional albedo), and the mean
/// and standard error of its reflected part.
fn albedo(b: &RoughThinDielectric, wo: Vec3, n: u32, seed: u32) -> (f64, f64, f64, f64) {
    let mut rng = Sampler::new(seed, 0, 5);
    let (mut sum, mut sum2, mut refl, mut refl2) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for _ in 0..n {
        let uc = rng.next();
        let u2 = Vec2::new(rng.next(), rng.next());
        if let Some(s) = b.sample(wo, uc, u2, TransportMode::Radiance) {
            let w = s.weight.x as f64;
            sum += w;
            sum2 += w * w;
            if s.event == Event::Reflect {
                refl += w;
                refl2 += w * w;
            }
        }
    }
    let n = n as f64;
    let mean = sum / n;
    let sigma = ((sum2 / n - mean * mean).max(0.0) / n).sqrt();
    let r = refl / n;
    (mean, sigma, r, ((refl2 / n - r * r).max(0.0) / n).sqrt())
}

/// White furnace: the albedo never exceeds 1 (R' + T' = 1, G2 ≤ G1), from either side; nearly
/// smooth, it is 1 less the lobe's own masking loss, and the reflected part is the smooth
/// sheet's R'(cosθo) (PBR 4th ed. §9.5).
#[test]
fn energy_and_smooth_limit() {
    for dist in [GGX, BECK] {
        for eta in [1.5f32, 2.4, 0.67] {
            for alpha in [2e-3f32, 0.1, 0.5, 1.0] {
                for c in [1.0f32, 0.6, 0.2, -0.5, -0.05] {
                    let b = sheet(eta, alpha, dist);
                    let (m, s, r, sr) = albedo(&b, wo_at(c), 40_000, 7);
                    assert!(
                        m <= 1.0 + 3.0 * s + 1e-6,
                        "{dist:?} η={eta} α={alpha} cos={c}: {m} ± {s}"
                    );
                    if alpha == 2e-3 && c.abs() >= 0.2 {
                        let smooth = ThinDielectric { eta }.reflectance(wo_at(c)) as f64;
                        assert!(m >= 0.995, "{dist:?} η={eta} cos={c}: albedo {m}");
                        assert!(
                            (r - smooth).abs() <= 3.0 * sr + 2e-3,
                            "{dist:?} η={eta} cos={c}: reflected {r} vs R' {smooth}"
                        );
                    }
                }
            }
        }
    }
}

/// Every sample's weight is f·|cos θi|/pdf from `eval` and `pdf`, and its direction lies on
/// the side its event says.
#[test]
fn sample_agrees_with_eval_and_pdf() {
    let mut rng = Sampler::new(9, 0, 2);
    for dist in [GGX, BECK] {
        for alpha in [0.05f32, 0.4, 1.0] {
            let b = sheet(1.5, alpha, dist);
            for _ in 0..5000 {
                let wo = random_dir(&mut rng);
                let (uc, u2) = (rng.next(), Vec2::new(rng.next(), rng.next()));
                let Some(s) = b.sample(wo, uc, u2, TransportMode::Radiance) else {
                    continue;
                };
                let f = b.eval(wo, s.wi, TransportMode::Radiance).x;
                let pdf = b.pdf(wo, s.wi);
                assert!((s.pdf - pdf).abs() <= 1e-4 * pdf, "pdf {} vs {pdf}", s.pdf);
                let w = f * s.wi.z.abs() / pdf;
                assert!(
                    (s.weight.x - w).abs() <= 1e-4 * w.max(1e-3),
                    "{} vs {w}",
                    s.weight.x
                );
                let same_side = wo.z * s.wi.z > 0.0;
                assert_eq!(same_side, s.event == Event::Reflect);
                assert!(!s.is_delta && s.eta_rel == 1.0);
            }
        }
    }
}

/// Sampled directions follow `pdf` over the whole sphere (χ², Šidák-corrected 1 % level over
/// the cases), with ∫pdf equal to the fraction of successful samples.
#[test]
fn chi2_sampling_matches_pdf() {
    let mut cases = Vec::new();
    for dist in [GGX, BECK] {
        for alpha in [0.1f32, 0.5] {
            for eta in [1.5f32, 0.67] {
                for c in [0.9f32, 0.3, -0.6] {
                    cases.push((dist, alpha, eta, c));
                }
            }
        }
    }
    let level = chi2::sidak_alpha(0.01, cases.len());
    let failures: Vec<String> = cases
        .par_iter()
        .enumerate()
        .filter_map(|(i, &(dist, alpha, eta, c))| {
            let cfg = Chi2Config {
                samples: 300_000,
                seed: 40 + i as u32,
                ..Chi2Config::default()
            };
            let b = Bsdf::RoughThinDielectric(sheet(eta, alpha, dist));
            let r = chi2::chi2_test(&b, wo_at(c), TransportMode::Radiance, &cfg);
            let tol = 5.0 * r.success_sigma() + 1e-4;
            let ok = r.p_value > level
                && r.invalid_samples == 0
                && r.delta_samples == 0
                && (r.zero_expected_hits as f64) <= 1e-5 * r.samples as f64
                && (r.pdf_integral - r.success_fraction).abs() <= tol;
            (!ok).then(|| {
                format!(
                    "{dist:?} α={alpha} η={eta} cos={c}: p={:.2e} ∫pdf={:.5} success={:.5}",
                    r.p_value, r.pdf_integral, r.success_fraction
                )
            })
        })
        .collect();
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// R' of the smooth sheet is what the rough one's reflection weights by: at normal incidence
/// both are R + T²R/(1 − R²) of the single interface.
#[test]
fn sheet_reflectance_is_the_airy_sum_of_one_interface() {
    let r = ((1.5f32 - 1.0) / 2.5).powi(2);
    let t = 1.0 - r;
    let expect = r + t * t * r / (1.0 - r * r);
    assert!((thin_dielectric_reflectance(1.0, 1.5) - expect).abs() <= 1e-6);
}

/// Thin glass (transmission without volume) with rough faces becomes the rough sheet, and
/// its `Features` name it and its distribution; smooth, index-matched or filmed it stays
/// the smooth sheet.
#[test]
fn thin_glass_with_roughness_becomes_the_rough_sheet() {
    let textures = [];
    let mut m = Material::glass("pane", 1.5);
    m.kind = MaterialKind::ThinGlass;
    m.roughness = 0.5;
    m.distribution = BECK;
    match m.bsdf(&textures, Vec2::ZERO, m.ior) {
        Bsdf::RoughThinDielectric(b) => {
            assert_eq!((b.eta, b.alpha, b.dist), (1.5, 0.25, BECK));
        }
        other => panic!("{other:?}"),
    }
    let mut smooth = m.clone();
    smooth.roughness = 0.0;
    assert!(matches!(
        smooth.bsdf(&textures, Vec2::ZERO, 1.5),
        Bsdf::ThinDielectric(_)
    ));
    assert!(matches!(
        m.bsdf(&textures, Vec2::ZERO, 1.0),
        Bsdf::ThinDielectric(_)
    ));
    let mut scene = Scene::load("builtin:frosted-panes").expect("built-in");
    let f = refract::scene::features::compute(&scene);
    assert!(
        f.contains(Features::ROUGH_THIN_GLASS | Features::GGX),
        "{f:?}"
    );
    assert!(f.contains(Features::THIN_GLASS), "the smooth pane: {f:?}");
    for mat in &mut scene.materials {
        mat.distribution = BECK;
    }
    let f = refract::scene::features::compute(&scene);
    assert!(
        f.contains(Features::BECKMANN) && !f.contains(Features::GGX),
        "{f:?}"
    );
}
