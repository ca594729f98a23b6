//! The denoiser (issue 36 item 3): it never writes to the accumulation film nor to the
//! unbiased EXR, it preserves what has no noise, and it brings a noisy image closer to a
//! converged one.

mod common_scenes;
use common_scenes::{gpu_context, wait_denoised};
use glam::Vec3;
use refract::bench::rel_mse;
use refract::cpu::Renderer;
use refract::denoise::{DenoiseParams, Guides, denoise, half_variance, render_guides};
use refract::render::{Estimator, RenderOptions};
use refract::scene::Scene;
use std::process::Command;

fn refract(args: &[&str]) -> (bool, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_refract"))
        .args(args)
        .output()
        .expect("run refract");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A fresh folder for one test's files.
fn tmp_dir(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("refract-denoise-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn render_args<'a>(out: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut a = vec![
        "render",
        "--scene",
        "builtin:cornell-glass",
        "--spp",
        "8",
        "--width",
        "48",
        "--height",
        "40",
        "--seed",
        "7",
        "--device",
        "cpu",
        "--estimator",
        "path",
        "--quiet",
        "--out",
        out,
    ];
    a.extend_from_slice(extra);
    a
}

#[test]
fn unbiased_exr_is_byte_identical_with_denoise() {
    let dir = tmp_dir("unbiased");
    let plain = dir.join("plain.exr");
    let with = dir.join("with.exr");
    let (ok, err) = refract(&render_args(plain.to_str().unwrap(), &[]));
    assert!(ok, "{err}");
    let (ok, err) = refract(&render_args(with.to_str().unwrap(), &["--denoise"]));
    assert!(ok, "{err}");
    let denoised = dir.join("with.denoised.exr");
    assert!(denoised.exists(), "no {}: {err}", denoised.display());
    let (a, b) = (
        std::fs::read(&plain).unwrap(),
        std::fs::read(&with).unwrap(),
    );
    assert!(a == b, "the unbiased EXR changed with --denoise");
    assert!(
        std::fs::read(&denoised).unwrap() != a,
        "the denoised EXR is the raw one"
    );
    assert!(!dir.join("plain.denoised.exr").exists());
}

#[test]
fn png_output_gets_a_denoised_png_and_exr() {
    let dir = tmp_dir("png");
    let out = dir.join("img.png");
    let (ok, err) = refract(&render_args(out.to_str().unwrap(), &["--denoise"]));
    assert!(ok, "{err}");
    for name in ["img.png", "img.denoised.png", "img.denoised.exr"] {
        assert!(dir.join(name).exists(), "no {name}: {err}");
    }
}

#[test]
fn denoise_with_shard_is_refused() {
    let dir = tmp_dir("shard");
    let out = dir.join("s.exr");
    let (ok, err) = refract(&render_args(
        out.to_str().unwrap(),
        &["--denoise", "--shard", "1/2"],
    ));
    assert!(!ok);
    assert!(
        err.contains("--denoise") && err.contains("--shard"),
        "{err}"
    );
}

fn small(spp_scene: &str) -> (Renderer, RenderOptions) {
    let r = Renderer::new(Scene::load(spp_scene).unwrap()).unwrap();
    let mut o = RenderOptions::from_scene(&r.scene);
    (o.width, o.height, o.estimator, o.seed) = (40, 40, Estimator::Path, 3);
    (r, o)
}

#[test]
fn render_with_half_leaves_the_film_as_render_makes_it() {
    let (r, o) = small("builtin:cornell-glass");
    let (plain, _) = r.render(&o, 6, None, |_| {});
    let (film, half, _) = r.render_with_half(&o, (6, None), |_| {});
    let (a, b) = (plain.image(), film.image());
    assert!(a.iter().zip(&b).all(|(x, y)| x.to_array() == y.to_array()));
    let (first, k) = half.expect("a half at 3 of 6 spp");
    assert_eq!(k, 3);
    assert!(first != b, "the half is the full image");
    let before = b.clone();
    let guides = render_guides(&r, (o.width, o.height), 2, o.seed);
    let var = half_variance(&first, &b, k, 6);
    let out = denoise(&b, Some(&var), &guides, &DenoiseParams::default());
    assert_eq!(before, b, "the denoiser changed its input");
    assert!(out != b);
}

#[test]
fn a_flat_image_stays_flat() {
    let (w, h) = (24u32, 20u32);
    let n = (w * h) as usize;
    let g = Guides {
        width: w,
        height: h,
        albedo: vec![Vec3::new(0.5, 0.25, 0.8); n],
        normal: vec![Vec3::Z; n],
        depth: vec![2.0; n],
        specular: vec![0.0; n],
    };
    let img = vec![Vec3::new(0.3, 0.1, 0.6); n];
    for var in [None, Some(vec![0.01f32; n])] {
        let out = denoise(&img, var.as_deref(), &g, &DenoiseParams::default());
        for (a, b) in out.iter().zip(&img) {
            assert!((*a - *b).abs().max_element() < 1e-5, "{a} vs {b}");
        }
    }
}

#[test]
fn denoising_brings_a_noisy_image_closer_to_the_converged_one() {
    let (r, o) = small("builtin:cornell-glass");
    let (reference, _) = r.render(&o, 512, None, |_| {});
    let reference = reference.image();
    let mut o8 = o;
    o8.seed = 11;
    let (film, half, _) = r.render_with_half(&o8, (8, None), |_| {});
    let raw = film.image();
    let (first, k) = half.unwrap();
    let var = half_variance(&first, &raw, k, 8);
    let guides = render_guides(&r, (o.width, o.height), 8, 5);
    let den = denoise(&raw, Some(&var), &guides, &DenoiseParams::default());
    let (e_raw, e_den) = (rel_mse(&raw, &reference), rel_mse(&den, &reference));
    assert!(
        e_den < 0.5 * e_raw,
        "denoised relMSE {e_den} vs raw {e_raw}"
    );
}

/// The WGSL filter and its CPU twin compute the same image (float tolerance), with the
/// measured variance and with the neighbourhood's.
#[test]
fn wgsl_filter_matches_the_cpu_twin() {
    let Some(ctx) = gpu_context("wgsl_filter_matches_the_cpu_twin") else {
        return;
    };
    let (r, mut o) = small("builtin:cornell-glass");
    (o.width, o.height) = (37, 29);
    let (film, half, _) = r.render_with_half(&o, (4, None), |_| {});
    let raw = film.image();
    let (first, k) = half.unwrap();
    let var = half_variance(&first, &raw, k, 4);
    let guides = render_guides(&r, (o.width, o.height), 2, 1);
    let gpu = refract::denoise::gpu::GpuDenoiser::new(&ctx).unwrap();
    let p = DenoiseParams::default();
    for v in [Some(var.as_slice()), None] {
        let cpu = denoise(&raw, v, &guides, &p);
        let dev = gpu.denoise(&ctx, &raw, v, &guides, &p).unwrap();
        let mut worst = 0.0f32;
        for (a, b) in cpu.iter().zip(&dev) {
            let err = (*a - *b).abs().max_element() / (a.abs().max_element() + 1e-2);
            worst = worst.max(err);
        }
        assert!(worst < 1e-3, "CPU and GPU differ by {worst} (relative)");
        assert!(cpu != raw, "the filter did nothing");
    }
}

/// `render --device gpu --denoise` filters on the render's device (the WGSL twin), and a CPU
/// render on the CPU; both write the denoised EXR beside the raw one.
#[test]
fn the_command_line_filters_on_the_renders_device() {
    if gpu_context("the_command_line_filters_on_the_renders_device").is_none() {
        return;
    }
    let dir = tmp_dir("device");
    for device in ["gpu", "cpu"] {
        let out = dir.join(format!("{device}.exr"));
        let mut args = render_args(out.to_str().unwrap(), &["--denoise"]);
        let at = args.iter().position(|a| *a == "--device").unwrap();
        args[at + 1] = device;
        args.retain(|a| *a != "--quiet");
        let (ok, err) = refract(&args);
        assert!(ok, "{err}");
        let want = if device == "gpu" {
            "denoised on the GPU (WGSL)"
        } else {
            "denoised on the CPU"
        };
        assert!(err.contains(want), "{device}: {err}");
        let denoised = dir.join(format!("{device}.denoised.exr"));
        assert!(
            std::fs::read(&denoised).unwrap() != std::fs::read(&out).unwrap(),
            "{device}: the denoised EXR is the raw one"
        );
    }
}

/// The viewer on the CPU backend, paused after its first samples.
fn paused_viewer() -> egui_kittest::Harness<'static, refract::app::ViewerApp> {
    common_scenes::paused_viewer(Box::new(refract::app::backend::CpuBackend::new(None)))
}

