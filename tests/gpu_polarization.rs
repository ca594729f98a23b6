//! Polarised transport on the GPU (issue 38; `cpu/polarized/chain.wgsl`,
//! `bsdf/polarized.wgsl`): the kernel against the CPU's polarised walk sample for sample (the
//! same random numbers: the images agree to rounding), the Fresnel ratio through a polariser
//! and Brewster's angle measured on the GPU, and what it refuses (other estimators, a path
//! filter, thin films). Skipped without an adapter
//! (`REFRACT_REQUIRE_GPU` makes that a failure).

mod common_scenes;

use common_scenes::polarizer_plate as plate;
use common_scenes::{N_GLASS, fresnel_sp, gpu_context};
use glam::Vec3;
use refract::cpu::Renderer;
use refract::film::Film;
use refract::gpu::{GpuContext, GpuRenderer};
use refract::paths::PathFilter;
use refract::render::{Estimator, Polarization, RenderOptions};
use refract::scene::Scene;
use refract::scene::material::MaterialKind;

/// `scene` at `w` × `h`.
fn sized(spec: &str, w: u32, h: u32) -> Scene {
    let mut s = Scene::load(spec).unwrap();
    s.settings.width = w;
    s.settings.height = h;
    s
}

/// `scene` with its solid glass made thin-walled sheets (the sheet's reflection and its
/// transmission through both faces).
fn thin_walled(mut scene: Scene) -> Scene {
    for m in &mut scene.materials {
        if m.kind == MaterialKind::Glass {
            m.kind = MaterialKind::ThinGlass;
        }
    }
    scene
}

/// The GPU's polarised image of `scene` behind `pol` (None: unpolarised), `spp` samples from
/// `seed`.
fn gpu_image(
    ctx: &GpuContext,
    scene: &Scene,
    pol: Option<Polarization>,
    (spp, seed): (u32, u32),
) -> Vec<Vec3> {
    let mut opts = RenderOptions::from_scene(scene);
    opts.seed = seed;
    let mut g = match pol {
        Some(p) => GpuRenderer::with_context_polarized(ctx.clone(), scene.clone(), opts, p),
        None => GpuRenderer::with_context(ctx.clone(), scene.clone(), opts),
    }
    .unwrap();
    let img = g.render(spp).unwrap();
    assert_eq!(img.dropped, 0, "{}: the GPU dropped samples", scene.name);
    img.mean
}

/// The CPU's polarised image (`Renderer::polarized_pass`) with the same samples.
fn cpu_image(scene: &Scene, pol: Polarization, (spp, seed): (u32, u32)) -> Vec<Vec3> {
    let r = Renderer::new(scene.clone()).unwrap();
    let mut opts = RenderOptions::from_scene(scene);
    opts.seed = seed;
    let (w, h) = (opts.width, opts.height);
    let mut film = Film::new(w, h);
    let mut stokes = refract::cpu::layers::LayerFilm::new(w, h, 4);
    assert!(r.polarized_pass(&opts, pol, (&mut film, &mut stokes), (0, spp), &|| false));
    assert_eq!(film.dropped, 0, "{}: the CPU dropped samples", scene.name);
    film.image()
}

/// Mean over pixels and channels.
fn mean(img: &[Vec3]) -> f64 {
    img.iter().map(|p| (p.x + p.y + p.z) as f64).sum::<f64>() / (3 * img.len()) as f64
}

/// Mean absolute difference per pixel channel, relative to the image's mean.
fn mean_abs_diff(a: &[Vec3], b: &[Vec3]) -> f64 {
    let d: f64 = a
        .iter()
        .zip(b)
        .map(|(p, q)| ((*p - *q).abs().element_sum()) as f64)
        .sum();
    d / (3 * a.len()) as f64 / mean(b).max(1e-12)
}

