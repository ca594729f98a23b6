//! Aimed photons (`render::photon_aim`) carry the same flux into the photon map as photons
//! emitted the way the lights emit them: the mean stored power per photon path agrees (Z-test
//! per channel) for area, two-sided area, point and spot lights, and a dispersive scene.

use super::*;
use crate::cpu::Renderer;
use crate::math::Color;
use crate::render::RenderOptions;
use crate::scene::{PunctualLight, Scene};
use glam::Vec3;

/// Mean and standard error per lane of the stored power per photon path, over `iterations`
/// photon passes of `paths` paths each.
fn flux(
    r: &Renderer,
    targets: Option<&PhotonTargets>,
    paths: u32,
    iterations: u32,
) -> [(f64, f64); 4] {
    let opts = RenderOptions::from_scene(&r.scene);
    let pt = r.integrator(&opts);
    let params = SppmParams {
        radius0: 0.01,
        photons_per_iteration: paths,
    };
    let (mut s1, mut s2) = ([0.0f64; 4], [0.0f64; 4]);
    for s in 0..iterations {
        let sp = pt.lanes(|| Sampler::new(u32::MAX, s, 5).next_1d());
        let pass = photon_pass(&pt, &params, s, 5, &sp, targets);
        // The flux of one iteration per path, as the density estimate weighs it.
        let mut sum = Color::ZERO;
        for ph in &pass.photons {
            sum += ph.beta * if ph.collapsed { 4.0 } else { 1.0 };
        }
        let x = sum / paths as f32;
        for k in 0..4 {
            s1[k] += x[k] as f64;
            s2[k] += (x[k] as f64).powi(2);
        }
    }
    let n = iterations as f64;
    std::array::from_fn(|k| {
        let m = s1[k] / n;
        (m, ((s2[k] / n - m * m).max(0.0) / n).sqrt())
    })
}

/// `caustic` with its glass block rough (α = 0.09, its own IOR, so no interface of it can be
/// index-matched): a caster that stores no photon, beside the smooth ball that does.
fn rough_block() -> Scene {
    let mut s = Scene::load("builtin:caustic").expect("builtin");
    let mut rough = crate::scene::Material::glass("rough block", 1.6);
    rough.roughness = 0.3;
    s.materials.push(rough);
    let id = s.materials.len() as u32 - 1;
    let ball = Vec3::new(0.0, 0.3, 0.0);
    let mut moved = 0;
    for t in 0..s.mesh.triangle_count() {
        let [a, b, c] = s.mesh.tri(t);
        if s.mesh.tri_material[t] == 1 && ((a + b + c) / 3.0).distance(ball) > 0.4 {
            s.mesh.tri_material[t] = id;
            moved += 1;
        }
    }
    assert_eq!(moved, 12, "the block's 12 triangles");
    s
}

fn scenes() -> Vec<(&'static str, Scene)> {
    let load = |n: &str| Scene::load(&format!("builtin:{n}")).expect("builtin");
    let mut punctual = load("caustic");
    // The area light off: a point light and a spot aimed past the ball.
    for m in &mut punctual.materials {
        m.emission = Vec3::ZERO;
    }
    punctual.punctual_lights = vec![
        PunctualLight::Point {
            position: Vec3::new(-1.2, 1.6, 0.3),
            intensity: Vec3::splat(20.0),
        },
        PunctualLight::Spot {
            position: Vec3::new(1.0, 1.8, 0.5),
            direction: Vec3::new(-0.5, -1.0, -0.3).normalize(),
            intensity: Vec3::splat(30.0),
            cos_inner: 0.95,
            cos_outer: 0.85,
        },
    ];
    let mut two_sided = load("caustic");
    for m in &mut two_sided.materials {
        if m.is_emissive() {
            m.double_sided = true;
        }
    }
    vec![
        ("caustic", load("caustic")),
        ("caustic, rough block", rough_block()),
        ("caustic, two-sided light", two_sided),
        ("caustic, point and spot", punctual),
        ("cornell-glass", load("cornell-glass")),
        ("caustic-mirror", load("caustic-mirror")),
        ("prism", load("prism")),
    ]
}

