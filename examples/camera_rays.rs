//! Whether camera-ray packets would pay (issue 14, part 3): closest-hit rays/s, one core, for
//! the camera rays of a 256² image in pixel order (coherent: neighbours share nodes) against
//! the same number of incoherent rays (`bench --quick`'s kind), and the share of a path
//! sample's queries that are camera rays.
//! Usage: cargo run --release --example camera_rays -- [scene]

use refract::cpu::Renderer;
use refract::cpu::camera_ray::camera_ray;
use refract::math::{rng::Sampler, sampling};
use refract::scene::Scene;
use refract::scene::camera::CameraRays;
use std::time::Instant;

const SIDE: u32 = 256;
const SPP: u32 = 8;

fn rate(rays: &[(glam::Vec3, glam::Vec3)], r: &Renderer) -> (f64, usize) {
    let mut best = 0.0f64;
    let mut hits = 0;
    for _ in 0..5 {
        let t = Instant::now();
        hits = rays
            .iter()
            .filter(|&&(o, d)| r.bvh.intersect(o, d, f32::INFINITY).is_some())
            .count();
        best = best.max(rays.len() as f64 / t.elapsed().as_secs_f64());
    }
    (best, hits)
}

fn main() -> anyhow::Result<()> {
    let spec = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "builtin:cornell-glass".into());
    let r = Renderer::new(Scene::load(&spec)?)?;
    let cam = CameraRays::new(&r.scene.camera);
    let mut coherent = Vec::new();
    for y in 0..SIDE {
        for x in 0..SIDE {
            for s in 0..SPP {
                let mut sampler = Sampler::new(y * SIDE + x, s, 1);
                let d = camera_ray(&cam, (x, y), (SIDE, SIDE), &mut sampler);
                coherent.push((cam.position, d));
            }
        }
    }
    let (lo, hi) = r.scene.bounds();
    let mut s = Sampler::new(0, 0, 1);
    let incoherent: Vec<_> = (0..coherent.len())
        .map(|_| {
            let u = glam::Vec3::new(s.next_1d(), s.next_1d(), s.next_1d());
            (
                lo + (hi - lo) * (0.1 + 0.8 * u),
                sampling::uniform_sphere(s.next_2d()),
            )
        })
        .collect();
    let (c, ch) = rate(&coherent, &r);
    let (i, ih) = rate(&incoherent, &r);
    println!(
        "{spec}: camera rays in pixel order {:.2} M rays/s ({ch} hits), incoherent {:.2} M rays/s \
         ({ih} hits), {:.2}x; best of 5, one core, {} rays each",
        c / 1e6,
        i / 1e6,
        c / i,
        coherent.len()
    );
    Ok(())
}
