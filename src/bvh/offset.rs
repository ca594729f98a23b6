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
///
/// On x86-64 the three coordinates go through SSE2 at once ([`offset_ray_origin_sse2`]),
/// bit for bit the scalar [`offset_ray_origin_scalar`] (the walks call this ~3 times per
/// vertex; the scalar form was 5 % of a cornell-glass render's instructions).
#[inline]
pub fn offset_ray_origin(p: Vec3, n: Vec3, scale: f32) -> Vec3 {
    #[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
    {
        offset_ray_origin_sse2(p, n, scale)
    }
    #[cfg(not(all(target_arch = "x86_64", target_feature = "sse2")))]
    {
        offset_ray_origin_scalar(p, n, scale)
    }
}

const ORIGIN: f32 = 1.0 / 32.0;
const FLOAT_SCALE: f32 = 1.0 / 65536.0;
const INT_SCALE: f32 = 256.0;

/// [`offset_ray_origin`] on the three lanes of one SSE2 register: Rust's saturating
/// `as i32` (NaN → 0, ≥ 2³¹ → `i32::MAX`, < −2³¹ → `i32::MIN`, the value `cvttps2dq`
/// already gives there), the signed integer step and the near-zero select, lane by lane.
#[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
#[inline]
pub fn offset_ray_origin_sse2(p: Vec3, n: Vec3, scale: f32) -> Vec3 {
    use glam::Vec3A;
    use std::arch::x86_64::*;
    let (pv, nv): (__m128, __m128) = (Vec3A::from(p).into(), Vec3A::from(n).into());
    // SAFETY: register arithmetic only (no memory access); SSE2 is enabled at compile time
    // (the `cfg` above), so every instruction exists on the machine running this.
    let r = unsafe {
        let x = _mm_mul_ps(_mm_set1_ps(INT_SCALE), nv);
        let too_big = _mm_castps_si128(_mm_cmpge_ps(x, _mm_set1_ps(2_147_483_648.0)));
        let mut of_i = _mm_cvttps_epi32(x);
        of_i = _mm_or_si128(
            _mm_and_si128(too_big, _mm_set1_epi32(i32::MAX)),
            _mm_andnot_si128(too_big, of_i),
        );
        of_i = _mm_and_si128(of_i, _mm_castps_si128(_mm_cmpord_ps(x, x)));
        // p < 0 (false for −0 and NaN, as in the scalar form): step the bits down, else up.
        let neg = _mm_castps_si128(_mm_cmplt_ps(pv, _mm_setzero_ps()));
        let step = _mm_sub_epi32(_mm_xor_si128(of_i, neg), neg);
        let pi = _mm_castsi128_ps(_mm_add_epi32(_mm_castps_si128(pv), step));
        let abs = _mm_andnot_ps(_mm_set1_ps(-0.0), pv);
        let near = _mm_cmplt_ps(abs, _mm_set1_ps(ORIGIN * scale));
        let pf = _mm_add_ps(pv, _mm_mul_ps(_mm_set1_ps(FLOAT_SCALE * scale), nv));
        _mm_or_ps(_mm_and_ps(near, pf), _mm_andnot_ps(near, pi))
    };
    Vec3::from(Vec3A::from(r))
}

/// [`offset_ray_origin`] one coordinate at a time (the reference the SIMD form must match).
#[cfg_attr(
    all(target_arch = "x86_64", target_feature = "sse2", not(test)),
    allow(dead_code)
)]
#[inline]
pub fn offset_ray_origin_scalar(p: Vec3, n: Vec3, scale: f32) -> Vec3 {
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

#[cfg(all(test, target_arch = "x86_64", target_feature = "sse2"))]
mod tests {
    use super::*;
    use crate::math::rng::Sampler;

    /// The SSE2 form equals the scalar one bit for bit, on random points and normals at
    /// every scale and on the edge values (±0, NaN, ±∞, huge, subnormal, near `ORIGIN`).
    #[test]
    fn sse2_offset_matches_scalar_bit_for_bit() {
        let edge = [
            0.0,
            -0.0,
            f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            1e30,
            -1e30,
            1e-40,
            -1e-40,
            ORIGIN,
            -ORIGIN,
            ORIGIN * 0.999,
            8.4e6,
            -3.0,
            0.7,
        ];
        let bits = |v: Vec3| [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()];
        let check = |p: Vec3, n: Vec3, scale: f32| {
            let (a, b) = (
                offset_ray_origin_sse2(p, n, scale),
                offset_ray_origin_scalar(p, n, scale),
            );
            assert_eq!(bits(a), bits(b), "p {p} n {n} scale {scale}");
        };
        for &a in &edge {
            for &b in &edge {
                check(Vec3::new(a, b, -a), Vec3::new(b, a, 1.0), 1.0);
                check(Vec3::new(b, 0.5, a), Vec3::new(a * 1e-3, -b, 0.0), 0.25);
            }
        }
        let mut s = Sampler::new(1, 2, 3);
        for i in 0..100_000 {
            let u = |s: &mut Sampler| (s.next_1d() - 0.5) * 2.0;
            let mag = 10f32.powi((i % 13) - 8);
            let p = Vec3::new(u(&mut s), u(&mut s), u(&mut s)) * mag;
            let n = Vec3::new(u(&mut s), u(&mut s), u(&mut s)).normalize_or_zero();
            check(p, n, [1.0, 0.5, 2f32.powi(-20)][i as usize % 3]);
        }
    }
}
