//! `refract` command line: view | render | trace | bench. No subcommand opens the viewer.

use anyhow::{Context, Result, bail};
use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use refract::cpu::Renderer;
use refract::film::{self, ToneMap};
use refract::math::spectrum;
use refract::render::settings::{DEFAULT_SCENE, ViewerSettings, abbreviate};
use refract::render::{Device, Estimator, RenderOptions};
use refract::scene::{MAX_IMAGE_SIDE, Scene};
use std::path::PathBuf;
use std::time::Duration;

mod cli_duration;
mod cli_layers;
mod cli_load;
mod cli_trace;
mod gpu_render;

use cli_duration::parse_duration;
use cli_load::LoadArgs;

#[derive(Parser)]
#[command(
    name = "refract",
    version,
    about = "Physically based light transport: glass, mirrors, Fresnel, caustics"
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Open the interactive viewer (the default when no subcommand is given).
    View(ViewArgs),
    /// Render a scene headless to .exr (linear float RGB) or .png (tone-mapped sRGB).
    Render(RenderArgs),
    /// The path inspector: every vertex of N camera paths through one pixel (JSON or a table).
    Trace(cli_trace::TraceArgs),
    /// Run time against error: CSV, PNG plot and Markdown table per scene.
    Bench(BenchArgs),
}

#[derive(clap::Args, Clone)]
struct BenchArgs {
    /// Scenes (paths or builtin:NAME); default: every built-in scene.
    #[arg(long, num_args = 1..)]
    scenes: Vec<String>,
    #[command(flatten)]
    load: LoadArgs,
    /// Time budget of each measured run.
    #[arg(long, default_value = "20s", value_parser = parse_duration)]
    budget: Duration,
    /// Output folder for bench.csv, bench.png, bench.md.
    #[arg(long, default_value = "bench")]
    out: PathBuf,
    #[arg(long, default_value_t = 128)]
    width: u32,
    #[arg(long, default_value_t = 128)]
    height: u32,
    /// Samples per pixel of the cached reference.
    #[arg(long, default_value_t = 1024)]
    ref_spp: u32,
    /// Reference cache folder.
    #[arg(long, default_value = "target/bench-cache")]
    cache: PathBuf,
    /// Estimators to measure: auto (picked by the scene's features, as `render` does), path,
    /// bdpt, lt (CPU), lt+pt (GPU). A run of `auto` is labelled "auto = X", or "X = auto" when
    /// X is also asked for by name (measured once).
    #[arg(long, num_args = 1.., default_values_t = [Estimator::Auto, Estimator::Path, Estimator::Bdpt],
        value_parser = Estimator::parser())]
    estimators: Vec<Estimator>,
    /// Estimator of the cached reference (bdpt converges much faster on caustics).
    #[arg(long, default_value = "bdpt", value_parser = Estimator::parser())]
    ref_estimator: Estimator,
    /// Renderer to measure: cpu, gpu (path and lt+pt) or all.
    #[arg(long, default_value = "cpu")]
    device: String,
    /// Only the micro-benchmarks (BVH rays/s, BSDF sampling).
    #[arg(long)]
    quick: bool,
    /// Heckbert path classes, each benched on its own, e.g. 'LS+DE' 'LS+DS+E' (the caustic
    /// alone and its mirror image); default: all paths.
    #[arg(long, num_args = 1..)]
    paths: Vec<String>,
    #[arg(long)]
    threads: Option<usize>,
    /// Also measure each CPU estimator with the environment image sampled uniformly (the
    /// comparison for environment importance sampling).
    #[arg(long)]
    env_uniform: bool,
}

/// An environment image from the command line (overrides the scene's).
#[derive(clap::Args, Clone, Default)]
struct EnvArgs {
    /// Equirectangular environment image (.hdr or .exr) lighting the scene.
    #[arg(long)]
    env: Option<PathBuf>,
    /// Radiance multiplier of the environment image (default 1, or the scene's).
    #[arg(long, allow_hyphen_values = true)]
    env_strength: Option<f32>,
    /// Rotation of the environment image about +Y in degrees (default 0, or the scene's).
    #[arg(long, allow_hyphen_values = true)]
    env_rotation: Option<f32>,
}

impl EnvArgs {
    /// Apply to `scene`; warnings are printed.
    fn apply(&self, scene: &mut Scene) -> Result<()> {
        let w = refract::scene::env_map::override_environment(
            scene,
            self.env.as_deref(),
            self.env_strength,
            self.env_rotation,
        )?;
        for w in w {
            eprintln!("warning: {w}");
        }
        Ok(())
    }
}

