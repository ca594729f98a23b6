//! `refract render --device gpu|auto`: the GPU path of the render command (kept out of
//! main.rs so the CLI stays small).

use anyhow::Result;
use refract::film;
use refract::gpu::{GpuContext, GpuRenderer, gpu_estimator};
use refract::render::{Device, Estimator, RenderOptions};
use refract::scene::Scene;

/// Render on the GPU if `args.device` asks for it (and, for `auto`, a hardware adapter exists).
/// Returns false when the caller should render on the CPU instead.
pub fn render(args: &super::RenderArgs, scene: &Scene, job: &super::cli_job::Job) -> Result<bool> {
    let (spp, tone) = (job.spp, job.tone);
    let forced = match args.device {
        Device::Cpu => return Ok(false),
        Device::Gpu => true,
        Device::Auto => false,
    };
    let filter = &job.filter;
    let estimator = match gpu_estimator(job.choice, scene) {
        Ok(e) => e,
        Err(e) if forced => return Err(e),
        Err(_) => return Ok(false),
    };
    let ctx = match GpuContext::new() {
        Ok(c) => c,
        Err(e) if !forced => {
            eprintln!("no GPU adapter ({e:#}); rendering on the CPU");
            return Ok(false);
        }
        Err(e) => return Err(e),
    };
    if ctx.is_software() {
        if !forced {
            eprintln!(
                "only a software GPU adapter ({}); rendering on the CPU (use --device gpu to force it)",
                ctx.describe()
            );
            return Ok(false);
        }
        eprintln!(
            "note: {} is a software adapter (CPU-emulated), expect it to be slow",
            ctx.describe()
        );
    }
    if job.choice == Estimator::Auto {
        let (_, why) = job.choice.resolve_gpu_why(scene);
        eprintln!("estimator auto: {estimator} ({why})");
    }
    let mut opts = RenderOptions::from_scene(scene);
    opts.max_film_bytes = job.max_film_bytes;
    opts.seed = job.seed;
    opts.set_filter(Some(filter));
    opts.estimator = estimator;
    let name = ctx.describe();
    let mut r = match GpuRenderer::with_context(ctx, scene.clone(), opts) {
        Ok(r) => r,
        Err(e) if !forced => {
            eprintln!("GPU renderer unavailable ({e:#}); rendering on the CPU");
            return Ok(false);
        }
        Err(e) => return Err(e),
    };
    let (bvh_time, depth, nodes) = r.bvh_info();
    eprintln!(
        "scene {} on GPU {name}: {} triangles, BVH2 {nodes} nodes depth {depth} built in {:.1} ms; {}x{}, {}, max depth {}, estimator {}{}{}",
        scene.name,
        scene.mesh.triangle_count(),
        bvh_time.as_secs_f64() * 1e3,
        opts.width,
        opts.height,
        super::cli_render::spp_text(spp, args.time_budget),
        opts.max_depth,
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
    eprintln!("{}", pipeline_report(&r));
    let bar = super::cli_render::spp_progress_bar(spp, args.quiet);
    let img = match r.render_with(spp.unwrap_or(u32::MAX), args.time_budget, |d| {
        bar.set_position(d)
    }) {
        Ok(img) => img,
        Err(e) if !forced => {
            bar.finish_and_clear();
            eprintln!("GPU render failed ({e:#}); rendering on the CPU");
            return Ok(false);
        }
        Err(e) => return Err(e),
    };
    bar.finish_and_clear();
    let stats = r.stats()?;
    film::save_image(
        &args.out,
        img.width,
        img.height,
        &img.mean,
        job.exposure,
        tone,
    )?;
    eprintln!(
        "wrote {} — {} spp in {:.2} s on the GPU, {:.3} M samples/s, {:.3} M path segments/s, {} NaN/Inf/negative samples dropped",
        args.out.display(),
        stats.spp,
        stats.elapsed.as_secs_f64(),
        stats.samples_per_sec() / 1e6,
        stats.segments_per_sec() / 1e6,
        stats.dropped
    );
    super::cli_render::budget_report(args.time_budget, stats.spp, r.batch_spp());
    Ok(true)
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
