//! The wide BVH against a brute-force loop over every triangle with the same watertight test
//! (`bvh::intersect_triangle`): exactly the same closest hit (bit-identical t, same triangle)
//! and the same occlusion answers, for every slab-test flavour this CPU runs, on random rays,
//! rays starting on surfaces, grazing rays and rays lying in box faces; and invalid rays.

use glam::Vec3;
use refract::bvh::{Bvh, Kernel, intersect_triangle};
use refract::scene::{Mesh, Scene};

/// SplitMix64 (Steele, Lea & Flood 2014): a small deterministic generator for test rays.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    fn f(&mut self) -> f32 {
        (self.next() >> 40) as f32 / (1u64 << 24) as f32
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
    fn dir(&mut self) -> Vec3 {
        let z = 1.0 - 2.0 * self.f();
        let r = (1.0 - z * z).max(0.0).sqrt();
        let phi = std::f32::consts::TAU * self.f();
        Vec3::new(r * phi.cos(), r * phi.sin(), z)
    }
}

/// Closest hit of all triangles, lowest index first on exact ties.
fn brute(mesh: &Mesh, o: Vec3, d: Vec3, tmax: f32) -> Option<(f32, u32)> {
    let mut best: Option<(f32, u32)> = None;
    for t in 0..mesh.triangle_count() {
        let limit = best.map_or(tmax, |b| b.0);
        if let Some((tt, _, _)) = intersect_triangle(mesh.tri(t), o, d, limit) {
            best = Some((tt, t as u32));
        }
    }
    best
}

/// A random point of triangle `t`.
fn point_on(mesh: &Mesh, t: usize, rng: &mut Rng) -> Vec3 {
    let [a, b, c] = mesh.tri(t);
    let (mut u, mut v) = (rng.f(), rng.f());
    if u + v > 1.0 {
        (u, v) = (1.0 - u, 1.0 - v);
    }
    a + (b - a) * u + (c - a) * v
}

/// Test rays of four kinds (see the module doc), each with its kind's name.
fn rays(mesh: &Mesh, n: usize, seed: u64) -> Vec<(&'static str, Vec3, Vec3)> {
    let mut rng = Rng(seed);
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for p in &mesh.positions {
        (lo, hi) = (lo.min(*p), hi.max(*p));
    }
    let size = (hi - lo).max_element();
    let mut out = Vec::new();
    for i in 0..n {
        let t = rng.below(mesh.triangle_count());
        let [a, b, c] = mesh.tri(t);
        let ng = (b - a).cross(c - a).normalize_or_zero();
        out.push(match i % 4 {
            0 => {
                let u = Vec3::new(rng.f(), rng.f(), rng.f());
                ("random", lo + (hi - lo) * (1.2 * u - 0.1), rng.dir())
            }
            1 => ("on surface", point_on(mesh, t, &mut rng), rng.dir()),
            2 => {
                // Towards a point of the triangle, within 1e-3 … 1e-7 radians of its plane.
                let p = point_on(mesh, t, &mut rng);
                let tangent = ((b - a) * rng.f() + (c - a) * rng.f()).normalize_or_zero();
                let tilt =
                    10f32.powf(-3.0 - 4.0 * rng.f()) * if rng.f() < 0.5 { -1.0 } else { 1.0 };
                let d = (tangent + ng * tilt).normalize_or_zero();
                ("grazing", p - d * size * (0.1 + rng.f()), d)
            }
            _ => {
                // In the plane of a coordinate through a vertex (a box face, an axis-aligned
                // wall or edge): one direction component exactly 0, sometimes two.
                let v = [a, b, c][rng.below(3)];
                let axis = rng.below(3);
                let mut d = rng.dir();
                d[axis] = 0.0;
                if rng.f() < 0.3 {
                    d[(axis + 1) % 3] = 0.0;
                }
                let mut o = v - d * size * rng.f();
                o[axis] = v[axis];
                ("in a box face", o, d.normalize_or_zero())
            }
        });
    }
    out.retain(|r| r.2 != Vec3::ZERO);
    out
}

