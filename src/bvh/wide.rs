//! The wide BVH: obvhs' binary PLOC tree collapsed to `W`-ary nodes whose child boxes are
//! uncompressed f32 in structure-of-arrays layout (one `[f32; W]` per slab plane), the layout
//! a SIMD box test loads directly (Wald, Benthin & Boulos 2008, "Getting Rid of Packets";
//! Dammertz et al. 2008, "Shallow Bounding Volume Hierarchies for Fast SIMD Ray Tracing").

use obvhs::bvh2::Bvh2;

/// Children per node: 8 (one AVX2 register, two SSE/NEON registers). Measured against 4 in
/// docs/performance.md.
pub const W: usize = 8;

/// Most triangles in one leaf (obvhs' collapse respects it; the child encoding holds ≤ 7).
pub const MAX_LEAF: u32 = 4;

/// Child word: bit 31 set = leaf, then 3 bits of triangle count and 28 bits of first triangle
/// (leaf order); bit 31 clear = index of an inner node.
const LEAF_BIT: u32 = 1 << 31;
const COUNT_SHIFT: u32 = 28;
const FIRST_MASK: u32 = (1 << COUNT_SHIFT) - 1;

/// Plane rows of [`WideNode::planes`]: 2·axis + 0 is the lower bound, 2·axis + 1 the upper.
pub const PLANES: usize = 6;

/// One node: the boxes of its `W` children and what they are. An unused slot has the empty
/// box lo = +∞, hi = −∞, which every slab test rejects.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
pub struct WideNode {
    pub planes: [[f32; W]; PLANES],
    pub child: [u32; W],
}

impl WideNode {
    const EMPTY: WideNode = WideNode {
        planes: [
            [f32::INFINITY; W],
            [f32::NEG_INFINITY; W],
            [f32::INFINITY; W],
            [f32::NEG_INFINITY; W],
            [f32::INFINITY; W],
            [f32::NEG_INFINITY; W],
        ],
        child: [0; W],
    };

    /// The slots holding leaves, as a bit mask computed without a branch per slot.
    #[inline(always)]
    pub fn leaf_slots(&self) -> u32 {
        const SHIFT: u32 = LEAF_BIT.trailing_zeros();
        self.child
            .iter()
            .enumerate()
            .fold(0, |m, (i, &w)| m | (w >> SHIFT) << i)
    }

    fn set_box(&mut self, slot: usize, lo: [f32; 3], hi: [f32; 3]) {
        for a in 0..3 {
            self.planes[2 * a][slot] = lo[a];
            self.planes[2 * a + 1][slot] = hi[a];
        }
    }
}

/// A decoded child word.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Child {
    Inner(u32),
    /// First triangle (leaf order) and count.
    Leaf(u32, u32),
}

#[inline(always)]
pub fn decode(word: u32) -> Child {
    if word & LEAF_BIT == 0 {
        Child::Inner(word)
    } else {
        Child::Leaf(word & FIRST_MASK, (word & !LEAF_BIT) >> COUNT_SHIFT)
    }
}

/// Give every leaf its own packet of `LANES` slots: the leaf word's first index becomes its
/// packet's index (slot = packet · `LANES` + lane). Returns, for each packet, the leaf's
/// first triangle in the BVH2's leaf order and its count.
pub fn number_packets(nodes: &mut [WideNode]) -> Vec<(u32, u32)> {
    let mut leaves = Vec::new();
    for node in nodes.iter_mut() {
        for word in node.child.iter_mut() {
            if *word & LEAF_BIT != 0
                && let Child::Leaf(first, count) = decode(*word)
            {
                *word = encode_leaf(leaves.len() as u32, count);
                leaves.push((first, count));
            }
        }
    }
    leaves
}

fn encode_leaf(first: u32, count: u32) -> u32 {
    assert!(
        first <= FIRST_MASK && (1..=7).contains(&count),
        "BVH leaf ({first}, {count}) does not fit the child encoding"
    );
    LEAF_BIT | (count << COUNT_SHIFT) | first
}

/// Collapse a BVH2 (root at node 0) into wide nodes (root at 0) and return them with the
/// depth of the wide tree. Each wide node takes the children of a BVH2 node and keeps opening
/// its inner child of largest surface area until it holds `W` children or only leaves
/// (the greedy SAH-driven collapse of Wald et al. 2008, §3).
pub fn collapse(bvh2: &Bvh2) -> (Vec<WideNode>, u32) {
    let mut nodes = vec![WideNode::EMPTY];
    let mut depth = 1;
    let mut work = vec![(0usize, 0usize, 1u32)];
    while let Some((b, w, d)) = work.pop() {
        depth = depth.max(d);
        let kids = open_children(bvh2, b);
        for (slot, &k) in kids.iter().enumerate() {
            let n = &bvh2.nodes[k];
            let word = if n.prim_count > 0 {
                encode_leaf(n.first_index, n.prim_count)
            } else {
                nodes.push(WideNode::EMPTY);
                work.push((k, nodes.len() - 1, d + 1));
                (nodes.len() - 1) as u32
            };
            nodes[w].set_box(slot, n.aabb.min.into(), n.aabb.max.into());
            nodes[w].child[slot] = word;
        }
    }
    (nodes, depth)
}

/// The BVH2 nodes that become the children of the wide node made from BVH2 node `b` (a leaf
/// root becomes the only child of the wide root).
fn open_children(bvh2: &Bvh2, b: usize) -> Vec<usize> {
    let node = &bvh2.nodes[b];
    if node.prim_count > 0 {
        return vec![b];
    }
    let first = node.first_index as usize;
    let mut kids = vec![first, first + 1];
    while kids.len() < W {
        let widest = kids
            .iter()
            .enumerate()
            .filter(|&(_, &k)| bvh2.nodes[k].prim_count == 0)
            .max_by(|a, b| {
                let area = |k: usize| bvh2.nodes[k].aabb.half_area();
                area(*a.1).total_cmp(&area(*b.1))
            });
        let Some((i, &k)) = widest else { break };
        let f = bvh2.nodes[k].first_index as usize;
        kids[i] = f;
        kids.push(f + 1);
    }
    kids
}
