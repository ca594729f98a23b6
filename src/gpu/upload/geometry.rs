//! Geometry arrays: triangles in BVH leaf order with their light-selection probabilities,
//! and per-vertex attributes.

use super::GpuBvh;
use crate::gpu::layout::{Triangle, Vertex};
use crate::scene::Scene;
use crate::scene::light::LightSet;

/// Triangles in leaf order with the light-selection probabilities of `lights`.
pub fn pack_triangles(scene: &Scene, bvh: &GpuBvh, lights: &LightSet) -> Vec<Triangle> {
    let mesh = &scene.mesh;
    let mut out: Vec<Triangle> = bvh
        .primitive_indices
        .iter()
        .map(|&t| {
            let t = t as usize;
            let [i0, i1, i2] = mesh.indices[t];
            let [p0, p1, p2] = mesh.tri(t);
            Triangle {
                p0: p0.to_array(),
                material: mesh.tri_material[t],
                p1: p1.to_array(),
                scene_tri: t as u32,
                p2: p2.to_array(),
                pick_prob: lights.tri_pick_prob.get(t).copied().unwrap_or(0.0),
                i0,
                i1,
                i2,
                area: mesh.area(t),
            }
        })
        .collect();
    if out.is_empty() {
        out.push(Triangle::default()); // bindings must not be empty
    }
    out
}

/// Per-vertex normals, uvs and tangents (zero when the mesh has none).
pub fn pack_vertices(scene: &Scene) -> Vec<Vertex> {
    let m = &scene.mesh;
    let mut out: Vec<Vertex> = m
        .normals
        .iter()
        .zip(&m.uvs)
        .enumerate()
        .map(|(i, (n, uv))| {
            let t = m.tangents.get(i).copied().unwrap_or_default();
            Vertex {
                normal: n.to_array(),
                u: uv.x,
                v: uv.y,
                tangent_w: t.w,
                tangent: t.truncate().to_array(),
            }
        })
        .collect();
    if out.is_empty() {
        out.push(Vertex::default());
    }
    out
}
