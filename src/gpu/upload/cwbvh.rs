//! The compressed 8-wide BVH for the GPU: obvhs' CWBVH builder (Ylitie, Karras & Laine 2017,
//! "Efficient Incoherent Ray Traversal on GPUs Through Compressed Wide BVHs", HPG) with every
//! child box re-quantised so that it encloses the child exactly as the WGSL decodes it.
//!
//! The traversal (src/gpu/cwbvh.wgsl) decodes a plane as `p + e·q` in f32: e is a power
//! of two and q ≤ 255, so e·q is exact and the sum rounds once, whether or not the compiler
//! fuses it. Here each decoded minimum is ≤ and each decoded maximum ≥ the child's exact
//! bounds (the min / max of its triangles' vertices), found by the same f32 arithmetic — so
//! the robust slab test on the decoded box never misses a triangle of the child, at any
//! scene scale. (obvhs quantises with `((min − p)·(1/e)).floor()`, whose roundings do not
//! guarantee that.)

use crate::gpu::layout::CwNode;
use anyhow::{Result, bail, ensure};
use glam::Vec3;
use obvhs::cwbvh::CwBvh;
use obvhs::cwbvh::node::CwBvhNode;
use obvhs::{BvhBuildParams, triangle::Triangle};
use std::time::Duration;

/// Deepest CWBVH (root = 1) the 64-word traversal stack holds: a group is two words and an
/// ordered traversal holds at most one pending group per level below the root.
pub const MAX_CWBVH_DEPTH: u32 = 33;

/// Traversal stack words per invocation for a CWBVH of `depth` levels: two per pending
/// group (at most `depth − 1`), rounded up to a multiple of 8, at least 8 (the workgroup
/// counter reduction and the wavefront queues borrow the stack's first words), at most 64.
pub fn cwbvh_stack_words(depth: u32) -> u32 {
    (2 * depth.saturating_sub(1))
        .next_multiple_of(8)
        .clamp(8, 64)
}

/// A CWBVH in GPU form.
pub struct Cwbvh {
    pub nodes: Vec<CwNode>,
    /// Scene triangle of each leaf slot.
    pub primitive_indices: Vec<u32>,
    /// Levels of wide nodes (root = 1).
    pub depth: u32,
}

/// An axis-aligned box, corners exact (vertex coordinates).
#[derive(Clone, Copy)]
struct Bounds {
    lo: Vec3,
    hi: Vec3,
}

impl Bounds {
    const EMPTY: Bounds = Bounds {
        lo: Vec3::splat(f32::INFINITY),
        hi: Vec3::splat(f32::NEG_INFINITY),
    };

    fn union(self, o: Bounds) -> Bounds {
        Bounds {
            lo: self.lo.min(o.lo),
            hi: self.hi.max(o.hi),
        }
    }
}

/// Build obvhs' CWBVH over `tris` with `params` (no spatial splits: a split triangle's leaf
/// box is not its vertices' box) and re-quantise it.
pub fn build_cwbvh(tris: &[Triangle], params: BvhBuildParams) -> Result<Cwbvh> {
    ensure!(!params.pre_split, "the GPU CWBVH takes no spatial splits");
    let mut core = Duration::ZERO;
    let cw = obvhs::cwbvh::builder::build_cwbvh_from_tris(tris, params, &mut core);
    let depth = checked_depth(&cw, tris.len())?;
    let bounds = node_bounds(&cw, tris);
    let nodes = cw
        .nodes
        .iter()
        .zip(&bounds)
        .map(|(n, b)| encode(n, *b, &bounds, &cw.primitive_indices, tris))
        .collect::<Result<Vec<_>>>()?;
    Ok(Cwbvh {
        nodes,
        primitive_indices: cw.primitive_indices,
        depth,
    })
}

/// Node index of inner child `c` of `n`: inner children are stored consecutively from
/// `child_base_idx` in slot order.
fn child_node(n: &CwBvhNode, c: usize) -> usize {
    let below = u32::from(n.imask) & ((1u32 << c) - 1);
    n.child_base_idx as usize + below.count_ones() as usize
}

/// Leaf slots of leaf child `c` of `n` (low 5 bits of its meta byte: offset from
/// `primitive_base_idx`; high 3 bits: the count in unary).
fn leaf_slots(n: &CwBvhNode, c: usize) -> std::ops::Range<usize> {
    let m = n.child_meta[c];
    let first = n.primitive_base_idx as usize + usize::from(m & 31);
    first..first + (m >> 5).count_ones() as usize
}

fn is_inner(n: &CwBvhNode, c: usize) -> bool {
    n.imask & (1 << c) != 0
}