#[derive(clap::Args, Clone, Default)]
struct ViewArgs {
    /// Scene: a .gltf/.glb path or builtin:NAME (default builtin:cornell-glass).
    scene: Option<String>,
    /// Close the window after this many frames (CI, screenshots); with --exit-after, not
    /// before the image has its first sample.
    #[arg(long)]
    frames: Option<u64>,
    #[command(flatten)]
    load: LoadArgs,
    /// Close the window after this much time (e.g. 5s, 2m).
    #[arg(long, value_parser = parse_duration)]
    exit_after: Option<Duration>,
    /// Renderer: auto (GPU on a hardware adapter, else CPU), cpu, or gpu (also on a software
    /// adapter such as lavapipe).
    #[arg(long, value_enum, ignore_case = true, default_value_t = Device::Auto)]
    device: Device,
    /// Open with the path inspector on pixel X Y of the scene's full-resolution image (the
    /// pixel `refract trace --pixel X Y` traces).
    #[arg(long, num_args = 2, value_names = ["X", "Y"])]
    inspect: Option<Vec<u32>>,
    /// What the viewport shows first: beauty, classes (dominant path class), tir, refraction
    /// or depth (heatmaps); the last four CPU only.
    #[arg(long, value_enum, ignore_case = true, default_value_t = refract::app::layer_view::ViewMode::Beauty)]
    view: refract::app::layer_view::ViewMode,
    /// Open a lecture demonstration: snell, fresnel, tir, caustic, prism or
    /// classes (the scene argument is then ignored).
    #[arg(long)]
    lecture: Option<String>,
    /// Light every emitter with one spectral line at this wavelength in nm (360–830; e.g.
    /// 589.3 sodium D, 632.8 He-Ne, 532 green laser, 405 violet laser) instead of white light:
    /// spectral transport, dispersive glass refracts with n(λ). CPU renderer only.
    #[arg(long, value_name = "NM", allow_hyphen_values = true)]
    light_line: Option<f32>,
    #[command(flatten)]
    env: EnvArgs,
}

