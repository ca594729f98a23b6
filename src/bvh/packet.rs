//! Four triangles of one leaf tested against a ray at once: the watertight test of Woop,
//! Benthin & Wald 2013 (JCGT 2(1), §3) lane by lane on a structure-of-arrays packet (the
//! multi-triangle leaf test of Wald et al. 2014, "Embree", §4.3). Each lane performs the same
//! operations in the same order as [`WatertightRay::intersect`] — the sheared coordinates
//! A[kx] − sx·A[kz], A[ky] − sy·A[kz] and sz·A[kz], the edge functions, the determinant and
//! t — so every lane rounds exactly like the one-triangle test and the traversal finds
//! bit-identical hits. Lanes with an edge function exactly 0 take the one-triangle test (its
//! f64 fallback, §3.3).

use super::watertight::{LeafTri, WatertightRay};
use glam::{BVec4A, Vec3A, Vec4};

/// Lanes per packet = the most triangles in a leaf (`wide::MAX_LEAF`).
pub const LANES: usize = 4;

/// Up to four triangles, vertex `i`'s axis `a` in `v[i][a]`; unused lanes hold NaN, which no
/// ray hits.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(16))]
pub struct TriPacket {
    pub v: [[Vec4; 3]; 3],
}

impl TriPacket {
    /// A packet of `tris` (at most [`LANES`]).
    pub fn new(tris: &[LeafTri]) -> TriPacket {
        debug_assert!(tris.len() <= LANES);
        let mut v = [[Vec4::NAN; 3]; 3];
        for (lane, t) in tris.iter().enumerate() {
            for (i, p) in [t.v0, t.v1, t.v2].into_iter().enumerate() {
                for a in 0..3 {
                    v[i][a][lane] = p[a];
                }
            }
        }
        TriPacket { v }
    }

    /// Lane `lane` as a one-triangle test's input.
    fn tri(&self, lane: usize) -> LeafTri {
        let p = |i: usize| Vec3A::new(self.v[i][0][lane], self.v[i][1][lane], self.v[i][2][lane]);
        LeafTri {
            v0: p(0),
            v1: p(1),
            v2: p(2),
        }
    }
}

/// The hits of one packet test: lanes in `mask` hit with (t, b1, b2).
pub struct PacketHits {
    pub mask: u32,
    pub t: [f32; LANES],
    pub b1: [f32; LANES],
    pub b2: [f32; LANES],
}

/// Per-ray constants of the packet test: the permutation and shear of [`WatertightRay`] as
/// axis indices and splatted factors.
#[derive(Clone, Copy)]
pub struct PacketRay {
    /// The origin's kx, ky and kz components.
    org: [Vec4; 3],
    k: [usize; 3],
    /// −sx, −sy, sz of the paper.
    neg_sx: Vec4,
    neg_sy: Vec4,
    sz: Vec4,
}

impl PacketRay {
    #[inline(always)]
    pub fn new(wt: &WatertightRay) -> PacketRay {
        let (org, k, s) = wt.shear();
        // An array, not `Vec3A`: indexing a `Vec3A` by a runtime axis is a `match` (a
        // branch per component, mispredicted on incoherent rays); an array is one load.
        let org = org.to_array();
        PacketRay {
            org: k.map(|a| Vec4::splat(org[a])),
            k,
            neg_sx: Vec4::splat(s[0]),
            neg_sy: Vec4::splat(s[1]),
            sz: Vec4::splat(s[2]),
        }
    }

    /// Sheared x, y and scaled z of vertex `i` relative to the ray origin, four lanes.
    #[inline(always)]
    fn sheared(&self, p: &TriPacket, i: usize) -> (Vec4, Vec4, Vec4) {
        let [kx, ky, kz] = self.k;
        let az = p.v[i][kz] - self.org[2];
        (
            (p.v[i][kx] - self.org[0]) + az * self.neg_sx,
            (p.v[i][ky] - self.org[1]) + az * self.neg_sy,
            az * self.sz,
        )
    }

