//! The GPU traversals (BVH2 and the compressed wide BVH) against a brute-force loop over every
//! triangle with the same watertight test — `traverse` over a one-leaf BVH2 holding every
//! triangle slot, the same kernel code — both run by the traversal probe (`gpu::bvh_probe`,
//! src/gpu/bvh_probe.wgsl): exactly the same closest hit (bit-identical
//! t, the same triangle or another at bit-identically the same t) and the same occlusion
//! answers for segments ending before, at and after it, on random rays, rays starting on
//! surfaces, grazing rays and rays lying in box faces, on several built-ins and on scenes
//! scaled by 1e-5 and 1e5; the CWBVH with its children tested one at a time (GPUs) and four at
//! once (`BVH_CHILDREN_X4`, CPU-emulated adapters). Also: the CWBVH's traversal stack holds every pending group.

mod common_scenes;
use common_scenes::gpu_context;
use glam::Vec3;
use refract::gpu::GpuContext;
use refract::gpu::bvh_probe::run_bvh_probe;
use refract::gpu::layout::{self, BvhProbeOut, BvhProbeRay};
use refract::gpu::pipeline::bvh_probe_source;
use refract::gpu::upload::{self, BvhLayout, GpuBvh};
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

/// A random point of triangle `t`.
fn point_on(mesh: &Mesh, t: usize, rng: &mut Rng) -> Vec3 {
    let [a, b, c] = mesh.tri(t);
    let (mut u, mut v) = (rng.f(), rng.f());
    if u + v > 1.0 {
        (u, v) = (1.0 - u, 1.0 - v);
    }
    a + (b - a) * u + (c - a) * v
}

/// Test rays of four kinds (see the module doc), as in tests/bvh_traversal.rs.
fn rays(mesh: &Mesh, n: usize, seed: u64) -> Vec<(Vec3, Vec3)> {
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
                (lo + (hi - lo) * (1.2 * u - 0.1), rng.dir())
            }
            1 => (point_on(mesh, t, &mut rng), rng.dir()),
            2 => {
                // Towards a point of the triangle, within 1e-3 … 1e-7 radians of its plane.
                let p = point_on(mesh, t, &mut rng);
                let tangent = ((b - a) * rng.f() + (c - a) * rng.f()).normalize_or_zero();
                let tilt =
                    10f32.powf(-3.0 - 4.0 * rng.f()) * if rng.f() < 0.5 { -1.0 } else { 1.0 };
                let d = (tangent + ng * tilt).normalize_or_zero();
                (p - d * size * (0.1 + rng.f()), d)
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
                (o, d.normalize_or_zero())
            }
        });
    }
    out.retain(|r| r.1 != Vec3::ZERO);
    out
}

fn probe_ray(o: Vec3, d: Vec3, tmax: f32, any_hit: bool) -> BvhProbeRay {
    BvhProbeRay {
        org: o.to_array(),
        tmax,
        dir: d.to_array(),
        any_hit: u32::from(any_hit),
    }
}

/// Trace `rays` through `bvh`; a device error fails the test.
fn probe(
    ctx: &GpuContext,
    s: &Scene,
    bvh: &GpuBvh,
    rays: &[BvhProbeRay],
    x4: bool,
) -> Vec<BvhProbeOut> {
    run_bvh_probe(ctx, s, bvh, rays, x4).expect("bvh probe")
}

/// A BVH2 of one leaf holding every slot of `bvh` in order, its box the scene's: `traverse`
/// over it is a brute-force loop through the same code (kernel, call site) as the BVH2's.
fn one_leaf(bvh: &GpuBvh, scene: &Scene) -> GpuBvh {
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for p in &scene.mesh.positions {
        (lo, hi) = (lo.min(*p), hi.max(*p));
    }
    GpuBvh {
        layout: BvhLayout::Bvh2,
        nodes: vec![layout::BvhNode {
            lo: lo.to_array(),
            prim_count: bvh.primitive_indices.len() as u32,
            hi: hi.to_array(),
            first_index: 0,
        }],
        wide_nodes: Vec::new(),
        depth: 1,
        ..bvh.clone()
    }
}

