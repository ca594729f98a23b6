//! Nested dielectrics (Schmidt & Budge 2002): the shared per-vertex step (`PathState::
//! interface`, `Interaction::new`, `PathState::scatter`) driven on rays built here, vertex by
//! vertex — a glass sphere in a water tank refracts with η = 1.5/1.33, an air bubble in glass
//! reflects totally beyond asin(1/1.5) and not before, priorities decide overlaps, a stack
//! overflow stays finite — and whole images: CPU path, CPU BDPT and GPU path agree on
//! glass-of-water (block Z-tests, as tests/absorption.rs), the nesting is visible (control), and
//! a non-nested scene renders bit-identically with the stack rule and the one-level rule.

mod common_scenes;
use common_scenes::*;
use glam::Vec3;
use refract::bsdf::{Bsdf, Event, TransportMode};
use refract::bvh::Bvh;
use refract::cpu::Renderer;
use refract::cpu::interaction::{Bounce, Interaction, offset_ray_origin_towards, surface};
use refract::cpu::medium::MEDIUM_STACK_DEPTH;
use refract::cpu::path_state::{Interface, PathState};
use refract::cpu::spectral::Spectral;
use refract::film::Film;
use refract::gpu::GpuRenderer;
use refract::math::Color;
use refract::render::{Estimator, RenderOptions};
use refract::scene::{Camera, Features, Material, Mesh, Scene};

/// One surface a followed ray met.
#[derive(Debug)]
struct Step {
    material: String,
    /// A real interface (else a false hit the ray passed).
    real: bool,
    /// The BSDF's η = n(inside)/n(enclosing) (0 for false hits).
    eta: f32,
    /// n_t/n_i of the sampled event, |cos θ| before and after (shading frame).
    eta_rel: f32,
    cos_i: f32,
    cos_t: f32,
    event: Option<Event>,
    /// The stack's entries after this surface, by name.
    stack: Vec<String>,
}

/// Follow the ray (o, d) through `scene` for up to `n` surfaces, choosing reflection or
/// transmission with `uc` at every dielectric (the walks' own step, nothing re-implemented).
fn follow(scene: &Scene, ray: (Vec3, Vec3), uc: f32, n: usize) -> Vec<Step> {
    follow_spectral(scene, ray, uc, n, &Spectral::RGB).0
}

/// [`follow`] with the path's colour lanes `sp`; also whether each real vertex was dispersive.
fn follow_spectral(
    scene: &Scene,
    (mut o, mut d): (Vec3, Vec3),
    uc: f32,
    n: usize,
    sp: &Spectral,
) -> (Vec<Step>, Vec<bool>) {
    let bvh = Bvh::build(&scene.mesh);
    let sp = *sp;
    let mut dispersive = vec![];
    let mut st = PathState::new(Color::ONE, false, true);
    let names = |st: &PathState| -> Vec<String> {
        st.media
            .entries()
            .iter()
            .map(|&m| scene.materials[m as usize].name.clone())
            .collect()
    };
    let mut steps = vec![];
    while steps.len() < n {
        let Some(h) = bvh.intersect(o, d, f32::INFINITY) else {
            break;
        };
        let hit = surface(scene, &h);
        let material = scene.materials[hit.material as usize].name.clone();
        let enclosing = match st.interface(scene, &hit, d) {
            Interface::Real(m) => m,
            Interface::Pass => {
                steps.push(Step {
                    material,
                    real: false,
                    eta: 0.0,
                    eta_rel: 1.0,
                    cos_i: 0.0,
                    cos_t: 0.0,
                    event: None,
                    stack: names(&st),
                });
                o = offset_ray_origin_towards(hit.p, hit.ng, d.dot(hit.ng), bvh.offset_scale());
                continue;
            }
            Interface::Lost => panic!("path lost after {} false hits", st.false_hits),
        };
        let it = Interaction::new(scene, &hit, d, &sp, bvh.offset_scale(), enclosing)
            .expect("a dielectric interaction");
        let Bsdf::SmoothDielectric(b) = it.bsdf else {
            panic!("{material}: not a smooth dielectric");
        };
        let Bounce::Continue { s, wi } = it.sample(uc, glam::Vec2::ZERO, TransportMode::Radiance)
        else {
            panic!("{material}: no sample");
        };
        st.scatter(scene, &it, &s, wi, TransportMode::Radiance);
        dispersive.push(it.dispersive);
        steps.push(Step {
            material,
            real: true,
            eta: b.eta,
            eta_rel: s.eta_rel,
            cos_i: it.wo.z.abs(),
            cos_t: s.wi.z.abs(),
            event: Some(s.event),
            stack: names(&st),
        });
        o = it.spawn(wi);
        d = wi;
    }
    (steps, dispersive)
}

