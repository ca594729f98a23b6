//! Meshes: primitives → world-space triangles of the merged scene mesh.

use super::Loader;
use super::accessor::AccessorData;
use crate::scene::Mesh;
mod tangents;

use glam::{Mat3, Mat4, Vec2, Vec3, Vec4};
use gltf::json;
use gltf::json::validation::Checked;
use tangents::Tangents;

/// A triangle primitive's attributes (object space, flat arrays) and indices, checked: every
/// index addresses a vertex and the attribute counts agree.
struct PrimitiveData {
    positions: Vec<f32>,
    normals: Option<Vec<f32>>,
    uvs: Option<Vec<f32>>,
    indices: Vec<u32>,
}

/// A primitive's vertices in world space; `flip` = mirrored transform (reverse the winding).
struct WorldVertices {
    positions: Vec<Vec3>,
    /// Unit normals (zero where missing or broken); None = the primitive has no normals.
    normals: Option<Vec<Vec3>>,
    /// TEXCOORD_0 (zero where missing or non-finite).
    uvs: Vec<Vec2>,
    tangents: Tangents,
    flip: bool,
}

impl Loader<'_> {
    pub(super) fn mesh_node(&mut self, ni: usize, mi: usize, world: Mat4) -> anyhow::Result<()> {
        let Some(mesh) = self.root.meshes.get(mi) else {
            self.skip_primitive(format!(
                "node {ni}: mesh {mi} does not exist (index out of range)"
            ));
            return Ok(());
        };
        for (pi, prim) in mesh.primitives.iter().enumerate() {
            match self.primitive(prim, world) {
                Ok(()) => {}
                Err(e) => self.skip_primitive(format!("mesh {mi} primitive {pi} (node {ni}): {e}")),
            }
        }
        Ok(())
    }

    /// Triangles a primitive will add (from its accessor counts, nothing decoded; an accessor
    /// over its own count limit counts 0 here: decoding it reports that error).
    fn primitive_triangles(&self, prim: &json::mesh::Primitive) -> u64 {
        let count = |a: usize| {
            self.root
                .accessors
                .get(a)
                .map(|a| a.count.0)
                .filter(|&c| c <= super::accessor::MAX_ACCESSOR_COUNT)
                .unwrap_or(0)
        };
        let vertices = prim
            .attributes
            .iter()
            .find(|(k, _)| matches!(k, Checked::Valid(json::mesh::Semantic::Positions)))
            .map_or(0, |(_, a)| count(a.value()));
        prim.indices.map_or(vertices, |i| count(i.value())) / 3
    }

    /// The scene stays within `limits.max_triangles` after instancing, checked from the accessor
    /// counts of every node the traversal will reach before anything is decoded (100,000
    /// nodes instancing one mesh would otherwise build 800 M triangles from a 3 MB file and
    /// abort on memory).
    pub(super) fn check_instanced_triangles(&self, roots: &[usize]) -> anyhow::Result<()> {
        let nodes = &self.root.nodes;
        let mut visited = vec![false; nodes.len()];
        let mut stack: Vec<usize> = roots.to_vec();
        let mut total = 0u64;
        while let Some(ni) = stack.pop() {
            let Some(node) = nodes.get(ni).filter(|_| !visited[ni]) else {
                continue;
            };
            visited[ni] = true;
            if let Some(mesh) = node.mesh.and_then(|m| self.root.meshes.get(m.value())) {
                total += mesh
                    .primitives
                    .iter()
                    .map(|p| self.primitive_triangles(p))
                    .sum::<u64>();
            }
            let max = self.limits.max_triangles;
            anyhow::ensure!(
                total <= max,
                "the scene has more than {max} triangles after instancing (reached at node \
                 {ni}): refused before building it (raise the budget with --max-triangles)"
            );
            stack.extend(node.children.iter().flatten().map(|c| c.value()));
        }
        Ok(())
    }

    fn skip_primitive(&mut self, what: String) {
        self.skipped_primitives += 1;
        if self.first_skip_reason.is_none() {
            self.first_skip_reason = Some(what.clone());
        }
        self.warnings.push(format!("skipped primitive: {what}"));
    }

    fn primitive(&mut self, prim: &json::mesh::Primitive, world: Mat4) -> Result<(), String> {
        match prim.mode {
            Checked::Valid(json::mesh::Mode::Triangles) => {}
            Checked::Valid(m) => {
                self.warnings.once(&format!("mode:{m:?}"), || {
                    format!("primitives with mode {m:?} are skipped (triangles only)")
                });
                return Ok(());
            }
            Checked::Invalid => return Err("invalid primitive mode".into()),
        }
        let data = self.primitive_data(prim)?;
        let material = self.material_for(prim.material.map(|m| m.value()))?;
        let mut verts = world_vertices(&data, world)?;
        verts.tangents = self.tangents_for(prim, &data, &verts, material, world);
        self.append_triangles(&data.indices, &verts, material)
    }

    /// Read and check a triangle primitive's attributes and indices.
    fn primitive_data(&mut self, prim: &json::mesh::Primitive) -> Result<PrimitiveData, String> {
        let attr =
            |s: json::mesh::Semantic| prim.attributes.get(&Checked::Valid(s)).map(|i| i.value());
        let pos_i = attr(json::mesh::Semantic::Positions).ok_or("it has no POSITION attribute")?;
        let positions = self.read_floats(pos_i, 3, "POSITION")?;
        let nv = positions.len() / 3;
        let normals = self.read_normals(attr(json::mesh::Semantic::Normals), nv)?;
        let uvs = self.read_uvs(attr(json::mesh::Semantic::TexCoords(0)), nv);
        let indices = self.read_indices(prim, nv)?;
        Ok(PrimitiveData {
            positions,
            normals,
            uvs,
            indices,
        })
    }

    /// The NORMAL accessor `ai` (if any), which must hold one normal per vertex (`nv`).
    fn read_normals(&self, ai: Option<usize>, nv: usize) -> Result<Option<Vec<f32>>, String> {
        let Some(i) = ai else { return Ok(None) };
        let n = self.read_floats(i, 3, "NORMAL")?;
        if n.len() != nv * 3 {
            return Err(format!(
                "NORMAL count {} differs from POSITION count {nv}",
                n.len() / 3
            ));
        }
        Ok(Some(n))
    }

    /// The TEXCOORD_0 accessor `ai` (if any) with one UV per vertex (`nv`); a broken or
    /// mismatched one is ignored with a warning.
    fn read_uvs(&mut self, ai: Option<usize>, nv: usize) -> Option<Vec<f32>> {
        match self.read_floats(ai?, 2, "TEXCOORD_0") {
            Ok(t) if t.len() / 2 == nv => Some(t),
            Ok(_) => {
                self.warnings
                    .push("TEXCOORD_0 count differs from POSITION count; UVs ignored".into());
                None
            }
            Err(e) => {
                self.warnings.push(format!("{e}; UVs ignored"));
                None
            }
        }
    }

    /// The primitive's indices (0..`nv` when it has none), each checked to address one of
    /// its `nv` vertices; a count that is not a multiple of 3 gets a warning.
    fn read_indices(
        &mut self,
        prim: &json::mesh::Primitive,
        nv: usize,
    ) -> Result<Vec<u32>, String> {
        let indices: Vec<u32> = match prim.indices {
            Some(ii) => match self.read_accessor(ii.value(), true)? {
                (AccessorData::Uint(v), 1) => v,
                _ => return Err(format!("index accessor {} must be scalar", ii.value())),
            },
            None => (0..nv as u32).collect(),
        };
        if let Some(&bad) = indices.iter().find(|&&i| i as usize >= nv) {
            return Err(format!("vertex index {bad} out of range ({nv} vertices)"));
        }
        if !indices.len().is_multiple_of(3) {
            self.warnings.push(format!(
                "index count {} is not a multiple of 3; trailing indices ignored",
                indices.len()
            ));
        }
        Ok(indices)
    }

    /// Append the primitive's non-degenerate triangles to the scene mesh. Vertices with a
    /// usable normal are shared; the others get the triangle's geometric normal (flat).
    fn append_triangles(
        &mut self,
        indices: &[u32],
        v: &WorldVertices,
        material: u32,
    ) -> Result<(), String> {
        let mut sink = VertexSink {
            out: &mut self.mesh,
            with_tangents: self.needs_tangents,
            remap: vec![u32::MAX; v.positions.len()],
            // Generated tangents belong to a triangle corner: such vertices are not shared.
            per_corner: matches!(v.tangents, Tangents::PerCorner(_)),
            bad_normals: 0,
        };
        for (f, tri) in indices.chunks_exact(3).enumerate() {
            let mut t = [tri[0] as usize, tri[1] as usize, tri[2] as usize];
            if v.flip {
                t.swap(1, 2);
            }
            let Some(gn) = geometric_normal(&v.positions, t) else {
                self.dropped_triangles += 1;
                continue;
            };
            let mut ids = [0u32; 3];
            for k in 0..3 {
                ids[k] = sink.corner(v, t[k], 3 * f + k, gn)?;
            }
            sink.out.indices.push(ids);
            sink.out.tri_material.push(material);
        }
        let bad_normals = sink.bad_normals;
        if bad_normals > 0 {
            self.warnings.push(format!(
                "{bad_normals} vertex normals were zero or non-finite; used the geometric normal"
            ));
        }
        Ok(())
    }
}

