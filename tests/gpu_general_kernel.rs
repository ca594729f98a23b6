//! The general kernel (issue 36): while a new specialisation compiles, the viewer renders
//! with its family's general kernel (`Specialization::general`: every material, light and
//! texture part compiled in, same estimator and maths). It must render the same image as the
//! specialised kernel — a block z-test over independent runs on scenes of each estimator
//! family — and a renderer compiling in the background must run it as soon as it is ready.

mod common_scenes;

use common_scenes::{block_means, block_z_test, gpu_context};
use refract::gpu::GpuRenderer;
use refract::render::{Estimator, RenderOptions};
use refract::scene::Scene;

/// Independent runs (seeds) of `scene` with `estimator`, general kernel or not: block means.
fn runs(
    ctx: &refract::gpu::GpuContext,
    scene: &Scene,
    estimator: Estimator,
    general: bool,
    spp: u32,
) -> Vec<Vec<f64>> {
    let mut opts = RenderOptions::from_scene(scene);
    opts.estimator = estimator;
    let mut g = GpuRenderer::with_context(ctx.clone(), scene.clone(), opts).expect("renderer");
    g.set_general_kernel(general);
    (0..6)
        .map(|seed| {
            let mut o = *g.options();
            o.seed = 100 + seed;
            g.set_options(o).expect("options");
            let img = g.render(spp).expect("render");
            assert_eq!(g.is_general(), general, "the kernel that ran");
            block_means(&img.mean, o.width, o.height)
        })
        .collect()
}

/// `name` at `w`×`h`.
fn small(name: &str, w: u32, h: u32) -> Scene {
    let mut s = Scene::load(&format!("builtin:{name}")).expect("built-in");
    s.settings.width = w;
    s.settings.height = h;
    s
}

#[test]
fn the_general_kernel_renders_what_the_specialised_one_renders() {
    let Some(ctx) = gpu_context("general_kernel") else {
        return;
    };
    for (name, estimator, spp) in [
        ("cornell-glass", Estimator::Path, 16),
        ("glass-slab", Estimator::Path, 16),
        // Rough glass: the general kernel has the environment image too, which orders its
        // NEE differently (`NEE_LIGHT_FIRST`): other random numbers, the same expectation.
        ("rough-glass", Estimator::Path, 16),
        ("caustic", Estimator::Sppm, 8),
        ("cornell-glass", Estimator::LtPt, 8),
        // Thin films are a family of their own: its general kernel has every part and films.
        ("thin-film", Estimator::Path, 8),
    ] {
        let scene = small(name, 48, 32);
        let own = runs(&ctx, &scene, estimator, false, spp);
        let general = runs(&ctx, &scene, estimator, true, spp);
        let z = block_z_test(&own, &general);
        eprintln!(
            "{name} {estimator}: {}/{} blocks within 3σ, image z {:.2}, means {:.4} / {:.4}; \
             bit-identical: {}",
            z.pass,
            z.blocks,
            z.z_image,
            z.mean_a,
            z.mean_b,
            own == general
        );
        assert!(
            z.rate() >= 0.9,
            "{name} {estimator}: {} of {} blocks",
            z.pass,
            z.blocks
        );
        assert!(
            z.z_image.abs() < 4.0,
            "{name} {estimator}: image z {}",
            z.z_image
        );
    }
}

