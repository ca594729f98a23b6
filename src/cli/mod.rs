//! `refract`'s command line: the arguments of every subcommand (clap), and what runs them,
//! one file per subcommand; `main.rs` only parses and reports the error.

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};
use refract::render::settings::abbreviate;
use refract::render::{Device, Estimator, Shard};
use refract::scene::Scene;
use std::path::PathBuf;
use std::time::Duration;

mod bench;
mod denoise;
mod duration;
mod gpu_render;
mod gpu_stokes;
mod job;
mod layers;
mod lecture;
mod load;
mod merge;
mod polarization;
mod progress;
mod race;
mod render;
mod shard;
mod shard_plan;
mod threads;
mod trace;
mod view;

use duration::parse_duration;
use load::LoadArgs;

#[derive(Parser)]
#[command(
    name = "refract",
    version = concat!(env!("CARGO_PKG_VERSION"), " (git ", env!("REFRACT_GIT_REV"), ")"),
    about = "Physically based light transport: glass, mirrors, Fresnel, caustics"
)]
pub(crate) struct Cli {
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
    Trace(trace::TraceArgs),
    /// Run time against error: CSV, PNG plot and Markdown table per scene.
    Bench(BenchArgs),
    /// The lecture's demos: `list` them (KEY, concept, caption) or `export DIR` a handout
    /// (every demo rendered to DIR/KEY.png and DIR/index.html).
    #[command(subcommand)]
    Lecture(lecture::LectureCommand),
    /// Merge the EXRs of `render --shard I/N` into one image (the mean weighted by spp); files
    /// of another render or overlapping shards are refused.
    Merge(merge::MergeArgs),
    /// Print a shell completion script: `refract completions bash > /etc/bash_completion.d/refract`
    /// (bash, zsh, fish, elvish, powershell).
    Completions { shell: clap_complete::Shell },
    /// Print the manual page (roff): `refract man > refract.1 && man ./refract.1`.
    Man,
    /// Open a small hidden window with one presenter and close it (`view` probes risky
    /// presenters this way, in a child process: `app::present`).
    #[command(name = "__probe-window", hide = true)]
    ProbeWindow {
        /// `glow` or `wgpu:BACKENDS`.
        presenter: String,
    },
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
    /// Image width (default 128; with --viewer 1920).
    #[arg(long)]
    width: Option<u32>,
    /// Image height (default 128; with --viewer 1080).
    #[arg(long)]
    height: Option<u32>,
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
    /// The viewer itself, headless: a scripted lecture of edits (IOR drag, rough glass,
    /// GGX → Beckmann, dispersion on/off, the caustic demo), each one's time to its first
    /// image and compile time, the UI thread's longest frame, frames/s and samples/s at
    /// --width × --height and in the default window; `--device cpu|gpu`, `--json FILE`.
    #[arg(long)]
    viewer: bool,
    /// With --viewer: write the report here as JSON (also printed).
    #[arg(long)]
    json: Option<PathBuf>,
    /// With --viewer: how long the IOR drag takes.
    #[arg(long, default_value = "5s", value_parser = parse_duration)]
    drag: Duration,
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
    /// What draws the window: auto (wgpu's Vulkan/Metal/DX12, then wgpu's GL, then glow:
    /// the first that can present), wgpu (WGPU_BACKEND picks its backends) or glow (OpenGL;
    /// the GPU then renders headless and its image is copied through the CPU).
    #[arg(long, value_enum, ignore_case = true, default_value_t = refract::app::present::WindowRenderer::Auto)]
    window_renderer: refract::app::present::WindowRenderer,
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
    /// path), or all; written as OUT.tir.exr etc. CPU path tracing only. With polarised
    /// transport: dop, aop (degree and angle of polarisation, OUT.dop.png, OUT.aop.png) and
    /// stokes (OUT.s0.exr … OUT.s3.exr); these imply --polarized.
    #[arg(long, value_name = "LIST")]
    aov: Option<String>,
    /// Estimator: path (path tracing, NEE + MIS), bdpt (bidirectional, MIS over all
    /// strategies), lt (pure light tracing), lt+pt (GPU: light tracing and path tracing
    /// combined by MIS; the CPU runs bdpt for it), auto (picked by the scene's features, the
    /// viewer's rule; the default, unless a --settings sidecar names one).
    #[arg(long, value_parser = Estimator::parser())]
    estimator: Option<Estimator>,
    /// With auto on the CPU: choose by short trials of path, sppm and bdpt (least measured
    /// relMSE × time) instead of the rule; experimental, it loses to the rule on several
    /// built-ins (docs/estimators.md, "Choosing by measurement").
    #[arg(long)]
    measure_auto: bool,
    /// Render shard I of N (1 ≤ I ≤ N): samples spp·(I−1)/N .. spp·I/N of the --spp asked
    /// for, into an .exr whose header records them; `refract merge` joins the N shards into
    /// the image one machine renders with the same seed. Needs --spp.
    #[arg(long, value_name = "I/N", value_parser = Shard::parse, allow_hyphen_values = true)]
    shard: Option<Shard>,
    /// Also write a denoised image beside the unbiased one: OUT.denoised.exr (and
    /// OUT.denoised.png when OUT is a .png); the unbiased OUT is written as without it. An
    /// edge-avoiding à-trous filter guided by first-hit albedo, normal and depth
    /// (docs/denoise.md): it blurs caustics seen through glass.
    #[arg(long)]
    denoise: bool,
    /// A linear polarising filter in front of the sensor, its axis at DEG degrees from the
    /// image's horizontal, counter-clockwise (0 passes horizontally polarised light, 90
    /// vertically): implies --polarized. CPU path tracing only (docs/polarization.md).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    polarizer: Option<f32>,
    /// Trace polarised light (a Stokes vector per path, Mueller matrices at every surface);
    /// without --polarizer the image is the total intensity. --aov dop,aop,stokes then writes
    /// the degree and angle of polarisation (false colour) and the Stokes components.
    #[arg(long)]
    polarized: bool,
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

/// Run what the command line asks for (no subcommand: the viewer).
pub(crate) fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Some(Command::Render(args)) => render::render(&args),
        Some(Command::Trace(args)) => trace::run(&args),
        Some(Command::Bench(args)) => bench::bench(&args),
        Some(Command::Merge(args)) => merge::run(&args),
        Some(Command::Lecture(cmd)) => lecture::run(&cmd),
        Some(Command::View(args)) => view::view(args),
        Some(Command::Completions { shell }) => {
            let mut cmd = <Cli as clap::CommandFactory>::command();
            clap_complete::generate(shell, &mut cmd, "refract", &mut std::io::stdout());
            Ok(())
        }
        Some(Command::Man) => {
            let cmd = <Cli as clap::CommandFactory>::command();
            clap_mangen::Man::new(cmd)
                .render(&mut std::io::stdout())
                .context("cannot write the manual page")
        }
        Some(Command::ProbeWindow { presenter }) => refract::app::present::probe_window(&presenter),
        None => view::view(ViewArgs::default()),
    }
}