fn glass(name: &str, ior: f32, priority: i32) -> Material {
    Material {
        priority,
        ..Material::glass(name, ior)
    }
}

fn test_scene(name: &str, mesh: Mesh, materials: Vec<Material>) -> Scene {
    let cam = Camera::look_at(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, Vec3::Y, 0.8);
    scene(name, mesh, materials, cam, 1.0)
}

/// A water tank (n = 1.33, 2 m cube) holding a glass sphere (n = 1.5, r = 0.5 m), flat-shaded
/// so that Snell's law holds exactly about the geometric normal.
fn sphere_in_tank() -> Scene {
    let mut m = Mesh::default();
    cuboid(&mut m, Vec3::splat(-1.0), Vec3::splat(1.0), 0);
    sphere(&mut m, Vec3::ZERO, 0.5, 48, 96, 1);
    let materials = vec![glass("water", 1.33, 0), glass("glass", 1.5, 0)];
    test_scene("sphere-in-tank", flatten(&m), materials)
}

const TRANSMIT: f32 = 1.0 - 1e-6;

#[test]
fn sphere_in_water_refracts_with_relative_ior() {
    let scene = sphere_in_tank();
    assert!(scene.features().contains(Features::NESTED));
    let steps = follow(&scene, (Vec3::new(0.21, 0.13, 3.0), -Vec3::Z), TRANSMIT, 4);
    for s in &steps {
        eprintln!("{s:?}");
    }
    let want = [
        // (surface, η of its BSDF, n_t/n_i of the transmission, stack after)
        ("water", 1.33, 1.33, vec!["water"]),
        ("glass", 1.5 / 1.33, 1.5 / 1.33, vec!["water", "glass"]),
        ("glass", 1.5 / 1.33, 1.33 / 1.5, vec!["water"]),
        ("water", 1.33, 1.0 / 1.33, vec![]),
    ];
    assert_eq!(steps.len(), want.len(), "{steps:?}");
    for (i, (s, (mat, eta, eta_rel, stack))) in steps.iter().zip(want).enumerate() {
        assert!(s.real, "vertex {i}: {s:?}");
        assert_eq!(s.material, mat, "vertex {i}");
        assert!(
            (s.eta - eta).abs() < 1e-6,
            "vertex {i}: η {} ≠ {eta}",
            s.eta
        );
        assert_eq!(s.event, Some(Event::Transmit), "vertex {i}");
        assert!((s.eta_rel - eta_rel).abs() < 1e-6, "vertex {i}: {s:?}");
        // Snell: n_i sin θi = n_t sin θt, i.e. sin θi = (n_t/n_i) sin θt.
        let (si, stt) = (
            (1.0 - s.cos_i * s.cos_i).max(0.0).sqrt(),
            (1.0 - s.cos_t * s.cos_t).max(0.0).sqrt(),
        );
        assert!(
            (si - s.eta_rel * stt).abs() < 1e-5,
            "vertex {i}: Snell {si} vs {}",
            s.eta_rel * stt
        );
        assert_eq!(s.stack, stack, "vertex {i}");
    }
    // The sphere really bends the ray (an off-axis hit, not normal incidence).
    assert!(steps[1].cos_i < 0.95, "{:?}", steps[1]);
}

