//! The watertight ray/triangle test: Woop, Benthin & Wald 2013, "Watertight Ray/Triangle
//! Intersection" (JCGT 2(1)).

use glam::Vec3A;

/// Triangle vertices stored in BVH leaf order (leaf ranges index this array directly).
#[derive(Clone, Copy, Debug)]
pub struct LeafTri {
    pub v0: Vec3A,
    pub v1: Vec3A,
    pub v2: Vec3A,
}

/// Per-ray constants of the watertight test: §3 of the paper, the axis permutation (kx, ky, kz)
/// and the shear factors kept as (−sx, −sy, sz), so that the sheared coordinates of a vertex
/// offset A are A[kx] + A[kz]·(−sx), A[ky] + A[kz]·(−sy) and A[kz]·sz — the paper's
/// expressions with the same roundings.
#[derive(Clone, Copy)]
pub struct WatertightRay {
    org: Vec3A,
    k: [usize; 3],
    s: [f32; 3],
}

impl WatertightRay {
    /// `dir` must have a nonzero component.
    #[inline(always)]
    pub fn new(org: Vec3A, dir: Vec3A) -> Self {
        let d = dir.to_array();
        let a = dir.abs();
        let kz = if a.x > a.y {
            if a.x > a.z { 0 } else { 2 }
        } else if a.y > a.z {
            1
        } else {
            2
        };
        let (mut kx, mut ky) = ([1, 2, 0][kz], [2, 0, 1][kz]);
        if d[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        WatertightRay {
            org,
            k: [kx, ky, kz],
            s: [-(d[kx] / d[kz]), -(d[ky] / d[kz]), 1.0 / d[kz]],
        }
    }

    /// The origin, the axis permutation (kx, ky, kz) and the factors (−sx, −sy, sz).
    #[inline(always)]
    pub fn shear(&self) -> (Vec3A, [usize; 3], [f32; 3]) {
        (self.org, self.k, self.s)
    }

    /// Sheared x, y and scaled z of vertex `v` relative to the origin.
    #[inline(always)]
    fn sheared(&self, v: Vec3A) -> (f32, f32, f32) {
        let a = (v - self.org).to_array();
        let [kx, ky, kz] = self.k;
        let az = a[kz];
        (
            a[kx] + az * self.s[0],
            a[ky] + az * self.s[1],
            az * self.s[2],
        )
    }

    /// Returns (t, b1, b2) for a hit with 0 < t < tmax, or None. The algorithm of §3 (no
    /// back-face culling); falls back to f64 edge functions when one of them is exactly zero
    /// (§3.3).
    #[inline(always)]
    pub fn intersect(&self, tri: &LeafTri, tmax: f32) -> Option<(f32, f32, f32)> {
        let (ax, ay, az) = self.sheared(tri.v0);
        let (bx, by, bz) = self.sheared(tri.v1);
        let (cx, cy, cz) = self.sheared(tri.v2);
        let mut u = cx * by - cy * bx;
        let mut v = ax * cy - ay * cx;
        let mut w = bx * ay - by * ax;
        if u == 0.0 || v == 0.0 || w == 0.0 {
            u = (cx as f64 * by as f64 - cy as f64 * bx as f64) as f32;
            v = (ax as f64 * cy as f64 - ay as f64 * cx as f64) as f32;
            w = (bx as f64 * ay as f64 - by as f64 * ax as f64) as f32;
        }
        if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
            return None;
        }
        let det = u + v + w;
        if det == 0.0 {
            return None;
        }
        let t_scaled = u * az + v * bz + w * cz;
        let inv = 1.0 / det;
        let t = t_scaled * inv;
        if !(t > 0.0 && t < tmax) {
            return None;
        }
        Some((t, v * inv, w * inv))
    }
}
