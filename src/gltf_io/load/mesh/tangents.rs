//! Tangent frames for normal-mapped primitives: the glTF TANGENT attribute when present,
//! else MikkTSpace tangents (Mikkelsen 2008, "Simulation of wrinkled surfaces revisited",
//! the tangent space glTF 2.0 §3.7.2.1 prescribes when TANGENT is absent).

use super::{PrimitiveData, WorldVertices};
use crate::gltf_io::load::Loader;
use glam::{Mat3, Mat4, Vec2, Vec3, Vec4};
use gltf::json;
use gltf::json::validation::Checked;

/// A primitive's tangents (xyz world, unit; w = bitangent sign).
pub(super) enum Tangents {
    /// The material has no normal map (or no frame could be built): zero tangents.
    None,
    /// One per vertex (the TANGENT attribute).
    PerVertex(Vec<Vec4>),
    /// One per triangle corner, 3·face + corner (generated: MikkTSpace may split a vertex).
    PerCorner(Vec<Vec4>),
}

impl Tangents {
    /// The tangent of vertex `v` at corner `corner` (3·face + k).
    pub(super) fn get(&self, v: usize, corner: usize) -> Vec4 {
        match self {
            Tangents::None => Vec4::ZERO,
            Tangents::PerVertex(t) => t.get(v).copied().unwrap_or(Vec4::ZERO),
            Tangents::PerCorner(t) => t.get(corner).copied().unwrap_or(Vec4::ZERO),
        }
    }
}

impl Loader<'_> {
    /// The tangents of a primitive whose material has a normal map (`Tangents::None`
    /// otherwise, or with a warning naming the material when the primitive has no
    /// TEXCOORD_0 to map the texture with).
    pub(super) fn tangents_for(
        &mut self,
        prim: &json::mesh::Primitive,
        data: &PrimitiveData,
        verts: &WorldVertices,
        material: u32,
        world: Mat4,
    ) -> Tangents {
        let Some(mat) = self.materials.get(material as usize) else {
            return Tangents::None;
        };
        let Some(r) = mat.normal_texture else {
            return Tangents::None;
        };
        let name = mat.name.clone();
        if data.uvs.is_none() {
            self.warnings.push(format!(
                "material '{name}': its normalTexture needs TEXCOORD_{} but a primitive using \
                 it has no texture coordinates; the normal map is ignored there",
                r.tex_coord
            ));
            return Tangents::None;
        }
        let attr = prim
            .attributes
            .get(&Checked::Valid(json::mesh::Semantic::Tangents))
            .map(|i| i.value());
        if let Some(ai) = attr {
            match self.read_floats(ai, 4, "TANGENT") {
                Ok(t) if t.len() == data.positions.len() / 3 * 4 => {
                    return Tangents::PerVertex(world_tangents(&t, world));
                }
                Ok(_) => self.warnings.push(format!(
                    "material '{name}': TANGENT count differs from POSITION count; tangents \
                     generated instead"
                )),
                Err(e) => self.warnings.push(format!(
                    "material '{name}': {e}; tangents generated instead"
                )),
            }
        }
        match generate(&data.indices, verts) {
            Some(t) => Tangents::PerCorner(t),
            None => {
                self.warnings.push(format!(
                    "material '{name}': MikkTSpace could not build tangents for a primitive; \
                     its normal map is ignored there"
                ));
                Tangents::None
            }
        }
    }
}

/// TANGENT (object space) → world: xyz by the linear part of `world` (tangents are surface
/// directions), w flipped under a mirroring transform (the loader reverses the winding, and
/// n × t changes sign relative to the mirrored bitangent). Broken entries become zero.
fn world_tangents(t: &[f32], world: Mat4) -> Vec<Vec4> {
    let m3 = Mat3::from_mat4(world);
    let mirror = if m3.determinant() < 0.0 { -1.0 } else { 1.0 };
    t.chunks_exact(4)
        .map(|c| {
            let v = (m3 * Vec3::new(c[0], c[1], c[2])).normalize_or_zero();
            if v.is_finite() && v != Vec3::ZERO && c[3].is_finite() {
                let w = if c[3] < 0.0 { -1.0 } else { 1.0 };
                v.extend(w * mirror)
            } else {
                Vec4::ZERO
            }
        })
        .collect()
}

/// MikkTSpace over the primitive's world-space triangles (the winding the mesh will use).
/// glTF's v axis points down the image while the normal texture's +Y points up, so the
/// generator sees (u, 1 − v): its bitangent then follows the texture's +Y.
fn generate(indices: &[u32], v: &WorldVertices) -> Option<Vec<Vec4>> {
    let faces: Vec<[usize; 3]> = indices
        .chunks_exact(3)
        .map(|t| {
            let mut f = [t[0] as usize, t[1] as usize, t[2] as usize];
            if v.flip {
                f.swap(1, 2);
            }
            f
        })
        .collect();
    let mut g = Geometry {
        faces: &faces,
        v,
        out: vec![Vec4::ZERO; 3 * faces.len()],
    };
    mikktspace::generate_tangents(&mut g).then_some(g.out)
}

struct Geometry<'a> {
    faces: &'a [[usize; 3]],
    v: &'a WorldVertices,
    out: Vec<Vec4>,
}

impl Geometry<'_> {
    fn face_normal(&self, face: usize) -> Vec3 {
        let [a, b, c] = self.faces[face].map(|i| self.v.positions[i]);
        (b - a).cross(c - a).normalize_or_zero()
    }
}

impl mikktspace::Geometry for Geometry<'_> {
    fn num_faces(&self) -> usize {
        self.faces.len()
    }
    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }
    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.v.positions[self.faces[face][vert]].to_array()
    }
    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        let i = self.faces[face][vert];
        let n = self.v.normals.as_ref().map_or(Vec3::ZERO, |n| n[i]);
        if n == Vec3::ZERO {
            self.face_normal(face)
        } else {
            n
        }
        .to_array()
    }
    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        let uv = self.v.uvs[self.faces[face][vert]];
        Vec2::new(uv.x, 1.0 - uv.y).to_array()
    }
    fn set_tangent_encoded(&mut self, t: [f32; 4], face: usize, vert: usize) {
        let t = Vec4::from(t);
        if let Some(o) = self.out.get_mut(3 * face + vert) {
            *o = if t.is_finite() { t } else { Vec4::ZERO };
        }
    }
}