#[test]
fn dispersion_takes_both_iors_at_the_hero_wavelength() {
    let sp = Spectral {
        lambdas: Some([450.0, 520.0, 590.0, 660.0]),
        line: None,
    };
    let ray = (Vec3::new(0.21, 0.13, 3.0), -Vec3::Z);
    // Dispersive glass in plain water, then plain glass in dispersive water.
    for (glass_abbe, water_abbe) in [(Some(20.0), None), (None, Some(30.0))] {
        let mut scene = sphere_in_tank();
        scene.materials[0].abbe = water_abbe;
        scene.materials[1].abbe = glass_abbe;
        let (w, g) = (&scene.materials[0], &scene.materials[1]);
        let want = g.ior_at(450.0) / w.ior_at(450.0);
        assert!((want - 1.5 / 1.33).abs() > 1e-3, "n(λ) differs from n_d");
        let (steps, dispersive) = follow_spectral(&scene, ray, TRANSMIT, 4, &sp);
        assert_eq!(steps[1].material, "glass");
        assert!(
            (steps[1].eta - want).abs() < 1e-6,
            "{} vs {want}",
            steps[1].eta
        );
        assert!((steps[2].eta - want).abs() < 1e-6);
        assert!(
            dispersive[1] && dispersive[2],
            "the glass/water interface disperses"
        );
        assert_eq!(dispersive[0], water_abbe.is_some(), "air/water");
    }
}

/// A glass block (n = 1.5) with an air bubble (n = 1, r = 0.5 m) at its centre, smooth-shaded
/// so that the incidence angle varies continuously with the impact parameter.
fn bubble_in_glass() -> Scene {
    let mut m = Mesh::default();
    cuboid(&mut m, Vec3::splat(-1.0), Vec3::splat(1.0), 0);
    sphere(&mut m, Vec3::ZERO, 0.5, 96, 192, 1);
    let materials = vec![glass("glass", 1.5, 0), glass("air", 1.0, 0)];
    test_scene("bubble-in-glass", m, materials)
}

#[test]
fn air_bubble_in_glass_reflects_totally_beyond_the_critical_angle() {
    let scene = bubble_in_glass();
    let sin_c = 1.0 / 1.5; // sin of the critical angle asin(n_air/n_glass)
    let (mut tir, mut refr) = (0, 0);
    let (mut onset, mut last_refracted) = (f32::INFINITY, 0.0f32);
    for k in 0..200 {
        // Impact parameters b across the critical one (sin θ ≈ b / r on the bubble).
        let b = 0.5 * (0.55 + 0.25 * k as f32 / 199.0);
        let steps = follow(&scene, (Vec3::new(b, 0.0, 3.0), -Vec3::Z), TRANSMIT, 2);
        assert_eq!(steps[0].material, "glass");
        let s = &steps[1];
        assert_eq!(s.material, "air", "{s:?}");
        assert!((s.eta - 1.0 / 1.5).abs() < 1e-6, "bubble η {}", s.eta);
        let sin_i = (1.0 - s.cos_i * s.cos_i).max(0.0).sqrt();
        let reflected = s.event == Some(Event::Reflect);
        if sin_i > sin_c + 1e-4 {
            assert!(reflected, "sin θ = {sin_i} beyond critical but {s:?}");
            tir += 1;
        } else if sin_i < sin_c - 1e-3 {
            assert!(!reflected, "sin θ = {sin_i} before critical but reflected");
            assert_eq!(s.stack, ["glass", "air"], "refraction enters the bubble");
            refr += 1;
        }
        if reflected {
            onset = onset.min(sin_i);
            assert_eq!(s.stack, ["glass"], "TIR keeps the path in the glass");
        } else {
            last_refracted = last_refracted.max(sin_i);
        }
    }
    // The analytic critical angle lies between the last refracted and the first totally
    // reflected ray of the sweep (steps of about 1.3e-3 in sin θ).
    eprintln!(
        "refracted up to sin θ = {last_refracted}, TIR from {onset}, analytic {sin_c}; \
         {tir} TIR, {refr} refracted"
    );
    assert!(
        tir > 20 && refr > 20,
        "the sweep straddles the critical angle"
    );
    assert!(last_refracted < sin_c && sin_c <= onset && onset - last_refracted < 4e-3);
}