/// The traversal of `bvh` (a CWBVH's children four at once with `x4`) against brute force on
/// `rays`: (hits, exact ties).
fn check(
    ctx: &GpuContext,
    (name, scene): (&str, &Scene),
    bvh: &GpuBvh,
    x4: bool,
    rays: &[(Vec3, Vec3)],
) -> (usize, usize) {
    let closest: Vec<_> = rays
        .iter()
        .map(|&(o, d)| probe_ray(o, d, f32::MAX, false))
        .collect();
    let brute = one_leaf(bvh, scene);
    let want = probe(ctx, scene, &brute, &closest, false);
    let got = probe(ctx, scene, bvh, &closest, x4);
    let tri = |o: &BvhProbeOut| bvh.primitive_indices[o.slot as usize];
    let (mut hits, mut ties, mut wrong) = (0, 0, Vec::new());
    for ((r, w), g) in rays.iter().zip(&want).zip(&got) {
        let same = match (w.found, g.found) {
            (0, 0) => true,
            (1, 1) if w.t.to_bits() == g.t.to_bits() && tri(w) == tri(g) => true,
            // Another triangle at bit-identically the same distance (a shared edge or vertex).
            (1, 1) if w.t.to_bits() == g.t.to_bits() => {
                ties += 1;
                true
            }
            _ => false,
        };
        hits += w.found as usize;
        if !same {
            wrong.push(format!("{r:?}: {g:?} instead of {w:?}"));
        }
    }
    // Occlusion of the segments ending at half, at and at twice the closest hit, and of the
    // whole ray: the first hit the traversal finds against the brute-force loop's.
    let mut shadow = Vec::new();
    for (&(o, d), w) in rays.iter().zip(&want) {
        let t = if w.found == 1 { w.t } else { 1.0 };
        for tmax in [0.5 * t, t, 2.0 * t, f32::MAX] {
            shadow.push(probe_ray(o, d, tmax, true));
        }
    }
    let want_s = probe(ctx, scene, &brute, &shadow, false);
    let got_s = probe(ctx, scene, bvh, &shadow, x4);
    for ((r, w), g) in shadow.iter().zip(&want_s).zip(&got_s) {
        if w.found != g.found {
            wrong.push(format!(
                "occlusion {r:?}: {} instead of {}",
                g.found, w.found
            ));
        }
    }
    assert!(
        wrong.is_empty(),
        "{name} ({:?}, x4 {x4}): {} of {} queries wrong:\n{}",
        bvh.layout,
        wrong.len(),
        closest.len() + shadow.len(),
        wrong[..wrong.len().min(12)].join("\n")
    );
    (hits, ties)
}

/// `scene` with every position multiplied by `k`.
fn scaled(mut scene: Scene, k: f32) -> Scene {
    for p in &mut scene.mesh.positions {
        *p *= k;
    }
    scene
}

