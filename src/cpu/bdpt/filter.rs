//! The Heckbert path filter on bidirectional paths in O(1) per connection. A full path reads,
//! light→eye, L, the light subpath's classes, the classes chosen at the two connection
//! vertices, the camera subpath's classes backwards, E. The light part is a prefix: its DFA
//! state is stored per light vertex. The camera part is a suffix: per camera vertex the set of
//! states from which it leads to acceptance is stored as a bit mask (the DFA has at most 32
//! states), built backwards from E one vertex at a time (the standard construction of the
//! states co-reachable under a word; Hopcroft & Ullman 1979, §2.3).

use super::Bdpt;
use super::vertex::Vertex;
use crate::paths::{DfaTable, MAX_STATES, Symbol};

/// The states of `f` from which reading `sym`, then a word accepted from `mask`, accepts.
fn pre_image(f: &DfaTable, mask: u32, sym: Symbol) -> u32 {
    (0..f.num_states().min(MAX_STATES as u32))
        .filter(|&q| in_mask(mask, f.step(q, sym)))
        .fold(0, |m, q| m | 1 << q)
}

#[inline]
fn in_mask(mask: u32, q: u32) -> bool {
    q < 32 && mask >> q & 1 == 1
}

/// The states from which E alone accepts.
fn e_mask(f: &DfaTable) -> u32 {
    (0..f.num_states().min(MAX_STATES as u32))
        .filter(|&q| f.is_accepting(f.step(q, Symbol::E)))
        .fold(0, |m, q| m | 1 << q)
}

impl Bdpt<'_> {
    /// Fill `filter` along a light subpath (DFA states after L and each vertex's class).
    pub(super) fn light_prefix_states(&self, light: &mut [Vertex]) {
        let Some(f) = self.filter else { return };
        let mut q = f.step(f.start(), Symbol::L);
        for (i, v) in light.iter_mut().enumerate() {
            if i > 0 {
                q = f.step(q, v.class);
            }
            v.filter = q;
        }
    }

    /// Fill `filter` along a camera subpath (accepting-state masks, camera vertex = E).
    pub(super) fn camera_suffix_masks(&self, cam: &mut [Vertex]) {
        let Some(f) = self.filter else { return };
        let mut mask = e_mask(f);
        for (i, v) in cam.iter_mut().enumerate() {
            if i > 0 {
                mask = pre_image(f, mask, v.class);
            }
            v.filter = mask;
        }
    }

    /// Does the full light→eye symbol string pass the filter? `light` and `cam` are the
    /// subpaths without the connection vertices, `cy`/`cz` the classes chosen there; both
    /// subpaths carry their prefix states.
    pub(super) fn accepted(
        &self,
        light: &[Vertex],
        cy: Option<Symbol>,
        cz: Option<Symbol>,
        cam: &[Vertex],
    ) -> bool {
        let Some(f) = self.filter else {
            return true;
        };
        let mut q = light
            .last()
            .map_or_else(|| f.step(f.start(), Symbol::L), |v| v.filter);
        for c in [cy, cz].into_iter().flatten() {
            q = f.step(q, c);
        }
        in_mask(cam.last().map_or_else(|| e_mask(f), |v| v.filter), q)
    }

    /// The direct form of `accepted` (the whole string from the start state), the oracle of
    /// the prefix form in tests.
    #[cfg(test)]
    pub(super) fn accepted_direct(
        &self,
        light: &[Vertex],
        cy: Option<Symbol>,
        cz: Option<Symbol>,
        cam: &[Vertex],
    ) -> bool {
        let Some(f) = self.filter else {
            return true;
        };
        let mut q = f.step(f.start(), Symbol::L);
        for v in light.iter().skip(1) {
            q = f.step(q, v.class);
        }
        for c in [cy, cz].into_iter().flatten() {
            q = f.step(q, c);
        }
        for v in cam.iter().skip(1).rev() {
            q = f.step(q, v.class);
        }
        f.is_accepting(f.step(q, Symbol::E))
    }
}
