//! Bounding volume hierarchy for the CPU: obvhs' PLOC BVH2 collapsed to our own wide BVH
//! (`wide`), traversed with a conservative SIMD slab test (`slab`, `simd_x86`, `simd_neon`,
//! flavour chosen at build: `kernel`) and the watertight ray/triangle test (`watertight`);
//! plus robust ray-origin offsets (`offset`). The GPU builds its own BVH2 (`gpu::upload`).

mod kernel;
mod offset;
mod packet;
#[cfg(target_arch = "aarch64")]
mod simd_neon;
#[cfg(target_arch = "x86_64")]
mod simd_x86;
mod slab;
mod traverse;
mod watertight;
mod wide;

pub use kernel::Kernel;
pub use offset::{offset_ray_origin, offset_scale};

use crate::scene::Mesh;
use glam::{Vec3, Vec3A};
use kernel::QueryFn;
use obvhs::{BvhBuildParams, triangle::Triangle};
use packet::{LANES, TriPacket};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};
use traverse::{QueryRay, Tree};
use watertight::{LeafTri, WatertightRay};
use wide::WideNode;

/// The mesh's triangles in obvhs' form, in scene order: the build input of the CPU's wide
/// BVH and of the GPU's BVH2 (`gpu::upload`).
pub(crate) fn triangles(mesh: &Mesh) -> Vec<Triangle> {
    (0..mesh.triangle_count())
        .map(|t| {
            let [a, b, c] = mesh.tri(t);
            Triangle {
                v0: a.into(),
                v1: b.into(),
                v2: c.into(),
            }
        })
        .collect()
}

/// obvhs' PLOC BVH2 over `tris` collapsed to wide nodes: (nodes, levels, triangle order of
/// the leaves); all empty without triangles.
fn build_wide(tris: &[Triangle]) -> (Vec<WideNode>, u32, Vec<u32>) {
    if tris.is_empty() {
        return (Vec::new(), 0, Vec::new());
    }
    let params = BvhBuildParams {
        max_prims_per_leaf: wide::MAX_LEAF,
        ..BvhBuildParams::medium_build()
    };
    let mut core = Duration::ZERO;
    let bvh2 = obvhs::bvh2::builder::build_bvh2_from_tris(tris, params, &mut core);
    let (nodes, depth) = wide::collapse(&bvh2);
    (nodes, depth, bvh2.primitive_indices)
}

/// Number the leaves of `nodes` as packets and fill them with their triangles (`order` maps
/// leaf ranges to indices into `tris`): (packets, scene triangle of each leaf slot).
fn pack_leaves(
    nodes: &mut [WideNode],
    order: &[u32],
    tris: &[Triangle],
) -> (Vec<TriPacket>, Vec<u32>) {
    let leaves = wide::number_packets(nodes);
    let mut leaf_to_tri = vec![u32::MAX; leaves.len() * LANES];
    let packets = leaves
        .iter()
        .enumerate()
        .map(|(k, &(first, count))| {
            let ids = &order[first as usize..(first + count) as usize];
            leaf_to_tri[k * LANES..k * LANES + ids.len()].copy_from_slice(ids);
            let leaf: Vec<LeafTri> = ids
                .iter()
                .map(|&i| {
                    let t = &tris[i as usize];
                    LeafTri {
                        v0: t.v0,
                        v1: t.v1,
                        v2: t.v2,
                    }
                })
                .collect();
            TriPacket::new(&leaf)
        })
        .collect();
    (packets, leaf_to_tri)
}

/// A closest-hit result.
#[derive(Clone, Copy, Debug)]
pub struct Hit {
    pub t: f32,
    /// Index into the scene's triangle list.
    pub tri: u32,
    /// Barycentric weights of v1 and v2 (v0 gets 1 − b1 − b2).
    pub b1: f32,
    pub b2: f32,
}

/// The acceleration structure of one scene.
pub struct Bvh {
    nodes: Vec<WideNode>,
    /// One packet of triangles per leaf (a leaf word's first index names its packet).
    packets: Vec<TriPacket>,
    /// Scene triangle index of each leaf slot (packet · `LANES` + lane; padding lanes
    /// `u32::MAX`, never hit).
    leaf_to_tri: Vec<u32>,
    /// Levels of wide nodes.
    depth: u32,
    kernel: Kernel,
    closest: QueryFn,
    any: QueryFn,
    /// Power of two the ray-offset constants scale with (see `offset_scale`).
    offset_scale: f32,
    /// Queries refused because the ray had a NaN or infinite component or a zero direction.
    invalid_rays: AtomicU64,
    pub build_time: Duration,
}