/// Every ray of `rays` against brute force: the closest hit, then occlusion for segments
/// ending before, at and after it. Returns the number of hits and exact ties seen.
fn check(name: &str, mesh: &Mesh, bvh: &Bvh, rays: &[(&str, Vec3, Vec3)]) -> (usize, usize) {
    let (mut hits, mut ties, mut wrong) = (0, 0, Vec::new());
    for &(kind, o, d) in rays {
        let want = brute(mesh, o, d, f32::INFINITY);
        let got = bvh.intersect(o, d, f32::INFINITY).map(|h| (h.t, h.tri));
        let same = match (want, got) {
            (None, None) => true,
            (Some(w), Some(g)) if w == g => true,
            // Another triangle at bit-identically the same distance (a shared edge or vertex).
            (Some(w), Some(g)) if w.0 == g.0 => {
                ties += 1;
                intersect_triangle(mesh.tri(g.1 as usize), o, d, f32::INFINITY)
                    .is_some_and(|h| h.0 == w.0)
            }
            _ => false,
        };
        hits += want.is_some() as usize;
        let t = want.map_or(1.0, |w| w.0);
        for tmax in [0.5 * t, t, 2.0 * t, f32::INFINITY] {
            let occluded = want.is_some_and(|w| w.0 < tmax);
            if bvh.occluded(o, d, tmax) != occluded {
                wrong.push(format!(
                    "{kind} {o} {d}: occluded({tmax}) should be {occluded}"
                ));
            }
        }
        if !same {
            wrong.push(format!("{kind} {o} {d}: {got:?} instead of {want:?}"));
        }
    }
    assert!(
        wrong.is_empty(),
        "{name} ({:?}): {} of {} rays wrong:\n{}",
        bvh.kernel(),
        wrong.len(),
        rays.len(),
        wrong[..wrong.len().min(12)].join("\n")
    );
    (hits, ties)
}

#[test]
fn wide_bvh_matches_brute_force() {
    let scenes = [
        "cornell-glass",
        "glass-slab",
        "prism",
        "caustic-mirror",
        "glass-of-water",
    ];
    for (s, name) in scenes.into_iter().enumerate() {
        let mesh = Scene::load(&format!("builtin:{name}"))
            .expect("built-in")
            .mesh;
        let mut bvh = Bvh::build(&mesh);
        let rays = rays(&mesh, 2400, 1 + s as u64);
        let mut kernels = 0;
        for k in Kernel::ALL {
            if !bvh.set_kernel(k) {
                continue;
            }
            kernels += 1;
            let (hits, ties) = check(name, &mesh, &bvh, &rays);
            eprintln!(
                "{name} ({} tris, {:?} nodes/depth), {k:?}: {} rays, {hits} hits, {ties} ties",
                mesh.triangle_count(),
                bvh.shape(),
                rays.len()
            );
            assert!(hits * 4 > rays.len(), "{name}: only {hits} hits");
        }
        assert!(kernels >= 2, "the scalar flavour and at least one SIMD one");
        assert_eq!(bvh.invalid_rays(), 0);
    }
}

/// NaN and infinite rays (origin, direction or tmax) and zero directions never enter the
/// traversal: no hit, not occluded, each counted once; +∞ tmax and empty segments are valid.
#[test]
fn invalid_rays_are_refused_and_counted() {
    let mesh = Scene::load("builtin:cornell-glass").expect("built-in").mesh;
    let bvh = Bvh::build(&mesh);
    let (o, d) = (Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.0, -1.0, 0.0));
    assert!(bvh.intersect(o, d, f32::INFINITY).is_some());
    assert!(bvh.occluded(o, d, f32::INFINITY));
    assert!(bvh.intersect(o, d, 0.0).is_none() && bvh.intersect(o, d, -1.0).is_none());
    assert_eq!(bvh.invalid_rays(), 0);
    let (nan, inf) = (f32::NAN, f32::INFINITY);
    let bad = [
        (Vec3::new(nan, 1.0, 0.0), d, inf),
        (Vec3::new(0.0, inf, 0.0), d, inf),
        (o, Vec3::new(0.0, nan, 0.0), inf),
        (o, Vec3::new(0.0, -inf, 0.0), inf),
        (o, Vec3::new(-inf, inf, 0.0), inf),
        (o, Vec3::ZERO, inf),
        (o, d, nan),
    ];
    for (i, &(o, d, tmax)) in bad.iter().enumerate() {
        assert!(bvh.intersect(o, d, tmax).is_none(), "ray {i} hit");
        assert!(!bvh.occluded(o, d, tmax), "ray {i} occluded");
        assert_eq!(
            bvh.invalid_rays(),
            2 * (i as u64 + 1),
            "ray {i} not counted"
        );
    }
}
