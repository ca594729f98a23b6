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

/// Where the relMSE comes from: the share of its sum carried by the worst 1 % and 10 % of
/// pixels, and the pixel box of the worst 1 % (x0..x1, y0..y1).
fn concentration(a: &[Vec3], r: &[Vec3], w: usize) -> (f64, f64, [usize; 4]) {
    let mut e: Vec<(f64, usize)> = a
        .iter()
        .zip(r)
        .enumerate()
        .map(|(i, (a, r))| (refract::bench::rel_mse(&[*a], &[*r]), i))
        .collect();
    e.sort_by(|x, y| y.0.total_cmp(&x.0));
    let total = e.iter().map(|x| x.0).sum::<f64>().max(1e-300);
    let share = |f: f64| {
        let n = ((e.len() as f64 * f).ceil() as usize).max(1);
        (e[..n].iter().map(|x| x.0).sum::<f64>() / total, n)
    };
    let (s1, n1) = share(0.01);
    let mut bx = [usize::MAX, 0, usize::MAX, 0];
    for &(_, i) in &e[..n1] {
        let (x, y) = (i % w, i / w);
        bx = [bx[0].min(x), bx[1].max(x), bx[2].min(y), bx[3].max(y)];
    }
    (s1, share(0.1).0, bx)
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
        let (s1, s10, b) = concentration(&img, &reference, w as usize);
        println!(
            "  worst 1 % of pixels carry {:.0} % of it (within x {}..{}, y {}..{}), worst 10 % {:.0} %",
            s1 * 100.0,
            b[0],
            b[1],
            b[2],
            b[3],
            s10 * 100.0
        );
    }
    Ok(())
}
