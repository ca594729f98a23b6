//! Path classes in one pass (`cpu::decompose`) and event heatmaps (`cpu::aov`): the classes
//! and `rest` partition the plain render of the same seed, a class equals its `--paths`
//! render where classes are disjoint, the layers leave the beauty image untouched, and the
//! heatmaps count what the path inspector records.

use glam::Vec3;
use refract::cpu::Renderer;
use refract::cpu::aov::EventCounter;
use refract::cpu::decompose::Decomposition;
use refract::cpu::inspect::{VertexEvent, trace_pixel};
use refract::paths::PathFilter;
use refract::render::RenderOptions;
use refract::scene::Scene;
use std::process::Command;

fn setup(name: &str, size: u32) -> (Renderer, RenderOptions) {
    let s = Scene::load(&format!("builtin:{name}")).expect("builtin");
    let r = Renderer::new(s).expect("valid");
    let mut o = RenderOptions::from_scene(&r.scene);
    (o.width, o.height, o.seed) = (size, size * 3 / 4, 5);
    (r, o)
}

fn plain(r: &Renderer, o: &RenderOptions, regex: &str, spp: u32) -> Vec<Vec3> {
    let mut o = *o;
    o.set_filter(Some(&PathFilter::parse(regex).expect("valid regex")));
    r.render(&o, spp, None, |_| {}).0.image()
}

/// Worst per-pixel |a − b| relative to the pixel's brightest channel (floor 1e-3).
fn worst_error(a: &[Vec3], b: &[Vec3]) -> f32 {
    a.iter()
        .zip(b)
        .map(|(a, b)| (*a - *b).abs().max_element() / b.max_element().max(1e-3))
        .fold(0.0, f32::max)
}

/// The decomposition's layers (classes, then rest) and the beauty image.
fn decompose(r: &Renderer, o: &RenderOptions, spec: &str, spp: u32) -> (Vec<Vec<Vec3>>, Vec<Vec3>) {
    let d = Decomposition::parse(spec).expect("valid classes");
    let proto = d.router();
    let (film, layers, _) = r.render_layered(o, (spp, None), &proto, |_| {});
    let images = (0..layers.layers)
        .map(|l| layers.image(l, film.spp))
        .collect();
    (images, film.image())
}

fn luminance_sum(img: &[Vec3]) -> f32 {
    img.iter().map(|p| p.x + p.y + p.z).sum()
}

#[test]
fn classes_and_rest_sum_to_the_unfiltered_render() {
    for scene in ["caustic", "cornell-glass", "materials"] {
        let (r, o) = setup(scene, 48);
        let all = plain(&r, &o, "", 8);
        let (layers, beauty) = decompose(&r, &o, "LE,LDE,LS+DE,LDS+E", 8);
        assert_eq!(layers.len(), 5);
        // The walk is the renderer's: the beauty image is bit for bit the plain render.
        assert_eq!(
            beauty, all,
            "{scene}: the layered render changed the beauty image"
        );
        let sum: Vec<Vec3> = (0..all.len())
            .map(|i| layers.iter().map(|l| l[i]).sum())
            .collect();
        // Same walk, same numbers: only the f32 order of the additions differs.
        let e = worst_error(&sum, &all);
        assert!(
            e < 1e-5,
            "{scene}: classes + rest differ from the render by {e}"
        );
        assert!(luminance_sum(&all) > 0.0);
        // Direct lighting and the remainder are never empty in these scenes.
        assert!(luminance_sum(&layers[1]) > 0.0, "{scene}: LDE empty");
        assert!(luminance_sum(&layers[4]) > 0.0, "{scene}: rest empty");
    }
}

#[test]
fn a_disjoint_class_equals_its_paths_render() {
    // materials has two-lobe (metal-rough) surfaces: their connections split by lobe.
    for (scene, classes) in [
        ("cornell-glass", ["LE", "LDE", "LS+DE"]),
        ("caustic", ["LDE", "LDDE", "LDS+E"]),
        ("materials", ["LE", "LDE", "LGE"]),
    ] {
        let (r, o) = setup(scene, 40);
        let (layers, _) = decompose(&r, &o, &classes.join(","), 8);
        for (k, class) in classes.iter().enumerate() {
            let filtered = plain(&r, &o, class, 8);
            let e = worst_error(&layers[k], &filtered);
            assert!(e < 1e-4, "{scene} {class}: layer vs --paths differ by {e}");
            // (The light itself is out of view in materials.)
            if *class != "LE" {
                assert!(luminance_sum(&filtered) > 0.0, "{scene} {class} is empty");
            }
        }
        let everything = plain(&r, &o, "", 8);
        let parts: Vec<Vec3> = (0..everything.len())
            .map(|i| layers.iter().map(|l| l[i]).sum())
            .collect();
        assert!(
            worst_error(&parts, &everything) < 1e-5,
            "{scene}: partition"
        );
    }
}

#[test]
fn overlapping_classes_go_to_the_first_match() {
    let (r, o) = setup("cornell-glass", 32);
    // L(D|S)*E takes everything LDE does not: LDE's image is the same as when alone.
    let (layers, _) = decompose(&r, &o, "LDE,L(D|S)*E", 8);
    let lde = plain(&r, &o, "LDE", 8);
    assert!(worst_error(&layers[0], &lde) < 1e-4);
    let rest_of_lde = plain(&r, &o, "L(D|S)*(S|DD|SD)E|LE", 8);
    assert!(worst_error(&layers[1], &rest_of_lde) < 1e-4);
}

