//! Renders split across machines (issue 37 item 4): `render --shard I/N` renders a disjoint
//! slice of the samples, and `refract merge` of all N shards is the one-machine render with
//! the same seed (CPU: path, bdpt, lt, sppm; GPU on lavapipe through the library API); merge
//! refuses files that do not belong together; `--shard` and its companions are validated.

mod common_scenes;
use glam::Vec3;
use refract::render::shard_exr::read_exr;
use refract::render::{Estimator, RenderOptions, Shard};
use refract::scene::Scene;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Small and few samples: every render here takes well under a second on the CPU.
const SIZE: [&str; 4] = ["--width", "32", "--height", "24"];
/// Not a multiple of 4: shards of 2 and 3 samples.
const SPP: u32 = 10;
/// Per-pixel relative tolerance of merged against one-machine pixels: the f32 rounding of
/// the shards' and the merge's files (about 6e-8 each), with room for f64 sum order.
const REL: f32 = 1e-6;

/// Run refract; (exit code, stderr). Fails the test on a signal or a panic.
fn refract(args: &[&str]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_refract"))
        .args(args)
        .output()
        .expect("run refract");
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    let code = out.status.code().expect("killed by a signal");
    assert!(!err.contains("panicked"), "{args:?} panicked:\n{err}");
    (code, err)
}

fn ok(args: &[&str]) -> String {
    let (code, err) = refract(args);
    assert_eq!(code, 0, "{args:?} failed:\n{err}");
    err
}

/// Assert a failure whose `error:` line contains every one of `words`.
fn fails_naming(args: &[&str], words: &[&str]) {
    let (code, err) = refract(args);
    assert_ne!(code, 0, "{args:?} succeeded:\n{err}");
    let line = err
        .lines()
        .find(|l| l.starts_with("error:"))
        .unwrap_or_else(|| panic!("no error line:\n{err}"));
    for w in words {
        assert!(line.contains(w), "'{w}' not in '{line}'");
    }
}

