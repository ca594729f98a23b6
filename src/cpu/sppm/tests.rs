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