/// Two overlapping boxes: A = [−1, 0.5]³-ish (n = 1.5), B shifted along −z (n = 1.2).
fn overlapping(prio_a: i32, prio_b: i32) -> Scene {
    let mut m = Mesh::default();
    cuboid(
        &mut m,
        Vec3::new(-1.0, -1.0, -0.5),
        Vec3::new(1.0, 1.0, 1.0),
        0,
    );
    cuboid(
        &mut m,
        Vec3::new(-1.2, -1.2, -1.0),
        Vec3::new(1.2, 1.2, 0.5),
        1,
    );
    test_scene(
        "overlap",
        m,
        vec![glass("A", 1.5, prio_a), glass("B", 1.2, prio_b)],
    )
}

fn summary(steps: &[Step]) -> Vec<(String, bool, f32)> {
    steps
        .iter()
        .map(|s| (s.material.clone(), s.real, (s.eta * 1e4).round() / 1e4))
        .collect()
}

#[test]
fn priority_decides_overlapping_volumes() {
    // Along −z at normal incidence (straight through): A's front face, B's front face (inside
    // A), A's back face (inside B), B's back face.
    let ray = (Vec3::new(0.1, 0.2, 3.0), -Vec3::Z);
    let r = |x: f32| (x * 1e4).round() / 1e4;
    let a_wins = summary(&follow(&overlapping(1, 0), ray, TRANSMIT, 8));
    let s = |m: &str, real, eta: f32| (m.to_string(), real, r(eta));
    assert_eq!(
        a_wins,
        [
            s("A", true, 1.5),
            s("B", false, 0.0),
            s("A", true, 1.5 / 1.2),
            s("B", true, 1.2),
        ]
    );
    let b_wins = summary(&follow(&overlapping(0, 2), ray, TRANSMIT, 8));
    assert_eq!(
        b_wins,
        [
            s("A", true, 1.5),
            s("B", true, 1.2 / 1.5),
            s("A", false, 0.0),
            s("B", true, 1.2),
        ]
    );
    // Equal priority: the volume entered last is the medium (B, entered inside A).
    let equal = summary(&follow(&overlapping(0, 0), ray, TRANSMIT, 8));
    assert_eq!(
        equal,
        [
            s("A", true, 1.5),
            s("B", true, 1.2 / 1.5),
            s("A", false, 0.0),
            s("B", true, 1.2),
        ]
    );
}

/// Six concentric spheres (n = 1.1 … 1.6 inwards): deeper than the stack.
fn onion() -> Scene {
    let mut m = Mesh::default();
    let mut materials = vec![];
    for k in 0..6u32 {
        sphere(&mut m, Vec3::ZERO, 1.0 - 0.12 * k as f32, 32, 64, k);
        materials.push(glass(&format!("s{k}"), 1.1 + 0.1 * k as f32, 0));
    }
    let mut s = test_scene("onion", m, materials);
    s.settings.max_depth = 24;
    s
}

#[test]
fn stack_overflow_is_safe() {
    const { assert!(MEDIUM_STACK_DEPTH < 6, "the onion must overflow the stack") };
    let scene = onion();
    let steps = follow(
        &scene,
        (Vec3::new(0.013, 0.021, 3.0), -Vec3::Z),
        TRANSMIT,
        12,
    );
    assert_eq!(steps.len(), 12, "{steps:?}");
    // The fifth entry forgets the outermost: four volumes stay tracked, innermost exact.
    assert_eq!(steps[5].stack, ["s2", "s3", "s4", "s5"]);
    assert!((steps[5].eta - 1.6 / 1.5).abs() < 1e-6);
    // Leaving s1 and s0 after the overflow: s1 is still known, s0 was forgotten and is left
    // towards air (a real interface, the stack unchanged).
    assert!((steps[10].eta - 1.2).abs() < 1e-6, "{:?}", steps[10]);
    assert!((steps[11].eta - 1.1).abs() < 1e-6, "{:?}", steps[11]);
    assert!(steps.iter().all(|s| s.real && s.eta.is_finite()));
    assert!(steps[11].stack.is_empty());
    // A whole image through the onion: no panic, no NaN, nothing dropped.
    let r = Renderer::new(scene).expect("valid scene");
    let opts = RenderOptions::from_scene(&r.scene);
    let mut film = Film::new(opts.width, opts.height);
    r.render_pass(&opts, &mut film, 0, 8);
    assert_eq!(film.dropped, 0);
    assert!(film.image().iter().all(|c| c.is_finite()));
}