/// Depth of the tree (root = 1) after checking every child index (greater than its
/// parent's, in range) and every leaf range (in range, naming existing triangles), and that
/// the depth fits the traversal stack.
fn checked_depth(cw: &CwBvh, tri_count: usize) -> Result<u32> {
    let mut depth = 0;
    let mut stack = vec![(0usize, 1u32)];
    while let Some((i, d)) = stack.pop() {
        depth = depth.max(d);
        let n = &cw.nodes[i];
        for c in (0..8).filter(|&c| n.child_meta[c] != 0) {
            if is_inner(n, c) {
                let k = child_node(n, c);
                ensure!(
                    i < k && k < cw.nodes.len(),
                    "CWBVH child index out of range"
                );
                stack.push((k, d + 1));
            } else {
                let slots = leaf_slots(n, c);
                ensure!(
                    slots.end <= cw.primitive_indices.len()
                        && cw.primitive_indices[slots]
                            .iter()
                            .all(|&t| (t as usize) < tri_count),
                    "CWBVH leaf range out of range"
                );
            }
        }
    }
    if depth > MAX_CWBVH_DEPTH {
        bail!("CWBVH depth {depth} exceeds the GPU traversal stack ({MAX_CWBVH_DEPTH})");
    }
    Ok(depth)
}

/// The exact box of child `c` of `n`, given the boxes of the nodes after it.
fn child_bounds(
    n: &CwBvhNode,
    c: usize,
    nodes: &[Bounds],
    prims: &[u32],
    tris: &[Triangle],
) -> Bounds {
    if is_inner(n, c) {
        return nodes[child_node(n, c)];
    }
    prims[leaf_slots(n, c)].iter().fold(Bounds::EMPTY, |b, &t| {
        let t = &tris[t as usize];
        let (v0, v1, v2) = (Vec3::from(t.v0), Vec3::from(t.v1), Vec3::from(t.v2));
        b.union(Bounds {
            lo: v0.min(v1).min(v2),
            hi: v0.max(v1).max(v2),
        })
    })
}

/// The exact box of every node, children before parents (a child's index is greater).
fn node_bounds(cw: &CwBvh, tris: &[Triangle]) -> Vec<Bounds> {
    let mut out = vec![Bounds::EMPTY; cw.nodes.len()];
    for i in (0..cw.nodes.len()).rev() {
        let n = &cw.nodes[i];
        out[i] = (0..8)
            .filter(|&c| n.child_meta[c] != 0)
            .fold(Bounds::EMPTY, |b, c| {
                b.union(child_bounds(n, c, &out, &cw.primitive_indices, tris))
            });
    }
    out
}

/// The plane `p + e·q` as the WGSL decodes it.
#[inline]
pub fn decode(p: f32, e: f32, q: u8) -> f32 {
    p + e * f32::from(q)
}

/// The smallest power of two e (a normal float) with `decode(lo, e, 255) ≥ hi`.
fn grid_step(lo: f32, hi: f32) -> Result<f32> {
    let want = (hi - lo) / 255.0;
    let mut e = if want > f32::MIN_POSITIVE {
        2f32.powi(want.log2().ceil() as i32)
    } else {
        f32::MIN_POSITIVE
    };
    while decode(lo, e, 255) < hi {
        e *= 2.0;
    }
    ensure!(
        e.is_normal() && decode(lo, e, 255).is_finite(),
        "scene bounds too large for the CWBVH's grid ({lo} … {hi})"
    );
    Ok(e)
}

/// The largest q with `decode(p, e, q) ≤ v` (decode is non-decreasing in q; q = 0 gives
/// p ≤ v).
fn floor_q(p: f32, e: f32, v: f32) -> u8 {
    let (mut lo, mut hi) = (0u8, 255u8);
    while lo < hi {
        let mid = lo + (hi - lo).div_ceil(2);
        if decode(p, e, mid) <= v {
            lo = mid;
        } else {
            hi = mid - 1;
        }
    }
    lo
}

