//! Polarised transport (issue 38, docs/polarization.md): the Fresnel ratio r⊥²/r∥² seen
//! through a linear polariser at 0° and 90°, Brewster's angle, agreement of the polarised
//! walk with the unpolarised one where no two polarising events follow each other, the
//! realisability of every BSDF's Mueller matrices, and the command line.

mod common_scenes;

use common_scenes::polarizer_plate as plate;
use common_scenes::{N_GLASS, block_means, block_z_test, fresnel_sp, quad, scene, sphere};
use glam::{Vec2, Vec3, Vec4};
use refract::bsdf::polarized::event_mueller;
use refract::bsdf::{
    Bsdf, BxDF, ComplexIor, Lambert, Metal, MicrofacetDistribution, Mirror, RoughConductor,
    RoughDielectric, RoughFresnelConductor, SmoothConductor, SmoothDielectric, ThinDielectric,
    TransportMode,
};
use refract::cpu::Renderer;
use refract::cpu::layers::LayerFilm;
use refract::cpu::polarized::{Polarization, STOKES_LAYERS};
use refract::film::Film;
use refract::math::Color;
use refract::math::mueller::degree_of_polarization;
use refract::render::RenderOptions;
use refract::scene::{Camera, Material, Mesh, Scene};

/// A polarised render of `r`: (beauty behind the filter, mean Stokes per pixel).
fn render_polarized(r: &Renderer, filter: Option<f32>, spp: u32, seed: u32) -> (Film, LayerFilm) {
    let mut opts = RenderOptions::from_scene(&r.scene);
    opts.seed = seed;
    let mut film = Film::new(opts.width, opts.height);
    let mut stokes = LayerFilm::new(opts.width, opts.height, STOKES_LAYERS);
    let pol = Polarization { filter };
    assert!(r.polarized_pass(&opts, pol, (&mut film, &mut stokes), (0, spp), &|| false));
    assert_eq!(film.dropped, 0, "the firewall dropped samples");
    (film, stokes)
}

/// Mean of the image's green channel (grey scenes: every channel is the same).
fn mean(img: &[Vec3]) -> f64 {
    img.iter().map(|p| p.y as f64).sum::<f64>() / img.len() as f64
}

#[test]
fn plate_reflection_through_polarizers_is_the_fresnel_ratio() {
    let theta_b = N_GLASS.atan();
    for deg in [20.0f32, 40.0, 50.0, 65.0, 75.0] {
        let theta = deg.to_radians();
        let r = Renderer::new(plate(theta)).unwrap();
        // The same seed: both filters see the same reflect-or-refract choices, so the ratio
        // has no sampling noise; what remains is the 0.2° spread of angles over the image.
        let (s_img, _) = render_polarized(&r, Some(0.0), 64, 7);
        let (p_img, _) = render_polarized(&r, Some(90f32.to_radians()), 64, 7);
        let (is, ip) = (mean(&s_img.image()), mean(&p_img.image()));
        let (rs, rp) = fresnel_sp(theta.cos() as f64, N_GLASS as f64);
        let want = rs * rs / (rp * rp);
        // The ratio's change over ±0.1° about θ (numerical derivative), plus f32 rounding.
        let (rs2, rp2) = fresnel_sp((theta + 0.1f32.to_radians()).cos() as f64, N_GLASS as f64);
        let tol = (rs2 * rs2 / (rp2 * rp2) - want).abs() + 1e-4 * want;
        let got = is / ip;
        eprintln!("θ {deg}°: I(0°)/I(90°) = {got:.5}, r⊥²/r∥² = {want:.5} ± {tol:.5}");
        assert!(
            (got - want).abs() <= tol,
            "θ {deg}°: {got} vs {want} ± {tol}"
        );
        // The s-filtered intensity is r⊥² L / 2 (L = 2) in the mean over samples (noisy:
        // a sample reflects with probability F); 5σ of the binomial choice.
        let f = 0.5 * (rs * rs + rp * rp);
        let n = 64.0 * 64.0;
        let sigma = (rs * rs) / f * (f * (1.0 - f) / n).sqrt();
        assert!(
            (is - rs * rs).abs() <= 5.0 * sigma,
            "θ {deg}°: {is} vs {}",
            rs * rs
        );
    }
    // At Brewster's angle the p-filtered reflection vanishes, and what is reflected is
    // fully polarised along the image's horizontal.
    let r = Renderer::new(plate(theta_b)).unwrap();
    let (s_img, stokes) = render_polarized(&r, Some(0.0), 64, 3);
    let (p_img, _) = render_polarized(&r, Some(90f32.to_radians()), 64, 3);
    let (is, ip) = (mean(&s_img.image()), mean(&p_img.image()));
    eprintln!(
        "Brewster {:.3}°: I(90°)/I(0°) = {:.3e}",
        theta_b.to_degrees(),
        ip / is
    );
    assert!(is > 0.05 && ip < 1e-4 * is, "s {is}, p {ip}");
    let s: Vec<Vec3> = (0..4).map(|k| mean_px(&stokes.image(k, 64))).collect();
    let sv = Vec4::new(s[0].y, s[1].y, s[2].y, s[3].y);
    assert!(degree_of_polarization(sv) > 0.999, "{sv}");
    assert!(sv.y > 0.999 * sv.x, "not horizontal: {sv}");
}

