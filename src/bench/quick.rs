//! `refract bench --quick`: micro-benchmarks of the CPU renderer's parts on one core and on
//! all cores — incoherent closest-hit and shadow rays/s through the BVH, BSDF sampling, and
//! path samples/s of a whole render of builtin:cornell-glass at 256² (issue 14's figures) —
//! and BDPT samples/s on builtin:caustic at 256² (issue 19's).
//! Timings, not tests: ratios measured side by side in one run are what to compare.

use crate::cpu::Renderer;
use crate::film::Film;
use crate::math::{rng::Sampler, sampling};
use crate::render::RenderOptions;
use crate::scene::Scene;
use anyhow::Result;
use glam::Vec3;
use rayon::prelude::*;
use std::fmt::Write as _;
use std::time::Instant;

/// Rays per measurement (1 M: a pass on two threads lasts ~30 ms; with 400 k, ~12 ms, a
/// scheduler hiccup on a 2-vCPU machine still showed through the median).
const RAYS: usize = 1_000_000;

/// The report for scene `spec` (its BVH) plus the cornell-glass render.
pub fn quick(spec: &str) -> Result<String> {
    let r = Renderer::new(Scene::load(spec)?)?;
    let rays = incoherent_rays(&r.scene);
    let threads = rayon::current_num_threads();
    let mut out = format!(
        "BVH ({} triangles, built in {:.1} ms), {RAYS} incoherent rays from inside the bounds:\n",
        r.scene.mesh.triangle_count(),
        r.bvh.build_time.as_secs_f64() * 1e3,
    );
    let closest = |&(o, d): &(Vec3, Vec3)| r.bvh.intersect(o, d, f32::INFINITY).is_some();
    let shadow = |&(o, d): &(Vec3, Vec3)| r.bvh.occluded(o, d, 1.0);
    for (what, f) in [
        (
            "closest-hit",
            &closest as &(dyn Fn(&(Vec3, Vec3)) -> bool + Sync),
        ),
        ("shadow", &shadow),
    ] {
        let (one, hits) = rate(|| rays.iter().filter(|x| f(x)).count());
        let (all, _) = rate(|| rays.par_iter().filter(|x| f(x)).count());
        let _ = writeln!(
            out,
            "  {what}: {:.2} M rays/s on 1 core, {:.2} M rays/s on {threads} threads ({hits} hits)",
            one / 1e6,
            all / 1e6
        );
    }
    out.push_str(&bsdf_report());
    out.push_str(&render_report()?);
    out.push_str(&bdpt_report()?);
    Ok(out)
}

/// Rays from uniform points in the middle 80% of the bounds, uniform directions.
fn incoherent_rays(scene: &Scene) -> Vec<(Vec3, Vec3)> {
    let (lo, hi) = scene.bounds();
    let mut s = Sampler::new(0, 0, 1);
    (0..RAYS)
        .map(|_| {
            let u = Vec3::new(s.next_1d(), s.next_1d(), s.next_1d());
            (
                lo + (hi - lo) * (0.1 + 0.8 * u),
                sampling::uniform_sphere(s.next_2d()),
            )
        })
        .collect()
}

/// Repetitions of each ray measurement; the median is reported.
const REPEATS: usize = 7;

/// Rays per second of `f` over [`RAYS`] rays (the median of [`REPEATS`] runs), and its result.
fn rate(f: impl Fn() -> usize) -> (f64, usize) {
    let mut n = 0;
    let r = median_of(REPEATS, || {
        let t = Instant::now();
        n = f();
        RAYS as f64 / t.elapsed().as_secs_f64()
    });
    (r, n)
}

/// The median of `runs` (odd) values of `f`.
fn median_of(runs: usize, mut f: impl FnMut() -> f64) -> f64 {
    let mut v: Vec<f64> = (0..runs).map(|_| f()).collect();
    v.sort_by(f64::total_cmp);
    v[runs / 2]
}

/// Nanoseconds per BSDF sample, one core.
fn bsdf_report() -> String {
    use crate::bsdf::{Bsdf, BxDF, Lambert, SmoothDielectric, TransportMode};
    let mut out = String::new();
    let bsdfs = [
        (
            "lambert",
            Bsdf::Lambert(Lambert::new(Vec3::splat(0.8).extend(0.0))),
        ),
        (
            "smooth dielectric",
            Bsdf::SmoothDielectric(SmoothDielectric { eta: 1.5 }),
        ),
    ];
    for (name, b) in bsdfs {
        let m = 2_000_000u32;
        let mut s = Sampler::new(1, 0, 2);
        let t = Instant::now();
        let mut acc = 0.0f32;
        for _ in 0..m {
            let wo = sampling::cosine_hemisphere(s.next_2d());
            if let Some(x) = b.sample(wo, s.next_1d(), s.next_2d(), TransportMode::Radiance) {
                acc += x.weight.x;
            }
        }
        let ns = t.elapsed().as_secs_f64() * 1e9 / m as f64;
        let _ = writeln!(
            out,
            "BSDF sample {name}: {ns:.1} ns/sample (checksum {acc:.1})"
        );
    }
    out
}

/// Path samples per second of builtin:cornell-glass at 256², depth 64, 16 spp: on one
/// thread and on all of the pool's, and which walk instance ran (`cpu::walk_spec`).
fn render_report() -> Result<String> {
    let r = Renderer::new(Scene::load("builtin:cornell-glass")?)?;
    let mut opts = RenderOptions::from_scene(&r.scene);
    (opts.width, opts.height, opts.max_depth) = (256, 256, 64);
    let spp = 16;
    let samples = f64::from(opts.width * opts.height * spp);
    let run = |film: &mut Film| {
        let t = Instant::now();
        r.render_pass(&opts, film, 0, spp);
        samples / t.elapsed().as_secs_f64()
    };
    let sp = crate::cpu::spectral::Spectral::new(r.spectral, r.line, || 0.5);
    let walk = if r.integrator(&opts).walk_features(&sp).lean() {
        "lean"
    } else {
        "general"
    };
    let all = run(&mut Film::new(opts.width, opts.height));
    let one_pool = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    let one = one_pool.install(|| run(&mut Film::new(opts.width, opts.height)));
    Ok(format!(
        "cornell-glass 256², depth 64, {spp} spp (path, {walk} walk): {:.2} M samples/s on 1 \
         thread, {:.2} M samples/s on {} threads\n",
        one / 1e6,
        all / 1e6,
        rayon::current_num_threads()
    ))
}

/// BDPT samples/s of builtin:caustic at 256², 8 spp, on all threads (issue 19's figure; the
/// median of 3 passes).
fn bdpt_report() -> Result<String> {
    let r = Renderer::new(Scene::load("builtin:caustic")?)?;
    let mut opts = RenderOptions::from_scene(&r.scene);
    (opts.width, opts.height) = (256, 256);
    opts.estimator = crate::render::Estimator::Bdpt;
    let spp = 8;
    let samples = f64::from(opts.width * opts.height * spp);
    let rate = median_of(3, || {
        let mut film = Film::new(opts.width, opts.height);
        let t = Instant::now();
        r.render_pass(&opts, &mut film, 0, spp);
        samples / t.elapsed().as_secs_f64()
    });
    Ok(format!(
        "caustic 256², {spp} spp (bdpt): {:.2} M samples/s on {} threads\n",
        rate / 1e6,
        rayon::current_num_threads()
    ))
}
