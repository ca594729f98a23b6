//! Scene → GPU arrays: the BVH2 repack (triangles stored in leaf order, consistent with
//! `primitive_indices`), vertex attributes, materials and the light distribution.
//! Pure CPU code (no wgpu), so it is testable without an adapter.

use super::layout::{self, BvhNode, Light, Material, Triangle, Vertex};
use crate::bsdf::Bsdf;
use crate::scene::light::{LightRef, LightSet};
use crate::scene::{MaterialKind, PunctualLight, Scene};
use anyhow::{Result, bail, ensure};
use glam::{Vec2, Vec3};
use obvhs::{BvhBuildParams, triangle::Triangle as ObvhsTriangle};
use std::time::{Duration, Instant};

/// Largest storage buffer we create (DESIGN: ≤ 128 MiB per buffer).
pub const MAX_BUFFER_BYTES: u64 = 128 << 20;

/// Deepest BVH2 the WGSL traversal stack handles (`STACK_SIZE` in scene.wgsl).
pub const MAX_BVH_DEPTH: u32 = 64;

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
}

/// Build an obvhs BVH2 over the scene's triangles and repack its nodes.
pub fn build_bvh(scene: &Scene) -> Result<GpuBvh> {
    let start = Instant::now();
    let mesh = &scene.mesh;
    let tris: Vec<ObvhsTriangle> = (0..mesh.triangle_count())
        .map(|t| {
            let [a, b, c] = mesh.tri(t);
            ObvhsTriangle {
                v0: a.into(),
                v1: b.into(),
                v2: c.into(),
            }
        })
        .collect();
    if tris.is_empty() {
        // One leaf with an empty (inverted) box: every ray misses.
        return Ok(GpuBvh {
            nodes: vec![BvhNode {
                lo: [f32::MAX; 3],
                prim_count: 0,
                hi: [-f32::MAX; 3],
                first_index: 0,
            }],
            build_time: start.elapsed(),
            ..Default::default()
        });
    }
    let mut core = Duration::ZERO;
    let bvh2 = obvhs::bvh2::builder::build_bvh2_from_tris(
        &tris,
        BvhBuildParams::medium_build(),
        &mut core,
    );
    let nodes: Vec<BvhNode> = bvh2
        .nodes
        .iter()
        .map(|n| BvhNode {
            lo: n.aabb.min.to_array(),
            prim_count: n.prim_count,
            hi: n.aabb.max.to_array(),
            first_index: n.first_index,
        })
        .collect();
    // Depth check (the WGSL stack is fixed-size) and index sanity.
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
                (n.first_index as u64 + n.prim_count as u64) <= bvh2.primitive_indices.len() as u64,
                "BVH leaf range out of range"
            );
        }
    }
    if depth > MAX_BVH_DEPTH {
        bail!("BVH depth {depth} exceeds the GPU traversal stack ({MAX_BVH_DEPTH})");
    }
    let mut slot_of_tri = vec![u32::MAX; tris.len()];
    for (slot, &t) in bvh2.primitive_indices.iter().enumerate() {
        if let Some(s) = slot_of_tri.get_mut(t as usize)
            && *s == u32::MAX
        {
            *s = slot as u32;
        }
    }
    Ok(GpuBvh {
        nodes,
        primitive_indices: bvh2.primitive_indices.clone(),
        slot_of_tri,
        depth,
        build_time: start.elapsed(),
    })
}

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

/// Per-vertex normals and uvs.
pub fn pack_vertices(scene: &Scene) -> Vec<Vertex> {
    let m = &scene.mesh;
    let mut out: Vec<Vertex> = m
        .normals
        .iter()
        .zip(&m.uvs)
        .map(|(n, uv)| Vertex {
            normal: n.to_array(),
            u: uv.x,
            v: uv.y,
            _pad: 0,
        })
        .collect();
    if out.is_empty() {
        out.push(Vertex::default());
    }
    out
}

/// The BSDF kind of a material: decided by the CPU's own `Material::bsdf` mapping, so CPU and
/// GPU can never disagree about which BSDF a material gets. A new `Bsdf` variant fails to
/// compile here until its WGSL twin exists.
pub fn bsdf_kind(scene: &Scene, m: &crate::scene::Material) -> (u32, Vec3) {
    match m.bsdf(&scene.textures, Vec2::ZERO, m.ior) {
        Bsdf::Lambert(b) => (layout::BSDF_LAMBERT, b.albedo.truncate()),
        Bsdf::Mirror(b) => (layout::BSDF_MIRROR, b.reflectance.truncate()),
        Bsdf::SmoothDielectric(_) => (layout::BSDF_SMOOTH_DIELECTRIC, m.base_color),
        // Not yet twinned in WGSL: `check_supported` rejects scenes that use these.
        _ => (u32::MAX, m.base_color),
    }
}