/// The mean pixel of an image.
fn mean_px(img: &[Vec3]) -> Vec3 {
    img.iter().copied().sum::<Vec3>() / img.len() as f32
}

/// A diffuse floor and back wall under an area light, a diffuse ball and one conductor
/// sphere of `metal` (complex IOR; rough ones take NEE through their Mueller BSDF): the only
/// polarising surface is convex, so no path meets two polarising events without a
/// depolarising one between them.
fn one_event_scene(metal: Metal, roughness: f32) -> Scene {
    let mut m = Mesh::default();
    quad(
        &mut m,
        Vec3::new(-3.0, 0.0, 3.0),
        Vec3::X * 6.0,
        Vec3::Z * -6.0,
        0,
    );
    quad(
        &mut m,
        Vec3::new(-3.0, 0.0, -1.5),
        Vec3::X * 6.0,
        Vec3::Y * 4.0,
        0,
    );
    quad(
        &mut m,
        Vec3::new(-0.5, 2.5, 0.5),
        Vec3::Z * -1.0,
        Vec3::X * 1.0,
        1,
    );
    sphere(&mut m, Vec3::new(-0.6, 0.45, 0.0), 0.45, 24, 48, 2);
    sphere(&mut m, Vec3::new(0.7, 0.45, 0.2), 0.45, 24, 48, 3);
    let materials = vec![
        Material::diffuse("floor", Vec3::new(0.6, 0.55, 0.5)),
        Material::emitter("light", Vec3::splat(8.0)),
        Material {
            conductor: Some(metal),
            ..refract::scene::builtin::glossy_metal("metal", Vec3::ONE, roughness)
        },
        Material::diffuse("ball", Vec3::new(0.2, 0.4, 0.7)),
    ];
    let cam = Camera::look_at(
        Vec3::new(0.0, 1.2, 3.5),
        Vec3::new(0.0, 0.5, 0.0),
        Vec3::Y,
        0.7,
    );
    let mut s = scene("one-event", m, materials, cam, 0.2);
    s.settings.width = 48;
    s.settings.height = 32;
    s
}

#[test]
fn unfiltered_polarized_render_agrees_with_the_unpolarized_one() {
    for (metal, roughness) in [(Metal::Au, 0.3), (Metal::Ag, 0.0)] {
        agree_without_filter(&Renderer::new(one_event_scene(metal, roughness)).unwrap());
    }
}

fn agree_without_filter(r: &Renderer) {
    let opts = RenderOptions::from_scene(&r.scene);
    let (w, h) = (opts.width, opts.height);
    let spp = 8;
    let unpolarized = |seed: u32| {
        let mut o = opts;
        o.seed = seed;
        let mut film = Film::new(w, h);
        r.render_pass(&o, &mut film, 0, spp);
        assert_eq!(film.dropped, 0);
        film.image()
    };
    // Independent seeds on the two sides: a block z-test (≥ 90 % of 8×8 blocks within 3σ,
    // the whole image within 4σ, σ from the spread between runs).
    let runs = 8;
    let a: Vec<Vec<f64>> = (0..runs)
        .map(|i| block_means(&render_polarized(r, None, spp, 100 + i).0.image(), w, h))
        .collect();
    let b: Vec<Vec<f64>> = (0..runs)
        .map(|i| block_means(&unpolarized(i), w, h))
        .collect();
    let t = block_z_test(&a, &b);
    eprintln!(
        "{}/{} blocks within 3σ, whole-image z {:.2}, means {:.5} vs {:.5}",
        t.pass, t.blocks, t.z_image, t.mean_a, t.mean_b
    );
    assert!(t.rate() >= 0.9 && t.z_image.abs() <= 4.0);
    // With one seed the two walks draw the same random numbers and every scalar factor is
    // the same: the intensities agree sample by sample up to float rounding.
    let (p, _) = render_polarized(r, None, spp, 5);
    let (p, u) = (p.image(), unpolarized(5));
    let worst = p
        .iter()
        .zip(&u)
        .map(|(a, b)| ((*a - *b).abs() / b.max(Vec3::splat(1e-2))).max_element())
        .fold(0.0f32, f32::max);
    eprintln!("same seed: worst relative difference {worst:.2e}");
    assert!(worst < 1e-4, "{worst}");
}

