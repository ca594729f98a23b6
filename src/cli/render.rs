//! The `render` command: the job on the GPU when it takes it, else on the CPU, and the
//! progress and timing lines both backends print.

use super::RenderArgs;
use super::job::{Job, prepare};
use super::layers::Layers;
use super::progress::{budget_report, spp_progress_bar, spp_text};
use super::race::race_cpu;
use super::threads::thread_pool;
use anyhow::{Context, Result};
use refract::cpu::Renderer;
use refract::film;
use refract::render::{Estimator, EstimatorPlan, RenderOptions, Runner};
use refract::scene::Scene;

/// The `render` command: prepare the job, then render on the GPU or the CPU.
pub(crate) fn render(args: &RenderArgs) -> Result<()> {
    // Before any work: a render whose image cannot be written is an error now, not after.
    film::check_output_path(&args.out).context("--out")?;
    super::denoise::check(args)?;
    let (polarized, aov) = super::polarization::parse(args)?;
    if let Some(p) = &polarized {
        return super::polarization::render(args, p);
    }
    let layers = Layers::parse(args.decompose.as_deref(), aov.as_deref())?;
    if let Some(l) = &layers {
        l.check_outputs(&args.out)?;
    }
    let (scene, mut job) = prepare(args)?;
    if let Some(l) = &layers {
        l.check(args.device, job.choice, job.filter.source())?;
        let size = (scene.settings.width, scene.settings.height);
        l.check_memory(size, job.max_film_bytes)?;
        // The layers come from the path tracer's camera walk (`auto` path-traces then).
        if job.plan.runs != Estimator::Path {
            eprintln!(
                "estimator auto: path (the layers need the path tracer; auto alone would \
                 pick {})",
                job.plan.runs
            );
        }
        job.choice = Estimator::Path;
        job.plan = EstimatorPlan::decide(Estimator::Path, &scene, Runner::Cpu);
    } else if super::gpu_render::render(args, &scene, &job)? {
        return Ok(());
    }
    render_cpu(args, scene, &job, layers.as_ref())
}

/// Render `scene` on the CPU (the path tracer's layers too, when asked) and write the image.
fn render_cpu(args: &RenderArgs, scene: Scene, job: &Job, layers: Option<&Layers>) -> Result<()> {
    let pool = thread_pool(args.threads)?;
    let renderer = Renderer::new(scene)?;
    let mut opts = cpu_options(&renderer, job);
    // `auto`: the estimators race on short trials, inside the time budget (`cli::race`).
    let started = std::time::Instant::now();
    let raced = layers
        .is_none()
        .then(|| pool.install(|| race_cpu(&renderer, job, &opts, args.time_budget)))
        .flatten();
    if let Some((report, size)) = &raced {
        opts.estimator = report.winner;
        eprintln!(
            "{} — trials took {:.2} s",
            report.line(*size),
            started.elapsed().as_secs_f64()
        );
    } else if let Some(note) = job.plan.note() {
        eprintln!("{note}");
    }
    let budget = args
        .time_budget
        .map(|b| b.saturating_sub(started.elapsed()));
    log_start(args, &renderer, &opts, job.spp);
    let bar = spp_progress_bar(job.spp, args.quiet);
    let n = job.spp.unwrap_or(u32::MAX);
    let mut half = None;
    let half_film = &mut half;
    let (film, layer_film, stats) = pool.install(|| match layers {
        Some(l) => {
            let proto = l.proto();
            let progress = |d| bar.set_position(d);
            let (f, lf, s) = renderer.render_layered(&opts, (n, budget), &proto, progress);
            (f, Some(lf), s)
        }
        None if args.denoise => {
            let progress = |d| bar.set_position(d);
            let (f, half, s) = renderer.render_with_half(&opts, (n, budget), progress);
            *half_film = half;
            (f, None, s)
        }
        None => {
            let (f, s) = renderer.render(&opts, n, budget, |d| bar.set_position(d));
            (f, None, s)
        }
    });
    bar.finish_and_clear();
    let (w, h) = (opts.width, opts.height);
    let what = (opts.estimator, "cpu");
    super::shard::save(args, &renderer.scene, job, (w, h), &film.image(), what)?;
    eprintln!(
        "wrote {} — {} spp in {:.2} s, {:.3} M samples/s, {} NaN/Inf/negative samples dropped",
        args.out.display(),
        stats.spp,
        stats.elapsed.as_secs_f64(),
        stats.samples_per_sec() / 1e6,
        stats.dropped
    );
    if let (Some(l), Some(lf)) = (layers, &layer_film) {
        l.save(&args.out, lf, film.spp)?;
    }
    let mean = film.image();
    let rendered = super::denoise::Rendered {
        size: (w, h),
        mean: &mean,
        spp: film.spp,
        half: half.as_ref().map(|(img, k)| (img.as_slice(), *k)),
    };
    super::denoise::write(args, &renderer, job, rendered)?;
    budget_report(args.time_budget, stats.spp, opts.pass_spp());
    Ok(())
}

/// The CPU renderer's options for `job` (`auto` as the rule resolves it).
fn cpu_options(renderer: &Renderer, job: &Job) -> RenderOptions {
    let mut opts = RenderOptions::from_scene(&renderer.scene);
    opts.max_film_bytes = job.max_film_bytes;
    opts.seed = job.seed;
    opts.first_sample = job.first_sample();
    opts.set_filter(Some(&job.filter));
    opts.estimator = job.plan.runs;
    if job.plan.runs == Estimator::LtPt {
        eprintln!("note: on the CPU, lt+pt renders with bdpt (its strategies are a superset)");
    }
    opts
}

/// One line on what is about to render: scene, triangles, BVH build time, size, spp, depth.
fn log_start(args: &RenderArgs, renderer: &Renderer, opts: &RenderOptions, spp: Option<u32>) {
    eprintln!(
        "scene {}: {} triangles, BVH built in {:.1} ms; {}x{}, {}, max depth {}",
        renderer.scene.name,
        renderer.scene.mesh.triangle_count(),
        renderer.bvh.build_time.as_secs_f64() * 1e3,
        opts.width,
        opts.height,
        spp_text(spp, args.time_budget),
        opts.max_depth
    );
}