#[derive(clap::Args, Clone)]
struct RenderArgs {
    /// Scene: a .gltf/.glb path or builtin:NAME (default: the settings' scene, else
    /// builtin:cornell-glass).
    #[arg(long)]
    scene: Option<String>,
    /// A viewer screenshot's .json sidecar: its scene, edits, options, exposure, tone map and
    /// spp; flags given explicitly override it.
    #[arg(long)]
    settings: Option<PathBuf>,
    #[command(flatten)]
    load: LoadArgs,
    /// Samples per pixel (default: the sidecar's, else the scene's extras.render.spp; with
    /// --time-budget alone, as many as the budget allows).
    #[arg(long)]
    spp: Option<u32>,
    /// Output file (.exr or .png).
    #[arg(long, default_value = "out.exr")]
    out: PathBuf,
    #[arg(long)]
    width: Option<u32>,
    #[arg(long)]
    height: Option<u32>,
    /// Mitsuba semantics: 1 = emitters only, 2 = direct lighting, …
    #[arg(long)]
    max_depth: Option<u32>,
    /// Russian roulette start depth.
    #[arg(long)]
    rr_depth: Option<u32>,
    /// Random seed (default 0).
    #[arg(long)]
    seed: Option<u32>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// Render for this much time (e.g. 10s, 2m, 500ms) and keep the samples done: alone, until
    /// the budget is spent; with --spp, whichever comes first. The last pass may overrun the
    /// budget by at most one pass.
    #[arg(long, value_parser = parse_duration)]
    time_budget: Option<Duration>,
    /// Exposure in stops for PNG output (default 0).
    #[arg(long, allow_hyphen_values = true)]
    exposure: Option<f32>,
    /// Tone map for PNG output: clamp, reinhard, aces (default clamp).
    #[arg(long)]
    tonemap: Option<String>,
    /// Heckbert path filter over L, D, G, S, E read light→eye, e.g. 'LS+DE' (caustics),
    /// 'LDE' (direct diffuse lighting); empty = all paths (the default).
    #[arg(long)]
    paths: Option<String>,
    /// Path classes in one render, comma-separated, first match wins: 'LE,LDE,LS+DE' writes
    /// OUT.LE.exr, OUT.LDE.exr, OUT.LSpDE.exr and OUT.rest.exr (every other path) next to
    /// OUT, which is their sum. A class may be named NAME=EXPR; unnamed, its file name spells
    /// + * ? | ( ) as p x q o _ -. CPU path tracing only.
    #[arg(long, value_name = "CLASSES")]
    decompose: Option<String>,
    /// Event heatmaps, comma-separated: tir (fraction of paths with a total internal
    /// reflection), refraction (fraction with a refraction), depth (mean surface vertices per
    /// path), or all; written as OUT.tir.exr etc. CPU path tracing only.
    #[arg(long, value_name = "LIST")]
    aov: Option<String>,
    /// Estimator: path (path tracing, NEE + MIS), bdpt (bidirectional, MIS over all
    /// strategies), lt (pure light tracing), lt+pt (GPU: light tracing and path tracing
    /// combined by MIS; the CPU runs bdpt for it), auto (picked by the scene's features, the
    /// viewer's rule; the default, unless a --settings sidecar names one).
    #[arg(long, value_parser = Estimator::parser())]
    estimator: Option<Estimator>,
    /// Hide the progress bar.
    #[arg(long)]
    quiet: bool,
    /// Most memory the film may take, in GiB (24 bytes per pixel, 36 with light tracing's
    /// splat film); an image beyond it is refused before anything is allocated.
    #[arg(long, default_value_t = 2.0, value_name = "GIB", value_parser = parse_gib)]
    max_film_gib: f64,
    /// Renderer: cpu, gpu, or auto (a hardware GPU if there is one, else the CPU).
    #[arg(long, value_enum, ignore_case = true, default_value_t = Device::Auto)]
    device: Device,
    /// Light every emitter with one spectral line at this wavelength in nm (360–830; e.g.
    /// 589.3 sodium D, 632.8 He-Ne, 532 green laser, 405 violet laser) instead of white light:
    /// spectral transport, dispersive glass refracts with n(λ). CPU renderer only.
    #[arg(long, value_name = "NM", allow_hyphen_values = true)]
    light_line: Option<f32>,
    #[command(flatten)]
    env: EnvArgs,
}

fn parse_tonemap(s: &str) -> Result<ToneMap> {
    Ok(match s.to_ascii_lowercase().as_str() {
        "clamp" | "none" => ToneMap::Clamp,
        "reinhard" => ToneMap::Reinhard,
        "aces" => ToneMap::Aces,
        _ => bail!("unknown tone map '{s}' (use clamp, reinhard or aces)"),
    })
}

/// Values of the render command resolved from flags and the settings sidecar.
struct Job {
    /// Samples per pixel; None: as many as `--time-budget` allows.
    spp: Option<u32>,
    tone: ToneMap,
    exposure: f32,
    seed: u32,
    filter: refract::paths::PathFilter,
    /// `--estimator`, resolved for the scene on the CPU (never `auto`).
    estimator: Estimator,
    /// `--estimator` as given (the GPU resolves `auto` by its own rule).
    choice: Estimator,
    /// `--max-film-gib` in bytes.
    max_film_bytes: u64,
}

fn render(args: &RenderArgs) -> Result<()> {
    // Before any work: a render whose image cannot be written is an error now, not after.
    film::check_output_path(&args.out).context("--out")?;
    let layers = cli_layers::Layers::parse(args.decompose.as_deref(), args.aov.as_deref())?;
    if let Some(l) = &layers {
        l.check_outputs(&args.out)?;
    }
    let (scene, mut job) = prepare(args)?;
    if let Some(l) = &layers {
        l.check(args.device, job.choice, job.filter.source())?;
        let size = (scene.settings.width, scene.settings.height);
        l.check_memory(size, job.max_film_bytes)?;
        // The layers come from the path tracer's camera walk (`auto` path-traces then).
        if job.estimator != Estimator::Path {
            eprintln!(
                "estimator auto: path (the layers need the path tracer; auto alone would \
                 pick {})",
                job.estimator
            );
        }
        job.estimator = Estimator::Path;
        job.choice = Estimator::Path;
    } else if gpu_render::render(args, &scene, &job)? {
        return Ok(());
    }
    render_cpu(args, scene, &job, layers.as_ref())
}