fn tmp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("refract-shard-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

fn s(p: &Path) -> String {
    p.display().to_string()
}

/// The render command of `scene` with `estimator` and `seed` on the CPU, writing `out`.
fn render_args(scene: &str, estimator: &str, seed: u32, out: &Path) -> Vec<String> {
    let mut a: Vec<String> = ["render", "--scene", scene, "--estimator", estimator]
        .iter()
        .chain(&SIZE)
        .map(|x| x.to_string())
        .collect();
    let more = [
        "--spp".to_owned(),
        SPP.to_string(),
        "--seed".into(),
        seed.to_string(),
        "--device".into(),
        "cpu".into(),
        "--quiet".into(),
        "--out".into(),
        s(out),
    ];
    a.extend(more);
    a
}

/// Render shard `i`/`n` into `dir`; its path.
fn shard(dir: &Path, job: (&str, &str, u32), i: u32, n: u32) -> PathBuf {
    shard_with(dir, job, (i, n), &[])
}

/// [`shard`] with `extra` flags (named in the file name).
fn shard_with(
    dir: &Path,
    (scene, estimator, seed): (&str, &str, u32),
    (i, n): (u32, u32),
    extra: &[&str],
) -> PathBuf {
    let tag: String = format!("{scene}{}", extra.concat())
        .chars()
        .filter(char::is_ascii_alphanumeric)
        .collect();
    let out = dir.join(format!("{tag}-{estimator}-{seed}-{i}of{n}.exr"));
    let mut a = render_args(scene, estimator, seed, &out);
    a.extend(["--shard".to_owned(), format!("{i}/{n}")]);
    a.extend(extra.iter().map(|x| x.to_string()));
    ok(&a.iter().map(String::as_str).collect::<Vec<_>>());
    out
}

fn merge(files: &[PathBuf], out: &Path) -> (i32, String) {
    let mut a = vec!["merge".to_owned()];
    a.extend(files.iter().map(|f| s(f)));
    a.extend(["--out".to_owned(), s(out)]);
    refract(&a.iter().map(String::as_str).collect::<Vec<_>>())
}

/// Every pixel of `a` within `REL` of `b`'s (relative to the larger); the largest seen.
fn assert_close(a: &[Vec3], b: &[Vec3], what: &str) -> f32 {
    assert_eq!(a.len(), b.len(), "{what}: sizes");
    let mut worst = 0.0f32;
    for (k, (p, q)) in a.iter().zip(b).enumerate() {
        for (x, y) in p.to_array().into_iter().zip(q.to_array()) {
            let scale = x.abs().max(y.abs());
            let rel = if scale > 0.0 {
                (x - y).abs() / scale
            } else {
                0.0
            };
            assert!(
                rel <= REL,
                "{what}: pixel {k}: {x} vs {y} (relative {rel:e})"
            );
            worst = worst.max(rel);
        }
    }
    worst
}

/// Four shards of `estimator` merged equal the one-machine render: same samples, so equal
/// to float rounding (a shard that ignored its offset would repeat shard 1's samples).
fn four_shards_equal_one_machine(estimator: &str) {
    let dir = tmp_dir(&format!("cpu-{}", estimator.replace('+', "p")));
    let job = ("builtin:cornell-glass", estimator, 7);
    let files: Vec<PathBuf> = (1..=4).map(|i| shard(&dir, job, i, 4)).collect();
    let one = dir.join("one.exr");
    let a = render_args(job.0, estimator, job.2, &one);
    ok(&a.iter().map(String::as_str).collect::<Vec<_>>());
    let full = dir.join("full.exr");
    let (code, err) = merge(&[3, 0, 2, 1].map(|k| files[k].clone()), &full);
    assert_eq!(code, 0, "merge failed:\n{err}");
    assert!(!err.contains("warning"), "a complete set: {err}");
    let merged = read_exr(&full).expect("merged EXR");
    let r = merged.record.expect("the merge's record");
    let all = 0..SPP;
    assert_eq!((r.spp, r.samples), (u64::from(SPP), vec![all]));
    assert_eq!(r.shard.to_string(), "merged 4/4");
    let single = read_exr(&one).expect("one-machine EXR");
    let worst = assert_close(&merged.pixels, &single.pixels, estimator);
    eprintln!("{estimator}: merged vs one machine, worst relative difference {worst:e}");
    let s1 = read_exr(&files[0]).expect("shard 1").pixels;
    let s2 = read_exr(&files[1]).expect("shard 2").pixels;
    assert_ne!(s1, s2, "{estimator}: shards 1 and 2 drew the same samples");
}

#[test]
fn four_cpu_shards_equal_one_machine_path() {
    four_shards_equal_one_machine("path");
}

#[test]
fn four_cpu_shards_equal_one_machine_bdpt() {
    four_shards_equal_one_machine("bdpt");
}

#[test]
fn four_cpu_shards_equal_one_machine_lt() {
    four_shards_equal_one_machine("lt");
}

/// sppm: iteration s keeps its photon radius r₁(s+1)^((α−1)/2) in whichever shard draws it,
/// so the merge is the one-machine render here too.
#[test]
fn four_cpu_shards_equal_one_machine_sppm() {
    four_shards_equal_one_machine("sppm");
}

/// A shard's header records what it holds: spp, seed, shard, samples, hash, estimator and
/// the settings as JSON.
#[test]
fn a_shard_records_its_samples_in_the_exr_header() {
    let dir = tmp_dir("header");
    let f = shard(&dir, ("builtin:cornell-glass", "bdpt", 3), 2, 4);
    let r = read_exr(&f).expect("shard").record.expect("record");
    assert_eq!((r.spp, r.spp_total, r.seed), (3, SPP, 3));
    assert_eq!(r.shard.to_string(), "2/4");
    assert_eq!(r.samples, vec![2..5]);
    assert_eq!(r.estimator, "bdpt");
    let settings: serde_json::Value = serde_json::from_str(&r.settings).expect("JSON");
    assert_eq!(settings["width"], 32);
    assert_eq!(settings["height"], 24);
    assert_eq!(settings["device"], "cpu");
    let again = shard(&dir, ("builtin:cornell-glass", "bdpt", 3), 3, 4);
    let r3 = read_exr(&again).expect("shard").record.expect("record");
    assert_eq!(r3.scene_hash, r.scene_hash, "the hash is stable");
    let other = shard(&dir, ("builtin:caustic", "bdpt", 3), 3, 4);
    let ro = read_exr(&other).expect("shard").record.expect("record");
    assert_ne!(ro.scene_hash, r.scene_hash, "another scene, another hash");
}

#[test]
fn merge_refuses_files_that_do_not_belong_together() {
    let dir = tmp_dir("refuse");
    let job = ("builtin:cornell-glass", "path", 1);
    let s1 = shard(&dir, job, 1, 4);
    let s2 = shard(&dir, job, 2, 4);
    let out = dir.join("m.exr");
    let reseeded = shard(&dir, ("builtin:cornell-glass", "path", 2), 2, 4);
    let (code, err) = merge(&[s1.clone(), reseeded.clone()], &out);
    assert_ne!(code, 0);
    assert!(err.contains("seed") && err.contains(&s(&reseeded)), "{err}");
    let bdpt = shard(&dir, ("builtin:cornell-glass", "bdpt", 1), 2, 4);
    let (code, err) = merge(&[s1.clone(), bdpt.clone()], &out);
    assert_ne!(code, 0);
    assert!(
        err.contains("estimator") && err.contains(&s(&bdpt)),
        "{err}"
    );
    let deeper = shard_with(&dir, job, (2, 4), &["--max-depth", "3"]);
    let (code, err) = merge(&[s1.clone(), deeper.clone()], &out);
    assert_ne!(code, 0);
    assert!(
        err.contains("settings.max_depth 3") && err.contains(&s(&deeper)),
        "{err}"
    );
    // Another scene with the same settings.
    let depth = ["--max-depth", "6", "--rr-depth", "4"];
    let here = shard_with(&dir, job, (1, 4), &depth);
    let there = shard_with(&dir, ("builtin:caustic", "path", 1), (2, 4), &depth);
    let (code, err) = merge(&[here, there.clone()], &out);
    assert_ne!(code, 0);
    assert!(
        err.contains("scene hash") && err.contains(&s(&there)),
        "{err}"
    );
    // The same shard twice (a copy), and a merge together with a shard it holds.
    let copy = dir.join("copy.exr");
    std::fs::copy(&s1, &copy).expect("copy");
    let (code, err) = merge(&[s1.clone(), copy.clone()], &out);
    assert_ne!(code, 0);
    assert!(
        err.contains("the same shard twice") && err.contains(&s(&copy)),
        "{err}"
    );
    let m12 = dir.join("m12.exr");
    assert_eq!(merge(&[s1.clone(), s2.clone()], &m12).0, 0);
    let (code, err) = merge(&[m12.clone(), s2.clone()], &out);
    assert_ne!(code, 0);
    assert!(err.contains("overlapping sample ranges"), "{err}");
    // A plain EXR without the record.
    let plain = dir.join("plain.exr");
    let a = render_args(job.0, "path", 1, &plain);
    ok(&a.iter().map(String::as_str).collect::<Vec<_>>());
    let (code, err) = merge(&[s1.clone(), plain.clone()], &out);
    assert_ne!(code, 0);
    assert!(
        err.contains("no refract.* attributes") && err.contains(&s(&plain)),
        "{err}"
    );
    assert!(!out.exists(), "nothing written on a refusal");
    // An incomplete set merges, naming the missing shards.
    let (code, err) = merge(&[s2, s1], &out);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("warning") && err.contains("3/4, 4/4"), "{err}");
    let r = read_exr(&out).expect("merge").record.expect("record");
    assert_eq!(r.shard.to_string(), "merged 2/4");
    assert_eq!(r.samples, vec![0..5]);
}