/// The unit geometric normal of the triangle with corners `t`; None when it is degenerate
/// (zero area) or not finite.
fn geometric_normal(wpos: &[Vec3], t: [usize; 3]) -> Option<Vec3> {
    let [a, b, c] = [wpos[t[0]], wpos[t[1]], wpos[t[2]]];
    let g = (b - a).cross(c - a);
    if !(a.is_finite() && b.is_finite() && c.is_finite() && g.is_finite())
        || g.length_squared() <= 0.0
    {
        return None;
    }
    let gn = g.normalize_or_zero();
    (gn != Vec3::ZERO).then_some(gn)
}

/// Where one primitive's vertices go: the scene mesh, and which source vertices it already
/// holds.
struct VertexSink<'m> {
    out: &'m mut Mesh,
    /// The mesh stores per-vertex tangents.
    with_tangents: bool,
    /// Source vertex → mesh vertex (`u32::MAX`: not added yet).
    remap: Vec<u32>,
    /// Tangents are per triangle corner, so no vertex is shared.
    per_corner: bool,
    /// Vertices whose normal was zero or non-finite.
    bad_normals: usize,
}

impl VertexSink<'_> {
    /// The mesh vertex for source vertex `i` at triangle corner `corner` (3·face + k) of a
    /// triangle with geometric normal `gn`: shared when it has a usable normal, else a new
    /// vertex with the geometric normal.
    fn corner(
        &mut self,
        v: &WorldVertices,
        i: usize,
        corner: usize,
        gn: Vec3,
    ) -> Result<u32, String> {
        let n = v.normals.as_ref().map(|n| n[i]).unwrap_or(Vec3::ZERO);
        let tan = v.tangents.get(i, corner);
        if n == Vec3::ZERO || self.per_corner {
            // No normal (flat shading) or a broken one: the geometric normal.
            if v.normals.is_some() && n == Vec3::ZERO {
                self.bad_normals += 1;
            }
            let n = if n == Vec3::ZERO { gn } else { n };
            self.push_vertex(v.positions[i], n, v.uvs[i], tan)
        } else {
            if self.remap[i] == u32::MAX {
                self.remap[i] = self.push_vertex(v.positions[i], n, v.uvs[i], tan)?;
            }
            Ok(self.remap[i])
        }
    }

    /// Add one vertex to the mesh and return its index.
    fn push_vertex(&mut self, p: Vec3, n: Vec3, t: Vec2, tan: Vec4) -> Result<u32, String> {
        let out = &mut *self.out;
        let id = u32::try_from(out.positions.len()).map_err(|_| "too many vertices".to_string())?;
        out.positions.push(p);
        out.normals.push(n);
        out.uvs.push(t);
        if self.with_tangents {
            out.tangents.push(tan);
        }
        Ok(id)
    }
}

