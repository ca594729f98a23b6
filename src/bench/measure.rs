//! Measured runs: which estimators a device runs for a scene, and their error-vs-time
//! curves on the CPU and the GPU.

use super::metrics::{mean_luminance, rel_mse, rmse, time_to};
use super::reference::reference;
use super::{BenchOptions, BenchPoint, BenchSummary, RUN_SEED};
use crate::cpu::Renderer;
use crate::film::Film;
use crate::render::{Estimator, EstimatorPlan, RenderOptions, Runner};
use crate::scene::Scene;
use anyhow::Result;
use glam::Vec3;
use std::time::Instant;

/// One scene restricted to one Heckbert class (`None` = all paths): reference, then every
/// estimator on every requested device.
pub(super) fn bench_class(
    r: &Renderer,
    uniform: Option<&Renderer>,
    spec: &str,
    o: &BenchOptions,
    class: Option<&str>,
) -> Result<(Vec<BenchPoint>, Vec<BenchSummary>)> {
    let (opts, filter) = class_options(r, class)?;
    let label = class.unwrap_or("all");
    if class.is_some() {
        eprintln!("  path class {label}");
    }
    // `auto` means the estimator the scene's features pick.
    let mut ro = o.clone();
    ro.ref_estimator = ro.ref_estimator.resolve(&r.scene);
    let o = &ro;
    let (a, b) = reference(r, spec, &opts, o)?;
    let reference: Vec<Vec3> = a.iter().zip(&b).map(|(x, y)| 0.5 * (*x + *y)).collect();
    let target = Target {
        spec,
        class: label,
        o,
        reference: &reference,
        // Var(A − B) = 2σ² while the averaged reference has σ²/2: its own relMSE ≈ relMSE(A,B)/4.
        ref_noise: rel_mse(&a, &b) / 4.0,
    };
    let mut out = Measured::default();
    out.gpu_runs(&r.scene, filter.as_ref(), &target);
    out.cpu_runs(r, uniform, opts, &target);
    Ok((out.points, out.sums))
}

/// The scene's render options restricted to `class` (a `--paths` expression; `None` = all
/// paths), and the parsed filter.
fn class_options(
    r: &Renderer,
    class: Option<&str>,
) -> Result<(RenderOptions, Option<crate::paths::PathFilter>)> {
    let mut opts = RenderOptions::from_scene(&r.scene);
    let filter = class
        .map(crate::paths::PathFilter::parse)
        .transpose()
        .map_err(|e| anyhow::anyhow!("--paths: {e}"))?;
    opts.set_filter(filter.as_ref());
    Ok((opts, filter))
}

/// The curve points and summary rows of one scene and path class, in measuring order.
#[derive(Default)]
struct Measured {
    points: Vec<BenchPoint>,
    sums: Vec<BenchSummary>,
}

impl Measured {
    /// Add one run's curve and summary.
    fn keep(&mut self, (p, s): (Vec<BenchPoint>, BenchSummary)) {
        self.points.extend(p);
        self.sums.push(s);
    }

    /// Measure every requested GPU run (when `--gpu`) on `scene` with `filter`; a run the
    /// GPU cannot do is skipped with a note.
    fn gpu_runs(
        &mut self,
        scene: &Scene,
        filter: Option<&crate::paths::PathFilter>,
        target: &Target,
    ) {
        let (o, spec) = (target.o, target.spec);
        let gpu_runs = if o.gpu {
            runs(&o.estimators, scene, true)
        } else {
            Vec::new()
        };
        for run in &gpu_runs {
            match measure_gpu(scene, filter, run, target) {
                Ok(m) => self.keep(m),
                Err(e) => eprintln!("  GPU {} skipped on {spec}: {e:#}", run.label()),
            }
        }
    }

    /// Measure every requested CPU run (when `--cpu`) with `r`, then the same runs with the
    /// environment image sampled uniformly (`uniform`; same reference).
    fn cpu_runs(
        &mut self,
        r: &Renderer,
        uniform: Option<&Renderer>,
        opts: RenderOptions,
        target: &Target,
    ) {
        let o = target.o;
        let cpu_runs = if o.cpu {
            runs(&o.estimators, &r.scene, false)
        } else {
            Vec::new()
        };
        for run in &cpu_runs {
            eprintln!("  measuring {} …", run.label());
            self.keep(measure(r, opts, run, target, ""));
        }
        // The same runs with the environment image sampled uniformly (same reference).
        for run in cpu_runs.iter().filter(|_| uniform.is_some()) {
            let Some(u) = uniform else { break };
            eprintln!(
                "  measuring {} with a uniformly sampled environment …",
                run.label()
            );
            self.keep(measure(u, opts, run, target, " env uniform"));
        }
    }
}

/// What every run of one scene and path class is measured against.
struct Target<'a> {
    spec: &'a str,
    /// The Heckbert class (`all` without a filter).
    class: &'a str,
    o: &'a BenchOptions,
    /// The reference image (mean of its two halves) and its own relMSE.
    reference: &'a [Vec3],
    ref_noise: f64,
}

