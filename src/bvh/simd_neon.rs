//! aarch64 slab test: NEON, 4 children at a time. `vmaxnmq`/`vminnmq` (IEEE maxNum/minNum)
//! return the non-NaN operand, which is `slab::Scalar`'s NaN rule.

use super::slab::{BoxTest, FAR_SCALE, SlabRay};
use super::wide::{W, WideNode};
use std::arch::aarch64::*;

pub struct Neon;

impl BoxTest for Neon {
    #[inline(always)]
    fn test(node: &WideNode, ray: &SlabRay, tmax: f32, tnear: &mut [f32; W]) -> u32 {
        const { assert!(W.is_multiple_of(4)) };
        let mut mask = 0;
        for h in 0..W / 4 {
            // SAFETY: NEON is part of the aarch64 baseline (checked again in `Kernel::detect`).
            // The loads read floats 4h..4h+4 of one `[f32; W]` row and the store writes the
            // same 4 of `tnear` (4h + 4 ≤ W).
            let m = unsafe {
                let slab = |row: &[f32; W], a: usize| {
                    let b = vld1q_f32(row.as_ptr().add(4 * h));
                    vmulq_f32(
                        vsubq_f32(b, vdupq_n_f32(ray.org[a])),
                        vdupq_n_f32(ray.inv[a]),
                    )
                };
                let mut tn = vdupq_n_f32(0.0);
                let mut tf = vdupq_n_f32(f32::INFINITY);
                for a in 0..3 {
                    let (near, far) = ray.rows(node, a);
                    tn = vmaxnmq_f32(slab(near, a), tn);
                    tf = vminnmq_f32(slab(far, a), tf);
                }
                tf = vminq_f32(vmulq_f32(tf, vdupq_n_f32(FAR_SCALE)), vdupq_n_f32(tmax));
                vst1q_f32(tnear.as_mut_ptr().add(4 * h), tn);
                let hit = vcleq_f32(tn, tf);
                let bits: [u32; 4] = [1, 2, 4, 8];
                vaddvq_u32(vandq_u32(hit, vld1q_u32(bits.as_ptr())))
            };
            mask |= m << (4 * h);
        }
        mask
    }
}