#[test]
fn shard_arguments_are_validated() {
    let dir = tmp_dir("args");
    let out = s(&dir.join("x.exr"));
    let base = ["render", "--scene", "builtin:cornell-glass", "--quiet"];
    let with = |extra: &[&str]| -> Vec<String> {
        base.iter()
            .chain(extra)
            .chain(["--out", out.as_str()].iter())
            .map(|x| x.to_string())
            .collect()
    };
    let check = |extra: &[&str], words: &[&str]| {
        let a = with(extra);
        fails_naming(&a.iter().map(String::as_str).collect::<Vec<_>>(), words);
    };
    for bad in ["0/4", "5/4", "1/0", "2", "a/4", "-1/4"] {
        check(&["--spp", "8", "--shard", bad], &["--shard", bad]);
    }
    check(&["--shard", "1/4"], &["--shard", "--spp"]);
    check(
        &["--shard", "1/4", "--spp", "8", "--time-budget", "1s"],
        &["--shard", "--time-budget"],
    );
    check(&["--shard", "5/8", "--spp", "4"], &["--shard", "--spp 4"]);
    check(
        &["--shard", "1/2", "--spp", "4", "--measure-auto"],
        &["--shard", "--measure-auto"],
    );
    check(
        &["--shard", "1/2", "--spp", "4", "--aov", "tir"],
        &["--shard", "--aov"],
    );
    let png = s(&dir.join("x.png"));
    let a = [
        "render",
        "--shard",
        "1/2",
        "--spp",
        "4",
        "--out",
        png.as_str(),
    ];
    fails_naming(&a, &["--out", "x.png", ".exr"]);
    fails_naming(&["merge", &out, "--out", &png], &["--out", ".exr"]);
    assert!(!dir.join("x.exr").exists(), "no work before the error");
}

