//! Ordered traversal of the wide BVH with a small fixed-size stack: the children a node's box
//! test accepts are visited nearest entry first (closest hit) or in slot order (occlusion,
//! which stops at the first hit); stacked entries keep their entry distance so those beyond
//! the closest hit so far are dropped when popped.

use super::packet::{LANES, PacketHits, PacketRay, TriPacket};
use super::slab::{BoxTest, SlabRay, TMAX_SCALE};
use super::watertight::WatertightRay;
use super::wide::{Child, W, WideNode, decode};
use glam::Vec3A;
use std::mem::MaybeUninit;

/// Stack entries held in place; deeper stacks (a wide tree deeper than ~9 levels, all of
/// whose children are hit) spill into a `Vec` that allocates only then.
const STACK: usize = 64;

/// A stacked child word and its box's entry distance.
#[derive(Clone, Copy, Default)]
struct Entry {
    word: u32,
    t: f32,
}

/// Entries `items[..len]` are initialised; left uninitialised otherwise, so that starting a
/// ray does not clear the whole array.
struct Stack {
    items: [MaybeUninit<Entry>; STACK],
    len: usize,
    spill: Vec<Entry>,
}

impl Stack {
    #[inline(always)]
    fn new() -> Stack {
        Stack {
            items: [const { MaybeUninit::uninit() }; STACK],
            len: 0,
            spill: Vec::new(),
        }
    }

    #[inline(always)]
    fn push(&mut self, e: Entry) {
        if self.len < STACK {
            self.items[self.len].write(e);
            self.len += 1;
        } else {
            self.spill.push(e);
        }
    }

    #[inline(always)]
    fn pop(&mut self) -> Option<Entry> {
        if !self.spill.is_empty() {
            return self.spill.pop();
        }
        if self.len == 0 {
            return None;
        }
        self.len -= 1;
        // SAFETY: `push` wrote every entry below the old `len`, and `len` only shrinks here.
        Some(unsafe { self.items[self.len].assume_init() })
    }
}

/// The geometry one traversal runs over.
#[derive(Clone, Copy)]
pub struct Tree<'a> {
    pub nodes: &'a [WideNode],
    pub packets: &'a [TriPacket],
}

/// What a query asks: a checked ray (finite, non-zero direction) and the far end of its
/// segment (not NaN, > 0).
#[derive(Clone, Copy)]
pub struct QueryRay {
    pub origin: Vec3A,
    pub dir: Vec3A,
    pub tmax: f32,
}

/// One query's per-ray constants: the ray in each form the tests take and the far end of its
/// segment. Built inside the traversal (compiled for its instruction set) rather than passed
/// in, so that the constants go straight to where the traversal keeps them.
#[derive(Clone, Copy)]
pub struct Query {
    pub slab: SlabRay,
    pub wt: WatertightRay,
    pub packet: PacketRay,
    pub tmax: f32,
}

/// A hit on leaf slot `slot` (packet · `LANES` + lane).
#[derive(Clone, Copy, Debug)]
pub struct SlotHit {
    pub t: f32,
    pub slot: u32,
    pub b1: f32,
    pub b2: f32,
}

impl Query {
    #[inline(always)]
    fn new(r: &QueryRay) -> Query {
        let wt = WatertightRay::new(r.origin, r.dir);
        Query {
            slab: SlabRay::new(r.origin.to_array(), r.dir.to_array()),
            packet: PacketRay::new(&wt),
            wt,
            tmax: r.tmax,
        }
    }
}

/// Closest hit in (0, tmax) (`ANY` = false) or any hit (`ANY` = true, returns the first found).
/// The tree has at least one triangle. One function on purpose: written as a step-at-a-time
/// state object the same traversal lost 25 % of its rays/s (docs/performance.md, "Session 9").
#[inline(always)]
pub fn traverse<K: BoxTest, const ANY: bool>(tree: Tree, ray: &QueryRay) -> Option<SlotHit> {
    let q = &Query::new(ray);
    let mut stack = Stack::new();
    let mut tnear = [0.0f32; W];
    let (mut tmax, mut best) = (q.tmax, None);
    let mut cur = 0u32;
    loop {
        match decode(cur) {
            Child::Inner(n) => {
                let node = &tree.nodes[n as usize];
                let mut mask = K::test(node, &q.slab, tmax * TMAX_SCALE, &mut tnear);
                if ANY {
                    // Occlusion: any hit ends the query whatever the order, so the leaves
                    // among the accepted children are tested at once, not stacked.
                    let mut leaves = mask & node.leaf_slots();
                    mask &= !leaves;
                    while leaves != 0 {
                        let i = leaves.trailing_zeros() as usize;
                        leaves &= leaves - 1;
                        if let Child::Leaf(packet, count) = decode(node.child[i]) {
                            let h = q.packet.intersect(
                                &q.wt,
                                &tree.packets[packet as usize],
                                count,
                                tmax,
                            );
                            if h.mask != 0 {
                                return Some(slot_hit(packet, h.mask.trailing_zeros(), &h));
                            }
                        }
                    }
                }
                if let Some(next) = push_hits::<ANY>(node, mask, &tnear, &mut stack) {
                    cur = next;
                    continue;
                }
            }
            Child::Leaf(packet, count) => {
                // All lanes against the entry tmax, then taken in lane order with the running
                // tmax: the hits a one-triangle-at-a-time loop would find.
                let h = q
                    .packet
                    .intersect(&q.wt, &tree.packets[packet as usize], count, tmax);
                let mut m = h.mask;
                while m != 0 {
                    let lane = m.trailing_zeros() as usize;
                    m &= m - 1;
                    let t = h.t[lane];
                    if t < tmax {
                        tmax = t;
                        best = Some(slot_hit(packet, lane as u32, &h));
                        if ANY {
                            return best;
                        }
                    }
                }
            }
        }
        cur = loop {
            match stack.pop() {
                None => return best,
                Some(e) if e.t <= tmax * TMAX_SCALE => break e.word,
                Some(_) => {}
            }
        };
    }
}

