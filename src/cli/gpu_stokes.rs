//! `render --device gpu --polarizer DEG --aov dop,aop,stokes`: the Stokes vector per pixel on
//! the GPU. The kernel reads one row of the Mueller chain (`cpu/polarized/chain.wgsl`), so the
//! four Stokes components come from four renders of the same samples behind four ideal
//! analysers (`GpuRenderer::set_analyzer`): horizontal H, vertical V, diagonal D (45°) and
//! right-circular R, each ½(1, ±1, 0, 0), ½(1, 0, 1, 0), ½(1, 0, 0, 1) · S. Then I = H + V,
//! Q = H − V, U = 2D − I, V = 2R − I (Collett, "Polarized Light", ch. 4, the Stokes
//! parameters as intensity measurements), exactly, sample by sample: the renders draw the
//! same random numbers. The image behind the render's own filter f is f · S.

use super::RenderArgs;
use super::gpu_render::{context, log_start, or_cpu};
use super::job::Job;
use super::progress::spp_progress_bar;
use anyhow::Result;
use glam::{Vec3, Vec4};
use refract::gpu::GpuRenderer;
use refract::render::{Device, Estimator, Polarization, RenderOptions};
use refract::scene::Scene;
use std::time::{Duration, Instant};

/// The analysers, in the order [`stokes_of`] reads them.
const ANALYZERS: [Vec4; 4] = [
    Vec4::new(0.5, 0.5, 0.0, 0.0),
    Vec4::new(0.5, -0.5, 0.0, 0.0),
    Vec4::new(0.5, 0.0, 0.5, 0.0),
    Vec4::new(0.5, 0.0, 0.0, 0.5),
];

/// A polarised GPU render's Stokes images and the beauty behind the filter.
pub(crate) struct StokesRender {
    pub(crate) size: (u32, u32),
    /// I, Q, U, V per pixel (linear RGB, the camera's frame).
    pub(crate) stokes: [Vec<Vec3>; 4],
    pub(crate) beauty: Vec<Vec3>,
    pub(crate) spp: u64,
    pub(crate) dropped: u64,
    pub(crate) elapsed: Duration,
}

/// I, Q, U, V from the four analysers' images (H, V, D, R).
fn stokes_of(m: &[Vec<Vec3>; 4]) -> [Vec<Vec3>; 4] {
    let n = m[0].len();
    let i: Vec<Vec3> = (0..n).map(|p| m[0][p] + m[1][p]).collect();
    let q = (0..n).map(|p| m[0][p] - m[1][p]).collect();
    let u = (0..n).map(|p| 2.0 * m[2][p] - i[p]).collect();
    let v = (0..n).map(|p| 2.0 * m[3][p] - i[p]).collect();
    [i, q, u, v]
}

/// Render the Stokes images on the GPU where `args.device` asks for it (and, for `auto`, a
/// hardware adapter exists); None: render on the CPU instead.
pub(crate) fn render_stokes(
    args: &RenderArgs,
    scene: &Scene,
    job: &Job,
    pol: Polarization,
) -> Result<Option<StokesRender>> {
    let forced = match args.device {
        Device::Cpu => return Ok(None),
        Device::Gpu => true,
        Device::Auto => false,
    };
    let Some(ctx) = context(forced)? else {
        return Ok(None);
    };
    let name = ctx.describe();
    let mut opts = RenderOptions::from_scene(scene);
    opts.max_film_bytes = job.max_film_bytes;
    opts.seed = job.seed;
    opts.estimator = Estimator::Path;
    let r = GpuRenderer::with_context_polarized(ctx, scene.clone(), opts, pol);
    let Some(mut r) = or_cpu(r, forced, "GPU renderer unavailable")? else {
        return Ok(None);
    };
    log_start(args, scene, job, &r, &name);
    let started = Instant::now();
    // The first analyser spends a quarter of the budget; the others render as many samples.
    let (mut n, mut budget) = (job.spp.unwrap_or(u32::MAX), args.time_budget.map(|b| b / 4));
    let bar = spp_progress_bar(job.spp, args.quiet);
    let mut images = Vec::with_capacity(4);
    let mut dropped = 0;
    for row in ANALYZERS {
        r.set_analyzer(Some(row))?;
        let img = r.render_with(n, budget, |d| bar.set_position(d));
        let Some(img) = or_cpu(img, forced, "GPU render failed")? else {
            return Ok(None);
        };
        (n, budget) = (img.spp.min(u64::from(u32::MAX)) as u32, None);
        dropped = img.dropped;
        images.push(img.mean);
    }
    bar.finish_and_clear();
    let m: [Vec<Vec3>; 4] = images.try_into().expect("four analysers");
    let stokes = stokes_of(&m);
    let f = pol.filter_row();
    let beauty = (0..stokes[0].len())
        .map(|p| {
            let s = [stokes[0][p], stokes[1][p], stokes[2][p], stokes[3][p]];
            (s[0] * f.x + s[1] * f.y + s[2] * f.z + s[3] * f.w).max(Vec3::ZERO)
        })
        .collect();
    let s = &scene.settings;
    Ok(Some(StokesRender {
        size: (s.width, s.height),
        stokes,
        beauty,
        spp: u64::from(n),
        dropped,
        elapsed: started.elapsed(),
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The analysers read H, V, D, R of a Stokes vector; `stokes_of` gives it back.
    #[test]
    fn four_analysers_give_back_the_stokes_vector() {
        let s = Vec4::new(1.0, 0.3, -0.4, 0.2);
        let read = ANALYZERS.map(|a| vec![Vec3::splat(a.dot(s))]);
        let got = stokes_of(&read);
        for (k, want) in s.to_array().into_iter().enumerate() {
            assert!((got[k][0].x - want).abs() < 1e-6, "{k}: {}", got[k][0].x);
        }
    }
}