#[test]
fn the_viewer_toggle_never_touches_the_accumulation() {
    let mut h = paused_viewer();
    let raw = h.state().backend().read_image().expect("samples");
    assert!(!h.state().denoise.on, "denoising is off by default");
    h.state_mut().denoise.on = true;
    wait_denoised(&mut h);
    let during = h.state().backend().read_image().unwrap();
    h.state_mut().denoise.on = false;
    h.step();
    let after = h.state().backend().read_image().unwrap();
    let bits = |a: &refract::app::backend::Accumulated| -> Vec<[u32; 3]> {
        a.pixels
            .iter()
            .map(|p| p.to_array().map(f32::to_bits))
            .collect()
    };
    assert_eq!(
        (raw.spp, during.spp, after.spp),
        (raw.spp, raw.spp, raw.spp)
    );
    assert!(
        bits(&raw) == bits(&during),
        "the accumulation changed while denoising"
    );
    assert!(
        bits(&raw) == bits(&after),
        "the accumulation changed after toggling off"
    );
    assert!(
        !h.state().denoise.showing(h.state().backend().generation()),
        "off, the viewport still paints the denoised image"
    );
}

#[test]
fn a_denoised_screenshot_shows_the_split_and_keeps_the_raw_exr() {
    let mut h = paused_viewer();
    let dir = tmp_dir("shot");
    h.state_mut().screenshot_dir = dir.clone();
    h.state_mut().denoise.on = true;
    h.state_mut().denoise.split = 0.5;
    wait_denoised(&mut h);
    let raw = h.state().backend().read_image().unwrap();
    let saved = h.state_mut().save_screenshot().expect("screenshot");
    let (_, _, exr) = refract::film::load_exr(&saved.exr).unwrap();
    let close = exr
        .iter()
        .zip(&raw.pixels)
        .all(|(a, b)| (*a - *b).abs().max_element() <= 1e-3 * b.max_element().max(1.0));
    assert!(close, "the screenshot's EXR is not the raw accumulation");
    let denoised_exr = saved.exr.with_extension("denoised.exr");
    assert!(denoised_exr.exists(), "no {}", denoised_exr.display());
    let png = image::open(&saved.png).unwrap().to_rgba8();
    let col = refract::denoise::badge::split_column(png.width(), 0.5);
    let line = (0..png.height()).all(|y| png.get_pixel(col, y).0 == [255, 255, 255, 255]);
    assert!(line, "no split line at column {col}");
}