impl Target<'_> {
    /// The curve's point after `spp` samples per pixel in `seconds`, for `img`.
    fn point(&self, run: (&str, &str), spp: u64, seconds: f64, img: &[Vec3]) -> BenchPoint {
        let (device, estimator) = run;
        let pixels = img.len() as f64;
        BenchPoint {
            scene: self.spec.to_string(),
            paths: self.class.to_string(),
            device: device.to_string(),
            estimator: estimator.to_string(),
            spp,
            seconds,
            samples_per_sec: spp as f64 * pixels / seconds.max(1e-9),
            rel_mse: rel_mse(img, self.reference),
            rmse: rmse(img, self.reference),
            lum_ratio: mean_luminance(img) / mean_luminance(self.reference).max(1e-12),
        }
    }

    /// The run's summary row from its curve.
    fn summary(&self, run: (&str, &str), points: &[BenchPoint]) -> BenchSummary {
        let (device, estimator) = run;
        BenchSummary {
            scene: self.spec.to_string(),
            paths: self.class.to_string(),
            device: device.to_string(),
            estimator: estimator.to_string(),
            samples_per_sec: points.last().map(|p| p.samples_per_sec).unwrap_or(0.0),
            t_rel_01: time_to(points, 0.01),
            t_rel_001: time_to(points, 0.001),
            ref_noise: self.ref_noise,
            ref_spp: self.o.ref_spp,
        }
    }
}

/// One measured run: the estimator the device runs, asked for by name, by `auto`, or both
/// (then measured once).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Run {
    pub estimator: Estimator,
    pub by_name: bool,
    pub by_auto: bool,
}

impl Run {
    /// The run's label: the estimator's name; "auto = X" for `auto` alone, "X = auto" when X is
    /// also asked for by name.
    pub fn label(&self) -> String {
        let e = self.estimator;
        match (self.by_name, self.by_auto) {
            (true, true) => format!("{e} = auto"),
            (false, true) => format!("auto = {e}"),
            _ => e.to_string(),
        }
    }
}

/// The runs of `asked` on the GPU (`gpu`) or the CPU for `scene`: `auto` resolved by the
/// scene's features as `render` does (on the CPU its lt+pt is rendered by bdpt, the superset);
/// estimators the device lacks skipped with a note (bdpt and lt on the GPU, lt+pt by name on
/// the CPU, whose bdpt covers it).
pub fn runs(asked: &[Estimator], scene: &Scene, gpu: bool) -> Vec<Run> {
    let mut runs: Vec<Run> = Vec::new();
    for &e in asked {
        let auto = e == Estimator::Auto;
        let runner = if gpu { Runner::Gpu } else { Runner::Cpu };
        let plan = EstimatorPlan::decide(e, scene, runner);
        if !plan.exact {
            // A benchmark measures what was asked: the GPU's lt+pt stand-in is its own run.
            eprintln!("  GPU: estimator {e} runs on the CPU only, skipped");
            continue;
        }
        let e = match (plan.runs, gpu) {
            (Estimator::LtPt, false) if auto => Estimator::Bdpt,
            (Estimator::LtPt, false) => {
                eprintln!(
                    "  CPU: lt+pt is the GPU estimator (the CPU's bdpt is its superset), skipped"
                );
                continue;
            }
            (e, _) => e,
        };
        let i = match runs.iter().position(|r| r.estimator == e) {
            Some(i) => i,
            None => {
                runs.push(Run {
                    estimator: e,
                    by_name: false,
                    by_auto: false,
                });
                runs.len() - 1
            }
        };
        runs[i].by_auto |= auto;
        runs[i].by_name |= !auto;
    }
    runs
}

/// A GPU estimator's curve: batches up to each power of two, image read back at each point
/// (the readback time is included in the wall time).
fn measure_gpu(
    scene: &Scene,
    filter: Option<&crate::paths::PathFilter>,
    run: &Run,
    t: &Target,
) -> Result<(Vec<BenchPoint>, BenchSummary)> {
    let mut go = RenderOptions::from_scene(scene);
    go.seed = RUN_SEED;
    let mut r = crate::gpu::GpuRenderer::new(scene.clone(), go)?;
    r.set_filter(filter);
    r.set_estimator(run.estimator)?;
    let device = format!("gpu ({})", r.adapter_info().name);
    let name = run.label();
    eprintln!("  measuring {name} on {device} …");
    let mut points = Vec::new();
    let start = Instant::now();
    let (mut done, mut next) = (0u64, 1u64);
    while start.elapsed() < t.o.budget || done < 1 {
        let img = r.render((next - done) as u32)?;
        done = next;
        let secs = start.elapsed().as_secs_f64();
        points.push(t.point((&device, &name), done, secs, &img.mean));
        next *= 2;
        if done >= 1 << 20 {
            break;
        }
    }
    let summary = t.summary((&device, &name), &points);
    Ok((points, summary))
}

/// A CPU estimator's curve: passes up to each power of two of spp, `suffix` appended to the
/// estimator's label.
fn measure(
    r: &Renderer,
    mut opts: RenderOptions,
    run: &Run,
    t: &Target,
    suffix: &str,
) -> (Vec<BenchPoint>, BenchSummary) {
    let estimator = format!("{}{suffix}", run.label());
    opts.estimator = run.estimator;
    opts.seed = RUN_SEED;
    let mut film = Film::new(opts.width, opts.height);
    let mut points = Vec::new();
    let start = Instant::now();
    let mut next_record = 1u64;
    let mut done = 0u64;
    while start.elapsed() < t.o.budget || done < 1 {
        let n = (next_record - done) as u32;
        r.render_pass(&opts, &mut film, done as u32, n);
        done = next_record;
        let secs = start.elapsed().as_secs_f64();
        points.push(t.point(("cpu", &estimator), done, secs, &film.image()));
        next_record *= 2;
        if done >= 1 << 20 {
            break;
        }
    }
    let summary = t.summary(("cpu", &estimator), &points);
    (points, summary)
}
