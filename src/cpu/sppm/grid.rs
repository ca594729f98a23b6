//! A hashed uniform grid over photon positions for fixed-radius queries (Hachisuka & Jensen
//! 2009, §4.2; Teschner et al. 2003, "Optimized Spatial Hashing for Collision Detection of
//! Deformable Objects", for the hash). Cells are 2r wide, so the ball of radius r around a
//! query point overlaps at most 2 × 2 × 2 cells; photons are sorted by bucket (a counting
//! sort), so a bucket is one contiguous slice.

use glam::{IVec3, Vec3};

/// Photon indices bucketed by the hash of their grid cell.
pub struct HashGrid {
    inv_cell: f32,
    mask: u32,
    /// `start[b]..start[b + 1]` indexes `order` for bucket b.
    start: Vec<u32>,
    /// Point indices, grouped by bucket.
    order: Vec<u32>,
    radius2: f32,
    /// The points' bounds grown by the radius: queries outside find nothing.
    lo: Vec3,
    hi: Vec3,
}

/// ⌊v⌋ per component without a libm call (baseline x86-64 has no SSE4.1 `roundps`). Exact
/// for |v| < 2³¹; beyond, the casts saturate, the same for building and querying.
#[inline(always)]
fn floor_i(v: Vec3) -> IVec3 {
    let t = v.as_ivec3(); // truncates towards zero
    t - IVec3::from(t.as_vec3().cmpgt(v)).abs()
}

#[inline]
fn hash(c: IVec3, mask: u32) -> u32 {
    let h = (c.x as u32).wrapping_mul(73_856_093)
        ^ (c.y as u32).wrapping_mul(19_349_663)
        ^ (c.z as u32).wrapping_mul(83_492_791);
    h & mask
}

impl HashGrid {
    /// Bucket `points` for queries of radius `radius` (> 0, finite).
    pub fn build(points: impl ExactSizeIterator<Item = Vec3> + Clone, radius: f32) -> HashGrid {
        let n = points.len();
        let buckets = (2 * n).next_power_of_two().max(16);
        let mask = buckets as u32 - 1;
        let inv_cell = 0.5 / radius;
        let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
        for p in points.clone() {
            lo = lo.min(p);
            hi = hi.max(p);
        }
        let cell = |p: Vec3| floor_i(p * inv_cell);
        let mut start = vec![0u32; buckets + 1];
        for p in points.clone() {
            start[hash(cell(p), mask) as usize + 1] += 1;
        }
        for b in 0..buckets {
            start[b + 1] += start[b];
        }
        let mut fill = start.clone();
        let mut order = vec![0u32; n];
        for (i, p) in points.enumerate() {
            let b = hash(cell(p), mask) as usize;
            order[fill[b] as usize] = i as u32;
            fill[b] += 1;
        }
        HashGrid {
            inv_cell,
            mask,
            start,
            order,
            radius2: radius * radius,
            lo: lo - Vec3::splat(radius),
            hi: hi + Vec3::splat(radius),
        }
    }

    /// The query radius squared.
    pub fn radius2(&self) -> f32 {
        self.radius2
    }

    /// Call `f(i)` for every point index whose bucket may hold points within the radius of
    /// `x` (each bucket once; the caller tests the distance).
    #[inline]
    pub fn candidates(&self, x: Vec3, mut f: impl FnMut(u32)) {
        // Cells overlapping [x − r, x + r]: with cells 2r wide, the lower corner's cell and
        // the one above it on each axis.
        if x.cmplt(self.lo).any() || x.cmpgt(self.hi).any() {
            return;
        }
        let lo = floor_i((x * self.inv_cell) - Vec3::splat(0.5));
        let mut seen = [u32::MAX; 8];
        let mut n_seen = 0;
        for dz in 0..2 {
            for dy in 0..2 {
                for dx in 0..2 {
                    let b = hash(lo + IVec3::new(dx, dy, dz), self.mask);
                    if seen[..n_seen].contains(&b) {
                        continue; // two cells hashed to one bucket: visit it once
                    }
                    seen[n_seen] = b;
                    n_seen += 1;
                    let (s, e) = (self.start[b as usize], self.start[b as usize + 1]);
                    for &i in &self.order[s as usize..e as usize] {
                        f(i);
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every point within the radius is offered exactly once, for queries all over a
    /// cloud that spans many cells (negative coordinates included).
    #[test]
    fn candidates_cover_the_ball_once() {
        let mut s = 1u32;
        let mut rnd = || {
            s = crate::math::rng::pcg_hash(s);
            crate::math::rng::u32_to_unit_f32(s) * 4.0 - 2.0
        };
        let pts: Vec<Vec3> = (0..3000).map(|_| Vec3::new(rnd(), rnd(), rnd())).collect();
        let r = 0.13;
        let grid = HashGrid::build(pts.iter().copied(), r);
        for _ in 0..500 {
            let x = Vec3::new(rnd(), rnd(), rnd());
            let mut offered = vec![0u32; pts.len()];
            grid.candidates(x, |i| offered[i as usize] += 1);
            for (i, p) in pts.iter().enumerate() {
                if p.distance_squared(x) <= grid.radius2() {
                    assert_eq!(offered[i], 1, "point {i} at {p} for query {x}");
                }
                assert!(offered[i] <= 1, "point {i} offered twice");
            }
        }
    }
}