/// The sidecar's environment image (relative to the sidecar's folder), then the `--env*`
/// flags over it.
fn apply_environment(
    args: &RenderArgs,
    sidecar: Option<&ViewerSettings>,
    scene: &mut Scene,
) -> Result<()> {
    if let (Some(s), Some(file)) = (sidecar, &args.settings)
        && let Some(e) = &s.environment
    {
        let dir = file.parent().unwrap_or(std::path::Path::new("."));
        for w in e
            .apply(scene, dir)
            .with_context(|| format!("settings '{}'", sidecar_file(args)))?
        {
            eprintln!("warning: {w}");
        }
    }
    args.env.apply(scene)
}

/// The scene to render (sidecar edits and flags applied) and the job's other values.
fn prepare(args: &RenderArgs) -> Result<(Scene, Job)> {
    let sidecar = args
        .settings
        .as_deref()
        .map(ViewerSettings::load)
        .transpose()?;
    let spec = args
        .scene
        .clone()
        .or_else(|| sidecar.as_ref().map(|s| s.scene.clone()))
        .unwrap_or_else(|| DEFAULT_SCENE.to_owned());
    let tone = match (&args.tonemap, &sidecar) {
        (Some(t), _) => parse_tonemap(t)?,
        (None, Some(s)) => s.display.tone_map,
        (None, None) => ToneMap::Clamp,
    };
    let (exposure, exposure_from) = match (args.exposure, &sidecar) {
        (Some(e), _) => (e, "--exposure".to_owned()),
        (None, Some(s)) => (s.display.exposure, sidecar_key(args, "display.exposure")),
        (None, None) => (0.0, String::new()),
    };
    if !exposure.is_finite() {
        bail!("{exposure_from} must be a finite number (exposure in stops), got {exposure}");
    }
    let mut scene = Scene::load_with(&spec, &args.load.limits())?;
    for w in &scene.warnings {
        eprintln!("warning: {w}");
    }
    apply_environment(args, sidecar.as_ref(), &mut scene)?;
    let mut sidecar_spp = None;
    if let Some(s) = &sidecar {
        // Headless, a sidecar's impossible material value is an error naming its key.
        for (k, e) in s.materials.iter().enumerate() {
            e.check()
                .with_context(|| sidecar_key(args, &format!("materials[{k}]")))?;
        }
        s.light
            .check()
            .with_context(|| sidecar_key(args, "light"))?;
        // The viewer's edits and options, exactly as the viewer applies them.
        let (edited, warnings) = s.apply(&scene);
        for w in warnings {
            eprintln!("warning: {w}");
        }
        // Light edits scale every emitter: an overflow names the sidecar keys it came from.
        edited.validate().with_context(|| {
            format!(
                "{} = {}, light.color = {:?}, light.temperature_k = {:?}",
                sidecar_key(args, "light.intensity"),
                s.light.intensity,
                s.light.color,
                s.light.temperature_k
            )
        })?;
        let o = s
            .render_options(&edited)
            .with_context(|| format!("settings '{}'", sidecar_file(args)))?;
        scene = edited;
        scene.settings.width = o.width;
        scene.settings.height = o.height;
        scene.settings.max_depth = o.max_depth;
        scene.settings.rr_depth = o.rr_depth;
        sidecar_spp = s.capture.as_ref().map(|c| c.spp);
    }
    if let Some(w) = args.width {
        scene.settings.width = w;
    }
    if let Some(h) = args.height {
        scene.settings.height = h;
    }
    if let Some(d) = args.max_depth {
        scene.settings.max_depth = d;
    }
    if let Some(r) = args.rr_depth {
        scene.settings.rr_depth = r;
    }
    if let Some(nm) = args.light_line {
        scene.settings.light_line_nm =
            Some(spectrum::check_light_line(nm, "--light-line").map_err(anyhow::Error::msg)?);
    }
    let s = scene.settings;
    check_size(args, sidecar.as_ref(), &spec, &s)?;
    let spp = resolve_spp(args, sidecar_spp, &spec, s.spp)?;
    if args.threads == Some(0) {
        bail!("--threads must be at least 1");
    }
    let seed = args
        .seed
        .or(sidecar.as_ref().map(|s| s.render.seed))
        .unwrap_or(0);
    let (paths, paths_from) = match (&args.paths, &sidecar) {
        (Some(p), _) => (p.clone(), "--paths".to_owned()),
        (None, Some(s)) => (s.render.paths.clone(), sidecar_key(args, "render.paths")),
        (None, None) => (String::new(), String::new()),
    };
    let filter = refract::paths::PathFilter::parse(&paths)
        .map_err(|e| anyhow::anyhow!("invalid {paths_from} '{}': {e}", abbreviate(&paths)))?;
    let choice = args
        .estimator
        .or(sidecar.as_ref().map(|s| s.render.estimator))
        .unwrap_or(Estimator::Auto);
    let (estimator, _) = choice.resolve_why(&scene);
    let job = Job {
        spp,
        tone,
        exposure,
        seed,
        filter,
        estimator,
        choice,
        max_film_bytes: film_budget(args),
    };
    Ok((scene, job))
}

