//! Ray-origin offsets that work at every scene scale.

use crate::scene::Mesh;
use glam::Vec3;

/// The largest power of two ≤ `x` (a positive normal float): its mantissa cleared.
#[inline]
fn pow2_floor(x: f32) -> f32 {
    f32::from_bits(x.to_bits() & 0xff80_0000)
}

/// The largest side of the mesh's bounding box (NaN or −∞ for an empty mesh).
pub(super) fn mesh_extent(mesh: &Mesh) -> f32 {
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for p in &mesh.positions {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    (hi - lo).max_element()
}

/// Offset a ray origin off a surface along the geometric normal `n` (pointing to the side
/// the ray leaves towards), by a few ULPs of the position's magnitude so that it works at any
/// scene scale. Wächter & Binder 2019, "A Fast and Robust Method for Avoiding
/// Self-Intersection", Ray Tracing Gems ch. 6, listing 6-1, with its two constants for
/// coordinates near zero (`ORIGIN`, `FLOAT_SCALE`, tuned for scenes of unit size) multiplied
/// by the scene's power-of-two `scale` (`offset_scale`), so the near-zero offset follows the
/// scene (a fixed 2⁻¹⁶ m threw rays out of a scene 1e-5 m across).
#[inline]
pub fn offset_ray_origin(p: Vec3, n: Vec3, scale: f32) -> Vec3 {
    const ORIGIN: f32 = 1.0 / 32.0;
    const FLOAT_SCALE: f32 = 1.0 / 65536.0;
    const INT_SCALE: f32 = 256.0;
    let (origin, float_scale) = (ORIGIN * scale, FLOAT_SCALE * scale);
    let off = |p: f32, n: f32| -> f32 {
        let of_i = (INT_SCALE * n) as i32;
        let bits = p.to_bits() as i32;
        let moved = if p < 0.0 {
            bits.wrapping_sub(of_i)
        } else {
            bits.wrapping_add(of_i)
        };
        let pi = f32::from_bits(moved as u32);
        if p.abs() < origin {
            p + float_scale * n
        } else {
            pi
        }
    };
    Vec3::new(off(p.x, n.x), off(p.y, n.y), off(p.z, n.z))
}

/// The power of two the ray-offset constants scale with: 2^⌊log₂(extent/2)⌋ of the mesh's
/// largest bounding-box side for scenes under 4 m (so a scene 1e-6 m across keeps its rays),
/// and 1 above (the constants are absolute floors for coordinates near zero: growing them with
/// the scene would step over thin features near the origin, e.g. a 0.1 mm slab in a 100 m
/// scene); 1 for an empty or degenerate mesh.
pub fn offset_scale(mesh: &Mesh) -> f32 {
    offset_scale_for(mesh_extent(mesh))
}

pub(super) fn offset_scale_for(extent: f32) -> f32 {
    let half = 0.5 * extent;
    if !half.is_finite() || half <= 0.0 {
        return 1.0;
    }
    pow2_floor(half.clamp(2f32.powi(-100), 1.0))
}
