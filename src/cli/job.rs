//! The render command's job: the scene with the `--settings` sidecar's edits and the flags
//! applied over it, and every other value resolved, each bad value an error naming the flag,
//! sidecar key or scene field it came from.

use super::RenderArgs;
use super::shard_plan::ShardPlan;
use anyhow::{Context, Result, bail};
use refract::film::ToneMap;
use refract::math::spectrum;
use refract::paths::PathFilter;
use refract::render::settings::{DEFAULT_SCENE, ViewerSettings, abbreviate};
use refract::render::{Estimator, EstimatorPlan, Runner};
use refract::scene::{MAX_IMAGE_SIDE, RenderSettings, Scene};

/// Values of the render command resolved from flags and the settings sidecar.
pub(crate) struct Job {
    /// Samples per pixel; None: as many as `--time-budget` allows.
    pub(crate) spp: Option<u32>,
    pub(crate) tone: ToneMap,
    pub(crate) exposure: f32,
    pub(crate) seed: u32,
    pub(crate) filter: PathFilter,
    /// The CPU's plan for `--estimator` (`render::estimator_plan`; `plan.runs` is never
    /// `auto`). The GPU makes its own from `choice`, by the same decision.
    pub(crate) plan: EstimatorPlan,
    /// `--estimator` as given.
    pub(crate) choice: Estimator,
    /// `auto` with `--measure-auto`: the CPU chooses by measurement (`cli::race`).
    pub(crate) measure_auto: bool,
    /// `--max-film-gib` in bytes.
    pub(crate) max_film_bytes: u64,
    /// The scene as given (flag, sidecar or the default).
    pub(crate) spec: String,
    /// `--shard I/N`: the slice of the samples to render (`spp` is its size then).
    pub(crate) shard: Option<ShardPlan>,
}

impl Job {
    /// Index of the first sample to render (a shard's slice; 0 otherwise).
    pub(crate) fn first_sample(&self) -> u32 {
        self.shard.as_ref().map_or(0, |p| p.samples.start)
    }
}

/// The scene to render (sidecar edits and flags applied) and the job's other values.
pub(crate) fn prepare(args: &RenderArgs) -> Result<(Scene, Job)> {
    let shard = super::shard_plan::plan(args)?;
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
    let (tone, exposure) = display(args, sidecar.as_ref())?;
    let mut scene = Scene::load_with(&spec, &args.load.limits())?;
    for w in &scene.warnings {
        eprintln!("warning: {w}");
    }
    apply_environment(args, sidecar.as_ref(), &mut scene)?;
    let sidecar_spp = match &sidecar {
        Some(s) => apply_sidecar(args, s, &mut scene)?,
        None => None,
    };
    apply_flags(args, &mut scene.settings)?;
    let s = scene.settings;
    check_size(args, sidecar.as_ref(), &spec, &s)?;
    let spp = match &shard {
        Some(p) => Some(p.samples.end - p.samples.start),
        None => resolve_spp(args, sidecar_spp, &spec, s.spp)?,
    };
    if args.threads == Some(0) {
        bail!("--threads must be at least 1");
    }
    let seed = args
        .seed
        .or(sidecar.as_ref().map(|s| s.render.seed))
        .unwrap_or(0);
    let filter = path_filter(args, sidecar.as_ref())?;
    let choice = args
        .estimator
        .or(sidecar.as_ref().map(|s| s.render.estimator))
        .unwrap_or(Estimator::Auto);
    let plan = EstimatorPlan::decide(choice, &scene, Runner::Cpu);
    let measure_auto = choice == Estimator::Auto && args.measure_auto;
    let job = Job {
        spp,
        tone,
        exposure,
        seed,
        filter,
        plan,
        choice,
        measure_auto,
        max_film_bytes: film_budget(args),
        spec,
        shard,
    };
    Ok((scene, job))
}

