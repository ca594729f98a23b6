//! The conservative ray/box slab test shared by every SIMD flavour, and its scalar version.
//!
//! Robustness (Ize 2013, "Robust BVH Ray Traversal", JCGT 2(2); pbrt-v4 §6.8.2): each slab
//! distance is computed as t = (b − o) · (1/d) with 1/d correctly rounded, three roundings in
//! all, so the computed t is within γ₃ = 3ε/(1 − 3ε) of the exact one relative to its own size
//! (ε = 2⁻²⁴) and keeps its sign. Scaling the far distance by 1 + 2γ₃ then makes the computed
//! interval contain the exact one whatever the scene's scale — no absolute epsilon. A zero
//! direction component gives 1/d = ±∞: the distance is ±∞ (origin outside or inside the slab)
//! or NaN (origin exactly on the plane, 0·∞); min/max are written so a NaN leaves the running
//! bound unchanged (the slab does not constrain a ray lying in it), as in pbrt-v4.

use super::wide::{W, WideNode};

/// γ₃ of Higham / pbrt-v4 for f32: 3ε/(1 − 3ε), ε = 2⁻²⁴ (half an ulp of 1).
const GAMMA3: f32 = 3.0 * (f32::EPSILON * 0.5) / (1.0 - 3.0 * (f32::EPSILON * 0.5));

/// Factor on a box's far distance: pbrt-v4 §6.8.2 (`tMax *= 1 + 2 * gamma(3)`).
pub const FAR_SCALE: f32 = 1.0 + 2.0 * GAMMA3;

/// Factor on the current closest hit when culling boxes by their entry distance: a box whose
/// computed entry lies a few ulps past the closest hit so far may still hold a triangle whose
/// (separately rounded) watertight t is smaller — a near-tie at shared edges and on box faces.
/// Relative, so scale-free; it visits only boxes within 2⁻¹⁹ of the hit distance.
pub const TMAX_SCALE: f32 = 1.0 + 16.0 * f32::EPSILON;

/// The per-ray constants of the slab test.
#[derive(Clone, Copy, Debug)]
pub struct SlabRay {
    pub org: [f32; 3],
    /// 1/d per axis, correctly rounded (±∞ for a zero component, signed like it).
    pub inv: [f32; 3],
    /// The direction is negative along the axis: its slab's near side is the upper plane.
    neg: [bool; 3],
}

impl SlabRay {
    #[inline(always)]
    pub fn new(org: [f32; 3], dir: [f32; 3]) -> SlabRay {
        let inv = dir.map(|d| 1.0 / d);
        SlabRay {
            org,
            inv,
            neg: inv.map(f32::is_sign_negative),
        }
    }

    /// The plane rows (`WideNode::planes`) of the near and far side of axis `a`'s slab. With
    /// `a` a constant of an unrolled loop both rows are fixed offsets: a select, no index
    /// arithmetic or bounds check per node.
    #[inline(always)]
    pub fn rows<'n>(&self, node: &'n WideNode, a: usize) -> (&'n [f32; W], &'n [f32; W]) {
        let (lo, hi) = (&node.planes[2 * a], &node.planes[2 * a + 1]);
        if self.neg[a] { (hi, lo) } else { (lo, hi) }
    }
}

/// A SIMD flavour of the slab test over one node's `W` children.
pub trait BoxTest {
    /// Bit i set when child i's box may overlap the ray segment [0, tmax]; `tnear[i]` gets the
    /// entry distance of each such child.
    fn test(node: &WideNode, ray: &SlabRay, tmax: f32, tnear: &mut [f32; W]) -> u32;
}

/// NaN-ignoring max: `acc` unless `t` is larger (a NaN `t` compares false). The same operand
/// order as x86 `maxps(t, acc)`.
#[inline(always)]
pub fn max_keep(t: f32, acc: f32) -> f32 {
    if t > acc { t } else { acc }
}

/// NaN-ignoring min, like `minps(t, acc)`.
#[inline(always)]
pub fn min_keep(t: f32, acc: f32) -> f32 {
    if t < acc { t } else { acc }
}

/// Plain arrays; LLVM vectorises the loop for the baseline target (SSE2 on x86-64).
pub struct Scalar;

impl BoxTest for Scalar {
    #[inline(always)]
    fn test(node: &WideNode, ray: &SlabRay, tmax: f32, tnear: &mut [f32; W]) -> u32 {
        let rows = [0, 1, 2].map(|a| ray.rows(node, a));
        let mut mask = 0;
        for i in 0..W {
            let (mut tn, mut tf) = (0.0f32, f32::INFINITY);
            for (a, (near, far)) in rows.iter().enumerate() {
                tn = max_keep((near[i] - ray.org[a]) * ray.inv[a], tn);
                tf = min_keep((far[i] - ray.org[a]) * ray.inv[a], tf);
            }
            tnear[i] = tn;
            mask |= ((tn <= (tf * FAR_SCALE).min(tmax)) as u32) << i;
        }
        mask
    }
}
