//! `refract trace`: the path inspector headless — every vertex of N camera paths through one
//! pixel, as JSON (`--json`) or a readable table.

use anyhow::{Context, Result, bail};
use refract::cpu::Renderer;
use refract::cpu::inspect::{self, DEFAULT_PATHS, MAX_PATHS};
use refract::paths::PathFilter;
use refract::render::RenderOptions;
use refract::render::settings::{DEFAULT_SCENE, abbreviate};
use refract::scene::Scene;

#[derive(clap::Args, Clone)]
pub struct TraceArgs {
    /// Scene: a .gltf/.glb path or builtin:NAME (default builtin:cornell-glass).
    #[arg(long)]
    scene: Option<String>,
    #[command(flatten)]
    load: super::load::LoadArgs,
    /// The pixel to trace through: column X, row Y (0, 0 = top left).
    #[arg(long, num_args = 2, value_names = ["X", "Y"], required = true)]
    pixel: Vec<u32>,
    /// Number of camera paths (samples 0..N of the pixel, as `render` draws them).
    #[arg(long, default_value_t = DEFAULT_PATHS)]
    paths: u32,
    /// Random seed (the same seed as `render --seed` gives the same paths).
    #[arg(long, default_value_t = 0)]
    seed: u32,
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
    /// Heckbert path filter as `render --paths` takes it, e.g. 'LS+DE'; default all paths.
    #[arg(long)]
    filter: Option<String>,
    /// Print JSON: {"pixel":[x,y],"paths":[{"heckbert","contribution","vertices":[…]}]}.
    #[arg(long)]
    json: bool,
}

pub fn run(args: &TraceArgs) -> Result<()> {
    let spec = args
        .scene
        .clone()
        .unwrap_or_else(|| DEFAULT_SCENE.to_owned());
    let scene = Scene::load_with(&spec, &args.load.limits())?;
    for w in &scene.warnings {
        eprintln!("warning: {w}");
    }
    let opts = options(args, &scene)?;
    let (x, y) = pixel(args, &opts)?;
    if !(1..=MAX_PATHS).contains(&args.paths) {
        bail!("--paths {} is out of range (1..={MAX_PATHS})", args.paths);
    }
    let renderer = Renderer::new(scene)?;
    let trace = inspect::trace_pixel(&renderer, &opts, (x, y), args.paths)
        .with_context(|| format!("tracing scene '{}'", abbreviate(&spec)))?;
    if args.json {
        println!("{}", trace.to_json()?);
    } else {
        print!("{}", inspect::format_table(&trace));
    }
    Ok(())
}

/// The render options of the trace: the scene's, overridden by the flags.
fn options(args: &TraceArgs, scene: &Scene) -> Result<RenderOptions> {
    let mut opts = RenderOptions::from_scene(scene);
    opts.width = args.width.unwrap_or(opts.width);
    opts.height = args.height.unwrap_or(opts.height);
    opts.max_depth = args.max_depth.unwrap_or(opts.max_depth);
    opts.rr_depth = args.rr_depth.unwrap_or(opts.rr_depth);
    opts.seed = args.seed;
    if let Some(f) = &args.filter {
        let filter = PathFilter::parse(f)
            .map_err(|e| anyhow::anyhow!("invalid --filter '{}': {e}", abbreviate(f)))?;
        opts.set_filter(Some(&filter));
    }
    let from = if args.width.is_some() || args.height.is_some() {
        "--width/--height".to_owned()
    } else {
        format!("extras.render of scene '{}'", abbreviate(&scene.name))
    };
    opts.check().with_context(|| from.clone())?;
    Ok(opts)
}

/// `--pixel X Y`, inside the image.
fn pixel(args: &TraceArgs, opts: &RenderOptions) -> Result<(u32, u32)> {
    let &[x, y] = args.pixel.as_slice() else {
        bail!("--pixel takes two numbers, X and Y");
    };
    let (w, h) = (opts.width, opts.height);
    if x >= w || y >= h {
        bail!("--pixel {x} {y} is outside the {w}x{h} image (X in 0..{w}, Y in 0..{h})");
    }
    Ok((x, y))
}
