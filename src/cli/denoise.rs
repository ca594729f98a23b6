//! `render --denoise`: the denoised image beside the unbiased one (`OUT.denoised.exr`, and
//! `OUT.denoised.png` for a PNG output). The unbiased image is written first and untouched;
//! the guides come from their own camera rays (`denoise::render_guides`). A GPU render is
//! filtered on its device (`denoise::gpu::GpuDenoiser`, the WGSL twin), a CPU render on the
//! CPU.

use super::RenderArgs;
use super::job::Job;
use anyhow::{Context, Result};
use glam::Vec3;
use refract::cpu::Renderer;
use refract::denoise::gpu::GpuDenoiser;
use refract::denoise::{DenoiseParams, denoise, half_variance, render_guides};
use refract::film::{check_output_path, save_image};
use refract::gpu::GpuContext;
use refract::scene::Scene;
use std::path::{Path, PathBuf};

/// Guide samples per pixel (the guides converge long before the image does).
const GUIDE_SPP: u32 = 16;

/// The files `--denoise` writes for the output `out`: `STEM.denoised.exr`, and
/// `STEM.denoised.png` when `out` is a PNG.
pub(crate) fn denoised_paths(out: &Path) -> Vec<PathBuf> {
    let png = out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    let mut paths = vec![out.with_extension("denoised.exr")];
    if png {
        paths.push(out.with_extension("denoised.png"));
    }
    paths
}

/// Before any work: `--denoise` with a shard is refused (a shard is a part of an image, the
/// denoiser wants the whole), and its outputs must be writable.
pub(crate) fn check(args: &RenderArgs) -> Result<()> {
    if !args.denoise {
        return Ok(());
    }
    anyhow::ensure!(
        args.shard.is_none(),
        "--denoise cannot be used with --shard: denoise the merged image's render instead"
    );
    for p in denoised_paths(&args.out) {
        check_output_path(&p).context("--denoise")?;
    }
    Ok(())
}

/// The mean image, and how the denoiser knows its noise: the mean of the first `k` samples
/// (the two-halves variance) or nothing (then it estimates it from the neighbourhood).
pub(crate) struct Rendered<'a> {
    pub(crate) size: (u32, u32),
    pub(crate) mean: &'a [Vec3],
    pub(crate) spp: u64,
    pub(crate) half: Option<(&'a [Vec3], u64)>,
}

/// [`write`] for a GPU render: a CPU renderer is built for the guides, and the filter runs
/// on the render's device `ctx` (the CPU twin, with a note, if it cannot).
pub(crate) fn write_for_scene(
    args: &RenderArgs,
    scene: &Scene,
    job: &Job,
    img: Rendered,
    ctx: &GpuContext,
) -> Result<()> {
    if !args.denoise {
        return Ok(());
    }
    write_on(args, &Renderer::new(scene.clone())?, job, img, Some(ctx))
}

/// Denoise `img` and write it beside `args.out` (nothing when `--denoise` is off).
/// `renderer`: the scene on the CPU (the guide rays are traced there).
pub(crate) fn write(
    args: &RenderArgs,
    renderer: &Renderer,
    job: &Job,
    img: Rendered,
) -> Result<()> {
    write_on(args, renderer, job, img, None)
}

/// [`write`], filtering on `ctx` when given.
fn write_on(
    args: &RenderArgs,
    renderer: &Renderer,
    job: &Job,
    img: Rendered,
    ctx: Option<&GpuContext>,
) -> Result<()> {
    if !args.denoise {
        return Ok(());
    }
    let started = std::time::Instant::now();
    let (w, h) = img.size;
    let guides = render_guides(renderer, (w, h), GUIDE_SPP, job.seed);
    let variance = img
        .half
        .map(|(first, k)| half_variance(first, img.mean, k, img.spp));
    let params = DenoiseParams::default();
    let on_gpu = ctx.and_then(|ctx| {
        GpuDenoiser::new(ctx)
            .and_then(|d| d.denoise(ctx, img.mean, variance.as_deref(), &guides, &params))
            .map_err(|e| eprintln!("the GPU filter failed ({e:#}); filtering on the CPU"))
            .ok()
    });
    let device = if on_gpu.is_some() {
        "GPU (WGSL)"
    } else {
        "CPU"
    };
    let out = on_gpu.unwrap_or_else(|| denoise(img.mean, variance.as_deref(), &guides, &params));
    for p in denoised_paths(&args.out) {
        save_image(&p, w, h, &out, job.exposure, job.tone)?;
        eprintln!("wrote {} (denoised)", p.display());
    }
    let how = if variance.is_some() {
        "variance from two halves of the samples"
    } else {
        "variance estimated from each pixel's neighbourhood"
    };
    eprintln!(
        "denoised on the {device} in {:.2} s ({how})",
        started.elapsed().as_secs_f64()
    );
    Ok(())
}
