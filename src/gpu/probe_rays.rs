//! Ray workloads for the traversal probe (`gpu::bvh_probe`): the rays one path-tracing
//! bounce of a scene traces — camera rays through a pixel grid, then from each camera hit a
//! bounce ray (uniform over the hemisphere the camera ray came from) and a shadow ray (to a
//! random point of a random emitting triangle, else a random hemisphere direction) — found
//! with the CPU BVH, so that the GPU layouts are compared on the same rays.

use super::layout::BvhProbeRay;
use crate::bvh::{Bvh, offset_ray_origin};
use crate::math::rng::Sampler;
use crate::scene::Scene;
use glam::Vec3;

/// The rays of one workload, by kind.
pub struct Workload {
    pub camera: Vec<BvhProbeRay>,
    pub bounce: Vec<BvhProbeRay>,
    pub shadow: Vec<BvhProbeRay>,
}

fn probe_ray(org: Vec3, dir: Vec3, tmax: f32, any_hit: bool) -> BvhProbeRay {
    BvhProbeRay {
        org: org.to_array(),
        tmax,
        dir: dir.to_array(),
        any_hit: u32::from(any_hit),
    }
}

/// A uniform direction on the hemisphere around `n`.
fn hemisphere(n: Vec3, s: &mut Sampler) -> Vec3 {
    let z = 1.0 - 2.0 * s.next_1d();
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = std::f32::consts::TAU * s.next_1d();
    let d = Vec3::new(r * phi.cos(), r * phi.sin(), z);
    if d.dot(n) < 0.0 { -d } else { d }
}

/// A uniform point of triangle `t`.
fn point_on(scene: &Scene, t: usize, s: &mut Sampler) -> Vec3 {
    let [a, b, c] = scene.mesh.tri(t);
    let (mut u, mut v) = (s.next_1d(), s.next_1d());
    if u + v > 1.0 {
        (u, v) = (1.0 - u, 1.0 - v);
    }
    a + (b - a) * u + (c - a) * v
}

/// The workload of `scene` over a `width` × `height` pixel grid (`seed` picks the jitter and
/// the directions).
pub fn workload(scene: &Scene, width: u32, height: u32, seed: u32) -> Workload {
    let bvh = Bvh::build(&scene.mesh);
    let emitters = scene.emissive_triangles();
    let aspect = width as f32 / height as f32;
    let mut w = Workload {
        camera: Vec::new(),
        bounce: Vec::new(),
        shadow: Vec::new(),
    };
    for y in 0..height {
        for x in 0..width {
            let mut s = Sampler::new(y * width + x, 0, seed);
            let (sx, sy) = (
                (x as f32 + s.next_1d()) / width as f32,
                (y as f32 + s.next_1d()) / height as f32,
            );
            let (o, d) = (scene.camera.position, scene.camera.ray_dir(sx, sy, aspect));
            w.camera.push(probe_ray(o, d, f32::MAX, false));
            let Some(hit) = bvh.intersect(o, d, f32::MAX) else {
                continue;
            };
            let [a, b, c] = scene.mesh.tri(hit.tri as usize);
            let mut n = (b - a).cross(c - a).normalize_or_zero();
            if n.dot(d) > 0.0 {
                n = -n;
            }
            let p = offset_ray_origin(o + d * hit.t, n, bvh.offset_scale());
            w.bounce
                .push(probe_ray(p, hemisphere(n, &mut s), f32::MAX, false));
            let shadow = if emitters.is_empty() {
                probe_ray(p, hemisphere(n, &mut s), f32::MAX, true)
            } else {
                let t = emitters[(s.next_1d() * emitters.len() as f32) as usize % emitters.len()];
                let to = point_on(scene, t as usize, &mut s) - p;
                let dist = to.length();
                probe_ray(p, to / dist, dist * (1.0 - 1e-4), true)
            };
            w.shadow.push(shadow);
        }
    }
    w
}
