//! Thin-film iridescence (`bsdf::Iridescent`, glTF `KHR_materials_iridescence`): rendered
//! reflectance against the Airy summation (Born & Wolf §7.6), the BSDF's sampling, reciprocity
//! and energy, a white furnace, and the glTF extension read and written.

mod common_scenes;
use common_scenes::*;
use glam::{Vec2, Vec3};
use refract::bsdf::chi2::{self, Chi2Config};
use refract::bsdf::thin_film::ThinFilm;
use refract::bsdf::{
    Bsdf, BxDF, ComplexIor, Event, Iridescent, Metal, MicrofacetDistribution as Dist,
    RoughConductor, RoughDielectric, SmoothConductor, SmoothDielectric, ThinDielectric,
    TransportMode,
};
use refract::cpu::Renderer;
use refract::math::complex::Complex;
use refract::math::rng::Sampler;
use refract::math::spectrum::rgb_matching;
use refract::math::{Color, rgb, sampling};
use refract::render::RenderOptions;
use refract::scene::{Camera, Iridescence, Material, MaterialKind, Mesh};

const FILM: ThinFilm = ThinFilm {
    ior: 1.38,
    thickness_nm: 420.0,
};

/// ∫ r̄(λ) R(λ) dλ over [360, 830] nm (midpoint rule, 0.1 nm): what a spectral render of a
/// reflectance spectrum R under a flat white illuminant converges to.
fn integrated_airy(film: ThinFilm, cos1: f32, n3: impl Fn(f32) -> Complex) -> Vec3 {
    let n = 4700;
    let dl = (830.0 - 360.0) / n as f32;
    let mut sum = glam::DVec3::ZERO;
    for i in 0..n {
        let l = 360.0 + (i as f32 + 0.5) * dl;
        sum += (rgb_matching(l) * film.airy(cos1, n3(l), l) * dl).as_dvec3();
    }
    sum.as_vec3()
}

/// A filmed half-space: a 100 m slab whose top face is the film, under a uniform white
/// environment, seen at `incidence_deg` through a 1 mrad camera. max_depth 2 keeps the paths
/// camera → top face → environment (a refracted path needs the bottom face: depth 3).
fn flat_film_render(mat: Material, incidence_deg: f32, spectral: bool, spp: u32) -> (Vec3, Vec3) {
    let mut m = Mesh::default();
    refract::scene::builtin::cuboid(
        &mut m,
        Vec3::new(-50.0, -100.0, -50.0),
        Vec3::new(50.0, 0.0, 50.0),
        0,
    );
    let t = incidence_deg.to_radians();
    let eye = Vec3::new(0.0, 10.0 * t.cos(), 10.0 * t.sin());
    let up = if incidence_deg == 0.0 {
        Vec3::Z
    } else {
        Vec3::Y
    };
    let cam = Camera::look_at(eye, Vec3::ZERO, up, 1e-3);
    let mut s = scene("flat-film", m, vec![mat], cam, 1.0);
    s.settings.max_depth = 2;
    s.settings.width = 64;
    s.settings.height = 64;
    let mut r = Renderer::new(s).expect("valid scene");
    r.spectral = spectral;
    let o = RenderOptions::from_scene(&r.scene);
    let img = r.render(&o, spp, None, |_| {}).0.image();
    let n = img.len() as f64;
    let mean = img.iter().map(|p| p.as_dvec3()).sum::<glam::DVec3>() / n;
    let var = img
        .iter()
        .map(|p| (p.as_dvec3() - mean).powf(2.0))
        .sum::<glam::DVec3>()
        / (n - 1.0);
    (mean.as_vec3(), (var / n).sqrt().as_vec3())
}

fn with_film(m: Material, film: ThinFilm) -> Material {
    Material {
        iridescence: Some(Iridescence {
            factor: 1.0,
            ior: film.ior,
            thickness_min: 0.0,
            thickness_max: film.thickness_nm,
            thickness_texture: None,
        }),
        ..m
    }
}