/// Reject what the GPU kernel cannot render yet (the CLI's `auto` falls back to the CPU).
pub fn check_supported(scene: &Scene) -> Result<()> {
    let f = scene.features();
    let mut missing = Vec::new();
    if f.textures {
        missing.push("textures");
    }
    if f.dispersion {
        missing.push("dispersion");
    }
    for (has, name) in [
        (f.thin_glass, "thin-walled glass"),
        (f.rough_glass, "rough glass"),
        (f.glossy_metal, "glossy metal"),
        (f.metal_rough, "the metallic-roughness material"),
    ] {
        if has {
            missing.push(name);
        }
    }
    if !missing.is_empty() {
        bail!(
            "the GPU renderer does not support {} yet (use --device cpu)",
            missing.join(", ")
        );
    }
    Ok(())
}

/// One GPU material.
pub fn pack_material(scene: &Scene, m: &crate::scene::Material) -> Material {
    let (bsdf, color) = bsdf_kind(scene, m);
    let sigma_a = m.sigma_a();
    let mut flags = 0;
    if m.is_emissive() {
        flags |= layout::MAT_EMISSIVE;
        if m.base_color == Vec3::ZERO {
            flags |= layout::MAT_BLACK_EMITTER;
        }
    }
    if m.double_sided {
        flags |= layout::MAT_DOUBLE_SIDED;
    }
    if m.is_transmissive() {
        flags |= layout::MAT_TRANSMISSIVE;
    }
    if m.kind == MaterialKind::Glass {
        flags |= layout::MAT_SOLID;
    }
    if sigma_a != Vec3::ZERO {
        flags |= layout::MAT_ABSORBS;
    }
    Material {
        base_color: color.to_array(),
        bsdf,
        emission: m.emission.to_array(),
        flags,
        sigma_a: sigma_a.to_array(),
        eta: m.ior,
        alpha: crate::bsdf::roughness_to_alpha(m.roughness),
        metallic: m.metallic,
        _pad0: 0,
        _pad1: 0,
    }
}

pub fn pack_materials(scene: &Scene) -> Vec<Material> {
    let mut out: Vec<Material> = scene
        .materials
        .iter()
        .map(|m| pack_material(scene, m))
        .collect();
    if out.is_empty() {
        out.push(Material::default());
    }
    out
}

/// The light distribution with its CDF. Returns (entries, light count); the array has at
/// least one (unused) entry.
pub fn pack_lights(scene: &Scene, bvh: &GpuBvh, lights: &LightSet) -> (Vec<Light>, u32) {
    let mut out: Vec<Light> = lights
        .lights
        .iter()
        .zip(&lights.cdf)
        .map(|(l, &cdf)| {
            let mut g = Light {
                cdf,
                ..Default::default()
            };
            match *l {
                LightRef::Triangle(t) => {
                    g.kind = layout::LIGHT_TRIANGLE;
                    g.index = bvh.slot_of_tri.get(t as usize).copied().unwrap_or(0);
                }
                LightRef::Punctual(i) => match scene.punctual_lights[i as usize] {
                    PunctualLight::Point {
                        position,
                        intensity,
                    } => {
                        g.kind = layout::LIGHT_POINT;
                        g.position = position.to_array();
                        g.intensity = intensity.to_array();
                    }
                    PunctualLight::Spot {
                        position,
                        direction,
                        intensity,
                        cos_inner,
                        cos_outer,
                    } => {
                        g.kind = layout::LIGHT_SPOT;
                        g.position = position.to_array();
                        g.direction = direction.to_array();
                        g.intensity = intensity.to_array();
                        g.cos_inner = cos_inner;
                        g.cos_outer = cos_outer;
                    }
                    PunctualLight::Directional {
                        direction,
                        irradiance,
                    } => {
                        g.kind = layout::LIGHT_DIRECTIONAL;
                        g.direction = direction.to_array();
                        g.intensity = irradiance.to_array();
                    }
                },
            }
            g
        })
        .collect();
    let count = out.len() as u32;
    if out.is_empty() {
        out.push(Light::default());
    }
    (out, count)
}

/// Bytes of a slice, with the 128 MiB per-buffer check.
pub fn checked_bytes<'a, T: bytemuck::Pod>(what: &str, data: &'a [T]) -> Result<&'a [u8]> {
    let bytes: &[u8] = bytemuck::cast_slice(data);
    ensure!(
        (bytes.len() as u64) <= MAX_BUFFER_BYTES,
        "scene too large for the GPU renderer: {what} needs {} MiB (limit {} MiB per buffer)",
        bytes.len() >> 20,
        MAX_BUFFER_BYTES >> 20
    );
    Ok(bytes)
}