/// The GPU kernel and the CPU walk draw the same random numbers in the same order, so a
/// polarised image is the same on both up to f32 rounding (and the rare path that rounding
/// sends the other way at a branch): measured ≤ 2e-4 of the mean (the dispersive prism;
/// ≤ 2e-6 elsewhere, lavapipe). The images must also differ from half the unpolarised GPU
/// image (what the filter would pass if the light were unpolarised) by far more than from
/// each other — else the comparison would not see the polarisation at all. Scenes: the Brewster plate behind both filter
/// angles (dielectric reflection and refraction), the metals (tabulated conductors with
/// complex IOR, smooth and rough; the ideal conductor), rough glass at 45° (the half vector),
/// the metal-rough materials (its two lobes), the dispersive prism (spectral lanes; total
/// internal reflection's phase), cornell-glass with a thin-walled sphere (the sheet).
#[test]
fn gpu_polarized_images_match_the_cpu_walk_sample_for_sample() {
    let Some(ctx) = gpu_context("gpu_polarized_images_match_the_cpu_walk_sample_for_sample") else {
        return;
    };
    let deg = |d: f32| Polarization {
        filter: Some(d.to_radians()),
    };
    let cases = [
        ("builtin:brewster", deg(0.0)),
        ("builtin:brewster", deg(90.0)),
        ("builtin:metals", deg(30.0)),
        ("builtin:rough-glass", deg(45.0)),
        ("builtin:materials", deg(120.0)),
        ("builtin:prism", deg(60.0)),
        ("thin:builtin:cornell-glass", deg(0.0)),
    ];
    for (spec, pol) in cases {
        let scene = match spec.strip_prefix("thin:") {
            Some(spec) => thin_walled(sized(spec, 48, 36)),
            None => sized(spec, 48, 36),
        };
        let run = (8, 11);
        let g = gpu_image(&ctx, &scene, Some(pol), run);
        let c = cpu_image(&scene, pol, run);
        // What the filter would pass of unpolarised light: half of it.
        let half: Vec<Vec3> = gpu_image(&ctx, &scene, None, run)
            .iter()
            .map(|p| 0.5 * *p)
            .collect();
        let (twin, effect) = (mean_abs_diff(&g, &c), mean_abs_diff(&half, &c));
        eprintln!(
            "{spec} behind {:.0}°: mean {:.5} (CPU {:.5}); |GPU − CPU| {twin:.2e}, \
             |unpolarised / 2 − CPU| {effect:.2e} of the mean",
            pol.filter.unwrap_or(0.0).to_degrees(),
            mean(&g),
            mean(&c)
        );
        assert!(twin <= 1e-3, "{spec}: GPU and CPU differ by {twin:.2e}");
        assert!(
            effect >= 30.0 * twin.max(1e-6),
            "{spec}: the filter changes the image by only {effect:.2e}"
        );
    }
}

/// Unfiltered polarised light through several polarising events (cornell-glass's sphere and
/// mirror box) on the GPU is the CPU's, and differs from the unpolarised render (issue 38:
/// "where it meets several the intensities differ physically").
#[test]
fn gpu_unfiltered_polarized_intensity_is_the_cpu_walks() {
    let Some(ctx) = gpu_context("gpu_unfiltered_polarized_intensity_is_the_cpu_walks") else {
        return;
    };
    let scene = sized("builtin:cornell-glass", 48, 48);
    let run = (8, 5);
    let pol = Polarization::default();
    let g = gpu_image(&ctx, &scene, Some(pol), run);
    let c = cpu_image(&scene, pol, run);
    let u = gpu_image(&ctx, &scene, None, run);
    let (twin, effect) = (mean_abs_diff(&g, &c), mean_abs_diff(&u, &c));
    eprintln!("cornell-glass: |GPU − CPU| {twin:.2e}, |unpolarised − CPU| {effect:.2e}");
    assert!(twin <= 1e-3, "GPU and CPU differ by {twin:.2e}");
    assert!(effect > 3.0 * twin, "no polarisation effect: {effect:.2e}");
}

/// The glass plate seen at θ through a polariser at 0° and 90° on the GPU: the ratio of the
/// reflections is r⊥²/r∥² of the exact Fresnel equations (tests/polarization.rs checks the
/// CPU the same way), and at Brewster's angle the 90° image is below 1e-4 of the 0° one.
#[test]
fn gpu_plate_reflection_through_polarizers_is_the_fresnel_ratio() {
    let Some(ctx) = gpu_context("gpu_plate_reflection_through_polarizers_is_the_fresnel_ratio")
    else {
        return;
    };
    let theta_b = N_GLASS.atan();
    for theta in [40f32.to_radians(), 65f32.to_radians(), theta_b] {
        let scene = plate(theta);
        let filter = |d: f32| {
            Some(Polarization {
                filter: Some(d.to_radians()),
            })
        };
        let is = mean(&gpu_image(&ctx, &scene, filter(0.0), (64, 7)));
        let ip = mean(&gpu_image(&ctx, &scene, filter(90.0), (64, 7)));
        let (rs, rp) = fresnel_sp(theta.cos() as f64, N_GLASS as f64);
        if theta == theta_b {
            eprintln!("Brewster: I(90°)/I(0°) = {:.3e}", ip / is);
            assert!(is > 0.05 && ip < 1e-4 * is, "s {is}, p {ip}");
            continue;
        }
        let want = rs * rs / (rp * rp);
        // The ratio's change over the ±0.1° the image spans, plus f32 rounding.
        let (rs2, rp2) = fresnel_sp((theta + 0.1f32.to_radians()).cos() as f64, N_GLASS as f64);
        let tol = (rs2 * rs2 / (rp2 * rp2) - want).abs() + 1e-4 * want;
        let got = is / ip;
        eprintln!(
            "θ {:.0}°: I(0°)/I(90°) = {got:.5}, r⊥²/r∥² = {want:.5} ± {tol:.5}",
            theta.to_degrees()
        );
        assert!((got - want).abs() <= tol, "{got} vs {want} ± {tol}");
    }
}

