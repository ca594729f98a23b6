//! Scale invariance on the CPU: every built-in scene, wrapped in a root node scaled by 1e-5,
//! 1e-3, 1e3 and 1e5 (positions, camera, absorption distances and punctual lights scaled
//! alike), renders the image of the unscaled scene with the same seeds — image means within
//! 1% and a block Z-test — and the scaled white furnace stays 1 within 3σ. Before the wide
//! BVH's slab test had error bounds instead of obvhs' fixed 1e-4 cut-off, scale 1e-4 made
//! cornell-glass 20–23% darker and 1e-5 rendered black.

mod common_scenes;
use common_scenes::*;
use refract::cpu::Renderer;
use refract::film::Film;
use refract::render::{Estimator, RenderOptions};
use refract::scene::{PunctualLight, Scene, builtin};

const SCALES: [f32; 4] = [1e-5, 1e-3, 1e3, 1e5];

/// The scene as if under a root node with uniform scale `k`: lengths times k, radiance
/// unchanged, punctual intensities times k² (irradiance falls with distance²).
fn scaled(mut s: Scene, k: f32) -> Scene {
    for p in &mut s.mesh.positions {
        *p *= k;
    }
    s.camera.position *= k;
    for m in &mut s.materials {
        m.attenuation_distance *= k;
    }
    for l in &mut s.punctual_lights {
        match l {
            PunctualLight::Point {
                position,
                intensity,
            }
            | PunctualLight::Spot {
                position,
                intensity,
                ..
            } => {
                *position *= k;
                *intensity *= k * k;
            }
            PunctualLight::Directional { .. } => {}
        }
    }
    s
}

/// Built-in `name` at 32×32, depth ≤ 16 (small: this runs 5 scales × 11 scenes).
fn small(name: &str) -> Scene {
    let mut s = Scene::load(&format!("builtin:{name}")).expect("built-in");
    (s.settings.width, s.settings.height) = (32, 32);
    s.settings.max_depth = s.settings.max_depth.min(16);
    s
}

fn runs(s: Scene) -> Vec<Vec<f64>> {
    let r = Renderer::new(s).expect("valid scene");
    cpu_block_runs(&r, Estimator::Path, 8, None, 7, 4)
}

#[test]
fn builtin_scenes_render_alike_at_every_scale() {
    for name in builtin::NAMES {
        let base = runs(small(name));
        for k in SCALES {
            let img = runs(scaled(small(name), k));
            let t = assert_blocks_agree(&format!("{name} at scale {k:e}"), &base, &img);
            assert!(
                (t.mean_b - t.mean_a).abs() <= 0.01 * t.mean_a,
                "{name} at scale {k:e}: mean {:.5} vs {:.5} unscaled",
                t.mean_b,
                t.mean_a
            );
        }
    }
}

/// Mean and standard error of the pixel means of builtin:furnace scaled by `k`, per channel.
fn furnace(k: f32) -> Vec<(f64, f64)> {
    let mut s = scaled(Scene::load("builtin:furnace").expect("built-in"), k);
    (s.settings.width, s.settings.height) = (48, 24);
    let r = Renderer::new(s).expect("valid scene");
    let opts = RenderOptions::from_scene(&r.scene);
    let mut film = Film::new(opts.width, opts.height);
    r.render_pass(&opts, &mut film, 0, 32);
    assert_eq!(film.dropped, 0);
    let img = film.image();
    let n = img.len() as f64;
    (0..3)
        .map(|c| {
            let m = img.iter().map(|p| p[c] as f64).sum::<f64>() / n;
            let var = img.iter().map(|p| (p[c] as f64 - m).powi(2)).sum::<f64>() / (n - 1.0);
            (m, (var / n).sqrt())
        })
        .collect()
}

#[test]
fn scaled_white_furnace_stays_one() {
    for k in [1.0].into_iter().chain(SCALES) {
        for (c, (m, sem)) in furnace(k).into_iter().enumerate() {
            eprintln!("furnace at scale {k:e}, channel {c}: {m:.5} ± {sem:.5}");
            assert!(
                (m - 1.0).abs() <= 3.0 * sem.max(1e-6),
                "furnace at scale {k:e}, channel {c}: {m:.5} ± {sem:.5}"
            );
        }
    }
}
