//! `refract bench`: run time against error (CSV, plot, Markdown table), and `--viewer`.

use super::BenchArgs;
use super::threads::thread_pool;
use anyhow::{Context, Result, bail};
use refract::film;
use refract::render::Device;
use refract::render::settings::abbreviate;
use refract::scene::MAX_IMAGE_SIDE;
use std::time::Duration;

/// `refract bench`: the quick check of one scene, or the full run (arguments checked and
/// outputs probed before any work) printing its table.
pub(super) fn bench(args: &BenchArgs) -> Result<()> {
    if args.viewer {
        return bench_viewer(args);
    }
    if args.quick {
        let spec = args
            .scenes
            .first()
            .cloned()
            .unwrap_or_else(|| "builtin:cornell-glass".into());
        print!("{}", refract::bench::quick(&spec)?);
        return Ok(());
    }
    let devices = check_bench_args(args)?;
    probe_bench_outputs(args)?;
    let opts = bench_options(args, devices);
    let pool = thread_pool(args.threads.filter(|&t| t > 0))?;
    let table = pool.install(|| refract::bench::run(&opts))?;
    println!("{table}");
    eprintln!(
        "wrote {0}/bench.csv, {0}/bench.png, {0}/bench.md",
        args.out.display()
    );
    Ok(())
}

/// `refract bench --viewer`: the headless viewer bench (`app::viewer_bench`), its report
/// printed as JSON and written to `--json`.
fn bench_viewer(args: &BenchArgs) -> Result<()> {
    let (width, height) = checked_size(args, (1920, 1080))?;
    let gpu = match args.device.to_ascii_lowercase().as_str() {
        "cpu" => false,
        "gpu" => true,
        d => bail!("--device {d}: the viewer bench runs on cpu or gpu"),
    };
    if let Some(f) = &args.json {
        film::probe_writable(f).context("--json")?;
    }
    let opts = refract::app::viewer_bench::ViewerBenchOptions {
        gpu,
        width,
        height,
        drag: args.drag,
        measure: args.budget.min(Duration::from_secs(5)),
    };
    let report = refract::app::viewer_bench::run(&opts)?;
    let json = serde_json::to_string_pretty(&report)?;
    println!("{json}");
    if let Some(f) = &args.json {
        std::fs::write(f, json)
            .with_context(|| format!("cannot write --json '{}'", f.display()))?;
    }
    Ok(())
}

/// `--width`/`--height`, or `default`; each within 1..=MAX_IMAGE_SIDE.
fn checked_size(args: &BenchArgs, default: (u32, u32)) -> Result<(u32, u32)> {
    let size = (
        args.width.unwrap_or(default.0),
        args.height.unwrap_or(default.1),
    );
    for (n, v) in [("width", size.0), ("height", size.1)] {
        if v == 0 || v > MAX_IMAGE_SIDE {
            bail!("--{n} {v} is out of range (1..={MAX_IMAGE_SIDE})");
        }
    }
    Ok(size)
}

/// Check the image size, `--device`, every `--paths` and `--ref-spp`, in that order; returns
/// whether to run (the CPU, a GPU).
fn check_bench_args(args: &BenchArgs) -> Result<(bool, bool)> {
    checked_size(args, (128, 128))?;
    let devices = Device::parse_bench(&args.device).map_err(anyhow::Error::msg)?;
    for p in &args.paths {
        refract::paths::PathFilter::parse(p)
            .map_err(|e| anyhow::anyhow!("--paths '{}': {e}", abbreviate(p)))?;
    }
    if args.ref_spp < 2 {
        bail!("--ref-spp must be at least 2 (two independent halves)");
    }
    Ok(devices)
}

/// Before any work: every output file and the reference cache can be written.
fn probe_bench_outputs(args: &BenchArgs) -> Result<()> {
    for f in ["bench.csv", "bench.png", "bench.md"] {
        film::probe_writable(&args.out.join(f)).context("--out")?;
    }
    let probe = format!(".write-probe-{}", std::process::id());
    film::probe_writable(&args.cache.join(probe)).context("--cache")?;
    Ok(())
}

/// The bench run `args` ask for on devices (`cpu`, `gpu`); no scenes named means every
/// built-in scene.
fn bench_options(args: &BenchArgs, (cpu, gpu): (bool, bool)) -> refract::bench::BenchOptions {
    let scenes = if args.scenes.is_empty() {
        refract::scene::builtin::NAMES
            .iter()
            .map(|n| format!("builtin:{n}"))
            .collect()
    } else {
        args.scenes.clone()
    };
    refract::bench::BenchOptions {
        scenes,
        limits: args.load.limits(),
        budget: args.budget,
        out: args.out.clone(),
        width: args.width.unwrap_or(128),
        height: args.height.unwrap_or(128),
        ref_spp: args.ref_spp,
        cache_dir: args.cache.clone(),
        estimators: args.estimators.clone(),
        ref_estimator: args.ref_estimator,
        cpu,
        gpu,
        paths: args.paths.clone(),
        env_uniform: args.env_uniform,
    }
}
