//! `render --polarizer DEG` and `render --polarized`: the polarised render — on the GPU
//! (`--device gpu`, or `auto` with a hardware adapter: the image behind the filter) or the
//! CPU (`cpu::polarized`, also the views `--aov dop,aop,stokes`; docs/polarization.md).
//! `--out dir/out.png` writes the image behind the filter to `out.png` and the views beside
//! it: `out.dop.png` + `out.dop.exr` (false colour and the value), `out.aop.png`, and
//! `out.s0.exr` … `out.s3.exr` (the Stokes components, linear RGB).

use super::RenderArgs;
use super::gpu_render;
use super::gpu_stokes;
use super::job::{Job, prepare};
use super::layers::layer_path;
use super::progress::spp_progress_bar;
use super::threads::thread_pool;
use anyhow::{Result, bail};
use glam::Vec3;
use refract::cpu::Renderer;
use refract::cpu::polarized::view;
use refract::film::{self, ToneMap};
use refract::render::settings::ViewerSettings;
use refract::render::{Estimator, EstimatorPlan, Polarization, RenderOptions, Runner};
use std::path::Path;

/// One view of a polarised render.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum PolView {
    Dop,
    Aop,
    Stokes,
}

impl PolView {
    fn parse(name: &str) -> Option<PolView> {
        match name {
            "dop" => Some(PolView::Dop),
            "aop" => Some(PolView::Aop),
            "stokes" => Some(PolView::Stokes),
            _ => None,
        }
    }
}

/// A polarised render asked for on the command line.
pub(crate) struct PolarizedRender {
    pub(crate) pol: Polarization,
    pub(crate) views: Vec<PolView>,
}

/// The polarised render the flags ask for (None: an ordinary render) and what is left of
/// `--aov` for the event heatmaps. The views dop, aop and stokes imply `--polarized`.
pub(crate) fn parse(args: &RenderArgs) -> Result<(Option<PolarizedRender>, Option<String>)> {
    let mut views = Vec::new();
    let mut rest = Vec::new();
    for item in args.aov.iter().flat_map(|a| a.split(',')).map(str::trim) {
        match PolView::parse(&item.to_ascii_lowercase()) {
            Some(v) if !views.contains(&v) => views.push(v),
            Some(_) => {}
            None => rest.push(item),
        }
    }
    // The flag, else a screenshot sidecar's `render.polarizer` (`--settings`).
    let sidecar = match (&args.polarizer, args.settings.as_deref()) {
        (None, Some(path)) => ViewerSettings::load(path)?.render.polarizer,
        _ => None,
    };
    let filter = match args.polarizer {
        Some(deg) if !deg.is_finite() => bail!("--polarizer: {deg} is not an angle in degrees"),
        Some(deg) => Some(deg.to_radians()),
        None => match sidecar {
            Some(deg) if !deg.is_finite() => {
                bail!("render.polarizer in the sidecar: {deg} is not an angle in degrees")
            }
            deg => deg.map(f32::to_radians),
        },
    };
    let rest = (!rest.is_empty()).then(|| rest.join(","));
    if filter.is_none() && !args.polarized && views.is_empty() {
        return Ok((None, rest));
    }
    if rest.is_some() || args.decompose.is_some() {
        bail!(
            "a polarised render (--polarizer, --polarized or --aov dop/aop/stokes) writes no \
             --decompose layers or event heatmaps (tir, refraction, depth): render those \
             separately"
        );
    }
    let pol = Polarization { filter };
    Ok((Some(PolarizedRender { pol, views }), None))
}

/// The render the polarised walk supports: the CPU path tracer over all paths, one machine.
fn check(args: &RenderArgs, job: &Job) -> Result<()> {
    let what = "polarised transport (--polarizer, --polarized)";
    if !matches!(job.choice, Estimator::Auto | Estimator::Path) {
        bail!(
            "{what} needs --estimator path (or auto), not {}",
            job.choice
        );
    }
    if !job.filter.source().trim().is_empty() {
        bail!("{what} renders every path: drop --paths (or a sidecar's render.paths)");
    }
    if args.shard.is_some() || args.denoise {
        bail!("{what} does not combine with --shard or --denoise");
    }
    Ok(())
}