/// The smallest q with `decode(p, e, q) ≥ v` (q = 255 satisfies it by `grid_step`).
fn ceil_q(p: f32, e: f32, v: f32) -> u8 {
    let (mut lo, mut hi) = (0u8, 255u8);
    while lo < hi {
        let mid = lo + (hi - lo) / 2;
        if decode(p, e, mid) >= v {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    lo
}

/// Node `n` (exact box `b`) in the GPU layout, its child planes re-quantised on the grid
/// p = b.lo, e = `grid_step` per axis.
fn encode(
    n: &CwBvhNode,
    b: Bounds,
    nodes: &[Bounds],
    prims: &[u32],
    tris: &[Triangle],
) -> Result<CwNode> {
    let p = b.lo.to_array();
    let (lo, hi) = (b.lo.to_array(), b.hi.to_array());
    let mut e = [0f32; 3];
    for a in 0..3 {
        e[a] = grid_step(lo[a], hi[a])?;
    }
    // q[axis][0 = min, 1 = max][child]
    let mut q = [[[0u8; 8]; 2]; 3];
    for c in (0..8).filter(|&c| n.child_meta[c] != 0) {
        let cb = child_bounds(n, c, nodes, prims, tris);
        let (clo, chi) = (cb.lo.to_array(), cb.hi.to_array());
        for a in 0..3 {
            q[a][0][c] = floor_q(p[a], e[a], clo[a]);
            q[a][1][c] = ceil_q(p[a], e[a], chi[a]);
        }
    }
    let word = |b: &[u8]| u32::from_le_bytes([b[0], b[1], b[2], b[3]]);
    let planes = |a: usize| {
        [
            word(&q[a][0][..4]),
            word(&q[a][0][4..]),
            word(&q[a][1][..4]),
            word(&q[a][1][4..]),
        ]
    };
    let exp = |e: f32| e.to_bits() >> 23;
    Ok(CwNode {
        p,
        e_imask: exp(e[0]) | exp(e[1]) << 8 | exp(e[2]) << 16 | u32::from(n.imask) << 24,
        child_base: n.child_base_idx,
        prim_base: n.primitive_base_idx,
        child_meta: [word(&n.child_meta[..4]), word(&n.child_meta[4..])],
        q_x: planes(0),
        q_y: planes(1),
        q_z: planes(2),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every decoded child box encloses its triangles, at scene scales 1e-5 … 1e5, on a
    /// mesh of random triangles (flat, sliver and ordinary ones).
    #[test]
    fn decoded_child_boxes_enclose_their_triangles() {
        let mut s = crate::math::rng::Sampler::new(7, 0, 1);
        for scale in [1e-5f32, 1.0, 3.7e2, 1e5] {
            let mut tris = Vec::new();
            for i in 0..600 {
                let mut r = || Vec3::new(s.next_1d(), s.next_1d(), s.next_1d()) * scale;
                let (a, b, c) = (r(), r() * 0.01, r() * 0.01);
                let (mut v1, mut v2) = (a + b, a + c);
                if i % 3 == 0 {
                    (v1.y, v2.y) = (a.y, a.y);
                }
                tris.push(Triangle {
                    v0: a.into(),
                    v1: v1.into(),
                    v2: v2.into(),
                });
            }
            let cw = build_cwbvh(&tris, BvhBuildParams::medium_build()).unwrap();
            check_enclosure(&cw, &tris);
        }
    }

    /// Walk the tree: every triangle lies in the decoded box of every child above it, and
    /// every triangle is reached once.
    fn check_enclosure(cw: &Cwbvh, tris: &[Triangle]) {
        let mut seen = 0;
        check_node(cw, tris, 0, &mut Vec::new(), &mut seen);
        assert_eq!(seen, tris.len());
    }

    fn check_node(
        cw: &Cwbvh,
        tris: &[Triangle],
        i: usize,
        boxes: &mut Vec<(Vec3, Vec3)>,
        seen: &mut usize,
    ) {
        let n = &cw.nodes[i];
        let e = |a: usize| f32::from_bits(((n.e_imask >> (8 * a)) & 0xff) << 23);
        let qs = [n.q_x, n.q_y, n.q_z];
        let byte = |w: [u32; 4], k: usize, c: usize| (w[k + c / 4] >> (8 * (c % 4))) as u8;
        let imask = n.e_imask >> 24;
        for c in 0..8 {
            let meta = (n.child_meta[c / 4] >> (8 * (c % 4))) as u8;
            if meta == 0 {
                continue;
            }
            let plane = |k: usize| {
                Vec3::from_array(std::array::from_fn(|a| {
                    decode(n.p[a], e(a), byte(qs[a], k, c))
                }))
            };
            boxes.push((plane(0), plane(2)));
            if imask & (1 << c) != 0 {
                let below = imask & ((1 << c) - 1);
                let k = n.child_base as usize + below.count_ones() as usize;
                check_node(cw, tris, k, boxes, seen);
            } else {
                let first = n.prim_base as usize + usize::from(meta & 31);
                let count = (meta >> 5).count_ones() as usize;
                for &t in &cw.primitive_indices[first..first + count] {
                    let t = &tris[t as usize];
                    for v in [t.v0, t.v1, t.v2].map(Vec3::from) {
                        for &(lo, hi) in boxes.iter() {
                            assert!(
                                v.cmpge(lo).all() && v.cmple(hi).all(),
                                "{v} outside {lo} … {hi}"
                            );
                        }
                    }
                    *seen += 1;
                }
            }
            boxes.pop();
        }
    }
}