impl Bvh {
    /// Build over the mesh's triangles: obvhs' PLOC BVH2 (medium preset: reinsertion before
    /// and after its leaf collapse, ≤ `wide::MAX_LEAF` triangles per leaf), collapsed to
    /// `wide::W`-ary nodes, slab-test flavour from `Kernel::detect`.
    pub fn build(mesh: &Mesh) -> Bvh {
        let start = Instant::now();
        let tris = triangles(mesh);
        let (mut nodes, depth, order) = build_wide(&tris);
        let (packets, leaf_to_tri) = pack_leaves(&mut nodes, &order, &tris);
        let kernel = Kernel::detect();
        let (closest, any) = kernel.queries().expect("detected kernels are supported");
        Bvh {
            nodes,
            packets,
            leaf_to_tri,
            depth,
            kernel,
            closest,
            any,
            offset_scale: offset::offset_scale_for(offset::mesh_extent(mesh)),
            invalid_rays: AtomicU64::new(0),
            build_time: start.elapsed(),
        }
    }

    /// Switch to slab-test flavour `k` (tests, measurements); false (and no change) when this
    /// CPU does not run it.
    pub fn set_kernel(&mut self, k: Kernel) -> bool {
        let Some((closest, any)) = k.queries() else {
            return false;
        };
        (self.kernel, self.closest, self.any) = (k, closest, any);
        true
    }

    pub fn kernel(&self) -> Kernel {
        self.kernel
    }

    /// Wide nodes and their levels.
    pub fn shape(&self) -> (usize, u32) {
        (self.nodes.len(), self.depth)
    }

    /// Queries refused so far for a NaN or infinite origin, direction or tmax (tmax = +∞ is
    /// valid) or a zero direction.
    pub fn invalid_rays(&self) -> u64 {
        self.invalid_rays.load(Ordering::Relaxed)
    }

    /// The scene's ray-offset scale (`offset_scale`), for `offset_ray_origin`.
    #[inline]
    pub fn offset_scale(&self) -> f32 {
        self.offset_scale
    }

    /// Closest hit along `origin + t·dir` for t in (0, tmax).
    #[inline]
    pub fn intersect(&self, origin: Vec3, dir: Vec3, tmax: f32) -> Option<Hit> {
        let q = self.query(origin, dir, tmax)?;
        let h = (self.closest)(self.tree(), &q)?;
        Some(Hit {
            t: h.t,
            tri: self.leaf_to_tri[h.slot as usize],
            b1: h.b1,
            b2: h.b2,
        })
    }

    /// True if anything is hit along `origin + t·dir` for t in (0, tmax).
    #[inline]
    pub fn occluded(&self, origin: Vec3, dir: Vec3, tmax: f32) -> bool {
        self.query(origin, dir, tmax)
            .is_some_and(|q| (self.any)(self.tree(), &q).is_some())
    }

    fn tree(&self) -> Tree<'_> {
        Tree {
            nodes: &self.nodes,
            packets: &self.packets,
        }
    }

    /// The traversal's form of a ray; None (counted when invalid) for rays that cannot hit.
    #[inline(always)]
    fn query(&self, origin: Vec3, dir: Vec3, tmax: f32) -> Option<QueryRay> {
        // Vec3A: each test one SIMD compare (the scalar form was ~19 instructions a query).
        let (o, d) = (Vec3A::from(origin), Vec3A::from(dir));
        let valid = (o.is_finite_mask() & d.is_finite_mask()).all()
            && d.cmpne(Vec3A::ZERO).any()
            && !tmax.is_nan();
        if !valid {
            self.invalid_rays.fetch_add(1, Ordering::Relaxed);
            return None;
        }
        if self.packets.is_empty() || tmax <= 0.0 {
            return None;
        }
        Some(QueryRay {
            origin: o,
            dir: d,
            tmax,
        })
    }
}

/// The watertight ray/triangle test alone (Woop et al. 2013, as the traversal runs it):
/// (t, b1, b2) for a hit with 0 < t < tmax. The reference of brute-force checks.
pub fn intersect_triangle(
    tri: [Vec3; 3],
    origin: Vec3,
    dir: Vec3,
    tmax: f32,
) -> Option<(f32, f32, f32)> {
    let [v0, v1, v2] = tri.map(Vec3A::from);
    WatertightRay::new(origin.into(), dir.into()).intersect(&LeafTri { v0, v1, v2 }, tmax)
}
