//! The O(1) per-connection forms agree with the direct ones on the subpaths the random walks
//! build: MIS weights from the stored partial sums (`mis::weight`) against the ratio
//! recurrence multiplied out (`mis_oracle`), and the Heckbert filter from stored prefix states
//! (`accepted`) against the whole string read from the start (`accepted_direct`).

use super::vertex::to_area;
use super::*;
use crate::cpu::Renderer;
use crate::paths::PathFilter;
use crate::render::RenderOptions;
use crate::scene::{PunctualLight, Scene};

/// Built-ins covering area, point, spot, directional and environment lights, glass, glossy
/// and dispersive materials (the MIS test skips samples whose light subpath starts at
/// infinity: `infinite_weight` weights those, not the recurrence).
fn scenes() -> Vec<Scene> {
    let mut names: Vec<Scene> = ["cornell-glass", "caustic", "prism", "materials", "sun-sky"]
        .iter()
        .map(|n| Scene::load(&format!("builtin:{n}")).expect("builtin"))
        .collect();
    let mut lit = Scene::load("builtin:cornell-glass").expect("builtin");
    lit.punctual_lights = vec![
        PunctualLight::Point {
            position: Vec3::new(0.3, 1.5, 0.2),
            intensity: Vec3::splat(2.0),
        },
        PunctualLight::Spot {
            position: Vec3::new(-0.4, 1.6, 0.0),
            direction: Vec3::new(0.1, -1.0, 0.0).normalize(),
            intensity: Vec3::splat(3.0),
            cos_inner: 0.9,
            cos_outer: 0.7,
        },
    ];
    names.push(lit);
    names
}

/// Both subpaths of one sample through pixel (x, y), with their prefix quantities.
fn subpaths<'a>(bd: &Bdpt<'a>, (x, y, i): (u32, u32, u32), scratch: &mut Scratch<'a>) {
    let max_depth = bd.pt.max_depth.max(1) as usize;
    scratch.cam.clear();
    scratch.light.clear();
    let mut sampler = Sampler::new(y * bd.cam.width + x, i, 3);
    let j = sampler.next_2d();
    let sp = bd.pt.lanes(|| sampler.next_1d());
    bd.camera_path(&mut scratch.cam, (x, y, j), max_depth, &mut sampler, &sp);
    let mut ls = sampler.with_dim(1 << 16);
    bd.light_path(&mut scratch.light, max_depth, &mut ls, &sp);
    bd.light_prefix_states(&mut scratch.light);
    mis::prefix_sums(&mut scratch.cam);
    mis::prefix_sums(&mut scratch.light);
}

/// Relative agreement to 1e-4 of two weights in [0, 1].
fn close(a: f32, b: f32) -> bool {
    a.is_finite() && b.is_finite() && (a - b).abs() <= 1e-4 * a.abs().max(b.abs()).max(1e-30)
}

/// The camera density of light vertex `y` as the t = 1 strategy computes it.
fn pdf_cam(bd: &Bdpt, cam0: &Vertex, y: &Vertex) -> f32 {
    let w = (cam0.p - y.p).normalize_or_zero();
    to_area(bd.cam.pdf_dir(-w), cam0, y)
}

#[test]
fn partial_sum_weights_equal_the_recurrence() {
    let mut compared = 0usize;
    for scene in scenes() {
        let r = Renderer::new(scene).expect("valid");
        let mut o = RenderOptions::from_scene(&r.scene);
        o.max_depth = 8;
        let integ = r.integrator(&o);
        let bd = Bdpt::new(&integ, BdptMode::Full, None, 24, 18);
        let mut scratch = Scratch::new();
        for (k, (x, y)) in (0..18)
            .flat_map(|y| (0..24).map(move |x| (x, y)))
            .enumerate()
        {
            subpaths(&bd, (x, y, k as u32), &mut scratch);
            let (cam, light) = (&scratch.cam, &scratch.light);
            if light.first().is_some_and(|v| v.is_infinite_light()) {
                continue; // weighted by `infinite_weight`, not by the recurrence
            }
            for t in 1..=cam.len() {
                for s in 0..=light.len() {
                    if s + t < 2 || (t == 1 && s == 0) {
                        continue;
                    }
                    let pdf_cam_y = (t == 1).then(|| pdf_cam(&bd, &cam[0], &light[s - 1]));
                    let (l, c) = (&light[..s], &cam[..t]);
                    let fast = mis::weight(l, c, &bd.connection_pdfs(l, c, t, pdf_cam_y));
                    let direct = bd.mis_weight(l, c, t, pdf_cam_y);
                    assert!(
                        close(fast, direct),
                        "{}: (s, t) = ({s}, {t}): {fast} vs {direct}",
                        r.scene.name
                    );
                    compared += 1;
                }
            }
        }
    }
    assert!(compared > 5000, "only {compared} strategies compared");
}

#[test]
fn prefix_filter_states_equal_the_whole_string() {
    let classes = [None, Some(Symbol::D), Some(Symbol::G), Some(Symbol::S)];
    let mut compared = 0usize;
    for regex in [
        "LS+DE",
        "L(D|G)*E",
        "LDS*E",
        "L(D|G|S)*E",
        "LS*DS+E",
        "LE",
        "L(S|D)D*G?E",
    ] {
        let filter = PathFilter::parse(regex).expect("regex");
        for scene in scenes().into_iter().take(4) {
            let r = Renderer::new(scene).expect("valid");
            let mut o = RenderOptions::from_scene(&r.scene);
            o.max_depth = 8;
            let integ = r.integrator(&o);
            let bd = Bdpt::new(&integ, BdptMode::Full, Some(filter.forward()), 16, 12);
            let mut scratch = Scratch::new();
            for (k, (x, y)) in (0..12)
                .flat_map(|y| (0..16).map(move |x| (x, y)))
                .enumerate()
            {
                subpaths(&bd, (x, y, k as u32), &mut scratch);
                let (cam, light) = (&scratch.cam, &scratch.light);
                for t in 1..=cam.len() {
                    for s in 0..=light.len() {
                        let (l, c) = (&light[..s.saturating_sub(1)], &cam[..t]);
                        for cy in classes {
                            for cz in classes {
                                assert_eq!(
                                    bd.accepted(l, cy, cz, c),
                                    bd.accepted_direct(l, cy, cz, c),
                                    "{regex}, s = {s}, t = {t}, {cy:?} {cz:?}"
                                );
                                compared += 1;
                            }
                        }
                    }
                }
            }
        }
    }
    assert!(compared > 10_000, "only {compared} filter checks");
}
