//! The path inspector (`cpu::inspect`, `refract trace`): what it records is what the step
//! did, and that obeys the optics — Snell's law at every refraction, the exact dielectric
//! Fresnel term, total internal reflection exactly past the critical angle — and its paths
//! are the renderer's samples (their mean is the rendered pixel).

mod common_scenes;

use glam::{Vec2, Vec3};
use refract::cpu::Renderer;
use refract::cpu::inspect::{PathRecord, PixelTrace, VertexEvent, VertexRecord, trace_pixel};
use refract::paths::Symbol;
use refract::render::RenderOptions;
use refract::scene::{Camera, Material, MaterialKind, Mesh, Scene, builtin};
use std::process::Command;

/// A right-angle (Porro) prism seen through its hypotenuse face in a uniform sky: a camera
/// ray enters at near-normal incidence and meets both 45° faces beyond the critical angle
/// (41.8° for n = 1.5), so it is totally reflected twice and leaves back towards the camera.
fn porro_prism() -> Scene {
    let mut mesh = Mesh::default();
    let tri = [
        Vec2::new(-1.0, 0.0),
        Vec2::new(1.0, 0.0),
        Vec2::new(0.0, -1.0),
    ];
    builtin::triangular_prism(&mut mesh, tri, -0.8, 0.8, 0);
    let cam = Camera::look_at(
        Vec3::new(0.3, 0.2, 4.0),
        Vec3::new(0.0, 0.0, -0.3),
        Vec3::Y,
        0.5,
    );
    common_scenes::scene(
        "porro-prism",
        mesh,
        vec![Material::glass("glass", 1.5)],
        cam,
        1.0,
    )
}

/// Small images so a coarse grid of pixels covers the glass of every scene.
fn small(scene: &Scene) -> RenderOptions {
    let mut o = RenderOptions::from_scene(scene);
    let aspect = scene.settings.width as f32 / scene.settings.height as f32;
    o.width = 48;
    o.height = (48.0 / aspect).round() as u32;
    o.seed = 7;
    o
}

/// Every path through a grid of pixels (every `step`-th pixel), `n` paths each.
fn grid_paths(scene: Scene, step: u32, n: u32) -> (Renderer, Vec<PathRecord>) {
    let opts = small(&scene);
    let r = Renderer::new(scene).expect("scene");
    let mut all = Vec::new();
    for y in (0..opts.height).step_by(step as usize) {
        for x in (0..opts.width).step_by(step as usize) {
            all.extend(trace_pixel(&r, &opts, (x, y), n).expect("trace").paths);
        }
    }
    (r, all)
}

fn sin_of(c: f32) -> f64 {
    let c = c as f64;
    (1.0 - c * c).max(0.0).sqrt()
}

/// Exact unpolarised dielectric reflectance from r∥ and r⊥ (Hecht, "Optics" §4.6.2), in f64
/// and independent of the renderer's code: η = η_t/η_i, cos θ_i and cos θ_t given.
fn fresnel_exact(cos_i: f64, cos_t: f64, eta: f64) -> f64 {
    let r_par = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    0.5 * (r_par * r_par + r_perp * r_perp)
}

/// F at `cos_i` with θ_t from Snell (f64); None past the critical angle.
fn fresnel_snell(cos_i: f64, eta: f64) -> Option<f64> {
    let c2 = 1.0 - (1.0 - cos_i * cos_i) / (eta * eta);
    (c2 > 0.0).then(|| fresnel_exact(cos_i, c2.sqrt(), eta))
}

/// How far F may be from the exact value: 2e-6 plus F's spread over the rounding of the f32
/// cosine it was computed from (±4e-7, a few ulps). Near the critical angle F is steep in
/// cos θ_i (∂F/∂cosθ_i → ∞), so there the bound is the input's conditioning, not a fudge.
fn fresnel_tolerance(cos_i: f32, eta: f64) -> f64 {
    let c = cos_i as f64;
    let d = 4e-7;
    let f0 = fresnel_snell(c, eta).unwrap_or(1.0);
    let spread =
        [c - d, c + d].map(|c| (fresnel_snell(c.clamp(0.0, 1.0), eta).unwrap_or(1.0) - f0).abs());
    2e-6 + spread[0].max(spread[1])
}

