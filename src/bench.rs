//! `refract bench`: run time against error. For each scene and each requested Heckbert path
//! class a high-spp reference is rendered once (two independent halves, cached by scene hash,
//! path filter and renderer version), then the renderer runs progressively and records wall
//! time, samples/s and error at powers-of-two spp.
//! Error metrics: relative MSE mean((x − ref)² / (ref² + 1e-2)) over pixels and channels,
//! RMSE, and the luminance ratio; the halves' disagreement gives the reference's noise floor.

use crate::cpu::Renderer;
use crate::film::{self, Film};
use crate::render::{Estimator, RenderOptions};
use crate::scene::Scene;
use anyhow::{Context, Result};
use glam::Vec3;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

mod plot;
mod quick;

pub use plot::plot;
pub use quick::quick;

/// Bump when a change alters rendered images (invalidates cached references).
pub const RENDERER_VERSION: u32 = 1;

/// Seeds of the reference halves and of the measured runs (all different streams).
const REF_SEEDS: [u32; 2] = [0x5eed_0001, 0x5eed_0002];
const RUN_SEED: u32 = 0x0bad_cafe;

#[derive(Clone, Debug)]
pub struct BenchOptions {
    pub scenes: Vec<String>,
    /// Budgets and URI permission of the glTF scenes.
    pub limits: crate::scene::gltf_load::LoadLimits,
    /// Time budget of the measured run per scene and device.
    pub budget: Duration,
    pub out: PathBuf,
    pub width: u32,
    pub height: u32,
    /// Samples per pixel of the reference (split over two halves).
    pub ref_spp: u32,
    pub cache_dir: PathBuf,
    /// Estimators to measure (each against the same reference); `auto` is resolved per scene
    /// and device ([`runs`]).
    pub estimators: Vec<Estimator>,
    /// Estimator of the reference (bdpt converges far faster on caustics).
    pub ref_estimator: Estimator,
    /// Measure the CPU renderer (every estimator).
    pub cpu: bool,
    /// Measure the GPU renderer (path and lt+pt; skipped with a message if no adapter).
    pub gpu: bool,
    /// Heckbert path classes, each measured on its own (its own reference and runs), e.g.
    /// `LS+DE` for the caustic alone and `LS+DS+E` for its mirror image; empty = one run on
    /// all paths.
    pub paths: Vec<String>,
    /// Also measure every CPU estimator with the environment image sampled uniformly on the
    /// sphere instead of by importance (labelled "… env uniform"; scenes with an image only).
    pub env_uniform: bool,
}

/// One point of an error-vs-time curve.
#[derive(Clone, Debug)]
pub struct BenchPoint {
    pub scene: String,
    /// The Heckbert class measured (`all` without a filter).
    pub paths: String,
    pub device: String,
    pub estimator: String,
    pub spp: u64,
    pub seconds: f64,
    pub samples_per_sec: f64,
    pub rel_mse: f64,
    pub rmse: f64,
    pub lum_ratio: f64,
}

/// Per-scene summary for the Markdown table.
#[derive(Clone, Debug)]
pub struct BenchSummary {
    pub scene: String,
    pub paths: String,
    pub device: String,
    pub estimator: String,
    pub samples_per_sec: f64,
    pub t_rel_01: Option<f64>,
    pub t_rel_001: Option<f64>,
    pub ref_noise: f64,
    pub ref_spp: u32,
}

/// Relative MSE: mean over pixels and channels of (x − ref)² / (ref² + 1e-2).
pub fn rel_mse(x: &[Vec3], reference: &[Vec3]) -> f64 {
    let mut s = 0.0f64;
    for (a, r) in x.iter().zip(reference) {
        for k in 0..3 {
            let (a, r) = (a[k] as f64, r[k] as f64);
            s += (a - r) * (a - r) / (r * r + 1e-2);
        }
    }
    s / (3 * x.len().max(1)) as f64
}

/// Root mean squared error over pixels and channels.
pub fn rmse(x: &[Vec3], reference: &[Vec3]) -> f64 {
    let mut s = 0.0f64;
    for (a, r) in x.iter().zip(reference) {
        s += (*a - *r).as_dvec3().length_squared();
    }
    (s / (3 * x.len().max(1)) as f64).sqrt()
}

