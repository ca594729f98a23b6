//! The GPU's tree: obvhs' BVH2 repacked into the GPU node layout, or its compressed 8-wide
//! BVH (`cwbvh`), checked against the fixed-size WGSL traversal stack.

use super::cwbvh::{build_cwbvh, cwbvh_stack_words};
use crate::gpu::layout::{BvhNode, CwNode};
use crate::scene::Scene;
use anyhow::{Result, bail, ensure};
use obvhs::{BvhBuildParams, bvh2::Bvh2};
use std::time::{Duration, Instant};

/// Which tree the GPU traverses (`REFRACT_GPU_BVH=bvh2|cwbvh` overrides the default).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum BvhLayout {
    /// obvhs' BVH2, two children per node (scene.wgsl `traverse_bvh2`).
    Bvh2,
    /// The compressed 8-wide BVH (cwbvh.wgsl `traverse_cwbvh`).
    #[default]
    Cwbvh,
}

impl BvhLayout {
    /// `REFRACT_GPU_BVH` (`bvh2` or `cwbvh`), else the default.
    pub fn from_env() -> BvhLayout {
        match std::env::var("REFRACT_GPU_BVH").as_deref() {
            Ok("bvh2") => BvhLayout::Bvh2,
            Ok("cwbvh") => BvhLayout::Cwbvh,
            _ => BvhLayout::default(),
        }
    }
}

/// obvhs' build preset of the GPU CWBVH, chosen by traversal cost (docs/gpu.md "The wide
/// BVH": of very_fast, fast, medium and slow without splits, each with up to 3 triangles a
/// leaf, and medium with 1 and 2, medium with 2 tests the fewest nodes + triangles per ray,
/// geometric mean over the built-ins, `examples/bvh_cost.rs --presets`).
pub fn cwbvh_params() -> BvhBuildParams {
    BvhBuildParams {
        max_prims_per_leaf: 2,
        ..BvhBuildParams::medium_build()
    }
}

/// Deepest BVH2 the WGSL traversal stack handles (`BVH_STACK_SIZE` in scene.wgsl).
pub const MAX_BVH_DEPTH: u32 = 64;

/// Traversal stack entries for a BVH2 of `depth` levels (root = 1): an ordered traversal
/// holds at most `depth − 1` entries; rounded up to a multiple of 8 (fewer specialisations),
/// at least 8 (the workgroup counter reduction borrows two entries), at most
/// [`MAX_BVH_DEPTH`].
pub fn bvh_stack_entries(depth: u32) -> u32 {
    depth
        .saturating_sub(1)
        .next_multiple_of(8)
        .clamp(8, MAX_BVH_DEPTH)
}

/// The GPU's tree.
#[derive(Clone, Debug, Default)]
pub struct GpuBvh {
    pub layout: BvhLayout,
    /// The BVH2's nodes (layout `Bvh2`; empty otherwise).
    pub nodes: Vec<BvhNode>,
    /// The CWBVH's nodes (layout `Cwbvh`; empty otherwise).
    pub wide_nodes: Vec<CwNode>,
    /// Scene triangle of each leaf slot (obvhs `primitive_indices`).
    pub primitive_indices: Vec<u32>,
    /// Leaf slot of each scene triangle (inverse of `primitive_indices`).
    pub slot_of_tri: Vec<u32>,
    /// Levels of the uploaded tree's nodes (root = 1).
    pub depth: u32,
    pub build_time: Duration,
    /// The ray-offset scale of the scene (`bvh::offset_scale`, the CPU's rule).
    pub offset_scale: f32,
}

impl GpuBvh {
    /// The node buffer's contents (binding 1: `nodes` in scene.wgsl).
    pub fn node_bytes(&self) -> &[u8] {
        match self.layout {
            BvhLayout::Bvh2 => bytemuck::cast_slice(&self.nodes),
            BvhLayout::Cwbvh => bytemuck::cast_slice(&self.wide_nodes),
        }
    }

    /// Nodes of the uploaded tree.
    pub fn node_count(&self) -> usize {
        self.nodes.len() + self.wide_nodes.len()
    }

    /// Traversal stack words per invocation (`BVH_STACK_SIZE`) for this tree.
    pub fn stack_words(&self) -> u32 {
        match self.layout {
            BvhLayout::Bvh2 => bvh_stack_entries(self.depth),
            BvhLayout::Cwbvh => cwbvh_stack_words(self.depth),
        }
    }
}

/// Build the tree of `layout` over the scene's triangles.
pub fn build_gpu_bvh(scene: &Scene, layout: BvhLayout) -> Result<GpuBvh> {
    match layout {
        BvhLayout::Bvh2 => build_bvh(scene),
        BvhLayout::Cwbvh => build_wide_bvh(scene, cwbvh_params()),
    }
}