/// Snell, Fresnel and TIR at every smooth-dielectric vertex; returns (refractions, TIRs).
fn check_optics(scene: &str, paths: &[PathRecord]) -> (usize, usize) {
    let (mut refr, mut tir) = (0, 0);
    for (i, p) in paths.iter().enumerate() {
        for (k, v) in p.vertices.iter().enumerate() {
            let at = format!("{scene} path {i} vertex {k} ({v:?})");
            match v.event {
                VertexEvent::Refract => {
                    refr += 1;
                    check_refraction(v, &at);
                }
                VertexEvent::Tir => {
                    tir += 1;
                    check_tir(v, &at);
                }
                VertexEvent::Reflect if v.fresnel.is_some() => check_fresnel_reflection(v, &at),
                _ => {}
            }
        }
    }
    (refr, tir)
}

fn cosines(v: &VertexRecord, at: &str) -> (f32, f32) {
    let ci = v.cos_i.unwrap_or_else(|| panic!("{at}: no cos_i"));
    let ct = v.cos_t.unwrap_or_else(|| panic!("{at}: no cos_t"));
    assert!(
        (0.0..=1.0).contains(&ci) && (0.0..=1.0).contains(&ct),
        "{at}: cosines"
    );
    (ci, ct)
}

/// Rounding of f32 cosines (a few ulps) propagated into sin θ = √(1 − cos²θ): δsin ≈
/// cos·δcos/sin, so the bound widens only at near-normal incidence.
fn snell_tolerance(ci: f32, ct: f32) -> f64 {
    let smin = sin_of(ci).min(sin_of(ct)).max(1e-3);
    1e-6 + 5e-7 / smin
}

fn check_refraction(v: &VertexRecord, at: &str) {
    let (ci, ct) = cosines(v, at);
    let (ei, et) = (v.eta_i as f64, v.eta_t as f64);
    // Snell: η_i sin θ_i = η_t sin θ_t.
    let (lhs, rhs) = (ei * sin_of(ci), et * sin_of(ct));
    assert!(
        (lhs - rhs).abs() <= snell_tolerance(ci, ct),
        "{at}: Snell η_i sinθ_i = {lhs} ≠ η_t sinθ_t = {rhs}"
    );
    assert!(lhs / et < 1.0, "{at}: refracted past the critical angle");
    let f = v.fresnel.unwrap_or_else(|| panic!("{at}: no Fresnel")) as f64;
    let exact = fresnel_exact(ci as f64, ct as f64, et / ei);
    let tol = fresnel_tolerance(ci, et / ei);
    assert!(
        (f - exact).abs() <= tol,
        "{at}: F = {f}, exact {exact} (±{tol})"
    );
    // The media the inspector names are the ones the BSDF refracted between.
    let step = v.step_eta_rel.expect("step eta") as f64;
    assert!(
        ((et / ei) - step).abs() <= 1e-6 * step,
        "{at}: η_t/η_i = {} but the step crossed η' = {step}",
        et / ei
    );
}

fn check_tir(v: &VertexRecord, at: &str) {
    let (ci, ct) = cosines(v, at);
    let ratio = v.eta_i as f64 * sin_of(ci) / v.eta_t as f64;
    assert!(
        ratio >= 1.0 - 1e-6,
        "{at}: TIR with η_i sinθ_i/η_t = {ratio} < 1"
    );
    assert_eq!(ct, 0.0, "{at}: cos_t under TIR");
    assert_eq!(v.fresnel, Some(1.0), "{at}: F under TIR");
}

