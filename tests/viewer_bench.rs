//! `refract bench --viewer` (issue 36): the viewer driven headless through its scripted
//! lecture writes a report with every edit's first-image and compile times, the UI thread's
//! frame times and the throughput at two sizes.

mod common_scenes;

use serde_json::Value;
use std::process::Command;

/// Run the bench on `device` and read its JSON report.
fn bench(device: &str, test: &str) -> Value {
    let dir = std::env::temp_dir().join(format!(
        "refract-viewer-bench-{test}-{}",
        std::process::id()
    ));
    std::fs::create_dir_all(&dir).expect("scratch dir");
    let json = dir.join("viewer.json");
    let out = Command::new(env!("CARGO_BIN_EXE_refract"))
        .args([
            "bench", "--viewer", "--device", device, "--width", "64", "--height", "48",
        ])
        .args(["--drag", "1s", "--budget", "1s", "--json"])
        .arg(&json)
        .output()
        .expect("run refract bench --viewer");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&json).expect("the JSON report");
    serde_json::from_str(&text).expect("valid JSON")
}

/// The report's shape and what must hold on any device.
fn check(r: &Value) {
    let edits = r["edits"].as_array().expect("edits");
    let names: Vec<&str> = edits
        .iter()
        .map(|e| e["name"].as_str().unwrap_or(""))
        .collect();
    assert_eq!(names.len(), 7, "{names:?}");
    assert!(names[1].starts_with("drag IOR"), "{names:?}");
    assert!(names.iter().any(|n| n.contains("Beckmann")), "{names:?}");
    assert!(names.iter().any(|n| n.contains("caustic")), "{names:?}");
    for e in edits {
        let first = e["first_image_ms"].as_f64().expect("first_image_ms");
        assert!(first.is_finite() && first > 0.0, "{e}");
        assert!(
            e["first_image_p50_ms"].as_f64().expect("p50") <= first + 1e-9,
            "{e}"
        );
        let (count, steps) = (
            e["count"].as_u64().expect("count"),
            e["steps"].as_u64().expect("steps"),
        );
        assert!(count >= 1 && steps >= count, "{e}");
        if let Some(c) = e["compile_ms"].as_f64() {
            assert!(e["kernel_change"].as_bool() == Some(true) || c > 0.0, "{e}");
        }
    }
    let (max, p95) = (
        r["ui_step_max_ms"].as_f64().expect("max"),
        r["ui_step_p95_ms"].as_f64().expect("p95"),
    );
    assert!(max >= p95 && p95 > 0.0, "{max} {p95}");
    let t = r["throughput"].as_array().expect("throughput");
    assert_eq!(t.len(), 2);
    assert_eq!(
        (t[0]["width"].as_u64(), t[0]["height"].as_u64()),
        (Some(64), Some(48))
    );
    for x in t {
        assert!(x["frames_per_s"].as_f64().expect("frames/s") > 0.0, "{x}");
    }
    assert!(
        r["spp_per_s"].as_f64().expect("spp/s") > 0.0,
        "64×48 renders within a second"
    );
}

#[test]
fn the_viewer_bench_on_the_cpu() {
    let r = bench("cpu", "cpu");
    check(&r);
    for e in r["edits"].as_array().expect("edits") {
        assert_eq!(
            e["kernel_change"].as_bool(),
            Some(false),
            "the CPU has no kernels: {e}"
        );
    }
    let drag = &r["edits"][1];
    assert!(
        drag["steps"].as_u64().expect("steps") >= 20,
        "one drag step a frame for a second: {drag}"
    );
}

#[test]
fn the_viewer_bench_on_the_gpu() {
    if common_scenes::gpu_context("the_viewer_bench_on_the_gpu").is_none() {
        return;
    }
    let r = bench("gpu", "gpu");
    check(&r);
    let dispersion = r["edits"]
        .as_array()
        .expect("edits")
        .iter()
        .find(|e| {
            e["name"]
                .as_str()
                .is_some_and(|n| n.starts_with("dispersion on"))
        })
        .expect("the dispersion edit");
    assert_eq!(
        dispersion["kernel_change"].as_bool(),
        Some(true),
        "{dispersion}"
    );
    assert!(dispersion["compile_ms"].as_f64().is_some(), "{dispersion}");
}