fn mean_luminance(x: &[Vec3]) -> f64 {
    x.iter()
        .map(|p| crate::math::color::luminance(*p) as f64)
        .sum::<f64>()
        / x.len().max(1) as f64
}

/// FNV-1a 64-bit hash (stable across runs, unlike std's SipHash keys).
fn fnv1a(bytes: &[u8], mut h: u64) -> u64 {
    for b in bytes {
        h ^= *b as u64;
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

fn scene_hash(spec: &str, opts: &RenderOptions, ref_spp: u32) -> u64 {
    let mut h = fnv1a(spec.as_bytes(), 0xcbf2_9ce4_8422_2325);
    if !spec.starts_with("builtin:")
        && let Ok(bytes) = std::fs::read(spec)
    {
        h = fnv1a(&bytes, h);
    }
    let filter = opts
        .filter
        .as_ref()
        .map(|f| format!("{:x}", fnv1a(bytemuck::cast_slice(&f.words()), 0)))
        .unwrap_or_default();
    let meta = format!(
        "{}x{} d{} rr{} spp{} v{} {:?} paths[{filter}]",
        opts.width,
        opts.height,
        opts.max_depth,
        opts.rr_depth,
        ref_spp,
        RENDERER_VERSION,
        opts.estimator
    );
    fnv1a(meta.as_bytes(), h)
}

/// Render (or load from the cache) the two reference halves.
fn reference(
    r: &Renderer,
    spec: &str,
    opts: &RenderOptions,
    o: &BenchOptions,
) -> Result<(Vec<Vec3>, Vec<Vec3>)> {
    let mut keyed = *opts;
    keyed.estimator = o.ref_estimator;
    let h = scene_hash(spec, &keyed, o.ref_spp);
    std::fs::create_dir_all(&o.cache_dir)
        .with_context(|| format!("cannot create cache folder '{}'", o.cache_dir.display()))?;
    let paths: Vec<PathBuf> = (0..2)
        .map(|i| o.cache_dir.join(format!("ref-{h:016x}-{i}.exr")))
        .collect();
    let mut halves = Vec::new();
    for (i, p) in paths.iter().enumerate() {
        if let Ok((w, hh, img)) = film::load_exr(p)
            && w == opts.width
            && hh == opts.height
        {
            halves.push(img);
            continue;
        }
        let mut ro = *opts;
        ro.seed = REF_SEEDS[i];
        ro.estimator = o.ref_estimator;
        eprintln!(
            "  reference half {} of {spec}: {} spp at {}x{} …",
            i + 1,
            o.ref_spp / 2,
            opts.width,
            opts.height
        );
        let (f, _) = r.render(&ro, (o.ref_spp / 2).max(1), None, |_| {});
        let img = f.image();
        film::save_image(p, opts.width, opts.height, &img, 0.0, film::ToneMap::Clamp)?;
        halves.push(img);
    }
    let b = halves.pop().unwrap_or_default();
    let a = halves.pop().unwrap_or_default();
    Ok((a, b))
}

/// Run the benchmark for one scene, every requested path class, device and estimator.
pub fn bench_scene_cpu(
    spec: &str,
    o: &BenchOptions,
) -> Result<(Vec<BenchPoint>, Vec<BenchSummary>)> {
    let mut scene = Scene::load_with(spec, &o.limits)?;
    anyhow::ensure!(
        scene.has_light(),
        "scene '{spec}' has no light (no emissive triangle, punctual light or environment): \
         every image is black, there is no error to measure"
    );
    scene.settings.width = o.width;
    scene.settings.height = o.height;
    let uniform = match &scene.env_map {
        Some(e) if o.env_uniform => {
            let mut u = scene.clone();
            u.env_map = Some(crate::scene::env_map::EnvImage {
                importance: false,
                ..e.clone()
            });
            Some(Renderer::new(u)?)
        }
        _ => None,
    };
    let r = Renderer::new(scene)?;
    let classes: Vec<Option<&str>> = if o.paths.is_empty() {
        vec![None]
    } else {
        o.paths.iter().map(|p| Some(p.as_str())).collect()
    };
    let (mut points, mut sums) = (Vec::new(), Vec::new());
    for class in classes {
        let (p, s) = bench_class(&r, uniform.as_ref(), spec, o, class)?;
        points.extend(p);
        sums.extend(s);
    }
    Ok((points, sums))
}

/// One scene restricted to one Heckbert class (`None` = all paths): reference, then every
/// estimator on every requested device.
fn bench_class(
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
        let resolved = if gpu {
            e.resolve_gpu_why(scene).0
        } else {
            e.resolve(scene)
        };
        let e = match (resolved, gpu) {
            (Estimator::LtPt, false) if auto => Estimator::Bdpt,
            (e @ (Estimator::Bdpt | Estimator::Lt), true) => {
                eprintln!("  GPU: estimator {e} runs on the CPU only, skipped");
                continue;
            }
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

/// Time at which the curve first reaches `target` (log-log interpolation between points).
pub fn time_to(points: &[BenchPoint], target: f64) -> Option<f64> {
    for w in points.windows(2) {
        let (p, q) = (&w[0], &w[1]);
        if p.rel_mse <= target {
            return Some(p.seconds);
        }
        if q.rel_mse <= target && p.rel_mse > 0.0 && q.rel_mse > 0.0 {
            let (lt0, lt1) = (p.seconds.ln(), q.seconds.ln());
            let (le0, le1) = (p.rel_mse.ln(), q.rel_mse.ln());
            let f = (target.ln() - le0) / (le1 - le0);
            return Some((lt0 + f * (lt1 - lt0)).exp());
        }
    }
    match points {
        [p] if p.rel_mse <= target => Some(p.seconds),
        _ => None,
    }
}

pub fn write_csv(path: &Path, points: &[BenchPoint]) -> Result<()> {
    let mut s = String::from(
        "scene,device,estimator,spp,seconds,samples_per_sec,rel_mse,rmse,lum_ratio,paths\n",
    );
    for p in points {
        writeln!(
            s,
            "{},{},{},{},{:.6},{:.1},{:.6e},{:.6e},{:.6},{}",
            csv_field(&p.scene),
            csv_field(&p.device),
            csv_field(&p.estimator),
            p.spp,
            p.seconds,
            p.samples_per_sec,
            p.rel_mse,
            p.rmse,
            p.lum_ratio,
            csv_field(&p.paths)
        )?;
    }
    std::fs::write(path, s).with_context(|| format!("cannot write '{}'", path.display()))
}

/// A CSV field, quoted when it holds a comma, quote or newline (RFC 4180), e.g. a GPU name
/// such as "llvmpipe (LLVM 15.0.6, 256 bits)".
fn csv_field(x: &str) -> String {
    if x.contains([',', '"', '\n']) {
        format!("\"{}\"", x.replace('"', "\"\""))
    } else {
        x.to_string()
    }
}

pub fn markdown_table(summaries: &[BenchSummary]) -> String {
    let fmt_t = |t: Option<f64>| t.map_or("not reached".to_string(), |t| format!("{t:.2} s"));
    let mut s = String::from(
        "| scene | device | estimator | paths | M samples/s | time to relMSE 0.01 | time to relMSE 0.001 | reference noise (relMSE, spp) |\n|---|---|---|---|---|---|---|---|\n",
    );
    for m in summaries {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {:.3} | {} | {} | {:.1e} ({} spp) |",
            m.scene,
            m.device,
            m.estimator,
            m.paths,
            m.samples_per_sec / 1e6,
            fmt_t(m.t_rel_01),
            fmt_t(m.t_rel_001),
            m.ref_noise,
            m.ref_spp
        );
    }
    s
}

/// Run everything and write `bench.csv`, `bench.png` and `bench.md` into `o.out`.
pub fn run(o: &BenchOptions) -> Result<String> {
    std::fs::create_dir_all(&o.out)
        .with_context(|| format!("cannot create '{}'", o.out.display()))?;
    let mut all = Vec::new();
    let mut sums = Vec::new();
    for spec in &o.scenes {
        eprintln!("bench {spec} …");
        let (pts, sum) = bench_scene_cpu(spec, o)?;
        all.extend(pts);
        sums.extend(sum);
    }
    write_csv(&o.out.join("bench.csv"), &all)?;
    plot(&o.out.join("bench.png"), &all)?;
    let table = markdown_table(&sums);
    std::fs::write(o.out.join("bench.md"), &table)
        .with_context(|| format!("cannot write '{}'", o.out.join("bench.md").display()))?;
    Ok(table)
}
