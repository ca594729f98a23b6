//! The camera rays of the CPU's camera walks (path tracing, sppm's camera pass, the path
//! inspector): one function, so every walk draws the same rays from the same sampler
//! dimensions.

use crate::math::rng::Sampler;
use crate::scene::camera::CameraRays;
use glam::Vec3;

/// The direction of a path tracer's camera ray through pixel `(x, y)` of a `(w, h)` image:
/// a uniform jitter over the pixel square (box filter), the sampler's first two dimensions.
/// The renderer and the path inspector draw their camera rays only through this.
#[inline]
pub fn camera_ray(
    cam: &CameraRays,
    (x, y): (u32, u32),
    (w, h): (u32, u32),
    sampler: &mut Sampler,
) -> Vec3 {
    let j = sampler.next_2d();
    let sx = (x as f32 + j.x) / w as f32;
    let sy = (y as f32 + j.y) / h as f32;
    cam.dir(sx, sy, w as f32 / h as f32)
}
