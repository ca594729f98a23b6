//! Hostile command lines (issue 16): never a panic, one `error:` line that names where the
//! bad value came from (flag, sidecar key, scene extras), and no work done before an output
//! that cannot be written is reported.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

/// Run refract; returns (exit code, stderr, wall time). Fails the test on a signal or a panic.
fn refract(args: &[&str]) -> (i32, String, Duration) {
    let t = Instant::now();
    let out = Command::new(env!("CARGO_BIN_EXE_refract"))
        .args(args)
        .output()
        .expect("run refract");
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    let code = out
        .status
        .code()
        .unwrap_or_else(|| panic!("killed by a signal: {}\n{err}", args[0]));
    assert!(!err.contains("panicked"), "{} panicked:\n{err}", args[0]);
    (code, err, t.elapsed())
}

/// Assert a failure whose `error:` line contains every one of `words`.
fn fails_naming(args: &[&str], words: &[&str]) -> Duration {
    let (code, err, t) = refract(args);
    assert_ne!(code, 0, "succeeded:\n{err}");
    let line = err
        .lines()
        .find(|l| l.starts_with("error:"))
        .unwrap_or_else(|| panic!("no error line:\n{err}"));
    let short: String = line.chars().take(400).collect();
    for w in words {
        assert!(line.contains(w), "'{w}' not in '{short}'");
    }
    assert!(line.chars().count() < 400, "error line too long: {short}");
    t
}

fn tmp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("refract-hostile-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

fn s(p: &Path) -> String {
    p.display().to_string()
}

#[test]
fn durations_are_checked_and_accept_scientific_notation() {
    let out = s(&tmp_dir("dur").join("x.exr"));
    for (flag, v) in [
        ("--time-budget", "1e30s"),
        ("--time-budget", "1e20"),
        ("--time-budget", "-1s"),
        ("--time-budget", "NaN"),
        ("--time-budget", "inf"),
        ("--time-budget", "3 fortnights"),
    ] {
        // `--flag=-1s`: clap reads a separate `-1s` as a flag.
        let arg = format!("{flag}={v}");
        fails_naming(&["render", &arg, "--out", &out], &[flag, "duration"]);
    }
    for v in ["1e30s", "-2m", "nan"] {
        let arg = format!("--budget={v}");
        fails_naming(&["bench", &arg], &["--budget", "duration"]);
    }
    for v in ["2e-3s", "5e-5m"] {
        let (code, err, _) = refract(&[
            "render",
            "--time-budget",
            v,
            "--spp",
            "1",
            "--width",
            "4",
            "--height",
            "4",
            "--quiet",
            "--device",
            "cpu",
            "--out",
            &out,
        ]);
        assert_eq!(code, 0, "--time-budget {v}: {err}");
    }
}

#[test]
fn unwritable_outputs_fail_before_rendering() {
    let d = tmp_dir("out");
    let file = d.join("a-file");
    std::fs::write(&file, b"not a folder").expect("write");
    let below = s(&file.join("x.exr"));
    let deep = s(&file.join("sub").join("x.png"));
    let is_dir = s(&tmp_dir("out-dir.exr"));
    for out in [&below, &deep, &is_dir] {
        // 4096² at 1 M spp would run for hours: the error must come first.
        let t = fails_naming(
            &[
                "render", "--spp", "1000000", "--width", "4096", "--height", "4096", "--out", out,
            ],
            &["--out", "cannot"],
        );
        assert!(t < Duration::from_secs(20), "{out}: {t:?}");
    }
    // A FIFO in the output's place: an error at once, not a write that blocks for a reader.
    let fifo = d.join("fifo.exr");
    let made = Command::new("mkfifo").arg(&fifo).status();
    if made.is_ok_and(|st| st.success()) {
        fails_naming(
            &["render", "--spp", "1", "--out", &s(&fifo)],
            &["--out", "not a regular file"],
        );
    }
    let (code, err, t) = refract(&["bench", "--out", &below, "--budget", "1h"]);
    assert_ne!(code, 0, "{err}");
    assert!(err.contains("error: --out"), "{err}");
    assert!(!err.contains("bench builtin"), "bench started: {err}");
    assert!(t < Duration::from_secs(20), "{t:?}");
    fails_naming(
        &[
            "bench",
            "--out",
            &s(&d.join("b")),
            "--cache",
            &below,
            "--budget",
            "1h",
        ],
        &["--cache", "is a file"],
    );
    // The probe leaves nothing behind, and an existing output is kept as it was.
    let keep = d.join("keep.png");
    std::fs::write(&keep, b"old").expect("write");
    fails_naming(
        &["render", "--spp", "0", "--out", &s(&keep)],
        &["--spp must be at least 1"],
    );
    assert_eq!(std::fs::read(&keep).expect("read"), b"old");
    fails_naming(
        &["render", "--spp", "0", "--out", &s(&d.join("new.exr"))],
        &["--spp"],
    );
    assert!(!d.join("new.exr").exists());
}

/// A one-triangle glTF (no light) with `extras` on its scene, and its buffer next to it.
fn unlit_gltf(dir: &Path, extras: &str) -> String {
    let pos: [f32; 9] = [0.0, 0.0, -1.0, 1.0, 0.0, -1.0, 0.0, 1.0, -1.0];
    let bytes: Vec<u8> = pos.iter().flat_map(|v| v.to_le_bytes()).collect();
    std::fs::write(dir.join("tri.bin"), &bytes).expect("write bin");
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0],"extras":{extras}}}],
"nodes":[{{"mesh":0}}],"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],
"accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3",
"min":[0,0,-1],"max":[1,1,-1]}}],
"bufferViews":[{{"buffer":0,"byteLength":36}}],"buffers":[{{"uri":"tri.bin","byteLength":36}}]}}"#
    );
    let p = dir.join("tri.gltf");
    std::fs::write(&p, json).expect("write gltf");
    s(&p)
}