const RUNS: u32 = 8;

/// glass-of-water at 48², the camera closer so that the glass fills the frame.
fn small_glass_of_water() -> Scene {
    let mut s = Scene::load("builtin:glass-of-water").expect("builtin");
    s.settings.width = 48;
    s.settings.height = 48;
    s.camera = Camera::look_at(
        Vec3::new(0.0, 0.22, 0.45),
        Vec3::new(0.0, 0.12, 0.0),
        Vec3::Y,
        0.5,
    );
    s
}

/// Block means of `RUNS` independent CPU renders (seeds `seed0`…) of `spp` each.
fn cpu_runs(scene: &Scene, est: Estimator, spp: u32, seed0: u32, nested: bool) -> Vec<Vec<f64>> {
    cpu_runs_filtered(scene, (est, None), spp, seed0, nested)
}

/// [`cpu_runs`] restricted to the Heckbert paths of `filter`.
fn cpu_runs_filtered(
    scene: &Scene,
    (est, filter): (Estimator, Option<&str>),
    spp: u32,
    seed0: u32,
    nested: bool,
) -> Vec<Vec<f64>> {
    let mut r = Renderer::new(scene.clone()).expect("valid scene");
    r.nested = nested;
    cpu_block_runs(&r, est, spp, filter, seed0, RUNS)
}

fn assert_agree(name: &str, a: &[Vec<f64>], b: &[Vec<f64>]) {
    assert_blocks_agree(name, a, b);
}

#[test]
fn glass_of_water_bdpt_and_lt_agree_with_path_tracing() {
    let scene = small_glass_of_water();
    assert!(scene.features().contains(Features::NESTED));
    let path = cpu_runs(&scene, Estimator::Path, 64, 0, true);
    let bdpt = cpu_runs(&scene, Estimator::Bdpt, 16, 100, true);
    assert_agree("glass-of-water: bdpt vs path", &bdpt, &path);
    // Light tracing reaches the camera only from non-specular vertices.
    let f = Some("L(D|G|S)*DE");
    let path_d = cpu_runs_filtered(&scene, (Estimator::Path, f), 64, 300, true);
    let lt_d = cpu_runs_filtered(&scene, (Estimator::Lt, f), 32, 400, true);
    assert_agree("glass-of-water, L(D|G|S)*DE: lt vs path", &lt_d, &path_d);
    // Control: the one-level rule (water and glass both against air, the overlap wrong) gives
    // a measurably different image, so the comparisons above test the stack.
    let flat = cpu_runs(&scene, Estimator::Path, 64, 200, false);
    let t = block_z_test(&flat, &path);
    eprintln!(
        "control: one-level vs nested: {}/{} blocks within 3σ",
        t.pass, t.blocks
    );
    // (It fails the criterion the nested estimators pass.)
    assert!(
        t.rate() < 0.9 || t.z_image.abs() > 4.0,
        "nesting is not visible: {:.1}% of blocks agree",
        t.rate() * 100.0
    );
}

