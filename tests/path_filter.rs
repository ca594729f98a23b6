//! Heckbert path filters in the renderer: disjoint classes add up to the unfiltered image,
//! LDE is direct diffuse lighting, LS+DE only where caustics land.

use glam::Vec3;
use refract::cpu::Renderer;
use refract::paths::PathFilter;
use refract::render::RenderOptions;
use refract::scene::Scene;

fn setup() -> (Renderer, RenderOptions) {
    let s = Scene::load("builtin:cornell-glass").expect("builtin");
    let r = Renderer::new(s).expect("valid");
    let mut o = RenderOptions::from_scene(&r.scene);
    o.width = 48;
    o.height = 48;
    o.seed = 3;
    (r, o)
}

fn render(r: &Renderer, o: &RenderOptions, regex: &str, spp: u32) -> Vec<Vec3> {
    let mut o = *o;
    let f = PathFilter::parse(regex).expect("valid regex");
    o.filter = if f.is_accept_all() {
        None
    } else {
        Some(*f.reversed())
    };
    r.render(&o, spp, None, |_| {}).0.image()
}

fn assert_sum_equals(parts: &[Vec<Vec3>], whole: &[Vec3], what: &str) {
    let mut worst = 0.0f32;
    for (i, w) in whole.iter().enumerate() {
        let s: Vec3 = parts.iter().map(|p| p[i]).sum();
        let err = (s - *w).abs().max_element() / w.max_element().max(1e-3);
        worst = worst.max(err);
    }
    // Same seed ⇒ the same random numbers drive each class, so the sum is exact up to f32
    // rounding of the per-sample contributions.
    assert!(
        worst < 1e-4,
        "{what}: worst relative per-pixel mismatch {worst}"
    );
}

#[test]
fn disjoint_classes_sum_to_unfiltered() {
    let (r, o) = setup();
    let all = render(&r, &o, "", 8);
    let parts = [
        render(&r, &o, "LE", 8),
        render(&r, &o, "L(D|G|S)*DE", 8),
        render(&r, &o, "L(D|G|S)*(G|S)E", 8),
    ];
    assert_sum_equals(&parts, &all, "LE + L(D|G|S)*DE + L(D|G|S)*(G|S)E");
    let total: f32 = all.iter().map(|p| p.y).sum();
    assert!(total > 0.0);
    for (p, name) in parts.iter().zip(["LE", "L(D|G|S)*DE", "L(D|G|S)*(G|S)E"]) {
        let e: f32 = p.iter().map(|p| p.y).sum();
        assert!(e > 0.0, "class {name} is empty");
    }
}

#[test]
fn lde_is_direct_diffuse_lighting() {
    let (r, o) = setup();
    let mut o2 = o;
    o2.max_depth = 2; // emitters + direct lighting only (Mitsuba semantics)
    let direct = render(&r, &o2, "", 8);
    let parts = [
        render(&r, &o, "LDE", 8),
        render(&r, &o, "LE", 8),
        render(&r, &o, "L(S|G)E", 8),
    ];
    assert_sum_equals(&parts, &direct, "LDE + LE + L(S|G)E vs max_depth 2");
}

#[test]
fn caustic_class_only_on_diffuse_surfaces_lit_through_glass() {
    let (r, o) = setup();
    let img = render(&r, &o, "LS+DE", 32);
    // Pixels whose camera ray hits the glass sphere or the mirror first end in ...SE or ...SE:
    // they cannot be LS+DE and must be exactly zero. Find them with a primary-ray probe.
    let integ = r.integrator(&o);
    let cam = r.scene.camera;
    let aspect = o.width as f32 / o.height as f32;
    let (mut specular_px, mut nonzero_specular) = (0, 0);
    let (mut diffuse_sum, mut diffuse_n) = (0.0f64, 0);
    for y in 0..o.height {
        for x in 0..o.width {
            let d = cam.ray_dir(
                (x as f32 + 0.5) / o.width as f32,
                (y as f32 + 0.5) / o.height as f32,
                aspect,
            );
            let Some(h) = r.bvh.intersect(cam.position, d, f32::INFINITY) else {
                continue;
            };
            let hit = integ.surface(&h);
            let m = &r.scene.materials[hit.material as usize];
            let v = img[(y * o.width + x) as usize];
            // only count pixels well inside one object (the jittered samples hit the same)
            let kind_consistent = [
                (-0.49f32, -0.49f32),
                (0.49, 0.49),
                (-0.49, 0.49),
                (0.49, -0.49),
            ]
            .iter()
            .all(|(dx, dy)| {
                let d2 = cam.ray_dir(
                    (x as f32 + 0.5 + dx) / o.width as f32,
                    (y as f32 + 0.5 + dy) / o.height as f32,
                    aspect,
                );
                r.bvh
                    .intersect(cam.position, d2, f32::INFINITY)
                    .map(|h2| integ.surface(&h2).material == hit.material)
                    .unwrap_or(false)
            });
            if !kind_consistent {
                continue;
            }
            if m.is_transmissive() || m.kind == refract::scene::MaterialKind::Mirror {
                specular_px += 1;
                if v.max_element() > 0.0 {
                    nonzero_specular += 1;
                }
            } else if !m.is_emissive() {
                diffuse_sum += v.y as f64;
                diffuse_n += 1;
            }
        }
    }
    assert!(
        specular_px > 20,
        "the probe found only {specular_px} glass/mirror pixels"
    );
    assert_eq!(
        nonzero_specular, 0,
        "LS+DE leaked into pixels that see glass/mirror directly"
    );
    assert!(
        diffuse_n > 0 && diffuse_sum > 0.0,
        "no caustic light on diffuse surfaces at all"
    );
}

#[test]
fn invalid_regex_is_a_clear_cli_error() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_refract"))
        .args([
            "render", "--paths", "L(DE", "--spp", "1", "--width", "8", "--height", "8",
        ])
        .args(["--out", "/tmp/refract-invalid-regex.exr", "--quiet"])
        .output()
        .expect("run refract");
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("position"),
        "error does not name the position: {err}"
    );
    assert_eq!(
        err.trim().lines().count(),
        1,
        "error should be one line: {err}"
    );
}