/// The image size and depth, each error naming where the value came from (flag, sidecar key
/// or the scene's `extras.render`).
fn check_size(
    args: &RenderArgs,
    sidecar: Option<&ViewerSettings>,
    spec: &str,
    s: &refract::scene::RenderSettings,
) -> Result<()> {
    let from = |flags: bool, key: &str| -> String {
        match sidecar {
            _ if flags => "--width/--height".to_owned(),
            Some(c) if c.capture.is_some() => sidecar_key(args, "capture.width/height"),
            Some(_) => sidecar_key(args, "render.render_scale"),
            None => format!("extras.render.{key} of scene '{}'", abbreviate(spec)),
        }
    };
    if s.width == 0 || s.height == 0 || s.width > MAX_IMAGE_SIDE || s.height > MAX_IMAGE_SIDE {
        bail!(
            "image size {}x{} from {} is out of range (1..={MAX_IMAGE_SIDE} per side)",
            s.width,
            s.height,
            from(
                args.width.is_some() || args.height.is_some(),
                "width/height"
            )
        );
    }
    let film = refract::film::Film::bytes_for(s.width, s.height);
    if film > film_budget(args) {
        bail!(
            "image size {}x{} from {} needs a {:.1} GiB film, more than the {} GiB budget \
             (raise it with --max-film-gib)",
            s.width,
            s.height,
            from(
                args.width.is_some() || args.height.is_some(),
                "width/height"
            ),
            film as f64 / (1u64 << 30) as f64,
            args.max_film_gib
        );
    }
    if s.max_depth == 0 {
        let from = match (args.max_depth, sidecar) {
            (Some(_), _) => "--max-depth".to_owned(),
            (None, Some(_)) => sidecar_key(args, "render.max_depth"),
            (None, None) => format!("extras.render.max_depth of scene '{}'", abbreviate(spec)),
        };
        bail!("{from} must be at least 1 (1 = emitters only)");
    }
    Ok(())
}

/// Samples per pixel: the flag, else (without a time budget) the sidecar's capture, else the
/// scene's; None when a time budget alone bounds the render. Zero is an error naming its source.
fn resolve_spp(
    args: &RenderArgs,
    sidecar_spp: Option<u64>,
    spec: &str,
    scene_spp: u32,
) -> Result<Option<u32>> {
    let (spp, spp_from) = match (args.spp, args.time_budget, sidecar_spp) {
        (Some(n), _, _) => (Some(n), "--spp".to_owned()),
        // A time budget alone is not capped by the sidecar's or the scene's spp.
        (None, Some(_), _) => (None, String::new()),
        (None, None, Some(n)) => (
            Some(u32::try_from(n).unwrap_or(u32::MAX)),
            sidecar_key(args, "capture.spp"),
        ),
        (None, None, None) => (
            Some(scene_spp),
            format!("extras.render.spp of scene '{}'", abbreviate(spec)),
        ),
    };
    if spp == Some(0) {
        bail!("{spp_from} must be at least 1");
    }
    Ok(spp)
}

/// `key` of the `--settings` sidecar, as errors name it: "display.exposure of settings 'x.json'".
fn sidecar_key(args: &RenderArgs, key: &str) -> String {
    format!("{key} of settings '{}'", sidecar_file(args))
}

/// The `--settings` file's path for an error line (abbreviated).
fn sidecar_file(args: &RenderArgs) -> String {
    let file = args.settings.as_deref().unwrap_or(std::path::Path::new(""));
    abbreviate(&file.display().to_string())
}

