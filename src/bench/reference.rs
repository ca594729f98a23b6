//! The reference image: two independent halves, cached by a stable hash of the scene,
//! the options and the renderer version.

use super::{BenchOptions, REF_SEEDS, RENDERER_VERSION};
use crate::cpu::Renderer;
use crate::film::{self};
use crate::render::RenderOptions;
use anyhow::{Context, Result};
use glam::Vec3;
use std::path::PathBuf;

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
pub(super) fn reference(
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
