//! GPU light tracing combined with path tracing by MIS (`lt+pt`, src/gpu/light_tracing.wgsl):
//! it converges to the path tracer's image on every built-in scene (block Z-test against the CPU
//! path tracer), through Heckbert filters and with punctual lights, and it beats path tracing
//! on caustics at equal sample count. Tests print a SKIP line without an adapter (CI installs
//! lavapipe and sets REFRACT_REQUIRE_GPU, so there they run).

mod common_scenes;
use common_scenes::*;
use glam::Vec3;
use refract::cpu::Renderer;
use refract::film::Film;
use refract::gpu::{GpuContext, GpuRenderer};
use refract::paths::PathFilter;
use refract::render::{Estimator, RenderOptions};
use refract::scene::{Features, PunctualLight, Scene};

fn context(test: &str) -> Option<GpuContext> {
    gpu_context(test)
}

fn small(spec: &str, w: u32, h: u32) -> Scene {
    let mut s = Scene::load(spec).unwrap();
    s.settings.width = w;
    s.settings.height = h;
    s
}

fn cpu_image(
    scene: &Scene,
    est: Estimator,
    seed: u32,
    spp: u32,
    filter: Option<&PathFilter>,
) -> Vec<Vec3> {
    let r = Renderer::new(scene.clone()).unwrap();
    let mut opts = RenderOptions::from_scene(&r.scene);
    opts.seed = seed;
    opts.estimator = est;
    opts.set_filter(filter);
    let mut film = Film::new(opts.width, opts.height);
    r.render_pass(&opts, &mut film, 0, spp);
    film.image()
}

/// k independent GPU images (seeds 1000…) of `estimator`.
fn gpu_runs(
    ctx: GpuContext,
    scene: &Scene,
    estimator: Estimator,
    filter: Option<&PathFilter>,
    k: u32,
    spp: u32,
) -> (Vec<Vec<Vec3>>, u64) {
    let mut opts = RenderOptions::from_scene(scene);
    let mut g = GpuRenderer::with_context(ctx, scene.clone(), opts).unwrap();
    g.set_filter(filter);
    g.set_estimator(estimator).unwrap();
    assert_eq!(g.effective_estimator(), estimator);
    let mut out = Vec::new();
    let mut dropped = 0;
    for i in 0..k {
        opts.seed = 1000 + i;
        g.set_options(opts).unwrap();
        let img = g.render(spp).unwrap();
        dropped += img.dropped;
        out.push(img.mean);
    }
    (out, dropped)
}

/// Block Z-test of GPU `lt+pt` (k runs of `spp`) against the CPU path tracer (k runs of
/// `ref_mult` × `spp`; caustic-heavy scenes need many more path-traced samples before their
/// heavy-tailed noise is estimated reliably).
fn converges_to_path(
    name: &str,
    scene: Scene,
    filter: Option<&str>,
    k: u32,
    spp: u32,
    ref_mult: u32,
) {
    converges_to(name, scene, filter, k, spp, Estimator::Path, ref_mult)
}

/// As `converges_to_path`, with the reference rendered by the CPU estimator `reference`.
fn converges_to(
    name: &str,
    scene: Scene,
    filter: Option<&str>,
    k: u32,
    spp: u32,
    reference: Estimator,
    ref_mult: u32,
) {
    let Some(ctx) = context(name) else {
        return;
    };
    let filter = filter.map(|f| PathFilter::parse(f).unwrap());
    let (w, h) = (scene.settings.width, scene.settings.height);
    let t0 = std::time::Instant::now();
    let (g, dropped) = gpu_runs(ctx, &scene, Estimator::LtPt, filter.as_ref(), k, spp);
    let tg = t0.elapsed();
    assert_eq!(dropped, 0, "{name}: the firewall dropped samples");
    let gs: Vec<Vec<f64>> = g.iter().map(|i| block_means(i, w, h)).collect();
    let t0 = std::time::Instant::now();
    let cs: Vec<Vec<f64>> = (0..k)
        .map(|i| {
            let img = cpu_image(&scene, reference, i, ref_mult * spp, filter.as_ref());
            block_means(&img, w, h)
        })
        .collect();
    let tc = t0.elapsed();
    let t = block_z_test(&gs, &cs);
    let (pass, nb, zt, rate) = (t.pass, t.blocks, t.z_image, t.rate());
    eprintln!(
        "{name}: {pass}/{nb} blocks within 3σ ({:.1}%), whole-image z = {zt:.2}, means {:.5} (lt+pt) vs {:.5} (CPU {reference}); GPU {:.2} s for {k}×{spp} spp, CPU {:.2} s for {k}×{} spp",
        rate * 100.0,
        t.mean_a,
        t.mean_b,
        tg.as_secs_f64(),
        tc.as_secs_f64(),
        ref_mult * spp
    );
    // With k − 1 = 7 degrees of freedom per side a block exceeds |t| = 3 about 2% of the time.
    assert!(
        rate >= 0.9,
        "{name}: only {:.1}% of blocks within 3σ",
        rate * 100.0
    );
    assert!(zt.abs() <= 4.0, "{name}: image means differ by {zt:.2}σ");
}