/// A partial Fresnel reflection at a dielectric: below the critical angle, F exact for the
/// refracted sibling's angle.
fn check_fresnel_reflection(v: &VertexRecord, at: &str) {
    let (ci, ct) = cosines(v, at);
    let (ei, et) = (v.eta_i as f64, v.eta_t as f64);
    let ratio = ei * sin_of(ci) / et;
    assert!(
        ratio <= 1.0 + 1e-6,
        "{at}: no TIR although η_i sinθ_i/η_t = {ratio} ≥ 1"
    );
    let (lhs, rhs) = (ei * sin_of(ci), et * sin_of(ct));
    assert!(
        (lhs - rhs).abs() <= snell_tolerance(ci, ct),
        "{at}: Snell {lhs} ≠ {rhs}"
    );
    let f = v.fresnel.expect("F") as f64;
    let exact = fresnel_exact(ci as f64, ct as f64, et / ei);
    let tol = fresnel_tolerance(ci, et / ei);
    assert!(
        (f - exact).abs() <= tol,
        "{at}: F = {f}, exact {exact} (±{tol})"
    );
}

/// The renderer's solid smooth glass only (thin sheets report R', not one interface's F).
fn assert_solid_glass_only(r: &Renderer) {
    for m in &r.scene.materials {
        assert_ne!(m.kind, MaterialKind::ThinGlass, "material '{}'", m.name);
    }
}

#[test]
fn snell_and_fresnel_at_every_refraction() {
    for name in ["glass-slab", "cornell-glass", "prism"] {
        let scene = builtin::load(name).expect("builtin");
        let (r, paths) = grid_paths(scene, 3, 8);
        assert_solid_glass_only(&r);
        let (refr, tir) = check_optics(name, &paths);
        eprintln!(
            "{name}: {} paths, {refr} refractions, {tir} TIRs",
            paths.len()
        );
        assert!(
            refr >= 50,
            "{name}: only {refr} refraction vertices to check"
        );
    }
}

#[test]
fn total_internal_reflection_exactly_past_the_critical_angle() {
    let (r, paths) = grid_paths(porro_prism(), 2, 8);
    assert_solid_glass_only(&r);
    let (refr, tir) = check_optics("porro-prism", &paths);
    eprintln!(
        "porro-prism: {} paths, {refr} refractions, {tir} TIRs",
        paths.len()
    );
    assert!(tir >= 100, "only {tir} TIR vertices");
    // The classic double reflection: in, TIR, TIR, out, to the sky.
    assert!(
        paths.iter().any(|p| p
            .vertices
            .iter()
            .filter(|v| v.event == VertexEvent::Tir)
            .count()
            >= 2
            && p.heckbert.starts_with("LSSSS")),
        "no path totally reflected twice"
    );
}

#[test]
fn heckbert_strings_match_the_vertex_classes() {
    let (_, paths) = grid_paths(builtin::load("cornell-glass").expect("builtin"), 4, 4);
    let mut connections = 0;
    for (i, p) in paths.iter().enumerate() {
        let classes: String = p.vertices.iter().rev().map(|v| v.class.as_char()).collect();
        assert_eq!(p.heckbert, classes, "path {i}");
        assert_eq!(p.vertices[0].class, Symbol::E, "path {i} starts at the eye");
        assert_eq!(p.vertices[0].event, VertexEvent::Camera, "path {i}");
        for (k, v) in p.vertices.iter().enumerate().skip(1) {
            let lobe_event = match v.class {
                Symbol::D => v.event == VertexEvent::Diffuse || v.event == VertexEvent::Absorbed,
                Symbol::G => v.event == VertexEvent::Glossy || v.event == VertexEvent::Absorbed,
                Symbol::S => matches!(
                    v.event,
                    VertexEvent::Reflect
                        | VertexEvent::Refract
                        | VertexEvent::Tir
                        | VertexEvent::Absorbed
                ),
                Symbol::L => v.event == VertexEvent::Emission && v.emitted.is_some(),
                Symbol::E => false,
            };
            assert!(
                lobe_event,
                "path {i} vertex {k}: class {:?} with event {:?}",
                v.class, v.event
            );
        }
        for c in &p.connections {
            connections += 1;
            let prefix: String = p.vertices[..=c.from]
                .iter()
                .rev()
                .map(|v| v.class.as_char())
                .collect();
            assert_eq!(
                c.heckbert,
                format!("L{prefix}"),
                "path {i} connection from {}",
                c.from
            );
        }
    }
    assert!(connections > 0, "no light connections recorded");
}