/// Build the CWBVH over the scene's triangles with obvhs preset `params`.
pub fn build_wide_bvh(scene: &Scene, params: BvhBuildParams) -> Result<GpuBvh> {
    let start = Instant::now();
    let mesh = &scene.mesh;
    let tris = crate::bvh::triangles(mesh);
    if tris.is_empty() {
        return Ok(GpuBvh {
            layout: BvhLayout::Cwbvh,
            nodes: Vec::new(),
            wide_nodes: vec![CwNode::default()],
            depth: 1,
            ..empty_bvh(start)
        });
    }
    let cw = build_cwbvh(&tris, params)?;
    let slot_of_tri = leaf_slots(&cw.primitive_indices, tris.len());
    Ok(GpuBvh {
        layout: BvhLayout::Cwbvh,
        nodes: Vec::new(),
        wide_nodes: cw.nodes,
        primitive_indices: cw.primitive_indices,
        slot_of_tri,
        depth: cw.depth,
        build_time: start.elapsed(),
        offset_scale: crate::bvh::offset_scale(mesh),
    })
}

/// Build an obvhs BVH2 over the scene's triangles and repack its nodes.
pub fn build_bvh(scene: &Scene) -> Result<GpuBvh> {
    let start = Instant::now();
    let mesh = &scene.mesh;
    let tris = crate::bvh::triangles(mesh);
    if tris.is_empty() {
        return Ok(empty_bvh(start));
    }
    let mut core = Duration::ZERO;
    let bvh2 = obvhs::bvh2::builder::build_bvh2_from_tris(
        &tris,
        BvhBuildParams::medium_build(),
        &mut core,
    );
    let nodes = repack_nodes(&bvh2);
    let depth = checked_depth(&nodes, bvh2.primitive_indices.len())?;
    let slot_of_tri = leaf_slots(&bvh2.primitive_indices, tris.len());
    Ok(GpuBvh {
        layout: BvhLayout::Bvh2,
        nodes,
        wide_nodes: Vec::new(),
        primitive_indices: bvh2.primitive_indices.clone(),
        slot_of_tri,
        depth,
        build_time: start.elapsed(),
        offset_scale: crate::bvh::offset_scale(mesh),
    })
}

/// The BVH of a scene without triangles: one leaf with an empty (inverted) box, so every
/// ray misses; `start` is when the build began.
fn empty_bvh(start: Instant) -> GpuBvh {
    GpuBvh {
        layout: BvhLayout::Bvh2,
        nodes: vec![BvhNode {
            lo: [f32::MAX; 3],
            prim_count: 0,
            hi: [-f32::MAX; 3],
            first_index: 0,
        }],
        build_time: start.elapsed(),
        offset_scale: 1.0,
        ..Default::default()
    }
}

/// The obvhs BVH2 nodes in the GPU node layout, in the same order.
fn repack_nodes(bvh2: &Bvh2) -> Vec<BvhNode> {
    bvh2.nodes
        .iter()
        .map(|n| BvhNode {
            lo: n.aabb.min.to_array(),
            prim_count: n.prim_count,
            hi: n.aabb.max.to_array(),
            first_index: n.first_index,
        })
        .collect()
}

/// Depth of the BVH2 rooted at `nodes[0]` (root = 1), after checking that every child
/// index and every leaf range (into `primitive_count` primitive indices) is in range and
/// that the depth fits the fixed-size WGSL traversal stack.
fn checked_depth(nodes: &[BvhNode], primitive_count: usize) -> Result<u32> {
    let mut depth = 0u32;
    let mut stack = vec![(0u32, 1u32)];
    while let Some((i, d)) = stack.pop() {
        depth = depth.max(d);
        let n = nodes
            .get(i as usize)
            .ok_or_else(|| anyhow::anyhow!("BVH node index {i} out of range"))?;
        if n.prim_count == 0 {
            ensure!(
                (n.first_index as usize + 1) < nodes.len(),
                "BVH child index out of range"
            );
            stack.push((n.first_index, d + 1));
            stack.push((n.first_index + 1, d + 1));
        } else {
            ensure!(
                (n.first_index as u64 + n.prim_count as u64) <= primitive_count as u64,
                "BVH leaf range out of range"
            );
        }
    }
    if depth > MAX_BVH_DEPTH {
        bail!("BVH depth {depth} exceeds the GPU traversal stack ({MAX_BVH_DEPTH})");
    }
    Ok(depth)
}

/// Leaf slot of each of `tri_count` scene triangles: the first slot of `primitive_indices`
/// that holds it (`u32::MAX` for a triangle in no leaf).
fn leaf_slots(primitive_indices: &[u32], tri_count: usize) -> Vec<u32> {
    let mut slot_of_tri = vec![u32::MAX; tri_count];
    for (slot, &t) in primitive_indices.iter().enumerate() {
        if let Some(s) = slot_of_tri.get_mut(t as usize)
            && *s == u32::MAX
        {
            *s = slot as u32;
        }
    }
    slot_of_tri
}
