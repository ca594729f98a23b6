//! The command line: clear one-line errors with a non-zero exit code, and working output files.

use std::process::Command;

fn refract(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_refract"))
        .args(args)
        .output()
        .expect("run refract");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn tmp(name: &str) -> String {
    let d = std::env::temp_dir().join(format!("refract-cli-{}", std::process::id()));
    std::fs::create_dir_all(&d).expect("temp dir");
    d.join(name).display().to_string()
}

#[test]
fn errors_are_one_clear_line() {
    let out = tmp("x.exr");
    let cases: &[(&[&str], &str)] = &[
        (
            &["render", "--scene", "/nonexistent/scene.glb", "--out", &out],
            "cannot read",
        ),
        (
            &["render", "--scene", "builtin:nope", "--out", &out],
            "unknown built-in",
        ),
        (&["render", "--width", "0", "--out", &out], "out of range"),
        (
            &[
                "render", "--width", "100000", "--height", "100000", "--out", &out,
            ],
            "out of range",
        ),
        (&["render", "--spp", "0", "--out", &out], "spp"),
        (
            &[
                "render",
                "--spp",
                "1",
                "--width",
                "4",
                "--height",
                "4",
                "--out",
                "/tmp/x.bmp",
            ],
            "unsupported output format",
        ),
        (&["render", "--tonemap", "sepia", "--out", &out], "tone map"),
        (&["render", "--threads", "0", "--out", &out], "threads"),
        (
            &["bench", "--paths", "L(S", "--scenes", "builtin:furnace"],
            "--paths",
        ),
    ];
    for (args, needle) in cases {
        let (ok, _, err) = refract(args);
        assert!(!ok, "{args:?} should fail");
        let line = err.trim();
        assert!(line.starts_with("error:"), "{args:?}: {line}");
        assert_eq!(line.lines().count(), 1, "{args:?}: not one line: {line}");
        assert!(line.contains(needle), "{args:?}: '{line}' lacks '{needle}'");
        assert!(!line.contains("panicked"), "{args:?} panicked");
    }
    // clap's own argument errors exit non-zero without a panic
    let (ok, _, err) = refract(&["render", "--time-budget", "ten seconds"]);
    assert!(!ok && err.contains("invalid duration"), "{err}");
    let (ok, _, err) = refract(&["render", "--estimator", "photons", "--out", &out]);
    assert!(
        !ok && err
            .contains("unknown estimator 'photons' (use auto, path, bdpt, lt, lt+pt or sppm)"),
        "{err}"
    );
}

#[test]
fn render_writes_exr_and_png() {
    let exr = tmp("c.exr");
    let png = tmp("c.png");
    for out in [&exr, &png] {
        let (ok, _, err) = refract(&[
            "render",
            "--scene",
            "builtin:cornell-glass",
            "--spp",
            "2",
            "--width",
            "24",
            "--height",
            "16",
            "--out",
            out,
            "--quiet",
        ]);
        assert!(ok, "{err}");
        assert!(
            err.contains("samples/s") && err.contains("dropped"),
            "{err}"
        );
    }
    let (w, h, img) = refract::film::load_exr(std::path::Path::new(&exr)).expect("read exr");
    assert_eq!((w, h), (24, 16));
    let mean: f32 = img.iter().map(|p| p.y).sum::<f32>() / img.len() as f32;
    assert!(mean > 0.01 && mean.is_finite(), "mean radiance {mean}");
    let png_img = image::open(&png).expect("read png").into_rgb8();
    assert_eq!(png_img.dimensions(), (24, 16));
}

#[test]
fn bench_writes_csv_plot_and_table() {
    let out = tmp("bench");
    let cache = tmp("bench-cache");
    let (ok, stdout, err) = refract(&[
        "bench",
        "--scenes",
        "builtin:furnace",
        "--width",
        "16",
        "--height",
        "8",
        "--ref-spp",
        "8",
        "--budget",
        "200ms",
        "--estimators",
        "path",
        "bdpt",
        "--out",
        &out,
        "--cache",
        &cache,
    ]);
    assert!(ok, "{err}");
    assert!(
        stdout.contains("| builtin:furnace | cpu | path |"),
        "{stdout}"
    );
    assert!(
        stdout.contains("| builtin:furnace | cpu | bdpt |"),
        "{stdout}"
    );
    let csv = std::fs::read_to_string(format!("{out}/bench.csv")).expect("csv");
    let rows: Vec<&str> = csv.lines().skip(1).collect();
    assert!(rows.len() >= 2, "{csv}");
    for r in rows {
        let rel: f64 = r
            .split(',')
            .nth(6)
            .expect("rel_mse column")
            .parse()
            .expect("number");
        assert!(rel.is_finite() && rel >= 0.0, "{r}");
    }
    assert!(std::path::Path::new(&format!("{out}/bench.png")).exists());
    assert!(std::path::Path::new(&format!("{out}/bench.md")).exists());
    // the second run reuses the cached reference
    let (ok, _, err2) = refract(&[
        "bench",
        "--scenes",
        "builtin:furnace",
        "--width",
        "16",
        "--height",
        "8",
        "--ref-spp",
        "8",
        "--budget",
        "100ms",
        "--estimators",
        "path",
        "--out",
        &out,
        "--cache",
        &cache,
    ]);
    assert!(
        ok && !err2.contains("reference half"),
        "reference not cached: {err2}"
    );
}

/// Several Heckbert classes in one run: each (scene, estimator, class) is its own row in
/// bench.md and its own curve in bench.csv (last column `paths`).
#[test]
fn bench_measures_each_path_class() {
    let out = tmp("bench-classes");
    let cache = tmp("bench-classes-cache");
    let (ok, stdout, err) = refract(&[
        "bench",
        "--scenes",
        "builtin:caustic-mirror",
        "--width",
        "16",
        "--height",
        "12",
        "--ref-spp",
        "8",
        "--budget",
        "100ms",
        "--estimators",
        "path",
        "--paths",
        "LS+DE",
        "LS+DS+E",
        "--out",
        &out,
        "--cache",
        &cache,
    ]);
    assert!(ok, "{err}");
    for class in ["LS+DE", "LS+DS+E"] {
        assert!(
            stdout.contains(&format!(
                "| builtin:caustic-mirror | cpu | path | {class} |"
            )),
            "{stdout}"
        );
    }
    let csv = std::fs::read_to_string(format!("{out}/bench.csv")).expect("csv");
    assert!(csv.lines().next().unwrap().ends_with(",paths"), "{csv}");
    let classes: Vec<&str> = csv
        .lines()
        .skip(1)
        .map(|r| r.rsplit(',').next().unwrap())
        .collect();
    assert!(
        classes.contains(&"LS+DE") && classes.contains(&"LS+DS+E"),
        "{csv}"
    );
    assert!(std::path::Path::new(&format!("{out}/bench.png")).exists());
}

/// `bench --quick` (issue 14, part 4) reports closest-hit and shadow rays/s on one core and
/// on all threads, and cornell-glass samples/s on one thread and on all: every figure a
/// positive number.
#[test]
fn bench_quick_reports_one_core_and_all_core_rates() {
    let (ok, out, err) = refract(&["bench", "--quick"]);
    assert!(ok, "{err}");
    // The number just before the first (or, for the all-thread figure, last) `before`.
    let figure = |line: &str, before: &str, last: bool| -> f64 {
        let at = if last {
            line.rfind(before)
        } else {
            line.find(before)
        };
        let i = at.unwrap_or_else(|| panic!("no '{before}' in '{line}'"));
        let num: String = line[..i].trim_end().rsplit(' ').next().unwrap_or("").into();
        num.parse()
            .unwrap_or_else(|_| panic!("'{num}' before '{before}' in '{line}'"))
    };
    for key in ["closest-hit:", "shadow:", "cornell-glass 256²"] {
        let line = out
            .lines()
            .find(|l| l.contains(key))
            .unwrap_or_else(|| panic!("no {key} line:\n{out}"));
        let (one, all) = if key.starts_with("cornell") {
            (
                figure(line, "M samples/s on 1 thread", false),
                figure(line, "M samples/s on ", true),
            )
        } else {
            (
                figure(line, "M rays/s on 1 core", false),
                figure(line, "M rays/s on ", true),
            )
        };
        assert!(one > 0.0 && all > 0.0, "{line}");
        assert!(line.contains("threads"), "{line}");
    }
    let bdpt = out
        .lines()
        .find(|l| l.contains("caustic 256²") && l.contains("(bdpt)"))
        .unwrap_or_else(|| panic!("no caustic bdpt line:\n{out}"));
    assert!(figure(bdpt, "M samples/s on ", true) > 0.0, "{bdpt}");
}

#[test]
fn bad_light_line_is_an_error_naming_the_flag() {
    for nm in ["0", "-3", "NaN", "900"] {
        let (ok, _, err) = refract(&[
            "render",
            "--scene",
            "builtin:prism",
            "--light-line",
            nm,
            "--spp",
            "1",
            "--device",
            "cpu",
            "--out",
            &tmp("line.png"),
        ]);
        assert!(!ok, "{nm} accepted");
        assert!(
            err.contains("--light-line") && err.contains("360"),
            "{nm}: {err}"
        );
    }
    let (ok, _, err) = refract(&[
        "render",
        "--scene",
        "builtin:prism",
        "--light-line",
        "589.3",
        "--spp",
        "1",
        "--width",
        "32",
        "--height",
        "20",
        "--device",
        "cpu",
        "--out",
        &tmp("line.png"),
    ]);
    assert!(ok, "{err}");
}
