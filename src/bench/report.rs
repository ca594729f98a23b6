//! The benchmark's outputs: the CSV of every point and the Markdown summary table.

use super::{BenchPoint, BenchSummary};
use anyhow::{Context, Result};
use std::fmt::Write as _;
use std::path::Path;

/// Every point as one CSV row (RFC 4180 quoting by the `csv` crate: a GPU name such as
/// "llvmpipe (LLVM 15.0.6, 256 bits)" holds a comma).
pub fn write_csv(path: &Path, points: &[BenchPoint]) -> Result<()> {
    let err = || format!("cannot write '{}'", path.display());
    let mut w = csv::Writer::from_path(path).with_context(err)?;
    w.write_record([
        "scene",
        "device",
        "estimator",
        "spp",
        "seconds",
        "samples_per_sec",
        "rel_mse",
        "rmse",
        "lum_ratio",
        "paths",
    ])
    .with_context(err)?;
    for p in points {
        w.write_record([
            p.scene.clone(),
            p.device.clone(),
            p.estimator.clone(),
            p.spp.to_string(),
            format!("{:.6}", p.seconds),
            format!("{:.1}", p.samples_per_sec),
            format!("{:.6e}", p.rel_mse),
            format!("{:.6e}", p.rmse),
            format!("{:.6}", p.lum_ratio),
            p.paths.clone(),
        ])
        .with_context(err)?;
    }
    w.flush().with_context(err)
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_quotes_a_device_name_with_a_comma() {
        let p = BenchPoint {
            scene: "cornell-glass".into(),
            paths: "all".into(),
            device: "llvmpipe (LLVM 15.0.6, 256 bits)".into(),
            estimator: "path".into(),
            spp: 16,
            seconds: 0.5,
            samples_per_sec: 1e6,
            rel_mse: 1e-3,
            rmse: 1e-2,
            lum_ratio: 1.0,
        };
        let dir = std::env::temp_dir().join(format!("refract-csv-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("bench.csv");
        write_csv(&path, &[p]).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let _ = std::fs::remove_dir_all(&dir);
        let mut lines = text.lines();
        assert!(
            lines
                .next()
                .unwrap()
                .starts_with("scene,device,estimator,spp,")
        );
        assert_eq!(
            lines.next().unwrap(),
            "cornell-glass,\"llvmpipe (LLVM 15.0.6, 256 bits)\",path,16,0.500000,1000000.0,\
             1.000000e-3,1.000000e-2,1.000000,all"
        );
    }
}