#[test]
fn lt_pt_converges_to_path_tracing_cornell_glass() {
    converges_to_path(
        "lt+pt cornell-glass",
        small("builtin:cornell-glass", 48, 48),
        None,
        8,
        8,
        4,
    );
}

#[test]
fn lt_pt_converges_to_path_tracing_caustic() {
    let s = small("builtin:caustic", 64, 48);
    converges_to_path("lt+pt caustic", s.clone(), None, 8, 8, 64);
    // And against the CPU's independent bidirectional implementation at equal spp.
    converges_to("lt+pt caustic vs bdpt", s, None, 8, 8, Estimator::Bdpt, 1);
}

#[test]
fn lt_pt_converges_to_path_tracing_glass_slab() {
    converges_to_path(
        "lt+pt glass-slab",
        small("builtin:glass-slab", 48, 32),
        None,
        8,
        8,
        4,
    );
}

#[test]
fn lt_pt_converges_to_path_tracing_rough_glass() {
    converges_to_path(
        "lt+pt rough-glass",
        small("builtin:rough-glass", 48, 32),
        None,
        8,
        8,
        4,
    );
}

#[test]
fn lt_pt_converges_to_path_tracing_materials() {
    converges_to_path(
        "lt+pt materials",
        small("builtin:materials", 48, 32),
        None,
        8,
        8,
        4,
    );
}

#[test]
fn lt_pt_converges_to_path_tracing_furnace() {
    converges_to_path(
        "lt+pt furnace",
        small("builtin:furnace", 32, 32),
        None,
        8,
        8,
        4,
    );
}

/// The path filter applies to the light-tracing strategy too: LS+DE (caustics only) and LDE.
#[test]
fn lt_pt_filtered_caustics_and_direct() {
    let s = small("builtin:cornell-glass", 48, 48);
    converges_to_path(
        "lt+pt cornell-glass LS+DE",
        s.clone(),
        Some("LS+DE"),
        8,
        8,
        64,
    );
    converges_to_path("lt+pt cornell-glass LDE", s, Some("LDE"), 8, 8, 4);
}

/// Point and spot lights start light subpaths too (LDE over a floor: NEE and light tracing
/// share every path, so a wrong MIS weight shows as a biased mean).
#[test]
fn lt_pt_punctual_lights() {
    for light in [
        PunctualLight::Point {
            position: Vec3::new(0.3, 2.0, 0.0),
            intensity: Vec3::splat(20.0),
        },
        PunctualLight::Spot {
            position: Vec3::new(0.0, 2.0, 0.2),
            direction: -Vec3::Y,
            intensity: Vec3::splat(20.0),
            cos_inner: 0.5f32.cos(),
            cos_outer: 0.7f32.cos(),
        },
    ] {
        let mut s = floor_scene(light, 1.2);
        s.settings.width = 32;
        s.settings.height = 32;
        converges_to_path(&format!("lt+pt {light:?}"), s, None, 8, 4, 4);
    }
}

/// Equal sample count on the caustic (LS+DE under the glass sphere): light tracing finds these
/// paths directly, so the per-block variance across independent runs must be far lower than
/// path tracing's.
#[test]
fn lt_pt_reduces_caustic_variance() {
    let name = "lt_pt_reduces_caustic_variance";
    let Some(ctx) = context(name) else {
        return;
    };
    let s = small("builtin:caustic", 64, 48);
    let f = PathFilter::parse("LS+DE").unwrap();
    let (w, h) = (64, 48);
    let ctx2 = GpuContext::from_adapter(ctx.adapter.clone()).unwrap();
    let (pt, _) = gpu_runs(ctx, &s, Estimator::Path, Some(&f), 8, 8);
    let (lt, _) = gpu_runs(ctx2, &s, Estimator::LtPt, Some(&f), 8, 8);
    let pb: Vec<Vec<f64>> = pt.iter().map(|i| block_means(i, w, h)).collect();
    let lb: Vec<Vec<f64>> = lt.iter().map(|i| block_means(i, w, h)).collect();
    let (mut vp, mut vl) = (0.0, 0.0);
    for b in 0..pb[0].len() {
        vp += run_stats(&pb, b).1;
        vl += run_stats(&lb, b).1;
    }
    eprintln!(
        "{name}: summed block variance path {vp:.3e}, lt+pt {vl:.3e}, ratio {:.1}",
        vp / vl
    );
    assert!(vl > 0.0, "light tracing found no caustic paths");
    assert!(
        vp > 5.0 * vl,
        "lt+pt variance {vl:.3e} is not 5× below path's {vp:.3e}"
    );
}

/// Dispersion: both walks carry hero wavelengths (the prism's rainbow is an L S S D E path that
/// light tracing finds directly). Against the CPU's bidirectional renderer (same spectral
/// model, independent code) and, with many more samples, the CPU path tracer.
#[test]
fn lt_pt_with_dispersion() {
    let s = small("builtin:prism", 48, 32);
    assert!(s.features().contains(Features::DISPERSION));
    converges_to(
        "lt+pt prism vs bdpt",
        s.clone(),
        None,
        8,
        8,
        Estimator::Bdpt,
        1,
    );
    converges_to_path("lt+pt prism", s, None, 8, 8, 64);
}