/// The PNG's tone map and exposure: the flags, else the sidecar's display, else clamp at 0
/// stops; a non-finite exposure is an error naming its source.
fn display(args: &RenderArgs, sidecar: Option<&ViewerSettings>) -> Result<(ToneMap, f32)> {
    let tone = match (&args.tonemap, sidecar) {
        (Some(t), _) => parse_tonemap(t)?,
        (None, Some(s)) => s.display.tone_map,
        (None, None) => ToneMap::Clamp,
    };
    let (exposure, exposure_from) = match (args.exposure, sidecar) {
        (Some(e), _) => (e, "--exposure".to_owned()),
        (None, Some(s)) => (s.display.exposure, sidecar_key(args, "display.exposure")),
        (None, None) => (0.0, String::new()),
    };
    if !exposure.is_finite() {
        bail!("{exposure_from} must be a finite number (exposure in stops), got {exposure}");
    }
    Ok((tone, exposure))
}

/// The sidecar's material and light edits and render options, exactly as the viewer applies
/// them, each bad value an error naming its key; returns the sidecar's captured spp.
fn apply_sidecar(args: &RenderArgs, s: &ViewerSettings, scene: &mut Scene) -> Result<Option<u64>> {
    // Headless, a sidecar's impossible material value is an error naming its key.
    for (k, e) in s.materials.iter().enumerate() {
        e.check()
            .with_context(|| sidecar_key(args, &format!("materials[{k}]")))?;
    }
    s.light
        .check()
        .with_context(|| sidecar_key(args, "light"))?;
    let (edited, warnings) = s.apply(scene);
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
    *scene = edited;
    let r = &mut scene.settings;
    (r.width, r.height, r.max_depth, r.rr_depth) = (o.width, o.height, o.max_depth, o.rr_depth);
    Ok(s.capture.as_ref().map(|c| c.spp))
}

/// The size, depth and light-line flags over the scene's (or sidecar's) settings.
fn apply_flags(args: &RenderArgs, s: &mut RenderSettings) -> Result<()> {
    s.width = args.width.unwrap_or(s.width);
    s.height = args.height.unwrap_or(s.height);
    s.max_depth = args.max_depth.unwrap_or(s.max_depth);
    s.rr_depth = args.rr_depth.unwrap_or(s.rr_depth);
    if let Some(nm) = args.light_line {
        s.light_line_nm =
            Some(spectrum::check_light_line(nm, "--light-line").map_err(anyhow::Error::msg)?);
    }
    Ok(())
}

/// The Heckbert path filter of `--paths`, else of the sidecar; an invalid one names its source.
fn path_filter(args: &RenderArgs, sidecar: Option<&ViewerSettings>) -> Result<PathFilter> {
    let (paths, paths_from) = match (&args.paths, sidecar) {
        (Some(p), _) => (p.clone(), "--paths".to_owned()),
        (None, Some(s)) => (s.render.paths.clone(), sidecar_key(args, "render.paths")),
        (None, None) => (String::new(), String::new()),
    };
    PathFilter::parse(&paths)
        .map_err(|e| anyhow::anyhow!("invalid {paths_from} '{}': {e}", abbreviate(&paths)))
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

/// The image size and depth, each error naming where the value came from (flag, sidecar key
/// or the scene's `extras.render`).
fn check_size(
    args: &RenderArgs,
    sidecar: Option<&ViewerSettings>,
    spec: &str,
    s: &RenderSettings,
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
pub(crate) fn sidecar_key(args: &RenderArgs, key: &str) -> String {
    format!("{key} of settings '{}'", sidecar_file(args))
}

/// The `--settings` file's path for an error line (abbreviated).
fn sidecar_file(args: &RenderArgs) -> String {
    let file = args.settings.as_deref().unwrap_or(std::path::Path::new(""));
    abbreviate(&file.display().to_string())
}

/// `--max-film-gib` in bytes.
pub(crate) fn film_budget(args: &RenderArgs) -> u64 {
    (args.max_film_gib * (1u64 << 30) as f64) as u64
}

pub(crate) fn parse_tonemap(s: &str) -> Result<ToneMap> {
    Ok(match s.to_ascii_lowercase().as_str() {
        "clamp" | "none" => ToneMap::Clamp,
        "reinhard" => ToneMap::Reinhard,
        "aces" => ToneMap::Aces,
        _ => bail!("unknown tone map '{s}' (use clamp, reinhard or aces)"),
    })
}
