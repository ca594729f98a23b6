//! The benchmark's outputs: the CSV of every point and the Markdown summary table.

use super::{BenchPoint, BenchSummary};
use anyhow::{Context, Result};
use std::fmt::Write as _;
use std::path::Path;

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