/// Polarised transport runs the path tracer over every path: the renderer refuses the other
/// estimators, a path filter and a non-finite angle with a message (never a panic), and a
/// filter set later takes the polarisation away.
#[test]
fn gpu_polarization_refuses_what_it_cannot_render() {
    let Some(ctx) = gpu_context("gpu_polarization_refuses_what_it_cannot_render") else {
        return;
    };
    let scene = sized("builtin:brewster", 16, 12);
    let opts = RenderOptions::from_scene(&scene);
    let pol = Polarization { filter: Some(0.3) };
    let mut g = GpuRenderer::with_context(ctx.clone(), scene.clone(), opts).unwrap();
    let nan = Polarization {
        filter: Some(f32::NAN),
    };
    let e = format!("{:#}", g.set_polarization(Some(nan)).unwrap_err());
    assert!(e.contains("finite"), "{e}");
    g.set_estimator(Estimator::Bdpt).unwrap();
    let e = format!("{:#}", g.set_polarization(Some(pol)).unwrap_err());
    assert!(e.contains("path estimator"), "{e}");
    g.set_estimator(Estimator::Path).unwrap();
    g.set_filter(Some(&PathFilter::parse("LS+DE").unwrap()));
    let e = format!("{:#}", g.set_polarization(Some(pol)).unwrap_err());
    assert!(e.contains("path filter"), "{e}");
    g.set_filter(None);
    g.set_polarization(Some(pol)).unwrap();
    assert_eq!(g.polarization(), Some(pol));
    let e = format!("{:#}", g.set_estimator(Estimator::Sppm).unwrap_err());
    assert!(e.contains("polarised"), "{e}");
    g.set_filter(Some(&PathFilter::parse("LDE").unwrap()));
    assert_eq!(
        g.polarization(),
        None,
        "a path filter takes polarisation away"
    );
    let opts = RenderOptions {
        estimator: Estimator::LtPt,
        ..RenderOptions::from_scene(&scene)
    };
    assert!(GpuRenderer::with_context_polarized(ctx.clone(), scene, opts, pol).is_err());
    // Thin films have no Mueller event on the GPU: refused, at the start and at an edit that
    // adds one (the material is kept as it was).
    let film = sized("builtin:thin-film", 16, 12);
    let opts = RenderOptions::from_scene(&film);
    let Err(e) = GpuRenderer::with_context_polarized(ctx.clone(), film, opts, pol) else {
        panic!("a polarised thin film was accepted");
    };
    let e = format!("{e:#}");
    assert!(
        e.contains("thin films") && e.contains("--device cpu"),
        "{e}"
    );
    let scene = sized("builtin:brewster", 16, 12);
    let opts = RenderOptions::from_scene(&scene);
    let mut g = GpuRenderer::with_context_polarized(ctx, scene.clone(), opts, pol).unwrap();
    let plate = (scene.materials.iter())
        .position(|m| m.kind == MaterialKind::Glass)
        .expect("the plate is glass");
    let mut filmed = scene.materials[plate].clone();
    filmed.iridescence = Some(Default::default());
    let e = format!("{:#}", g.set_material(plate, filmed).unwrap_err());
    assert!(e.contains("thin films"), "{e}");
    assert_eq!(g.polarization(), Some(pol));
}

/// `render --device gpu --aov dop,aop,stokes`: the Stokes images from four analysers on the
/// GPU (`cli/gpu_stokes.rs`) are the CPU walk's, sample for sample (the same seed), and so is
/// the image behind the filter; Q is far from zero on the Brewster plate (the check has power).
#[test]
fn gpu_stokes_views_match_the_cpu() {
    if gpu_context("gpu_stokes_views_match_the_cpu").is_none() {
        return;
    }
    let dir = std::env::temp_dir().join(format!("refract-gpu-stokes-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let render = |device: &str| {
        let out = dir.join(format!("{device}.exr"));
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_refract"))
            .args(["render", "--scene", "builtin:brewster", "--polarizer", "30"])
            .args(["--aov", "dop,aop,stokes", "--spp", "8", "--width", "48"])
            .args(["--height", "36", "--seed", "2", "--device", device, "--out"])
            .arg(&out)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr).into_owned();
        assert!(o.status.success(), "{device}: {err}");
        let load = |name: &str| refract::film::load_exr(&dir.join(name)).unwrap().2;
        let layers: Vec<Vec<Vec3>> = (0..4)
            .map(|k| load(&format!("{device}.s{k}.exr")))
            .collect();
        (load(&format!("{device}.exr")), layers, err)
    };
    let (gb, gs, err) = render("gpu");
    assert!(err.contains("on the GPU, four analysers"), "{err}");
    let (cb, cs, _) = render("cpu");
    let scale = mean(&cs[0]);
    let worst = |a: &[Vec3], b: &[Vec3]| {
        a.iter()
            .zip(b)
            .map(|(p, q)| (*p - *q).abs().max_element() as f64)
            .fold(0.0, f64::max)
            / scale
    };
    for k in 0..4 {
        let w = worst(&gs[k], &cs[k]);
        eprintln!(
            "s{k}: worst |GPU − CPU| {w:.2e} of mean I, mean {:.4}",
            mean(&cs[k])
        );
        assert!(w < 1e-3, "s{k}: {w}");
    }
    let wb = worst(&gb, &cb);
    assert!(wb < 1e-3, "beauty: {wb}");
    assert!(mean(&cs[1]) > 0.1 * scale, "no polarisation to compare");
    std::fs::remove_dir_all(&dir).ok();
}