/// Every BSDF this renderer has.
fn bsdfs() -> Vec<Bsdf> {
    let rough = RoughConductor {
        reflectance: Color::ONE,
        alpha: 0.3,
        dist: MicrofacetDistribution::Ggx,
    };
    let film = refract::bsdf::thin_film::ThinFilm {
        ior: 1.33,
        thickness_nm: 400.0,
    };
    let filmed = |b: Bsdf| refract::bsdf::Iridescent::over(b, film, 1.0);
    vec![
        filmed(Bsdf::SmoothDielectric(SmoothDielectric { eta: 1.5 })),
        filmed(Bsdf::RoughDielectric(RoughDielectric {
            eta: 1.5,
            alpha: 0.3,
            dist: MicrofacetDistribution::Ggx,
        })),
        filmed(Bsdf::SmoothConductor(SmoothConductor {
            ior: ComplexIor::rgb(Metal::Au),
            tint: Color::ONE,
        })),
        Bsdf::Lambert(Lambert {
            albedo: Color::splat(0.5),
            uniform: false,
        }),
        Bsdf::Mirror(Mirror {
            reflectance: Color::ONE,
        }),
        Bsdf::SmoothDielectric(SmoothDielectric { eta: 1.5 }),
        Bsdf::ThinDielectric(ThinDielectric { eta: 1.5 }),
        Bsdf::RoughDielectric(RoughDielectric {
            eta: 1.5,
            alpha: 0.3,
            dist: MicrofacetDistribution::Ggx,
        }),
        Bsdf::RoughConductor(rough),
        Bsdf::SmoothConductor(SmoothConductor {
            ior: ComplexIor::rgb(Metal::Au),
            tint: Color::ONE,
        }),
        Bsdf::RoughFresnelConductor(RoughFresnelConductor {
            ior: ComplexIor::rgb(Metal::Cu),
            lobe: rough,
        }),
        Bsdf::MetalRough(refract::bsdf::MetalRough {
            base_color: Color::new(0.9, 0.6, 0.3, 0.0),
            metallic: 0.5,
            alpha: 0.2,
            ior: 1.5,
            specular_factor: 1.0,
            specular_color: Color::ONE,
        }),
    ]
}

#[test]
fn every_bsdf_event_is_a_physical_mueller_matrix() {
    // Probe Stokes vectors: unpolarised and fully polarised ones over the Poincaré sphere.
    let mut probe = vec![Vec4::X];
    for i in 0..8 {
        for j in 0..5 {
            let (az, el) = (i as f32 * 0.785, -1.2 + j as f32 * 0.6);
            probe.push(Vec4::new(
                1.0,
                el.cos() * az.cos(),
                el.cos() * az.sin(),
                el.sin(),
            ));
        }
    }
    for b in bsdfs() {
        for k in 0..200 {
            let a = (k as f32 + 0.5) / 200.0;
            let side = if k % 2 == 0 { 1.0 } else { -1.0 };
            let wo = Vec3::new(
                (a * 7.0).sin() * 0.9,
                (a * 3.0).cos() * 0.3,
                side * a + 0.05,
            )
            .normalize();
            let u = Vec2::new((a * 13.7).fract(), (a * 29.3).fract());
            let Some(s) = b.sample(wo, (a * 5.3).fract(), u, TransportMode::Radiance) else {
                continue;
            };
            let lanes = event_mueller(&b, wo, s.wi, s.event, s.lobe);
            for m in lanes.iter().take(3) {
                assert!((m.x_axis.x - 1.0).abs() < 1e-5, "{b:?}: m00 {}", m.x_axis.x);
                let r0 = m.row(0);
                let rest = (r0.y * r0.y + r0.z * r0.z + r0.w * r0.w).sqrt();
                assert!(rest <= 1.0 + 1e-5, "{b:?}: row 0 {r0}");
                for p in &probe {
                    let o = *m * *p;
                    assert!(o.x >= -1e-5, "{b:?}: negative intensity {o}");
                    if o.x > 1e-4 {
                        let dop = degree_of_polarization(o);
                        assert!(dop <= 1.0 + 1e-3, "{b:?}: DoP {dop} from {p} ({s:?})");
                    }
                }
            }
        }
    }
}