#[test]
fn a_background_compile_renders_with_the_general_kernel_first() {
    let Some(ctx) = gpu_context("general_first") else {
        return;
    };
    let scene = small("cornell-glass", 32, 24);
    let opts = RenderOptions::from_scene(&scene);
    let mut g = GpuRenderer::with_context_in_background(ctx, scene, opts).expect("renderer");
    // Off by default on software drivers (lavapipe here): compiling shares their cores.
    g.set_compile_ahead(true);
    // Both the specialised and the general kernel compile on worker threads; whichever is
    // ready first renders, and once the specialised one is, it does.
    let start = std::time::Instant::now();
    while !g.pipelines_ready().expect("compile") {
        assert!(start.elapsed().as_secs() < 300, "nothing compiled in 300 s");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let first = g.render(1).expect("render");
    assert_eq!(first.spp, 1);
    while g.is_compiling() {
        assert!(start.elapsed().as_secs() < 300, "not specialised in 300 s");
        g.pipelines_ready().expect("compile");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    assert!(!g.is_general(), "the specialised kernel runs once compiled");
    let more = g.render(1).expect("render");
    assert_eq!(more.spp, 2, "accumulation goes on across the switch");
}

/// A lecture's next demo prepared ahead (`GpuRenderer::compile_ahead_for`, what
/// `Backend::prepare_for` calls when a demo opens): its family's general kernel compiles
/// while the current scene renders, so opening it renders at once — with the general kernel
/// while its own specialisation compiles — instead of waiting for a compile.
#[test]
fn the_next_scene_prepared_ahead_renders_at_once() {
    let Some(ctx) = gpu_context("prepared_ahead") else {
        return;
    };
    let now = small("cornell-glass", 32, 24);
    // The next demo: dispersion (spectral) and bidirectional (what `auto` picks for it),
    // another family than what the current renderer compiles for its own edits.
    let next = small("prism", 32, 24);
    let next_opts = RenderOptions {
        estimator: Estimator::LtPt,
        ..RenderOptions::from_scene(&next)
    };
    let mut g =
        GpuRenderer::with_context_in_background(ctx, now.clone(), RenderOptions::from_scene(&now))
            .expect("renderer");
    g.set_compile_ahead(true);
    let family = g.general_kernel_for(&next, &next_opts);
    assert!(family.spectral, "the prism's family is spectral");
    assert!(
        !g.is_compiled(family),
        "not compiled before it is asked for"
    );
    g.compile_ahead_for(&next, &next_opts).expect("queued");
    let start = std::time::Instant::now();
    while !g.is_compiled(family) {
        assert!(
            start.elapsed().as_secs() < 600,
            "not compiled ahead in 600 s"
        );
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    g.set_scene(next, next_opts).expect("the next scene");
    g.set_estimator(Estimator::LtPt).expect("lt+pt");
    assert!(
        g.pipelines_ready().expect("compile"),
        "the prepared general kernel renders at once"
    );
    let img = g.render(1).expect("render");
    assert_eq!(img.spp, 1);
    assert!(img.mean.iter().all(|p| p.is_finite()));
}

/// A burst of edits, each asking for another specialisation, compiles at most the adapter's
/// limit of them at once (one on software drivers) and then the latest asked for: the ones
/// in between are superseded, never compiled. Unbounded, a soak's burst started 59 workers at
/// once and was killed for memory on lavapipe (tests/viewer_soak.rs).
#[test]
fn a_burst_of_edits_compiles_the_first_and_the_latest_only() {
    use refract::gpu::pipeline::{MAX_WORKERS, MAX_WORKERS_SOFTWARE, Pipelines};
    let Some(ctx) = gpu_context("edit_burst") else {
        return;
    };
    let cap = if ctx.is_software() {
        MAX_WORKERS_SOFTWARE
    } else {
        MAX_WORKERS
    };
    let base = refract::gpu::pipeline::Specialization::for_scene(&small("furnace", 16, 16))
        .expect("specialisation");
    // Distinct specialisations of one scene family: an edit burst's worth.
    let burst: Vec<_> = [(false, false), (true, false), (false, true), (true, true)]
        .into_iter()
        .map(
            |(mirror, beckmann)| refract::gpu::pipeline::Specialization {
                bsdfs: refract::bsdf::BsdfParts {
                    mirror,
                    ..base.bsdfs
                },
                beckmann,
                wavefront: false,
                ..base
            },
        )
        .collect();
    let mut p = Pipelines::new(&ctx).expect("pipelines");
    for &spec in &burst {
        p.compile_in_background(spec).expect("start");
        assert!(p.workers() <= cap, "{} workers, limit {cap}", p.workers());
    }
    let latest = *burst.last().expect("burst");
    if cap < burst.len() {
        assert_eq!(p.waiting(), Some(latest), "the latest request waits");
    }
    let start = std::time::Instant::now();
    while p.is_compiling() {
        assert!(start.elapsed().as_secs() < 600, "not compiled in 600 s");
        p.poll().expect("compile");
        assert!(p.workers() <= cap, "{} workers, limit {cap}", p.workers());
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    assert!(p.is_ready(burst[0]) && p.is_ready(latest));
    for &spec in &burst[cap..burst.len() - 1] {
        assert!(!p.is_ready(spec), "a superseded request was compiled");
    }
}

/// The pipeline cache keeps at most its capacity of specialisations: the least recently used
/// specialised one goes first, the family's general kernel stays (it renders while the others
/// compile), and what was dropped compiles again when asked for. Unbounded, a viewer session
/// kept every pipeline it compiled (on lavapipe 50–250 MB each once executed).
#[test]
fn the_pipeline_cache_keeps_at_most_its_capacity() {
    use refract::gpu::pipeline::{Pipelines, Specialization};
    let Some(ctx) = gpu_context("pipeline_capacity") else {
        return;
    };
    let base = Specialization::for_scene(&small("furnace", 16, 16)).expect("specialisation");
    let [a, b, c, d] =
        [(false, false), (true, false), (false, true), (true, true)].map(|(mirror, beckmann)| {
            Specialization {
                bsdfs: refract::bsdf::BsdfParts {
                    mirror,
                    ..base.bsdfs
                },
                beckmann,
                wavefront: false,
                ..base
            }
        });
    let general = a.general();
    let mut p = Pipelines::new(&ctx).expect("pipelines");
    p.set_capacity(2);
    for spec in [a, b, c] {
        p.compile(spec).expect("compile");
        assert!(p.cached_specializations() <= 2);
    }
    assert!(
        !p.is_ready(a) && p.is_ready(b) && p.is_ready(c),
        "a, the oldest, dropped"
    );
    p.compile(general).expect("general");
    assert!(!p.is_ready(b) && p.is_ready(c) && p.is_ready(general));
    p.compile(d).expect("compile");
    assert!(
        !p.is_ready(c) && p.is_ready(general) && p.is_ready(d),
        "the older specialised kernel goes, not the general one"
    );
    let compiled = p.compiled;
    p.compile(a).expect("again");
    assert!(
        p.is_ready(a) && p.compiled > compiled,
        "a dropped kernel compiles again"
    );
    assert_eq!(p.cached_specializations(), 2);
    p.set_capacity(1);
    assert_eq!(
        p.cached_specializations(),
        1,
        "shrinking drops the excess now"
    );
}