#[test]
fn glass_of_water_gpu_agrees_with_cpu() {
    let Some(ctx) = gpu_context("glass-of-water (GPU)") else {
        return;
    };
    let scene = small_glass_of_water();
    let cpu = cpu_runs(&scene, Estimator::Path, 64, 0, true);
    let mut g = GpuRenderer::with_context(ctx, scene.clone(), RenderOptions::from_scene(&scene))
        .expect("GPU renderer");
    assert!(g.specialization().nested, "the nested kernel is used");
    for est in [Estimator::Path, Estimator::LtPt] {
        g.set_estimator(est).expect("estimator");
        assert_eq!(g.specialization().light_tracing, est == Estimator::LtPt);
        let runs: Vec<Vec<f64>> = (0..RUNS)
            .map(|i| {
                let mut opts = RenderOptions::from_scene(&scene);
                opts.seed = 1000 + i;
                g.set_options(opts).expect("options");
                let img = g.render(16).expect("render");
                assert_eq!(img.dropped, 0, "GPU {est}: the firewall dropped samples");
                block_means(&img.mean, 48, 48)
            })
            .collect();
        assert_agree(
            &format!("glass-of-water: GPU {est} vs CPU path"),
            &runs,
            &cpu,
        );
    }
}

#[test]
fn dispersive_glass_of_water_gpu_agrees_with_cpu() {
    let Some(ctx) = gpu_context("dispersive glass-of-water (GPU)") else {
        return;
    };
    let mut scene = small_glass_of_water();
    for m in scene.materials.iter_mut().filter(|m| m.name == "glass") {
        m.abbe = Some(20.0);
    }
    let f = scene.features();
    assert!(f.contains(Features::NESTED) && f.contains(Features::DISPERSION));
    let cpu = cpu_runs(&scene, Estimator::Path, 64, 0, true);
    let mut g = GpuRenderer::with_context(ctx, scene.clone(), RenderOptions::from_scene(&scene))
        .expect("GPU renderer");
    let runs: Vec<Vec<f64>> = (0..RUNS)
        .map(|i| {
            let mut opts = RenderOptions::from_scene(&scene);
            opts.seed = 1000 + i;
            g.set_options(opts).expect("options");
            let img = g.render(16).expect("render");
            assert_eq!(img.dropped, 0, "GPU: the firewall dropped samples");
            block_means(&img.mean, 48, 48)
        })
        .collect();
    assert_agree(
        "dispersive glass-of-water: GPU path vs CPU path",
        &runs,
        &cpu,
    );
}

#[test]
fn non_nested_scene_renders_identically_with_the_stack() {
    let mut scene = Scene::load("builtin:cornell-glass").expect("builtin");
    scene.settings.width = 40;
    scene.settings.height = 40;
    assert!(!scene.features().contains(Features::NESTED));
    let mut r = Renderer::new(scene).expect("valid scene");
    let mut render = |nested: bool, est: Estimator| {
        r.nested = nested;
        let mut opts = RenderOptions::from_scene(&r.scene);
        opts.estimator = est;
        let mut film = Film::new(opts.width, opts.height);
        r.render_pass(&opts, &mut film, 0, 8);
        film.image()
    };
    for est in [Estimator::Path, Estimator::Bdpt] {
        let (one, stack) = (render(false, est), render(true, est));
        assert!(one.iter().any(|c| c.max_element() > 0.0));
        assert_eq!(
            one, stack,
            "{est}: the stack rule changed a non-nested image"
        );
    }
}

#[test]
fn only_nested_builtins_get_the_stack() {
    for name in refract::scene::builtin::NAMES {
        let s = Scene::load(&format!("builtin:{name}")).expect("builtin");
        let nested = s.features().contains(Features::NESTED);
        assert_eq!(nested, *name == "glass-of-water", "{name}");
    }
    // A priority alone asks for the stack; disjoint volumes do not.
    let mut m = Mesh::default();
    sphere(&mut m, Vec3::new(-1.0, 0.0, 0.0), 0.4, 8, 16, 0);
    sphere(&mut m, Vec3::new(1.0, 0.0, 0.0), 0.4, 8, 16, 1);
    let mut s = test_scene("apart", m, vec![glass("a", 1.5, 0), glass("b", 1.3, 0)]);
    assert!(!s.features().contains(Features::NESTED));
    s.materials[1].priority = 3;
    assert!(s.features().contains(Features::NESTED));
}
