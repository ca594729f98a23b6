//! `refract bench`: run time against error. For each scene and each requested Heckbert path
//! class a high-spp reference is rendered once (two independent halves, cached by scene hash,
//! path filter and renderer version), then the renderer runs progressively and records wall
//! time, samples/s and error at powers-of-two spp.
//! Error metrics: relative MSE mean((x − ref)² / (ref² + 1e-2)) over pixels and channels,
//! RMSE, and the luminance ratio; the halves' disagreement gives the reference's noise floor.

use crate::cpu::Renderer;
use crate::render::Estimator;
use crate::scene::Scene;
use anyhow::{Context, Result};
use std::path::PathBuf;
use std::time::Duration;

mod measure;
mod metrics;
mod plot;
mod quick;
mod reference;
mod report;

use measure::bench_class;

pub use measure::{Run, runs};
pub use metrics::{rel_mse, rmse, time_to};
pub use report::{markdown_table, write_csv};

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
    pub limits: crate::gltf_io::load::LoadLimits,
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