#[test]
fn gpu_traversal_matches_brute_force() {
    let Some(ctx) = gpu_context("gpu_traversal_matches_brute_force") else {
        return;
    };
    let load = |n: &str| Scene::load(&format!("builtin:{n}")).expect("built-in");
    let scenes = [
        ("cornell-glass", load("cornell-glass")),
        ("glass-slab", load("glass-slab")),
        ("prism", load("prism")),
        ("caustic-mirror", load("caustic-mirror")),
        ("glass-of-water", load("glass-of-water")),
        ("materials", load("materials")),
        ("cornell-glass × 1e-5", scaled(load("cornell-glass"), 1e-5)),
        ("glass-of-water × 1e5", scaled(load("glass-of-water"), 1e5)),
    ];
    for (s, (name, scene)) in scenes.into_iter().enumerate() {
        let rays = rays(&scene.mesh, 2400, 1 + s as u64);
        let forms = [
            (BvhLayout::Bvh2, false),
            (BvhLayout::Cwbvh, false),
            (BvhLayout::Cwbvh, true),
        ];
        for (layout, x4) in forms {
            let bvh = upload::build_gpu_bvh(&scene, layout).expect("BVH");
            let (hits, ties) = check(&ctx, (name, &scene), &bvh, x4, &rays);
            eprintln!(
                "{name} ({} tris), {layout:?} x4 {x4} ({} nodes, depth {}): {} rays, {hits} hits, {ties} ties",
                scene.mesh.triangle_count(),
                bvh.node_count(),
                bvh.depth,
                rays.len()
            );
            assert!(hits * 4 > rays.len(), "{name}: only {hits} hits");
        }
    }
}

/// The probe's structs match their WGSL, and so does the CWBVH node (also in the integrator).
#[test]
fn bvh_probe_layouts_match_wgsl() {
    let src = bvh_probe_source();
    layout::check_layout::<layout::BvhProbeRay>(&src).unwrap();
    layout::check_layout::<layout::BvhProbeOut>(&src).unwrap();
    layout::check_layout::<layout::CwNode>(&src).unwrap();
    let integrator = refract::gpu::pipeline::integrator_source();
    layout::check_layout::<layout::CwNode>(&integrator).unwrap();
}

/// cwbvh.wgsl's loop over the uploaded CWBVHs of every built-in, with every child box hit:
/// a group waits on the stack only while a node of it is being descended, so at most
/// depth − 1 groups (two words each) are pending, within `upload::cwbvh_stack_words`.
#[test]
fn cwbvh_stack_holds_every_pending_group() {
    for name in refract::scene::builtin::NAMES {
        let scene = Scene::load(&format!("builtin:{name}")).expect("built-in");
        let bvh = upload::build_gpu_bvh(&scene, BvhLayout::Cwbvh).unwrap();
        let words = bvh.stack_words() as usize;
        for oct in 0..8u32 {
            let most = max_pending_groups(&bvh, oct);
            assert!(
                most < bvh.depth as usize && 2 * most <= words,
                "{name}: {most} groups pending, depth {}, {words} words",
                bvh.depth
            );
        }
    }
    assert_eq!(upload::cwbvh_stack_words(1), 8);
    assert_eq!(upload::cwbvh_stack_words(9), 16);
    assert_eq!(upload::cwbvh_stack_words(33), 64);
}

/// The most groups on the stack of `traverse_cwbvh` with every child hit, for octant `oct`.
fn max_pending_groups(bvh: &GpuBvh, oct: u32) -> usize {
    let nodes = &bvh.wide_nodes;
    let (mut stack, mut most) = (Vec::<(u32, u32)>::new(), 0);
    let mut group = (0u32, 0x8000_0000u32);
    loop {
        if group.1 & 0xff00_0000 != 0 {
            let bit = 31 - group.1.leading_zeros();
            let slot = (bit - 24) ^ oct;
            let node = group.0 + (group.1 & ((1 << slot) - 1)).count_ones();
            group.1 &= !(1 << bit);
            if group.1 & 0xff00_0000 != 0 {
                stack.push(group);
                most = most.max(stack.len());
            }
            let n = &nodes[node as usize];
            let imask = n.e_imask >> 24;
            let mut hits = 0u32;
            for c in 0..8u32 {
                let m = (n.child_meta[c as usize / 4] >> (8 * (c % 4))) & 255;
                if m != 0 && imask & (1 << c) != 0 {
                    hits |= 1 << (24 + (c ^ oct));
                }
            }
            group = (n.child_base, hits | imask);
        }
        if group.1 & 0xff00_0000 == 0 {
            match stack.pop() {
                Some(g) => group = g,
                None => return most,
            }
        }
    }
}