/// Σ connections + Σ emission = the sample's estimate, per path.
fn assert_contributions_add_up(paths: &[PathRecord]) {
    for (i, p) in paths.iter().enumerate() {
        let mut sum = Vec3::ZERO;
        for c in &p.connections {
            sum += Vec3::from(c.contribution);
        }
        for v in &p.vertices {
            sum += Vec3::from(v.emitted.unwrap_or([0.0; 3]));
        }
        let total = Vec3::from(p.contribution);
        assert!(
            (sum - total).abs().max_element() <= 1e-5 * total.abs().max_element().max(1.0),
            "path {i}: parts {sum} ≠ contribution {total}"
        );
    }
}

/// The mean over the traced paths, counting only what the film accepts.
fn film_mean(trace: &PixelTrace, spectral: bool) -> Vec3 {
    let mut sum = glam::DVec3::ZERO;
    for p in &trace.paths {
        let v = Vec3::from(p.contribution);
        let ok = if spectral {
            v.is_finite()
        } else {
            refract::film::sample_is_valid(v)
        };
        if ok {
            sum += v.as_dvec3();
        }
    }
    (sum / trace.paths.len() as f64).as_vec3()
}

#[test]
fn paths_are_the_renderers_samples() {
    // (scene, pixel, whether that pixel looks through glass)
    let cases = [
        ("cornell-glass", (24, 26), true),
        ("prism", (20, 14), false),
        ("glass-slab", (22, 15), true),
    ];
    for (name, px, through_glass) in cases {
        let scene = builtin::load(name).expect("builtin");
        let opts = small(&scene);
        let r = Renderer::new(scene).expect("scene");
        let trace = trace_pixel(&r, &opts, px, 64).expect("trace");
        assert_contributions_add_up(&trace.paths);
        let refracts = trace
            .paths
            .iter()
            .flat_map(|p| &p.vertices)
            .any(|v| v.event == VertexEvent::Refract);
        assert!(
            refracts || !through_glass,
            "{name} {px:?}: no path refracts"
        );
        let (film, _) = r.render(&opts, 64, None, |_| {});
        let rendered = film.pixel(px.0, px.1);
        let traced = film_mean(&trace, r.spectral);
        eprintln!("{name} {px:?}: rendered {rendered}, traced {traced}");
        assert!(
            rendered.max_element() > 0.0,
            "{name}: a black pixel proves nothing"
        );
        assert!(
            (rendered - traced).abs().max_element() <= 1e-5 * rendered.abs().max_element(),
            "{name}: rendered {rendered} ≠ traced mean {traced}"
        );
    }
}

#[test]
fn many_paths_estimate_the_converged_pixel() {
    // Independent seeds: the traced mean and a 1024-spp render agree within their errors.
    let scene = builtin::load("cornell-glass").expect("builtin");
    let mut opts = small(&scene);
    let px = (12, 30);
    let r = Renderer::new(scene).expect("scene");
    opts.seed = 1;
    let (film, _) = r.render(&opts, 1024, None, |_| {});
    opts.seed = 2;
    let trace = trace_pixel(&r, &opts, px, 4096).expect("trace");
    let n = trace.paths.len() as f64;
    let lum = |c: [f32; 3]| (c[0] as f64 + c[1] as f64 + c[2] as f64) / 3.0;
    let m = trace.paths.iter().map(|p| lum(p.contribution)).sum::<f64>() / n;
    let var = trace
        .paths
        .iter()
        .map(|p| (lum(p.contribution) - m).powi(2))
        .sum::<f64>()
        / (n - 1.0);
    let rendered = lum(film.pixel(px.0, px.1).to_array());
    // Standard error of the difference: the trace's variance / N plus the render's / 1024.
    let se = (var / n + var / 1024.0).sqrt();
    eprintln!(
        "traced {m} ± {}, rendered {rendered}, z = {}",
        (var / n).sqrt(),
        (m - rendered) / se
    );
    assert!(
        m > 0.0 && (m - rendered).abs() <= 4.0 * se,
        "traced {m}, rendered {rendered}, σ {se}"
    );
}