    /// Test the first `count` lanes of `p` for hits with 0 < t < tmax.
    #[inline(always)]
    pub fn intersect(
        &self,
        wt: &WatertightRay,
        p: &TriPacket,
        count: u32,
        tmax: f32,
    ) -> PacketHits {
        let (ax, ay, az) = self.sheared(p, 0);
        let (bx, by, bz) = self.sheared(p, 1);
        let (cx, cy, cz) = self.sheared(p, 2);
        let u = cx * by - cy * bx;
        let v = ax * cy - ay * cx;
        let w = bx * ay - by * ax;
        let zero = Vec4::ZERO;
        let lanes = (1u32 << count) - 1;
        let edge0 = (u.cmpeq(zero) | v.cmpeq(zero) | w.cmpeq(zero)).bitmask() & lanes;
        let neg = u.cmplt(zero) | v.cmplt(zero) | w.cmplt(zero);
        let pos = u.cmpgt(zero) | v.cmpgt(zero) | w.cmpgt(zero);
        let det = u + v + w;
        let t_scaled = u * az + v * bz + w * cz;
        let inv = Vec4::ONE / det;
        let t = t_scaled * inv;
        let ok: BVec4A =
            !(neg & pos) & det.cmpne(zero) & t.cmpgt(zero) & t.cmplt(Vec4::splat(tmax));
        let mut hits = PacketHits {
            mask: ok.bitmask() & lanes & !edge0,
            t: t.to_array(),
            b1: (v * inv).to_array(),
            b2: (w * inv).to_array(),
        };
        let mut rest = edge0;
        while rest != 0 {
            let lane = rest.trailing_zeros() as usize;
            rest &= rest - 1;
            if let Some((t, b1, b2)) = wt.intersect(&p.tri(lane), tmax) {
                hits.mask |= 1 << lane;
                (hits.t[lane], hits.b1[lane], hits.b2[lane]) = (t, b1, b2);
            }
        }
        hits
    }
}

// A leaf must fit one packet.
const _: () = assert!(super::wide::MAX_LEAF as usize == LANES);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::rng::Sampler;

    fn v3(s: &mut Sampler, scale: f32) -> Vec3A {
        Vec3A::new(s.next_1d() - 0.5, s.next_1d() - 0.5, s.next_1d() - 0.5) * scale
    }

    /// Every lane of a packet reports exactly what the one-triangle test reports for that
    /// triangle (t, b1, b2 bit for bit), for partial packets, rays through shared vertices and
    /// edges (edge functions exactly 0, the f64 fallback) and axis-aligned rays.
    #[test]
    fn lanes_match_the_one_triangle_test_bit_for_bit() {
        let mut s = Sampler::new(7, 0, 11);
        let mut hits = 0;
        let mut fallbacks = 0;
        for case in 0..20_000 {
            let count = 1 + case % LANES;
            let shared = v3(&mut s, 2.0);
            let tris: Vec<LeafTri> = (0..count)
                .map(|_| LeafTri {
                    v0: shared,
                    v1: v3(&mut s, 2.0),
                    v2: v3(&mut s, 2.0),
                })
                .collect();
            let mut org = v3(&mut s, 8.0);
            let dir = match case % 5 {
                // Along z through the shared vertex: sheared coordinates, hence edge
                // functions, exactly 0 (the f64 fallback).
                0 => {
                    org = shared - Vec3A::new(0.0, 0.0, 5.0);
                    Vec3A::new(0.0, 0.0, 1.0)
                }
                1 => Vec3A::new(0.0, 0.0, 1.0),
                2 => Vec3A::new(-1.0, 0.0, 0.0),
                _ => v3(&mut s, 1.0),
            };
            if dir == Vec3A::ZERO {
                continue;
            }
            let wt = WatertightRay::new(org, dir);
            let tmax = if case % 3 == 0 { f32::INFINITY } else { 4.0 };
            let h = PacketRay::new(&wt).intersect(&wt, &TriPacket::new(&tris), count as u32, tmax);
            for (lane, tri) in tris.iter().enumerate() {
                let one = wt.intersect(tri, tmax);
                let got = (h.mask >> lane & 1 == 1).then(|| (h.t[lane], h.b1[lane], h.b2[lane]));
                let bits =
                    |x: Option<(f32, f32, f32)>| x.map(|(a, b, c)| [a, b, c].map(f32::to_bits));
                assert_eq!(bits(got), bits(one), "case {case} lane {lane}");
                hits += one.is_some() as u32;
                fallbacks += (case % 5 == 0 && one.is_some()) as u32;
            }
            assert_eq!(h.mask >> count, 0, "lanes past the count never hit");
        }
        assert!(
            hits > 2_000 && fallbacks > 100,
            "{hits} hits, {fallbacks} through vertices"
        );
    }
}
