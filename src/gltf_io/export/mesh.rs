//! Geometry: the triangles of one material as a glTF primitive (vertices renumbered,
//! attributes and indices written as accessors).

use super::binary::Buffers;
use crate::scene::Mesh;
use glam::Vec3;

/// Accessor indices of one material's primitive.
pub(super) struct MeshAccessors {
    pub(super) position: usize,
    pub(super) normal: usize,
    pub(super) uv: usize,
    pub(super) indices: usize,
}

/// Write the triangles of material `mi` (vertices renumbered in first-use order) into
/// `buffers`; `None` when no triangle uses it.
pub(super) fn material_mesh(
    mesh: &Mesh,
    mi: usize,
    buffers: &mut Buffers,
) -> Option<MeshAccessors> {
    let (verts, idx) = material_vertices(mesh, mi)?;
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    let (mut pos, mut nrm, mut uv) = (Vec::new(), Vec::new(), Vec::new());
    for &v in &verts {
        let p = mesh.positions[v];
        lo = lo.min(p);
        hi = hi.max(p);
        pos.extend_from_slice(bytemuck::cast_slice::<f32, u8>(&p.to_array()));
        nrm.extend_from_slice(bytemuck::cast_slice::<f32, u8>(&mesh.normals[v].to_array()));
        uv.extend_from_slice(bytemuck::cast_slice::<f32, u8>(&mesh.uvs[v].to_array()));
    }
    let n = verts.len();
    Some(MeshAccessors {
        position: buffers.accessor(&pos, n, "VEC3", 5126, 34962, Some((lo, hi))),
        normal: buffers.accessor(&nrm, n, "VEC3", 5126, 34962, None),
        uv: buffers.accessor(&uv, n, "VEC2", 5126, 34962, None),
        indices: buffers.accessor(
            bytemuck::cast_slice(&idx),
            idx.len(),
            "SCALAR",
            5125,
            34963,
            None,
        ),
    })
}

/// (mesh vertex of each new vertex, new indices) of the triangles of material `mi`.
fn material_vertices(mesh: &Mesh, mi: usize) -> Option<(Vec<usize>, Vec<u32>)> {
    let tris: Vec<usize> = (0..mesh.indices.len())
        .filter(|&t| mesh.tri_material[t] as usize == mi)
        .collect();
    if tris.is_empty() {
        return None;
    }
    let mut remap = vec![u32::MAX; mesh.positions.len()];
    let mut verts: Vec<usize> = Vec::new();
    let mut idx: Vec<u32> = Vec::with_capacity(tris.len() * 3);
    for &t in &tris {
        for v in mesh.indices[t] {
            let v = v as usize;
            if remap[v] == u32::MAX {
                remap[v] = verts.len() as u32;
                verts.push(v);
            }
            idx.push(remap[v]);
        }
    }
    Some((verts, idx))
}