/// The GPU renderer from a sample offset: four shards' images weighted by spp equal the
/// one-machine image (path tracing and lt+pt on lavapipe).
#[test]
fn four_gpu_shards_equal_one_machine() {
    let Some(ctx) = common_scenes::gpu_context("four_gpu_shards_equal_one_machine") else {
        return;
    };
    let mut scene = Scene::load("builtin:cornell-glass").expect("scene");
    (scene.settings.width, scene.settings.height) = (32, 24);
    for estimator in [Estimator::Path, Estimator::LtPt] {
        let mut opts = RenderOptions::from_scene(&scene);
        (opts.seed, opts.estimator) = (5, estimator);
        let mut g = refract::gpu::GpuRenderer::with_context(ctx.clone(), scene.clone(), opts)
            .expect("GPU renderer");
        let one = g.render(SPP).expect("one machine").mean;
        let mut sum = vec![[0.0f64; 3]; one.len()];
        let mut first = None;
        for index in 1..=4 {
            let r = Shard { index, count: 4 }.samples(SPP);
            g.set_options(RenderOptions {
                first_sample: r.start,
                ..opts
            })
            .expect("options");
            let img = g.render(r.end - r.start).expect("shard").mean;
            let w = f64::from(r.end - r.start);
            for (a, p) in sum.iter_mut().zip(&img) {
                for (s, v) in a.iter_mut().zip(p.to_array()) {
                    *s += w * f64::from(v);
                }
            }
            match &first {
                None => first = Some(img),
                Some(f) if index == 2 => assert_ne!(f, &img, "{estimator}: shards 1 and 2 equal"),
                Some(_) => {}
            }
        }
        let merged: Vec<Vec3> = sum
            .iter()
            .map(|a| Vec3::from_array(a.map(|v| (v / f64::from(SPP)) as f32)))
            .collect();
        let worst = assert_close(&merged, &one, &format!("GPU {estimator}"));
        eprintln!("GPU {estimator}: merged vs one machine, worst relative difference {worst:e}");
    }
}