/// The hit of lane `lane` of packet `packet` (slot = packet · `LANES` + lane).
#[inline(always)]
fn slot_hit(packet: u32, lane: u32, h: &PacketHits) -> SlotHit {
    let l = lane as usize;
    SlotHit {
        t: h.t[l],
        slot: packet * LANES as u32 + lane,
        b1: h.b1[l],
        b2: h.b2[l],
    }
}

/// Push the children in `mask` and return the one to visit next: the nearest (its siblings
/// stacked farthest first), or for `ANY` the last in slot order. None when the mask is empty.
/// One and two children (most nodes an incoherent ray enters) take straight-line paths with
/// the general loop's order: of equal entry distances the higher slot is visited first.
#[inline(always)]
fn push_hits<const ANY: bool>(
    node: &WideNode,
    mask: u32,
    tnear: &[f32; W],
    stack: &mut Stack,
) -> Option<u32> {
    if mask == 0 {
        return None;
    }
    let i = mask.trailing_zeros() as usize;
    let rest = mask & (mask - 1);
    if rest == 0 {
        return Some(node.child[i]);
    }
    if rest & (rest - 1) == 0 {
        let j = rest.trailing_zeros() as usize;
        let (a, b) = (node.child[i], node.child[j]);
        let (next, later) = if ANY || tnear[i] >= tnear[j] {
            ((b, tnear[j]), (a, tnear[i]))
        } else {
            ((a, tnear[i]), (b, tnear[j]))
        };
        stack.push(Entry {
            word: later.0,
            t: later.1,
        });
        return Some(next.0);
    }
    push_sorted::<ANY>(node, mask, tnear, stack)
}

/// [`push_hits`] for any number of children: insertion by decreasing entry distance.
#[inline(always)]
fn push_sorted<const ANY: bool>(
    node: &WideNode,
    mut mask: u32,
    tnear: &[f32; W],
    stack: &mut Stack,
) -> Option<u32> {
    let mut hits = [Entry::default(); W];
    let mut k = 0;
    while mask != 0 {
        let i = mask.trailing_zeros() as usize;
        mask &= mask - 1;
        let e = Entry {
            word: node.child[i],
            t: tnear[i],
        };
        // Insertion into `hits[..k]`, sorted by decreasing entry distance.
        let mut j = k;
        while !ANY && j > 0 && hits[j - 1].t < e.t {
            hits[j] = hits[j - 1];
            j -= 1;
        }
        hits[j] = e;
        k += 1;
    }
    let (last, rest) = hits[..k].split_last()?;
    for &e in rest {
        stack.push(e);
    }
    Some(last.word)
}

#[cfg(test)]
mod tests {
    use super::super::wide::PLANES;
    use super::*;
    use crate::math::rng::Sampler;

    /// What a push left: the child to visit next and the stack from the bottom.
    fn run(
        f: fn(&WideNode, u32, &[f32; W], &mut Stack) -> Option<u32>,
        node: &WideNode,
        mask: u32,
        tnear: &[f32; W],
    ) -> (Option<u32>, Vec<(u32, u32)>) {
        let mut stack = Stack::new();
        let next = f(node, mask, tnear, &mut stack);
        let mut rest = Vec::new();
        while let Some(e) = stack.pop() {
            rest.push((e.word, e.t.to_bits()));
        }
        rest.reverse();
        (next, rest)
    }

    /// The one- and two-child fast paths visit and stack exactly what the general insertion
    /// does, for closest-hit and any-hit order, including equal entry distances (which decide
    /// between hits at equal t).
    #[test]
    fn fast_paths_push_what_the_insertion_pushes() {
        let mut s = Sampler::new(3, 0, 5);
        let mut node = WideNode {
            planes: [[0.0; W]; PLANES],
            child: [0; W],
        };
        for (i, c) in node.child.iter_mut().enumerate() {
            *c = 100 + i as u32;
        }
        let mut cases = 0;
        for mask in 0u32..(1 << W) {
            for round in 0..8 {
                // Few distinct distances, so that ties are common.
                let tnear: [f32; W] = std::array::from_fn(|_| {
                    if round == 0 {
                        1.0
                    } else {
                        (s.next_1d() * 3.0).floor()
                    }
                });
                assert_eq!(
                    run(push_hits::<false>, &node, mask, &tnear),
                    run(push_sorted::<false>, &node, mask, &tnear),
                    "closest hit, mask {mask:#b}, tnear {tnear:?}"
                );
                assert_eq!(
                    run(push_hits::<true>, &node, mask, &tnear),
                    run(push_sorted::<true>, &node, mask, &tnear),
                    "any hit, mask {mask:#b}"
                );
                cases += 1;
            }
        }
        assert_eq!(cases, 8 << W);
    }
}
