//! The BVH2 for the GPU: built with obvhs, repacked into the GPU node layout and checked
//! against the fixed-size WGSL traversal stack.

use crate::gpu::layout::BvhNode;
use crate::scene::Scene;
use anyhow::{Result, bail, ensure};
use obvhs::{BvhBuildParams, bvh2::Bvh2};
use std::time::{Duration, Instant};

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

/// The BVH2 in GPU form.
#[derive(Clone, Debug, Default)]
pub struct GpuBvh {
    pub nodes: Vec<BvhNode>,
    /// Scene triangle of each leaf slot (obvhs `primitive_indices`).
    pub primitive_indices: Vec<u32>,
    /// Leaf slot of each scene triangle (inverse of `primitive_indices`).
    pub slot_of_tri: Vec<u32>,
    pub depth: u32,
    pub build_time: Duration,
    /// The ray-offset scale of the scene (`bvh::offset_scale`, the CPU's rule).
    pub offset_scale: f32,
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
        nodes,
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