#[test]
fn errors_name_their_source() {
    let d = tmp_dir("src");
    let out = s(&d.join("x.exr"));
    // spp 0 from the scene's extras, from a sidecar, from the flag.
    let scene = unlit_gltf(&d, r#"{"render":{"spp":0}}"#);
    fails_naming(
        &["render", "--scene", &scene, "--out", &out],
        &["extras.render.spp", "tri.gltf"],
    );
    let capture = r#""capture":{"width":4,"height":4,"spp":0,"dropped":0,"device":"cpu",
        "elapsed_s":0,"png":"x.png","exr":"x.exr"}"#;
    let sidecar = d.join("spp.json");
    std::fs::write(&sidecar, format!("{{{capture}}}")).expect("write");
    fails_naming(
        &["render", "--settings", &s(&sidecar), "--out", &out],
        &["capture.spp", "spp.json"],
    );
    let size = d.join("size.json");
    std::fs::write(
        &size,
        format!("{{{}}}", capture.replace(r#""width":4"#, r#""width":0"#)),
    )
    .expect("write");
    fails_naming(
        &["render", "--settings", &s(&size), "--out", &out],
        &["capture.width/height", "size.json", "out of range"],
    );
    fails_naming(
        &["render", "--width", "0", "--out", &out],
        &["--width/--height", "out of range"],
    );
    fails_naming(
        &["render", "--max-depth", "0", "--out", &out],
        &["--max-depth must be at least 1"],
    );
    // Exposure and light intensity from a sidecar.
    let exposure = d.join("exposure.json");
    std::fs::write(&exposure, r#"{"display":{"exposure":1e39}}"#).expect("write");
    fails_naming(
        &["render", "--settings", &s(&exposure), "--out", &out],
        &["exposure", "exposure.json"],
    );
    let light = d.join("light.json");
    std::fs::write(&light, r#"{"light":{"intensity":3e38}}"#).expect("write");
    fails_naming(
        &["render", "--settings", &s(&light), "--out", &out],
        &["light.intensity", "light.json", "emission"],
    );
    for (name, json, key) in [
        ("inf", r#"{"light":{"intensity":1e39}}"#, "intensity"),
        ("neg", r#"{"light":{"intensity":-5}}"#, "intensity"),
        ("colour", r#"{"light":{"color":[1,-1,1]}}"#, "color"),
        ("size", r#"{"light":{"size":-2}}"#, "size"),
    ] {
        let p = d.join(format!("light-{name}.json"));
        std::fs::write(&p, json).expect("write");
        let file = format!("light-{name}.json");
        fails_naming(
            &["render", "--settings", &s(&p), "--out", &out],
            &["light of settings", &file, key],
        );
    }
    // A long --paths expression is abbreviated, from the flag and from a sidecar.
    let long = format!("{}X", "LD".repeat(50_000));
    fails_naming(
        &["render", "--paths", &long, "--out", &out],
        &["--paths", "…"],
    );
    fails_naming(&["bench", "--paths", &long], &["--paths", "…"]);
    let paths = d.join("paths.json");
    std::fs::write(&paths, format!(r#"{{"render":{{"paths":"{long}"}}}}"#)).expect("write");
    fails_naming(
        &["render", "--settings", &s(&paths), "--out", &out],
        &["render.paths", "paths.json", "…"],
    );
    // Absurd thread counts: one line, the flag named once.
    let (code, err, _) = refract(&["render", "--threads", "100000", "--out", &out]);
    assert_ne!(code, 0);
    assert_eq!(err.matches("--threads").count(), 1, "{err}");
    assert_eq!(
        err.lines().filter(|l| l.starts_with("error:")).count(),
        1,
        "{err}"
    );
    let (bench_out, cache) = (s(&d.join("bench-t")), s(&d.join("cache-t")));
    fails_naming(
        &[
            "bench",
            "--threads",
            "100000",
            "--out",
            &bench_out,
            "--cache",
            &cache,
        ],
        &["--threads"],
    );
    // A glTF without any light is lit by the built-in studio environment, with a warning
    // (it used to be black, and `bench` refused it).
    let unlit = unlit_gltf(&tmp_dir("unlit"), "{}");
    let (code, err, _) = refract(&[
        "render", "--scene", &unlit, "--out", &out, "--spp", "1", "--width", "4", "--height", "4",
        "--device", "cpu", "--quiet",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.lines()
            .any(|l| l.starts_with("warning:") && l.contains("no light") && l.contains("studio")),
        "no studio warning:\n{err}"
    );
}

#[test]
fn sidecar_material_values_that_break_energy_are_errors() {
    use refract::render::settings::ViewerSettings;
    let d = tmp_dir("mat");
    let out = s(&d.join("x.exr"));
    let base = refract::scene::builtin::cornell_glass();
    let glass = base
        .materials
        .iter()
        .position(|m| m.kind == refract::scene::MaterialKind::Glass)
        .expect("cornell-glass has a glass material");
    type Breaker = fn(&mut refract::scene::Material);
    let cases: [(&str, Breaker, &str); 4] = [
        ("ior", |m| m.ior = 1e-30, "ior"),
        (
            "albedo",
            |m| m.base_color = glam::Vec3::splat(1e30),
            "base_color",
        ),
        ("roughness", |m| m.roughness = -3.0, "roughness"),
        (
            "absorb",
            |m| m.attenuation_color = glam::Vec3::splat(2.0),
            "attenuation_color",
        ),
    ];
    for (name, breaker, key) in cases {
        let mut m = base.materials[glass].clone();
        breaker(&mut m);
        let mut sidecar = ViewerSettings::for_scene("builtin:cornell-glass");
        sidecar.set_material(glass, &m);
        let path = d.join(format!("{name}.json"));
        sidecar.save(&path).expect("save sidecar");
        let materials = format!("materials[0] of settings '{}'", s(&path));
        fails_naming(
            &["render", "--settings", &s(&path), "--out", &out],
            &[&materials, key, "out of range"],
        );
    }
}

/// The film budget is checked before anything is allocated: the largest allowed image side
/// (16384², a 6 GiB f64 film) is one error line naming the budget and where the size came
/// from, at once (before: the allocation aborted the process).
#[test]
fn a_film_over_budget_is_an_error_before_allocating() {
    let t = fails_naming(
        &[
            "render",
            "--scene",
            "builtin:furnace",
            "--width",
            "16384",
            "--height",
            "16384",
            "--spp",
            "1",
            "--out",
            "/tmp/refract-never-written.exr",
            "--quiet",
        ],
        &[
            "16384x16384",
            "--width/--height",
            "GiB budget",
            "--max-film-gib",
        ],
    );
    assert!(t.as_secs_f64() < 10.0, "took {t:?}");
    // The budget is the user's: lowered, a 256² film (1.5 MiB) is over 0.001 GiB.
    let out = s(&tmp_dir("film-gib").join("x.exr"));
    let small = [
        "--width", "256", "--height", "256", "--spp", "1", "--out", &out,
    ];
    let mut args = vec![
        "render",
        "--scene",
        "builtin:furnace",
        "--max-film-gib",
        "0.001",
    ];
    args.extend(small);
    fails_naming(&args, &["256x256", "0.001 GiB budget"]);
    for bad in ["0", "-1", "inf", "lots"] {
        let flag = format!("--max-film-gib={bad}");
        let (code, err, _) = refract(&["render", &flag, "--out", &out]);
        assert_ne!(code, 0, "{bad}: {err}");
        assert!(
            err.contains("--max-film-gib") && err.contains("GiB"),
            "{bad}: {err}"
        );
    }
}

/// `--settings` naming a FIFO (which would block forever), `/dev/zero` (never ends) or a folder
/// is refused before reading; a sidecar over its size budget too.
#[test]
fn settings_from_pipes_and_devices_are_refused() {
    let d = tmp_dir("settings-fifo");
    let out = s(&d.join("x.exr"));
    let fifo = d.join("pipe.json");
    let _ = std::fs::remove_file(&fifo);
    if Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .is_ok_and(|st| st.success())
    {
        let t = fails_naming(
            &["render", "--settings", &s(&fifo), "--out", &out],
            &["settings", "not a regular file", "pipe.json"],
        );
        assert!(t < Duration::from_secs(20), "took {t:?}");
    }
    for p in ["/dev/zero", d.to_str().expect("utf-8 temp dir")] {
        fails_naming(
            &["render", "--settings", p, "--out", &out],
            &["settings", "not a regular file"],
        );
    }
    let big = d.join("big.json");
    std::fs::write(&big, vec![b' '; (16 << 20) + 1]).expect("big sidecar");
    fails_naming(
        &["render", "--settings", &s(&big), "--out", &out],
        &["settings", "big.json", "allowed"],
    );
}

/// A shipped glTF over a lowered `--max-triangles` is one error line naming the flag.
#[test]
fn load_budget_flags_reach_the_loader() {
    let out = s(&tmp_dir("budget-flags").join("x.exr"));
    let glb = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/prism.glb");
    fails_naming(
        &[
            "render",
            "--scene",
            glb,
            "--max-triangles",
            "3",
            "--out",
            &out,
        ],
        &["prism", "--max-triangles"],
    );
    fails_naming(
        &[
            "bench",
            "--scenes",
            glb,
            "--max-triangles",
            "3",
            "--budget",
            "1s",
        ],
        &["prism", "--max-triangles"],
    );
}