/// Render the polarised image and its views, one line per file written.
pub(crate) fn render(args: &RenderArgs, pr: &PolarizedRender) -> Result<()> {
    for p in outputs(&args.out, &pr.views) {
        film::check_output_path(&p)?;
    }
    let (scene, mut job) = prepare(args)?;
    check(args, &job)?;
    job.choice = Estimator::Path;
    job.plan = EstimatorPlan::decide(Estimator::Path, &scene, Runner::Cpu);
    if pr.views.is_empty() {
        if gpu_render::render_polarized(args, &scene, &job, pr.pol)? {
            return Ok(());
        }
    } else if let Some(s) = gpu_stokes::render_stokes(args, &scene, &job, pr.pol)? {
        return write_gpu_stokes(args, pr, &job, &s);
    }
    let pool = thread_pool(args.threads)?;
    let renderer = Renderer::new(scene)?;
    let mut opts = RenderOptions::from_scene(&renderer.scene);
    opts.max_film_bytes = job.max_film_bytes;
    opts.seed = job.seed;
    opts.estimator = Estimator::Path;
    opts.check()?;
    let bar = spp_progress_bar(job.spp, args.quiet);
    let n = job.spp.unwrap_or(u32::MAX);
    let (film, stokes, stats) = pool.install(|| {
        renderer.render_polarized(&opts, pr.pol, (n, args.time_budget), |d| {
            bar.set_position(d)
        })
    });
    bar.finish_and_clear();
    let (w, h) = (opts.width, opts.height);
    film::save_image(&args.out, w, h, &film.image(), job.exposure, job.tone)?;
    let filter = filter_text(pr.pol);
    eprintln!(
        "wrote {} ({filter}) — {} spp polarised in {:.2} s, {} NaN/Inf/negative samples dropped",
        args.out.display(),
        stats.spp,
        stats.elapsed.as_secs_f64(),
        stats.dropped
    );
    let layers: Vec<Vec<Vec3>> = (0..4).map(|k| stokes.image(k, film.spp)).collect();
    save_views(&args.out, &pr.views, (w, h), &layers)
}

/// What the filter passes.
fn filter_text(pol: Polarization) -> String {
    match pol.filter {
        Some(a) => format!("behind a linear polariser at {:.1}°", a.to_degrees()),
        None => "total intensity, no filter".to_owned(),
    }
}

/// Write a GPU Stokes render (`gpu_stokes`): the image behind the filter and the views.
fn write_gpu_stokes(
    args: &RenderArgs,
    pr: &PolarizedRender,
    job: &Job,
    s: &gpu_stokes::StokesRender,
) -> Result<()> {
    let (w, h) = s.size;
    film::save_image(&args.out, w, h, &s.beauty, job.exposure, job.tone)?;
    eprintln!(
        "wrote {} ({}) — {} spp polarised on the GPU, four analysers in {:.2} s, {} NaN/Inf/negative samples dropped",
        args.out.display(),
        filter_text(pr.pol),
        s.spp,
        s.elapsed.as_secs_f64(),
        s.dropped
    );
    save_views(&args.out, &pr.views, (w, h), &s.stokes)
}

/// Every file the views write for `--out out`.
fn outputs(out: &Path, views: &[PolView]) -> Vec<std::path::PathBuf> {
    let png = |name: &str| layer_path(out, name).with_extension("png");
    views
        .iter()
        .flat_map(|v| match v {
            PolView::Dop => vec![png("dop"), layer_path(out, "dop")],
            PolView::Aop => vec![png("aop")],
            PolView::Stokes => (0..4).map(|k| layer_path(out, &format!("s{k}"))).collect(),
        })
        .collect()
}

/// Write the views of the mean Stokes images (I, Q, U, V), in the order of [`outputs`].
fn save_views(
    out: &Path,
    views: &[PolView],
    (w, h): (u32, u32),
    layers: &[Vec<Vec3>],
) -> Result<()> {
    let px: Vec<[Vec3; 4]> = (0..layers[0].len())
        .map(|i| std::array::from_fn(|k| layers[k][i]))
        .collect();
    let images: Vec<Vec<Vec3>> = views
        .iter()
        .flat_map(|v| match v {
            PolView::Dop => {
                let grey = view::dop_values(&px).into_iter().map(Vec3::splat).collect();
                vec![view::dop_image(&px), grey]
            }
            PolView::Aop => vec![view::aop_image(&px)],
            PolView::Stokes => layers.to_vec(),
        })
        .collect();
    for (path, img) in outputs(out, views).into_iter().zip(images) {
        film::save_image(&path, w, h, &img, 0.0, ToneMap::Clamp)?;
        eprintln!("wrote {}", path.display());
    }
    Ok(())
}