#[test]
fn a_pixel_outside_the_image_is_an_error() {
    let scene = builtin::load("glass-slab").expect("builtin");
    let opts = small(&scene);
    let r = Renderer::new(scene).expect("scene");
    let e = trace_pixel(&r, &opts, (opts.width, 0), 4).expect_err("outside");
    assert!(e.to_string().contains("outside"), "{e}");
    assert!(trace_pixel(&r, &opts, (0, 0), 0).is_err(), "zero paths");
}

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

const TRACE: &[&str] = &[
    "trace",
    "--scene",
    "builtin:glass-slab",
    "--width",
    "64",
    "--height",
    "48",
    "--pixel",
    "30",
    "20",
    "--paths",
    "6",
    "--json",
];

#[test]
fn cli_json_has_the_documented_shape() {
    let (ok, out, err) = refract(TRACE);
    assert!(ok, "{err}");
    let j: serde_json::Value = serde_json::from_str(&out).expect("JSON");
    assert_eq!(j["pixel"], serde_json::json!([30, 20]));
    let paths = j["paths"].as_array().expect("paths");
    assert_eq!(paths.len(), 6);
    let mut refractions = 0;
    for p in paths {
        assert!(
            p["heckbert"].as_str().is_some_and(|h| h.ends_with('E')),
            "{p}"
        );
        assert_eq!(p["contribution"].as_array().map(Vec::len), Some(3), "{p}");
        let vs = p["vertices"].as_array().expect("vertices");
        assert_eq!(vs.len(), p["heckbert"].as_str().map_or(0, str::len));
        for v in vs {
            for key in [
                "p",
                "class",
                "event",
                "material",
                "eta_i",
                "eta_t",
                "cos_i",
                "cos_t",
                "fresnel",
                "throughput",
            ] {
                assert!(v.get(key).is_some(), "vertex without '{key}': {v}");
            }
            assert_eq!(v["p"].as_array().map(Vec::len), Some(3));
            assert_eq!(v["throughput"].as_array().map(Vec::len), Some(3));
            if v["event"] == "refract" {
                refractions += 1;
                assert_eq!(v["material"], "glass");
                assert!(
                    v["eta_i"].is_f64() && v["cos_t"].is_f64() && v["fresnel"].is_f64(),
                    "{v}"
                );
            }
        }
    }
    assert!(
        refractions > 0,
        "pixel (30, 20) should look through the slab: {out}"
    );
    // Deterministic for a seed, different for another.
    let (_, again, _) = refract(TRACE);
    assert_eq!(out, again);
    let mut seeded = TRACE.to_vec();
    seeded.extend(["--seed", "5"]);
    let (_, other, _) = refract(&seeded);
    assert_ne!(out, other);
}

#[test]
fn cli_errors_name_the_flag() {
    let cases: &[(&[&str], &str)] = &[
        (
            &[
                "trace",
                "--scene",
                "builtin:glass-slab",
                "--pixel",
                "640",
                "0",
            ],
            "--pixel 640 0 is outside",
        ),
        (&["trace", "--pixel", "5", "5", "--paths", "0"], "--paths"),
        (
            &["trace", "--pixel", "5", "5", "--width", "0"],
            "--width/--height",
        ),
        (&["trace", "--pixel", "5"], "--pixel"),
        (&["trace", "--pixel", "5", "-3"], "--pixel"),
        (
            &["trace", "--pixel", "1", "1", "--filter", "LX"],
            "--filter",
        ),
    ];
    for (args, want) in cases {
        let (ok, _, err) = refract(args);
        assert!(!ok, "{args:?} succeeded");
        assert!(err.contains(want), "{args:?}: '{err}' lacks '{want}'");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
}

#[test]
fn table_lists_every_vertex() {
    let mut args: Vec<&str> = TRACE.to_vec();
    args.pop();
    let (ok, out, err) = refract(&args);
    assert!(ok, "{err}");
    assert!(out.contains("path 5:"), "{out}");
    assert!(out.contains("refract") && out.contains("glass"), "{out}");
    assert!(out.contains("light connection"), "{out}");
}
