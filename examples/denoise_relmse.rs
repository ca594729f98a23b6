//! The denoiser's benchmark (issue 36 item 3): relMSE against a long reference of the raw
//! and denoised images at several spp, on the CPU path tracer.
//! `cargo run --release --example denoise_relmse -- [SCENE] [SIZE] [REF_SPP]`
//! (defaults builtin:cornell-glass 128 4096). The reference is cached in `target/` by
//! scene, size and spp; the denoised and raw 16-spp images are written there as PNGs.
use anyhow::Context;
use glam::Vec3;
use refract::bench::rel_mse;
use refract::cpu::Renderer;
use refract::denoise::{DenoiseParams, denoise, half_variance, render_guides};
use refract::film::{ToneMap, load_exr, save_image};
use refract::render::{Estimator, RenderOptions};
use refract::scene::Scene;
use std::path::PathBuf;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let spec = args.first().map_or("builtin:cornell-glass", |s| s.as_str());
    let size: u32 = args.get(1).map_or(Ok(128), |s| s.parse()).context("SIZE")?;
    let ref_spp: u32 = args
        .get(2)
        .map_or(Ok(4096), |s| s.parse())
        .context("REF_SPP")?;
    let renderer = Renderer::new(Scene::load(spec)?)?;
    let mut opts = RenderOptions::from_scene(&renderer.scene);
    (opts.width, opts.height, opts.estimator) = (size, size, Estimator::Path);
    // `DENOISE_SEED`: the seed of the measured renders (the reference's is its own).
    opts.seed = std::env::var("DENOISE_SEED")
        .map_or(Ok(1), |s| s.parse())
        .context("DENOISE_SEED")?;
    let reference = reference(&renderer, &opts, spec, ref_spp)?;
    let mut params = DenoiseParams::default();
    if let Ok(v) = std::env::var("DENOISE_PARAMS") {
        // Tuning: "iterations,sigma_l,sigma_n,sigma_z".
        let f: Vec<f32> = v.split(',').map(str::parse).collect::<Result<_, _>>()?;
        anyhow::ensure!(
            f.len() == 4,
            "DENOISE_PARAMS: iterations,sigma_l,sigma_n,sigma_z"
        );
        params = DenoiseParams {
            iterations: f[0] as u32,
            sigma_l: f[1],
            sigma_n: f[2],
            sigma_z: f[3],
        };
    }
    println!(
        "scene {spec}, {size}², seed {}, reference {ref_spp} spp (path), {params:?}",
        opts.seed
    );
    println!("| spp | raw relMSE | denoised relMSE | guide spp |");
    println!("|----:|-----------:|----------------:|----------:|");
    for spp in [4u32, 16, 64, 256] {
        // Two halves of the same samples: the film is that of one render of `spp`.
        let mut film = refract::film::Film::new(size, size);
        renderer.render_pass(&opts, &mut film, 0, spp / 2);
        let first = film.image();
        renderer.render_pass(&opts, &mut film, spp / 2, spp - spp / 2);
        let raw = film.image();
        let var = half_variance(&first, &raw, (spp / 2) as u64, spp as u64);
        let guide_spp = spp.min(16);
        let guides = render_guides(&renderer, (size, size), guide_spp, opts.seed);
        let den = denoise(&raw, Some(&var), &guides, &params);
        let (r, d) = (rel_mse(&raw, &reference), rel_mse(&den, &reference));
        println!("| {spp} | {r:.4} | {d:.4} | {guide_spp} |");
        if spp == 16 {
            let out = PathBuf::from("target/denoise-example");
            save(&out.join("raw16.png"), size, &raw)?;
            save(&out.join("denoised16.png"), size, &den)?;
            save(&out.join("reference.png"), size, &reference)?;
        }
    }
    Ok(())
}

/// The cached reference (rendered and written on the first run).
fn reference(
    r: &Renderer,
    opts: &RenderOptions,
    spec: &str,
    spp: u32,
) -> anyhow::Result<Vec<Vec3>> {
    let name = spec.replace([':', '/', '.'], "_");
    let path = PathBuf::from(format!(
        "target/denoise-ref-{name}-{}-{spp}.exr",
        opts.width
    ));
    if let Ok((w, h, img)) = load_exr(&path) {
        anyhow::ensure!(
            (w, h) == (opts.width, opts.height),
            "stale {}",
            path.display()
        );
        return Ok(img);
    }
    let mut o = *opts;
    o.seed = 0xdead;
    eprintln!("rendering the reference ({spp} spp) to {}", path.display());
    let (film, _) = r.render(&o, spp, None, |_| {});
    let img = film.image();
    save_image(&path, o.width, o.height, &img, 0.0, ToneMap::default())?;
    Ok(img)
}

fn save(path: &std::path::Path, size: u32, img: &[Vec3]) -> anyhow::Result<()> {
    save_image(path, size, size, img, 0.0, ToneMap::default())
}