/// A rayon pool of `threads` workers (default: all cores); a failure is one line naming the
/// flag and the OS's reason once.
fn thread_pool(threads: Option<usize>) -> Result<rayon::ThreadPool> {
    // Far more than any machine's cores; more would only exhaust the OS (or take minutes).
    const MAX_THREADS: usize = 4096;
    let mut pool = rayon::ThreadPoolBuilder::new();
    if let Some(t) = threads {
        anyhow::ensure!(
            t <= MAX_THREADS,
            "--threads {t} is more than {MAX_THREADS} worker threads"
        );
        pool = pool.num_threads(t);
    }
    pool.build().map_err(|e| match threads {
        Some(t) => anyhow::anyhow!("--threads {t}: cannot start {t} worker threads ({e})"),
        None => anyhow::anyhow!("cannot start worker threads ({e})"),
    })
}

/// `--max-film-gib` in bytes.
fn film_budget(args: &RenderArgs) -> u64 {
    (args.max_film_gib * (1u64 << 30) as f64) as u64
}

/// A positive, finite number of GiB, at most 2²⁰ (1 PiB).
fn parse_gib(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 && v <= (1u64 << 20) as f64 => Ok(v),
        _ => Err(format!(
            "'{}' is not a size in GiB (a positive number up to 1048576)",
            abbreviate(s)
        )),
    }
}

fn render_cpu(
    args: &RenderArgs,
    scene: Scene,
    job: &Job,
    layers: Option<&cli_layers::Layers>,
) -> Result<()> {
    let &Job {
        spp,
        tone,
        exposure,
        seed,
        estimator,
        ..
    } = job;
    let pool = thread_pool(args.threads)?;
    let renderer = Renderer::new(scene)?;
    let mut opts = RenderOptions::from_scene(&renderer.scene);
    opts.max_film_bytes = job.max_film_bytes;
    opts.seed = seed;
    opts.set_filter(Some(&job.filter));
    opts.estimator = estimator;
    if job.choice == Estimator::Auto {
        let (_, why) = job.choice.resolve_why(&renderer.scene);
        eprintln!("estimator auto: {estimator} ({why})");
    }
    if estimator == Estimator::LtPt {
        eprintln!("note: on the CPU, lt+pt renders with bdpt (its strategies are a superset)");
    }

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
    let bar = spp_progress_bar(spp, args.quiet);
    let n = spp.unwrap_or(u32::MAX);
    let (film, layer_film, stats) = pool.install(|| match layers {
        Some(l) => {
            let proto = l.proto();
            let progress = |d| bar.set_position(d);
            let (f, lf, s) =
                renderer.render_layered(&opts, (n, args.time_budget), &proto, progress);
            (f, Some(lf), s)
        }
        None => {
            let (f, s) = renderer.render(&opts, n, args.time_budget, |d| bar.set_position(d));
            (f, None, s)
        }
    });
    bar.finish_and_clear();
    film::save_image(
        &args.out,
        opts.width,
        opts.height,
        &film.image(),
        exposure,
        tone,
    )?;
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
    budget_report(args.time_budget, stats.spp, opts.pass_spp());
    Ok(())
}

/// The samples asked for, as the render commands log them: "64 spp", or "spp until 2s" for a
/// time budget alone.
fn spp_text(spp: Option<u32>, budget: Option<Duration>) -> String {
    match (spp, budget) {
        (Some(n), _) => format!("{n} spp"),
        (None, Some(b)) => format!("spp until {b:?}"),
        (None, None) => "spp unbounded".to_owned(),
    }
}

/// With a time budget, one line on how far it got: the spp reached and the pass size (the
/// most the last pass can overrun the budget by).
fn budget_report(budget: Option<Duration>, spp: u64, pass_spp: u32) {
    if let Some(b) = budget {
        eprintln!("time budget {b:?}: {spp} spp reached in passes of {pass_spp} spp");
    }
}

