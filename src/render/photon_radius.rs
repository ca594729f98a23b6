//! The photon-gathering radius of `sppm`, shared by the CPU and GPU renderers: r₁ a few
//! pixel footprints at the distance of the scene's centre, shrinking per iteration as
//! r_s² = r₁² · (s + 1)^(α − 1), α = 2/3 (Knaus & Zwicker 2011, "Progressive Photon Mapping:
//! A Probabilistic Approach", eq. 15 in closed form), so the average over iterations is
//! consistent.

use crate::scene::Camera;
use glam::Vec3;

/// The radius exponent of Knaus & Zwicker 2011 (and Hachisuka & Jensen 2009's α).
pub const ALPHA: f32 = 2.0 / 3.0;
/// The exponent of the radius schedule, (α − 1)/2: r_s = r₁ (s + 1)^RADIUS_EXPONENT (the GPU
/// evaluates it per iteration, `gpu::layout::Params::photon_radius_exp`).
pub const RADIUS_EXPONENT: f32 = (ALPHA - 1.0) / 2.0;
/// The first iteration's radius in pixel footprints at the scene's centre.
pub const RADIUS_PIXELS: f32 = 1.5;

/// r₁ (world units) for an image `height` pixels tall of a scene with `bounds` seen by `cam`.
pub fn radius0(cam: &Camera, bounds: (Vec3, Vec3), height: u32) -> f32 {
    let centre = 0.5 * (bounds.0 + bounds.1);
    let mut dist = (centre - cam.position).length();
    let diag = (bounds.1 - bounds.0).length();
    if !(dist.is_finite() && dist > 0.0) {
        dist = diag.max(1.0);
    }
    let footprint = dist * 2.0 * (0.5 * cam.yfov).tan() / height.max(1) as f32;
    let r = RADIUS_PIXELS * footprint;
    if r.is_finite() && r > 0.0 {
        r
    } else {
        1e-3 * diag.max(1e-6)
    }
}

/// The radius of iteration `s` (0-based): r₁ · (s + 1)^((α − 1)/2).
pub fn radius(r0: f32, s: u32) -> f32 {
    r0 * ((s as f64 + 1.0).powf(0.5 * (ALPHA as f64 - 1.0))) as f32
}