/// A substrate's name, material and index as a function of λ (nm).
type Substrate = (&'static str, Material, Box<dyn Fn(f32) -> Complex>);

/// The substrates of the check: glass, gold (tabulated η, k) and a grey metal of the scene
/// contract (F₀ = 0.6 → η = (1 + √F₀)/(1 − √F₀)), each with its index as a function of λ.
fn substrates() -> Vec<Substrate> {
    let f0: f32 = 0.6;
    let grey_eta = (1.0 + f0.sqrt()) / (1.0 - f0.sqrt());
    vec![
        (
            "glass",
            Material::glass("glass", 1.5),
            Box::new(|_| Complex::real(1.5)),
        ),
        (
            "gold",
            Material {
                conductor: Some(Metal::Au),
                ..Material::mirror("gold", Vec3::ONE)
            },
            Box::new(|l| {
                let (eta, k) = Metal::Au.ior_at(l);
                Complex::new(eta, k)
            }),
        ),
        (
            "grey",
            Material::mirror("grey", Vec3::splat(f0)),
            Box::new(move |_| Complex::real(grey_eta)),
        ),
    ]
}

/// The target: a flat film on a substrate under a uniform environment, at normal and
/// 45° incidence, renders (spectrally) the Airy reflectance integrated over each colour band
/// within 1 % per band. The only noise is the wavelength sampling's: 4 M samples per render
/// bring it to about 0.2 % (σ is printed).
#[test]
fn spectral_render_matches_the_airy_summation() {
    for (name, mat, n3) in substrates() {
        for deg in [0.0f32, 45.0] {
            let (got, sem) = flat_film_render(with_film(mat.clone(), FILM), deg, true, 1024);
            let want = integrated_airy(FILM, deg.to_radians().cos(), &n3);
            let rel = ((got - want) / want).abs();
            println!("{name} {deg}°: render {got} ± {sem}, Airy {want}, rel. err {rel}");
            assert!(
                rel.max_element() < 0.01,
                "{name} at {deg}°: render {got} ± {sem} vs Airy {want}"
            );
        }
    }
}

/// RGB paths use Belcour & Barla's analytic integral: the render is `ThinFilm::rgb` (exactly
/// on metals, whose one reflection is deterministic; within 4σ on glass, which picks
/// reflection with probability P and weights it R/P), and that stays within the fit's
/// measured accuracy (0.03 per channel, `bsdf::thin_film` unit tests) of the integrated
/// Airy sum.
#[test]
fn rgb_render_is_the_analytic_integral() {
    for (name, mat, n3) in substrates() {
        for deg in [0.0f32, 45.0] {
            let cos = deg.to_radians().cos();
            let (got, sem) = flat_film_render(with_film(mat.clone(), FILM), deg, false, 64);
            let bsdf = mat.bsdf(&[], Vec2::ZERO, mat.ior);
            let want = match Iridescent::over(bsdf, FILM, 1.0) {
                Bsdf::Iridescent(b) => b.reflectance(cos).truncate(),
                other => panic!("{other:?}"),
            };
            // A tabulated metal's RGB lanes use its RGB η, k: compare with the substrate's
            // own index only where it is one number.
            assert!(
                ((got - want).abs() - 4.0 * sem).max_element() < 1e-5,
                "{name} {deg}°: {got} ± {sem} vs {want}"
            );
            if name != "gold" {
                let exact = integrated_airy(FILM, cos, &n3);
                assert!(
                    (got - exact).abs().max_element() < 0.03,
                    "{name}: {got} vs {exact}"
                );
            }
        }
    }
}

/// The filmed BSDFs of the point-wise checks: smooth and rough, dielectric (both sides),
/// sheet, tabulated and contract metals; RGB and spectral lanes.
fn filmed() -> Vec<Bsdf> {
    let mut bases = vec![
        Bsdf::SmoothDielectric(SmoothDielectric { eta: 1.5 }),
        Bsdf::ThinDielectric(ThinDielectric { eta: 1.0 }),
        Bsdf::ThinDielectric(ThinDielectric { eta: 1.5 }),
        Bsdf::SmoothConductor(SmoothConductor {
            ior: ComplexIor::rgb(Metal::Au),
            tint: Color::ONE,
        }),
    ];
    for dist in [Dist::Ggx, Dist::Beckmann] {
        for alpha in [0.05f32, 0.3, 0.8] {
            for eta in [1.33f32, 2.42] {
                bases.push(Bsdf::RoughDielectric(RoughDielectric { eta, alpha, dist }));
            }
            bases.push(Bsdf::RoughConductor(RoughConductor {
                reflectance: rgb(0.9, 0.6, 0.3),
                alpha,
                dist,
            }));
        }
    }
    let mut out = Vec::new();
    for b in bases {
        for d in [150.0f32, 500.0] {
            let film = ThinFilm {
                ior: 1.45,
                thickness_nm: d,
            };
            let f = Iridescent::over(b, film, 1.0);
            out.push(f);
            out.push(f.at_wavelengths([420.0, 510.0, 590.0, 660.0]));
        }
    }
    out
}

fn rough(b: &Bsdf) -> bool {
    matches!(b, Bsdf::Iridescent(i) if !i.is_smooth())
}

fn transmits(b: &Bsdf) -> bool {
    matches!(b, Bsdf::Iridescent(i) if i.can_transmit())
}

fn random_dir(rng: &mut Sampler, two_sided: bool) -> Vec3 {
    let w = sampling::uniform_sphere(rng.next2());
    if two_sided {
        w
    } else {
        Vec3::new(w.x, w.y, w.z.abs())
    }
}

fn rel_err(a: Color, b: Color) -> f32 {
    (a - b).abs().max_element() / a.abs().max(b.abs()).max_element().max(1e-30)
}

/// Non-delta samples: weight = f|cos|/pdf, and eval/pdf reproduce the sample's f and pdf.
#[test]
fn sample_weight_equals_f_cos_over_pdf() {
    let mut count = 0;
    for (k, b) in filmed().iter().filter(|b| rough(b)).enumerate() {
        let mut rng = Sampler::new(k as u32, 0, 91);
        for i in 0..3000 {
            let mode = [TransportMode::Radiance, TransportMode::Importance][i % 2];
            let wo = random_dir(&mut rng, transmits(b));
            let (uc, u2) = (rng.next(), rng.next2());
            let Some(s) = b.sample(wo, uc, u2, mode) else {
                continue;
            };
            count += 1;
            assert!(
                !s.is_delta && s.pdf > 0.0 && s.weight.is_finite(),
                "{b:?} {s:?}"
            );
            assert_eq!(
                s.event == Event::Reflect,
                s.wi.z * wo.z > 0.0,
                "{b:?} {s:?}"
            );
            let w = s.f * (s.wi.z.abs() / s.pdf);
            assert!(
                rel_err(w, s.weight) <= 1e-4,
                "{b:?}: {:?} vs {w:?}",
                s.weight
            );
            let p = b.pdf(wo, s.wi);
            assert!(
                (p - s.pdf).abs() <= 1e-5 * s.pdf,
                "{b:?}: pdf {p} vs {}",
                s.pdf
            );
            let f = b.eval(wo, s.wi, mode);
            assert!(rel_err(f, s.f) <= 1e-5, "{b:?}: eval {f:?} vs {:?}", s.f);
        }
    }
    assert!(count > 50_000, "{count} samples");
}

/// Reflection f(wo, wi) = f(wi, wo); transmission f(wo, wi)/η(wo)² = f(wi, wo)/η(wi)²
/// (Veach 1997 eq. 5.14) — the film's R and T = 1 − R are functions of the outside angle.
#[test]
fn reciprocity() {
    let mut pairs = [0usize; 2];
    for (k, b) in filmed().iter().filter(|b| rough(b)).enumerate() {
        let Bsdf::Iridescent(film) = b else { continue };
        let eta = match film.base {
            refract::bsdf::FilmBase::Dielectric { eta } => eta,
            _ => 1.0,
        };
        let side = |w: Vec3| if w.z > 0.0 { 1.0 } else { eta };
        let mut rng = Sampler::new(k as u32, 2, 92);
        for _ in 0..10_000 {
            let wo = random_dir(&mut rng, transmits(b));
            let wi = random_dir(&mut rng, transmits(b));
            let r = TransportMode::Radiance;
            let (f, fr) = (b.eval(wo, wi, r), b.eval(wi, wo, r));
            if f.max_element() < 1e-6 && fr.max_element() < 1e-6 {
                continue;
            }
            if wo.z * wi.z > 0.0 {
                pairs[0] += 1;
                assert!(rel_err(f, fr) < 1e-4, "{b:?}: {f:?} vs {fr:?}");
            } else {
                pairs[1] += 1;
                let (a, c) = (f / side(wo).powi(2), fr / side(wi).powi(2));
                assert!(rel_err(a, c) < 1e-4, "{b:?}: {a:?} vs {c:?}");
            }
        }
    }
    assert!(pairs[0] > 10_000 && pairs[1] > 5_000, "{pairs:?}");
}

/// Energy: the directional albedo (importance mode) is at most 1 + 3σ in every lane, from
/// both sides, normal to grazing; a smooth filmed dielectric or sheet returns exactly 1 in
/// every lane (R + T = 1: the film absorbs nothing).
#[test]
fn energy_at_most_one_and_smooth_dielectrics_keep_all_of_it() {
    for (k, b) in filmed().iter().enumerate() {
        let lanes = match b {
            Bsdf::Iridescent(i) if i.lambdas.is_some() => 4,
            _ => 3,
        };
        for (j, &c) in [1.0f32, 0.7, 0.3, 0.05].iter().enumerate() {
            for inside in [false, true] {
                if inside && !transmits(b) {
                    continue;
                }
                let s = (1.0 - c * c).sqrt();
                let wo = Vec3::new(
                    s * 0.7f32.cos(),
                    s * 0.7f32.sin(),
                    if inside { -c } else { c },
                );
                let n = 20_000;
                let (mut s1, mut s2) = (glam::DVec4::ZERO, glam::DVec4::ZERO);
                for i in 0..n {
                    let mut rng = Sampler::new(i, (k * 8 + j) as u32, 93);
                    let (uc, u2) = (rng.next(), rng.next2());
                    if let Some(smp) = b.sample(wo, uc, u2, TransportMode::Importance) {
                        let w = smp.weight.as_dvec4();
                        s1 += w;
                        s2 += w * w;
                    }
                }
                let mean = s1 / n as f64;
                let sigma =
                    ((s2 / n as f64 - mean * mean).max(glam::DVec4::ZERO) / n as f64).sqrt();
                for l in 0..lanes {
                    assert!(
                        mean[l] - 3.0 * sigma[l] <= 1.0,
                        "{b:?} cos {c} inside {inside}: lane {l} albedo {} ± {}",
                        mean[l],
                        sigma[l]
                    );
                    if transmits(b) && !rough(b) {
                        // Every sample's weight averages to exactly 1: R/P·P + T/(1−P)·(1−P).
                        assert!(
                            (mean[l] - 1.0).abs() < 5.0 * sigma[l] + 1e-5,
                            "{b:?} cos {c}: lane {l} albedo {} ± {}",
                            mean[l],
                            sigma[l]
                        );
                    }
                }
            }
        }
    }
}

/// χ²: the sampled directions of the rough filmed BSDFs follow their pdf (Šidák level over
/// the cases; the selection by the mean reflectance changes the pdf, not just the weights).
#[test]
fn chi2_rough_filmed() {
    let cases: Vec<(Bsdf, Vec3)> = filmed()
        .into_iter()
        .filter(rough)
        .flat_map(|b| {
            let mut v = vec![(b, Vec3::new(0.3, 0.2, 0.93).normalize())];
            if transmits(&b) {
                v.push((b, Vec3::new(0.5, -0.2, -0.84).normalize()));
            }
            v
        })
        .collect();
    let alpha = chi2::sidak_alpha(0.01, cases.len());
    for (i, (b, wo)) in cases.iter().enumerate() {
        let cfg = Chi2Config {
            samples: 100_000,
            seed: 500 + i as u32,
            ..Chi2Config::default()
        };
        let r = chi2::chi2_test(b, *wo, TransportMode::Radiance, &cfg);
        assert!(
            r.p_value > alpha && r.invalid_samples == 0 && r.pdf_integral <= 1.0 + 1e-4,
            "{b:?} wo {wo}: p {:.3e} (level {alpha:.2e}), ∫pdf {:.5}, invalid {}",
            r.p_value,
            r.pdf_integral,
            r.invalid_samples
        );
    }
}

/// A white furnace (radiance 1 everywhere): a filmed glass sphere returns what the bare glass
/// sphere returns (R + T = 1 at every interface; the faceted sphere itself loses ≈ 3.5e-4 of
/// the light, film or not), a filmed rough grey metal sphere never more than it receives
/// (≤ 1 + 3σ per channel).
#[test]
fn white_furnace() {
    let film = ThinFilm {
        ior: 1.33,
        thickness_nm: 380.0,
    };
    let glass = Material::glass("glass", 1.5);
    let metal = Material {
        kind: MaterialKind::GlossyMetal,
        metallic: 1.0,
        roughness: 0.5,
        ..Material::mirror("metal", Vec3::splat(0.9))
    };
    let bare = furnace(glass.clone(), 64);
    let filmed = furnace(with_film(glass, film), 512);
    for ch in 0..3 {
        let ((b, sb), (f, sf)) = (bare[ch], filmed[ch]);
        println!("glass channel {ch}: bare {b:.5} ± {sb:.5}, filmed {f:.5} ± {sf:.5}");
        assert!(f <= 1.0 + 3.0 * sf, "filmed glass: {f} ± {sf}");
        let s = (sb * sb + sf * sf).sqrt();
        assert!(
            (f - b).abs() <= 3.0 * s,
            "channel {ch}: filmed {f} ± {sf} vs bare {b} ± {sb}"
        );
    }
    for (ch, (m, s)) in furnace(with_film(metal, film), 64).into_iter().enumerate() {
        println!("metal channel {ch}: {m:.5} ± {s:.5}");
        assert!(m <= 1.0 + 3.0 * s, "filmed metal: {m} ± {s}");
    }
}

/// A unit sphere of `mat` in a white furnace: the image's mean and standard error per channel.
fn furnace(mat: Material, spp: u32) -> [(f64, f64); 3] {
    let mut m = Mesh::default();
    refract::scene::builtin::sphere(&mut m, Vec3::ZERO, 1.0, 24, 48, 0);
    let cam = Camera::look_at(Vec3::new(0.0, 0.0, 2.6), Vec3::ZERO, Vec3::Y, 0.7);
    let mut s = scene("furnace", flatten(&m), vec![mat], cam, 1.0);
    s.settings.max_depth = 256;
    s.settings.rr_depth = 256;
    let r = Renderer::new(s).expect("valid");
    let o = RenderOptions::from_scene(&r.scene);
    let img = r.render(&o, spp, None, |_| {}).0.image();
    std::array::from_fn(|ch| {
        let v: Vec<f64> = img.iter().map(|p| p[ch] as f64).collect();
        let mean = v.iter().sum::<f64>() / v.len() as f64;
        let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (v.len() - 1) as f64;
        (mean, (var / v.len() as f64).sqrt())
    })
}