/// The render commands' progress bar over `spp` samples per pixel, a counter of samples
/// when only a time budget bounds them (hidden when `quiet`).
fn spp_progress_bar(spp: Option<u32>, quiet: bool) -> ProgressBar {
    if quiet {
        return ProgressBar::hidden();
    }
    let (bar, template) = match spp {
        Some(n) => (
            ProgressBar::new(n as u64),
            "{bar:40} {pos}/{len} spp  {elapsed_precise} eta {eta}",
        ),
        None => (
            ProgressBar::new_spinner(),
            "{spinner} {pos} spp  {elapsed_precise}",
        ),
    };
    bar.set_style(
        ProgressStyle::with_template(template).unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar
}

fn bench(args: &BenchArgs) -> Result<()> {
    if args.quick {
        let spec = args
            .scenes
            .first()
            .cloned()
            .unwrap_or_else(|| "builtin:cornell-glass".into());
        print!("{}", refract::bench::quick(&spec)?);
        return Ok(());
    }
    for (n, v) in [("width", args.width), ("height", args.height)] {
        if v == 0 || v > MAX_IMAGE_SIDE {
            bail!("--{n} {v} is out of range (1..={MAX_IMAGE_SIDE})");
        }
    }
    let (cpu, gpu) = Device::parse_bench(&args.device).map_err(anyhow::Error::msg)?;
    for p in &args.paths {
        refract::paths::PathFilter::parse(p)
            .map_err(|e| anyhow::anyhow!("--paths '{}': {e}", abbreviate(p)))?;
    }
    if args.ref_spp < 2 {
        bail!("--ref-spp must be at least 2 (two independent halves)");
    }
    // Before any work: every output file and the reference cache can be written.
    for f in ["bench.csv", "bench.png", "bench.md"] {
        film::probe_writable(&args.out.join(f)).context("--out")?;
    }
    let probe = format!(".write-probe-{}", std::process::id());
    film::probe_writable(&args.cache.join(probe)).context("--cache")?;
    let scenes = if args.scenes.is_empty() {
        refract::scene::builtin::NAMES
            .iter()
            .map(|n| format!("builtin:{n}"))
            .collect()
    } else {
        args.scenes.clone()
    };
    let opts = refract::bench::BenchOptions {
        scenes,
        limits: args.load.limits(),
        budget: args.budget,
        out: args.out.clone(),
        width: args.width,
        height: args.height,
        ref_spp: args.ref_spp,
        cache_dir: args.cache.clone(),
        estimators: args.estimators.clone(),
        ref_estimator: args.ref_estimator,
        cpu,
        gpu,
        paths: args.paths.clone(),
        env_uniform: args.env_uniform,
    };
    let pool = thread_pool(args.threads.filter(|&t| t > 0))?;
    let table = pool.install(|| refract::bench::run(&opts))?;
    println!("{table}");
    eprintln!(
        "wrote {0}/bench.csv, {0}/bench.png, {0}/bench.md",
        args.out.display()
    );
    Ok(())
}

fn view(args: ViewArgs) -> Result<()> {
    let inspect = match args.inspect.as_deref() {
        None => None,
        Some(&[x, y]) => Some((x, y)),
        Some(_) => bail!("--inspect takes two numbers, X and Y"),
    };
    let env = &args.env;
    let env = (env.env.is_some() || env.env_strength.is_some() || env.env_rotation.is_some()).then(
        || refract::app::EnvOverride {
            file: env.env.clone(),
            strength: env.env_strength,
            rotation: env.env_rotation,
        },
    );
    if let Some(nm) = args.light_line {
        spectrum::check_light_line(nm, "--light-line").map_err(anyhow::Error::msg)?;
    }
    let lecture = args
        .lecture
        .as_deref()
        .map(refract::app::lecture::find)
        .transpose()?;
    refract::app::run(refract::app::ViewOptions {
        inspect,
        env,
        scene: lecture.map(|d| d.scene.to_owned()).or(args.scene),
        lecture: lecture.map(|d| d.key),
        frames: args.frames,
        exit_after: args.exit_after,
        device: args.device,
        limits: args.load.limits(),
        view: args.view,
        light_line: args.light_line,
    })
}

fn main() {
    // Vulkan drivers complain on stderr when XDG_RUNTIME_DIR is unset (headless machines, CI).
    if std::env::var_os("XDG_RUNTIME_DIR").is_none() {
        let dir = std::env::temp_dir().join(format!("refract-xdg-{}", std::process::id()));
        if std::fs::create_dir_all(&dir).is_ok() {
            // SAFETY: called first thing in `main`, before any other thread exists, so no
            // concurrent reader of the environment can observe the write.
            unsafe { std::env::set_var("XDG_RUNTIME_DIR", &dir) };
        }
    }
    let cli = Cli::parse();
    let result = match cli.command {
        Some(Command::Render(args)) => render(&args),
        Some(Command::Trace(args)) => cli_trace::run(&args),
        Some(Command::Bench(args)) => bench(&args),
        Some(Command::View(args)) => view(args),
        None => view(ViewArgs::default()),
    };
    if let Err(e) = result {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}