#[test]
fn aimed_photons_carry_the_lights_flux() {
    for (name, scene) in scenes() {
        let r = Renderer::new(scene).expect("valid");
        let (targets, fraction) = r.photon_aim();
        assert!(!targets.spheres.is_empty(), "{name}: no targets");
        let plain = flux(&r, None, 4096, 48);
        let aimed = flux(&r, Some(targets), 1024, 48);
        assert!(plain[0].0 > 0.0, "{name}: no caustic flux without aiming");
        for k in 0..4 {
            let ((a, sa), (b, sb)) = (aimed[k], plain[k]);
            if a == 0.0 && b == 0.0 {
                continue; // a spectral lane a dispersive vertex always collapses
            }
            let z = (a - b) / (sa * sa + sb * sb).sqrt();
            assert!(
                z.abs() < 4.0,
                "{name}, lane {k}: aimed {a} ± {sa}, plain {b} ± {sb}"
            );
        }
        // Where the casters take little of the light, aiming is worth it: the variance per
        // path traced is less than half (an aimed path, which goes through the glass, costs
        // more rays than one that lands on the floor).
        if *fraction < 0.1 {
            let per_path = |(_, se): (f64, f64), n: f64| se * se * n;
            let (a, p) = (per_path(aimed[0], 1024.0), per_path(plain[0], 4096.0));
            assert!(2.0 * a < p, "{name}: variance × paths {a} aimed, {p} plain");
        }
    }
}

/// The share of `paths` aimed photon paths that store a photon, over `iterations` passes.
fn stored_share(r: &Renderer, targets: &PhotonTargets, paths: u32, iterations: u32) -> f64 {
    let opts = RenderOptions::from_scene(&r.scene);
    let pt = r.integrator(&opts);
    let params = SppmParams {
        radius0: 0.01,
        photons_per_iteration: paths,
    };
    let stored: usize = (0..iterations)
        .map(|s| {
            let sp = pt.lanes(|| Sampler::new(u32::MAX, s, 9).next_1d());
            photon_pass(&pt, &params, s, 9, &sp, Some(targets))
                .photons
                .len()
        })
        .sum();
    stored as f64 / f64::from(paths * iterations)
}

/// Photon work per iteration is spent on photons: rough glass, which stores none, is no
/// target, so most aimed paths reach a diffuse surface through the smooth casters. With the
/// rough block aimed at as well (the targets of the same geometry all smooth), the share
/// stored falls with the block's share of the solid angle — the waste this rule removes.
#[test]
fn aimed_paths_store_photons() {
    let rough = Renderer::new(rough_block()).expect("valid");
    let (targets, _) = rough.photon_aim();
    assert_eq!(targets.spheres.len(), 1, "the ball only: {targets:?}");
    let share = stored_share(&rough, targets, 2048, 8);
    let mut smooth_scene = rough_block();
    if let Some(m) = smooth_scene.materials.last_mut() {
        m.roughness = 0.0;
    }
    let all = PhotonTargets::new(&smooth_scene);
    assert_eq!(all.spheres.len(), 7, "the ball and the block's six faces");
    let wasteful = stored_share(&rough, &all, 2048, 8);
    eprintln!("caustic, rough block: {share:.3} of the paths stored, {wasteful:.3} aimed at all");
    assert!(share > 0.5, "{share}");
    assert!(share > 1.5 * wasteful, "{share} vs {wasteful}");
    for name in ["caustic", "cornell-glass", "caustic-mirror", "glass-slab"] {
        let r = Renderer::new(Scene::load(&format!("builtin:{name}")).expect("builtin"))
            .expect("valid");
        let share = stored_share(&r, &r.photon_aim().0, 2048, 8);
        eprintln!("{name}: {share:.3} of the aimed paths stored");
        assert!(share > 0.2, "{name}: {share}");
    }
}
