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

/// Per-ray constants of the watertight test: §3 of the paper (axis permutation and shear).
#[derive(Clone, Copy)]
pub struct WatertightRay {
    org: Vec3A,
    kx: usize,
    ky: usize,
    kz: usize,
    sx: f32,
    sy: f32,
    sz: f32,
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
        WatertightRay {
            org,
            kx,
            ky,
            kz,
            sx: dir[kx] / dir[kz],
            sy: dir[ky] / dir[kz],
            sz: 1.0 / dir[kz],
        }
    }

    /// Returns (t, b1, b2) for a hit with 0 < t < tmax, or None. The algorithm of §3 (no
    /// back-face culling); falls back to f64 edge functions when one of them is exactly zero
    /// (§3.3).
    #[inline(always)]
    pub fn intersect(&self, tri: &LeafTri, tmax: f32) -> Option<(f32, f32, f32)> {
        let a = tri.v0 - self.org;
        let b = tri.v1 - self.org;
        let c = tri.v2 - self.org;
        let (kx, ky, kz) = (self.kx, self.ky, self.kz);
        let ax = a[kx] - self.sx * a[kz];
        let ay = a[ky] - self.sy * a[kz];
        let bx = b[kx] - self.sx * b[kz];
        let by = b[ky] - self.sy * b[kz];
        let cx = c[kx] - self.sx * c[kz];
        let cy = c[ky] - self.sy * c[kz];
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
        let az = self.sz * a[kz];
        let bz = self.sz * b[kz];
        let cz = self.sz * c[kz];
        let t_scaled = u * az + v * bz + w * cz;
        let inv = 1.0 / det;
        let t = t_scaled * inv;
        if !(t > 0.0 && t < tmax) {
            return None;
        }
        Some((t, v * inv, w * inv))
    }
}
