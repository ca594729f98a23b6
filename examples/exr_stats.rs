//! Compare linear EXR renders against a reference without Python: mean per channel, the
//! ratio of means, relMSE (the bench's metric) and the 8×8-block relative differences.
//!
//! `cargo run --release --example exr_stats -- REFERENCE.exr A.exr [B.exr …]`; a reference
//! written `R0.exr+R1.exr` is the mean of both (the bench's two cached halves).

use anyhow::{Context, ensure};
use glam::Vec3;
use refract::film::image_io::load_exr;
use std::path::Path;

fn mean(img: &[Vec3]) -> Vec3 {
    img.iter().copied().sum::<Vec3>() / img.len().max(1) as f32
}

/// Median and maximum over 8×8 blocks of |a − r| / (|r| + 0.02) (luminance-free, per channel).
fn block_diff(a: &[Vec3], r: &[Vec3], w: usize, h: usize) -> (f32, f32) {
    let mut rel = Vec::new();
    for by in 0..h / 8 {
        for bx in 0..w / 8 {
            let (mut sa, mut sr) = (Vec3::ZERO, Vec3::ZERO);
            for y in by * 8..by * 8 + 8 {
                for x in bx * 8..bx * 8 + 8 {
                    sa += a[y * w + x];
                    sr += r[y * w + x];
                }
            }
            let d = (sa - sr).abs() / (sr.abs() + Vec3::splat(0.02 * 64.0));
            rel.push(d.max_element());
        }
    }
    rel.sort_by(f32::total_cmp);
    let med = rel.get(rel.len() / 2).copied().unwrap_or(0.0);
    (med, rel.last().copied().unwrap_or(0.0))
}

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    ensure!(
        args.len() >= 2,
        "usage: exr_stats REFERENCE.exr A.exr [B.exr …]"
    );
    let mut halves = Vec::new();
    for part in args[0].split('+') {
        halves.push(load_exr(Path::new(part)).with_context(|| format!("reference {part}"))?);
    }
    let (w, h) = (halves[0].0, halves[0].1);
    ensure!(
        halves.iter().all(|r| (r.0, r.1) == (w, h)),
        "the reference parts differ in size"
    );
    let n = halves.len() as f32;
    let reference: Vec<Vec3> = (0..halves[0].2.len())
        .map(|i| halves.iter().map(|r| r.2[i]).sum::<Vec3>() / n)
        .collect();
    let mr = mean(&reference);
    println!(
        "{}: {w}x{h}, mean {:.5} {:.5} {:.5}",
        args[0], mr.x, mr.y, mr.z
    );
    for path in &args[1..] {
        let (wa, ha, img) = load_exr(Path::new(path)).with_context(|| path.clone())?;
        ensure!(
            (wa, ha) == (w, h),
            "{path}: {wa}x{ha}, the reference is {w}x{h}"
        );
        let m = mean(&img);
        let rel = refract::bench::rel_mse(&img, &reference);
        let (med, max) = block_diff(&img, &reference, w as usize, h as usize);
        println!(
            "{path}: mean ratio {:.4} {:.4} {:.4}, relMSE {rel:.3e}, block rel diff median {med:.4} max {max:.4}",
            m.x / mr.x,
            m.y / mr.y,
            m.z / mr.z
        );
    }
    Ok(())
}