/// The glass slab's event layer at `spp` samples and the options it used.
fn slab_events(spp: u32, size: u32) -> (Renderer, RenderOptions, Vec<[f32; 3]>, Vec<Vec3>) {
    let (r, o) = setup("glass-slab", size);
    let proto = Some(EventCounter::default());
    let (film, layers, _) = r.render_layered(&o, (spp, None), &proto, |_| {});
    let ev = layers
        .image(0, film.spp)
        .iter()
        .map(|v| v.to_array())
        .collect();
    (r, o, ev, film.image())
}

#[test]
fn heatmaps_count_the_inspectors_events() {
    let spp = 32;
    let (r, o, ev, beauty) = slab_events(spp, 80);
    assert_eq!(
        beauty,
        plain(&r, &o, "", spp),
        "AOVs changed the beauty image"
    );
    let (w, h) = (o.width, o.height);
    let px = |x: u32, y: u32| ev[(y * w + x) as usize];
    // The slab's edges pipe light by total internal reflection.
    let max_tir = ev.iter().map(|e| e[0]).fold(0.0, f32::max);
    assert!(
        max_tir > 0.5,
        "no light-pipe region: max TIR fraction {max_tir}"
    );
    // Every camera ray hits the floor or the slab: at least one vertex.
    assert!(ev.iter().all(|e| e[2] >= 1.0), "a path without a vertex");
    // Far floor (top corners) mostly sees no glass; where the slab is hit first, a path
    // refracts more often than not.
    let corner = px(0, 0);
    assert!(corner[0] < 0.2 && corner[1] < 0.5, "corner {corner:?}");
    // Per pixel, the fractions are the inspector's counts of the same samples.
    for (x, y) in [(0, 0), (w / 2, h / 2), (w / 3, h / 2), (w - 1, h - 1)] {
        let t = trace_pixel(&r, &o, (x, y), spp).expect("trace");
        let has = |e: VertexEvent| {
            t.paths
                .iter()
                .filter(|p| p.vertices.iter().any(|v| v.event == e))
                .count() as f32
                / spp as f32
        };
        let vertices: usize = t.paths.iter().map(|p| p.vertices.len() - 1).sum();
        let escaped_env = t
            .paths
            .iter()
            .filter(|p| {
                p.vertices
                    .last()
                    .is_some_and(|v| v.material == "environment")
            })
            .count();
        let mean_depth = (vertices - escaped_env) as f32 / spp as f32;
        let e = px(x, y);
        assert!(
            (e[0] - has(VertexEvent::Tir)).abs() < 1e-6,
            "({x},{y}) tir {e:?}"
        );
        assert!(
            (e[1] - has(VertexEvent::Refract)).abs() < 1e-6,
            "({x},{y}) refr {e:?}"
        );
        assert!(
            (e[2] - mean_depth).abs() < 1e-5,
            "({x},{y}) depth {e:?} vs {mean_depth}"
        );
    }
}

#[test]
fn heatmap_zero_on_a_diffuse_wall_seen_directly() {
    // max depth 2: camera → surface → one more vertex. A path whose first vertex is the
    // diffuse floor can meet the glass only at its last vertex, where nothing scatters: the
    // TIR fraction is exactly 0 there, while the slab's pixels refract.
    let (r, mut o) = setup("glass-slab", 64);
    o.max_depth = 2;
    let proto = Some(EventCounter::default());
    let (film, layers, _) = r.render_layered(&o, (8, None), &proto, |_| {});
    let ev = layers.image(0, film.spp);
    assert!(ev.iter().all(|e| e.x == 0.0), "TIR with max depth 2");
    assert!(ev.iter().any(|e| e.y > 0.5), "no pixel refracts");
}

fn refract(args: &[&str]) -> (bool, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_refract"))
        .args(args)
        .output()
        .expect("run refract");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn cli_writes_the_layers_and_names_its_errors() {
    let d = std::env::temp_dir().join(format!("refract-decompose-{}", std::process::id()));
    std::fs::create_dir_all(&d).expect("temp dir");
    let out = d.join("c.exr").display().to_string();
    let base = [
        "render",
        "--scene",
        "builtin:caustic",
        "--spp",
        "2",
        "--width",
        "32",
        "--height",
        "24",
        "--quiet",
        "--out",
        &out,
    ];
    let with = |extra: &[&str]| {
        let mut a: Vec<&str> = base.to_vec();
        a.extend_from_slice(extra);
        refract(&a)
    };
    let (ok, err) = with(&[
        "--decompose",
        "LE,LS+DE,glass=L(D|S)*SE",
        "--aov",
        "tir,depth",
    ]);
    assert!(ok, "{err}");
    for f in ["c.LE", "c.LSpDE", "c.glass", "c.rest", "c.tir", "c.depth"] {
        let p = d.join(format!("{f}.exr"));
        let (w, h, img) = refract::film::load_exr(&p).expect("layer file");
        assert_eq!((w, h, img.len()), (32, 24, 32 * 24), "{f}");
    }
    assert!(!d.join("c.refraction.exr").exists());
    for (extra, needle) in [
        (
            &["--decompose", "LE,L(DE"][..],
            "--decompose: class 2 'L(DE'",
        ),
        (
            &["--decompose", "LE", "--estimator", "bdpt"][..],
            "--decompose needs --estimator path",
        ),
        (
            &["--aov", "tir", "--device", "gpu"][..],
            "--aov is CPU only",
        ),
        (&["--aov", "bounces"][..], "--aov: unknown AOV 'bounces'"),
        (&["--decompose", "LE", "--paths", "LDE"][..], "drop --paths"),
        (
            &["--decompose", "LE,LDE", "--max-film-gib", "0.00005"][..],
            "--decompose: a 32x24 image with 3 layers needs",
        ),
    ] {
        let (ok, err) = with(extra);
        assert!(!ok, "{extra:?} succeeded");
        assert!(err.contains(needle), "{extra:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{extra:?}: {err}");
    }
}