#[test]
fn command_line_renders_the_brewster_pair_and_refuses_what_it_cannot_do() {
    let dir = std::env::temp_dir().join(format!("refract-polarization-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("b.png");
    let run = |extra: &[&str]| {
        std::process::Command::new(env!("CARGO_BIN_EXE_refract"))
            .args([
                "render",
                "--scene",
                "builtin:brewster",
                "--width",
                "24",
                "--height",
            ])
            .args(["16", "--spp", "1", "--quiet", "--device", "cpu", "--out"])
            .arg(&out)
            .args(extra)
            .output()
            .unwrap()
    };
    let ok = run(&["--polarizer", "90", "--aov", "dop,aop,stokes"]);
    assert!(
        ok.status.success(),
        "{}",
        String::from_utf8_lossy(&ok.stderr)
    );
    for f in [
        "b.png",
        "b.dop.png",
        "b.dop.exr",
        "b.aop.png",
        "b.s0.exr",
        "b.s3.exr",
    ] {
        assert!(dir.join(f).is_file(), "{f} missing");
    }
    for (flags, says) in [
        (&["--polarized", "--paths", "LSDE"][..], "--paths"),
        (&["--polarizer", "10", "--aov", "dop,tir"][..], "tir"),
        (
            &["--polarized", "--estimator", "bdpt"][..],
            "--estimator path",
        ),
        (&["--polarizer", "NaN"][..], "--polarizer"),
    ] {
        let o = run(flags);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            !o.status.success() && err.contains(says),
            "{flags:?}: {err}"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn viewer_polarizer_removes_the_brewster_reflection() {
    let backend = refract::app::backend::CpuBackend::new(None);
    common_scenes::assert_viewer_polarizer_removes_the_brewster_reflection(Box::new(backend));
}

#[test]
fn fresnel_plot_cursor_is_the_inspected_points_angle() {
    use refract::app::panels::fresnel::inspected_angle;
    let r = Renderer::new(Scene::load("builtin:brewster").unwrap()).unwrap();
    let mut opts = RenderOptions::from_scene(&r.scene);
    // An odd size: the centre pixel's centre is the image's, where the camera looks at
    // the plate at Brewster's angle; 161 rows of a 43° field of view keep the pixel's
    // footprint to ±0.14°.
    (opts.width, opts.height) = (241, 161);
    let trace = refract::cpu::inspect::trace_pixel(&r, &opts, (120, 80), 4).unwrap();
    let (deg, leaving) = inspected_angle(&trace, None, "glass-plate").expect("the plate");
    let want = 1.5f64.atan().to_degrees();
    eprintln!("inspected θ {deg:.3}°, Brewster {want:.3}°");
    assert!((deg - want).abs() < 0.3 && !leaving, "{deg}");
    assert_eq!(inspected_angle(&trace, None, "no-such-material"), None);
}

/// A screenshot taken behind the polariser records it in its sidecar (`render.polarizer`,
/// degrees): `render --settings` renders behind it, and a viewer opened on the sidecar starts
/// behind it.
#[test]
fn a_screenshot_sidecar_keeps_the_polarizer() {
    use refract::app::ViewerApp;
    use refract::render::settings::ViewerSettings;
    let dir = std::env::temp_dir().join(format!("refract-pol-shot-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = "builtin:brewster";
    let mut settings = ViewerSettings::for_scene(scene);
    settings.render.render_scale = 0.0625;
    settings.render.fit_viewport = false;
    let backend = Box::new(refract::app::backend::CpuBackend::new(None));
    let mut app = ViewerApp::with_backend(Scene::load(scene).unwrap(), settings, backend).unwrap();
    app.screenshot_dir = dir.clone();
    app.set_polarizer(Some(90.0));
    let start = std::time::Instant::now();
    while app.backend().read_image().is_none_or(|a| a.spp < 2) {
        assert!(start.elapsed().as_secs() < 120, "no samples");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let saved = app.save_screenshot().unwrap();
    let sidecar = ViewerSettings::load(&saved.json).unwrap();
    assert_eq!(sidecar.render.polarizer, Some(90.0));
    let out = dir.join("again.png");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_refract"))
        .args(["render", "--settings"])
        .arg(&saved.json)
        .args([
            "--spp", "2", "--width", "24", "--height", "16", "--device", "cpu",
        ])
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        o.status.success() && err.contains("behind a linear polariser at 90.0°"),
        "{err}"
    );
    let backend = Box::new(refract::app::backend::CpuBackend::new(None));
    let reopened = ViewerApp::with_backend(Scene::load(scene).unwrap(), sidecar, backend).unwrap();
    assert_eq!(reopened.polarizer, Some(90.0));
    std::fs::remove_dir_all(&dir).ok();
}
