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

/// Per-ray constants of the watertight test: §3 of the paper (axis permutation kx, ky, kz and
/// shear sx, sy, sz), kept as three row vectors so that the sheared coordinates of a vertex
/// offset A are dot products: A·mx = A[kx] − sx·A[kz], A·my = A[ky] − sy·A[kz], A·mz =
/// sz·A[kz]. The other terms are products with 0 (exact zeros), so each dot product rounds
/// exactly like the paper's expression.
#[derive(Clone, Copy)]
pub struct WatertightRay {
    org: Vec3A,
    mx: Vec3A,
    my: Vec3A,
    mz: Vec3A,
    /// The permutation (kx, ky, kz) and the factors −sx, −sy, sz (`shear`).
    k: [usize; 3],
    s: [f32; 3],
}

impl WatertightRay {
    /// `dir` must have a nonzero component.
    #[inline(always)]
    pub fn new(org: Vec3A, dir: Vec3A) -> Self {
        let a = dir.abs();
        let kz = if a.x > a.y {
            if a.x > a.z { 0 } else { 2 }
        } else if a.y > a.z {
            1
        } else {
            2
        };
        let mut kx = (kz + 1) % 3;
        let mut ky = (kx + 1) % 3;
        if dir[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        let row = |k: usize, s: f32| {
            let mut m = [0.0f32; 3];
            m[k] = 1.0;
            m[kz] = -s;
            Vec3A::from(m)
        };
        let mut mz = [0.0f32; 3];
        mz[kz] = 1.0 / dir[kz];
        let (sx, sy) = (dir[kx] / dir[kz], dir[ky] / dir[kz]);
        WatertightRay {
            org,
            mx: row(kx, sx),
            my: row(ky, sy),
            mz: Vec3A::from(mz),
            k: [kx, ky, kz],
            s: [-sx, -sy, mz[kz]],
        }
    }

    /// The origin, the axis permutation (kx, ky, kz) and the factors (−sx, −sy, sz) of §3:
    /// A·mx = A[kx] + A[kz]·(−sx), A·my = A[ky] + A[kz]·(−sy), A·mz = A[kz]·sz.
    #[inline(always)]
    pub fn shear(&self) -> ([f32; 3], [usize; 3], [f32; 3]) {
        (self.org.to_array(), self.k, self.s)
    }

    /// Returns (t, b1, b2) for a hit with 0 < t < tmax, or None. The algorithm of §3 (no
    /// back-face culling); falls back to f64 edge functions when one of them is exactly zero
    /// (§3.3).
    #[inline(always)]
    pub fn intersect(&self, tri: &LeafTri, tmax: f32) -> Option<(f32, f32, f32)> {
        let a = tri.v0 - self.org;
        let b = tri.v1 - self.org;
        let c = tri.v2 - self.org;
        let (ax, ay) = (a.dot(self.mx), a.dot(self.my));
        let (bx, by) = (b.dot(self.mx), b.dot(self.my));
        let (cx, cy) = (c.dot(self.mx), c.dot(self.my));
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
        let (az, bz, cz) = (a.dot(self.mz), b.dot(self.mz), c.dot(self.mz));
        let t_scaled = u * az + v * bz + w * cz;
        let inv = 1.0 / det;
        let t = t_scaled * inv;
        if !(t > 0.0 && t < tmax) {
            return None;
        }
        Some((t, v * inv, w * inv))
    }
}
