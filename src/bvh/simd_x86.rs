//! x86-64 slab tests: AVX2 (all 8 children in one register) and SSE (4 at a time). The
//! arithmetic is `slab::Scalar`'s, operand order included (`maxps(t, acc)` returns `acc` when
//! `t` is NaN), so all flavours return the same mask.

use super::slab::{BoxTest, FAR_SCALE, SlabRay};
use super::wide::{W, WideNode};
use std::arch::x86_64::*;

pub struct Avx2;

impl BoxTest for Avx2 {
    #[inline(always)]
    fn test(node: &WideNode, ray: &SlabRay, tmax: f32, tnear: &mut [f32; W]) -> u32 {
        const { assert!(W == 8) };
        // SAFETY: only selected when `is_x86_feature_detected!("avx2")` held (`Kernel::detect`),
        // and only called inlined into `#[target_feature(enable = "avx2")]` functions. The
        // loads read the 8 floats of one `[f32; 8]` row and the store writes the 8 of `tnear`
        // (unaligned forms: no alignment requirement).
        unsafe {
            let slab = |row: &[f32; W], a: usize| {
                let b = _mm256_loadu_ps(row.as_ptr());
                _mm256_mul_ps(
                    _mm256_sub_ps(b, _mm256_set1_ps(ray.org[a])),
                    _mm256_set1_ps(ray.inv[a]),
                )
            };
            let mut tn = _mm256_setzero_ps();
            let mut tf = _mm256_set1_ps(f32::INFINITY);
            for a in 0..3 {
                let (near, far) = ray.rows(node, a);
                tn = _mm256_max_ps(slab(near, a), tn);
                tf = _mm256_min_ps(slab(far, a), tf);
            }
            tf = _mm256_min_ps(
                _mm256_mul_ps(tf, _mm256_set1_ps(FAR_SCALE)),
                _mm256_set1_ps(tmax),
            );
            _mm256_storeu_ps(tnear.as_mut_ptr(), tn);
            _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(tn, tf)) as u32
        }
    }
}

pub struct Sse;

impl BoxTest for Sse {
    #[inline(always)]
    fn test(node: &WideNode, ray: &SlabRay, tmax: f32, tnear: &mut [f32; W]) -> u32 {
        const { assert!(W.is_multiple_of(4)) };
        let mut mask = 0;
        for h in 0..W / 4 {
            // SAFETY: SSE is part of the x86-64 baseline. The loads read floats 4h..4h+4 of
            // one `[f32; W]` row and the store writes the same 4 of `tnear` (in bounds: 4h + 4
            // ≤ W; unaligned forms).
            let m = unsafe {
                let slab = |row: &[f32; W], a: usize| {
                    let b = _mm_loadu_ps(row.as_ptr().add(4 * h));
                    _mm_mul_ps(
                        _mm_sub_ps(b, _mm_set1_ps(ray.org[a])),
                        _mm_set1_ps(ray.inv[a]),
                    )
                };
                let mut tn = _mm_setzero_ps();
                let mut tf = _mm_set1_ps(f32::INFINITY);
                for a in 0..3 {
                    let (near, far) = ray.rows(node, a);
                    tn = _mm_max_ps(slab(near, a), tn);
                    tf = _mm_min_ps(slab(far, a), tf);
                }
                tf = _mm_min_ps(_mm_mul_ps(tf, _mm_set1_ps(FAR_SCALE)), _mm_set1_ps(tmax));
                _mm_storeu_ps(tnear.as_mut_ptr().add(4 * h), tn);
                _mm_movemask_ps(_mm_cmple_ps(tn, tf)) as u32
            };
            mask |= m << (4 * h);
        }
        mask
    }
}