/// World transform; normals with the inverse-transpose; mirrored → flip winding.
fn world_vertices(d: &PrimitiveData, world: Mat4) -> Result<WorldVertices, String> {
    let nv = d.positions.len() / 3;
    let m3 = Mat3::from_mat4(world);
    let det = m3.determinant();
    if !(det.is_finite() && det != 0.0) {
        return Err("its node transform is singular".into());
    }
    let normal_m = m3.inverse().transpose();
    let positions = &d.positions;
    let p = |i: usize| {
        world.transform_point3(Vec3::new(
            positions[3 * i],
            positions[3 * i + 1],
            positions[3 * i + 2],
        ))
    };
    let wpos: Vec<Vec3> = (0..nv).map(p).collect();
    let wnrm: Option<Vec<Vec3>> = d.normals.as_ref().map(|n| {
        (0..nv)
            .map(|i| {
                let v = normal_m * Vec3::new(n[3 * i], n[3 * i + 1], n[3 * i + 2]);
                if v.is_finite() {
                    v.normalize_or_zero()
                } else {
                    Vec3::ZERO
                }
            })
            .collect()
    });
    let uv = |i: usize| -> Vec2 {
        match &d.uvs {
            Some(t) => {
                let v = Vec2::new(t[2 * i], t[2 * i + 1]);
                if v.is_finite() { v } else { Vec2::ZERO }
            }
            None => Vec2::ZERO,
        }
    };
    Ok(WorldVertices {
        positions: wpos,
        normals: wnrm,
        uvs: (0..nv).map(uv).collect(),
        tangents: Tangents::None,
        flip: det < 0.0,
    })
}
