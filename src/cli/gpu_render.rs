//! `refract render --device gpu|auto`: the GPU path of the render command (kept out of
//! main.rs so the CLI stays small).

use super::RenderArgs;
use super::job::Job;
use super::progress::{budget_report, spp_progress_bar, spp_text};
use anyhow::Result;
use refract::gpu::{GpuContext, GpuRenderer};
use refract::render::{Device, EstimatorPlan, Polarization, RenderOptions, Runner};
use refract::scene::Scene;

/// Render on the GPU if `args.device` asks for it (and, for `auto`, a hardware adapter exists).
/// Returns false when the caller should render on the CPU instead.
pub fn render(args: &RenderArgs, scene: &Scene, job: &Job) -> Result<bool> {
    render_with(args, scene, job, None)
}

/// [`render`] tracing polarised light behind `pol`'s filter (`GpuRenderer::set_polarization`;
/// the caller has checked for the path estimator, no path filter and no Stokes views).
pub fn render_polarized(
    args: &RenderArgs,
    scene: &Scene,
    job: &Job,
    pol: Polarization,
) -> Result<bool> {
    render_with(args, scene, job, Some(pol))
}

fn render_with(
    args: &RenderArgs,
    scene: &Scene,
    job: &Job,
    pol: Option<Polarization>,
) -> Result<bool> {
    let forced = match args.device {
        Device::Cpu => return Ok(false),
        Device::Gpu => true,
        Device::Auto => false,
    };
    let plan = EstimatorPlan::decide(job.choice, scene, Runner::Gpu);
    if !plan.exact && !forced {
        // Free to choose the device: the CPU runs exactly what was asked.
        return Ok(false);
    }
    let Some(ctx) = context(forced)? else {
        return Ok(false);
    };
    if let Some(note) = plan.note() {
        eprintln!("{note}");
    }
    let mut opts = RenderOptions::from_scene(scene);
    opts.max_film_bytes = job.max_film_bytes;
    opts.seed = job.seed;
    opts.first_sample = job.first_sample();
    opts.set_filter(Some(&job.filter));
    opts.estimator = plan.runs;
    let name = ctx.describe();
    let r = match pol {
        Some(p) => GpuRenderer::with_context_polarized(ctx, scene.clone(), opts, p),
        None => GpuRenderer::with_context(ctx, scene.clone(), opts),
    };
    let Some(mut r) = or_cpu(r, forced, "GPU renderer unavailable")? else {
        return Ok(false);
    };
    log_start(args, scene, job, &r, &name);
    eprintln!("{}", pipeline_report(&r));
    let bar = spp_progress_bar(job.spp, args.quiet);
    let n = job.spp.unwrap_or(u32::MAX);
    let img = r.render_with(n, args.time_budget, |d| bar.set_position(d));
    bar.finish_and_clear();
    let Some(img) = or_cpu(img, forced, "GPU render failed")? else {
        return Ok(false);
    };
    let stats = r.stats()?;
    let (w, h) = (img.width, img.height);
    let what = (r.effective_estimator(), "gpu");
    super::shard::save(args, scene, job, (w, h), &img.mean, what)?;
    let filter = match pol {
        Some(Polarization { filter: Some(a) }) => {
            format!(" (behind a linear polariser at {:.1}°)", a.to_degrees())
        }
        Some(_) => " (polarised, total intensity)".to_owned(),
        None => String::new(),
    };
    eprintln!(
        "wrote {}{filter} — {} spp in {:.2} s on the GPU, {:.3} M samples/s, {:.3} M path segments/s, {} NaN/Inf/negative samples dropped",
        args.out.display(),
        stats.spp,
        stats.elapsed.as_secs_f64(),
        stats.samples_per_sec() / 1e6,
        stats.segments_per_sec() / 1e6,
        stats.dropped
    );
    let rendered = super::denoise::Rendered {
        size: (w, h),
        mean: &img.mean,
        spp: stats.spp,
        half: None,
    };
    super::denoise::write_for_scene(args, scene, job, rendered, r.context())?;
    budget_report(args.time_budget, stats.spp, r.batch_spp());
    Ok(true)
}

/// The GPU to render on: None (render on the CPU, saying why) when `auto` finds no adapter
/// or only a software one; `--device gpu` (`forced`) takes a software adapter with a note
/// and makes a missing one an error.
pub(super) fn context(forced: bool) -> Result<Option<GpuContext>> {
    let Some(ctx) = or_cpu(GpuContext::new(), forced, "no GPU adapter")? else {
        return Ok(None);
    };
    if ctx.is_software() {
        if !forced {
            eprintln!(
                "only a software GPU adapter ({}); rendering on the CPU (use --device gpu to force it)",
                ctx.describe()
            );
            return Ok(None);
        }
        eprintln!(
            "note: {} is a software adapter (CPU-emulated), expect it to be slow",
            ctx.describe()
        );
    }
    Ok(Some(ctx))
}

/// `r`'s value; for a failure, None (render on the CPU, saying "`what` (error)") unless the
/// GPU was `forced`, which makes it the command's error.
pub(super) fn or_cpu<T>(r: Result<T>, forced: bool, what: &str) -> Result<Option<T>> {
    match r {
        Ok(v) => Ok(Some(v)),
        Err(e) if !forced => {
            eprintln!("{what} ({e:#}); rendering on the CPU");
            Ok(None)
        }
        Err(e) => Err(e),
    }
}

/// One line on what is about to render: scene and adapter, BVH, size, spp, depth, estimator,
/// path filter and spectral mode.
pub(super) fn log_start(args: &RenderArgs, scene: &Scene, job: &Job, r: &GpuRenderer, name: &str) {
    let (bvh_time, depth, nodes) = r.bvh_info();
    let tree = match r.bvh_layout() {
        refract::gpu::upload::BvhLayout::Bvh2 => "BVH2",
        refract::gpu::upload::BvhLayout::Cwbvh => "CWBVH",
    };
    let s = &scene.settings;
    let filter = &job.filter;
    eprintln!(
        "scene {} on GPU {name}: {} triangles, {tree} {nodes} nodes depth {depth} built in {:.1} ms; {}x{}, {}, max depth {}, estimator {}{}{}",
        scene.name,
        scene.mesh.triangle_count(),
        bvh_time.as_secs_f64() * 1e3,
        s.width,
        s.height,
        spp_text(job.spp, args.time_budget),
        s.max_depth,
        r.effective_estimator(),
        if filter.is_accept_all() {
            String::new()
        } else {
            format!(", paths '{}'", filter.source())
        },
        if r.specialization().spectral {
            ", spectral (hero wavelengths)"
        } else {
            ""
        }
    );
}

/// "GPU pipelines compiled in … ms (pipeline cache …)": how long the kernels took to compile
/// and whether the driver pipeline cache was warm (`gpu::pipeline_cache`).
fn pipeline_report(r: &GpuRenderer) -> String {
    let ms = r.last_compile_time().map_or(0.0, |t| t.as_secs_f64() * 1e3);
    let cache = match (r.pipeline_cache_loaded(), r.pipeline_cache_path()) {
        (None, _) => "no pipeline cache on this device".to_owned(),
        (Some(_), None) => "pipeline cache in memory only".to_owned(),
        (Some(0), Some(p)) => format!("pipeline cache cold, saved to {}", p.display()),
        (Some(n), Some(p)) => format!("pipeline cache: {n} bytes loaded from {}", p.display()),
    };
    format!("GPU pipelines compiled in {ms:.0} ms ({cache})")
}
