//! Minimal glTF 2.0 (.glb) writer for scenes, following the scene contract in DESIGN.md so
//! that [`super::gltf_load::load_slice`] reads back the same scene (and Blender can open it).
//!
//! One mesh (and node) per used material with POSITION, NORMAL, TEXCOORD_0 and u32 indices;
//! the camera and the punctual lights as nodes; `scenes[0].extras.render` and
//! `.environment`. Textures are not written (built-in scenes have none).

use super::{Material, MaterialKind, Mesh, PunctualLight, Scene};
use crate::bsdf::MicrofacetDistribution;
use glam::{Quat, Vec3};
use serde_json::{Map, Value, json};

/// Binary glTF of `scene`.
pub fn export_glb(scene: &Scene) -> anyhow::Result<Vec<u8>> {
    scene.validate()?;
    let mut buffers = Buffers::default();
    let mut meshes: Vec<Value> = Vec::new();
    let mut nodes: Vec<Value> = Vec::new();
    let mut used_ext: Vec<&str> = Vec::new();

    for (mi, mat) in scene.materials.iter().enumerate() {
        if let Some(mesh) = material_mesh(&scene.mesh, mi, &mut buffers) {
            nodes.push(json!({ "name": mat.name, "mesh": meshes.len() }));
            meshes.push(json!({
                "name": mat.name,
                "primitives": [{
                    "attributes": {
                        "POSITION": mesh.position, "NORMAL": mesh.normal, "TEXCOORD_0": mesh.uv
                    },
                    "indices": mesh.indices, "material": mi, "mode": 4
                }]
            }));
        }
    }

    let materials: Vec<Value> = scene
        .materials
        .iter()
        .map(|m| material_json(m, &mut used_ext))
        .collect();

    let (camera_node, cameras) = camera_json(scene);
    nodes.push(camera_node);

    let mut lights: Vec<Value> = Vec::new();
    for (li, l) in scene.punctual_lights.iter().enumerate() {
        let (light, node) = light_json(li, l);
        lights.push(light);
        nodes.push(node);
    }

    let (root, bin) = root_json(
        scene,
        Parts {
            buffers,
            nodes,
            meshes,
            materials,
            cameras,
            lights,
            used_ext,
        },
    );
    Ok(glb(&serde_json::to_vec(&root)?, &bin))
}

/// The binary chunk with its buffer views and accessors, filled in order.
#[derive(Default)]
struct Buffers {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Buffers {
    /// Append `bytes` (4-byte aligned) as a buffer view + accessor; returns the accessor index.
    fn accessor(
        &mut self,
        bytes: &[u8],
        count: usize,
        ty: &str,
        ctype: u32,
        target: u32,
        minmax: Option<(Vec3, Vec3)>,
    ) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let view = self.views.len();
        self.views.push(json!({
            "buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len(), "target": target
        }));
        self.bin.extend_from_slice(bytes);
        let mut acc = json!({
            "bufferView": view, "componentType": ctype, "count": count, "type": ty
        });
        if let Some((lo, hi)) = minmax {
            acc["min"] = json!(lo.to_array());
            acc["max"] = json!(hi.to_array());
        }
        self.accessors.push(acc);
        self.accessors.len() - 1
    }
}

/// Accessor indices of one material's primitive.
struct MeshAccessors {
    position: usize,
    normal: usize,
    uv: usize,
    indices: usize,
}

/// Write the triangles of material `mi` (vertices renumbered in first-use order) into
/// `buffers`; `None` when no triangle uses it.
fn material_mesh(mesh: &Mesh, mi: usize, buffers: &mut Buffers) -> Option<MeshAccessors> {
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

/// (camera node, `cameras` array). Camera: local −Z is the view direction, rotation columns
/// right/up/back.
fn camera_json(scene: &Scene) -> (Value, Value) {
    let cam = &scene.camera;
    let q = Quat::from_mat3(&cam.rotation).normalize();
    let node = json!({
        "name": "camera", "camera": 0,
        "translation": cam.position.to_array(), "rotation": q.to_array()
    });
    let s = &scene.settings;
    let cameras = json!([{
        "type": "perspective",
        "perspective": {
            "yfov": cam.yfov, "znear": 0.001,
            "aspectRatio": s.width as f32 / s.height.max(1) as f32
        }
    }]);
    (node, cameras)
}

/// (KHR_lights_punctual light, its node) of punctual light `li`.
fn light_json(li: usize, l: &PunctualLight) -> (Value, Value) {
    let (ty, pos, dir, power) = match *l {
        PunctualLight::Point {
            position,
            intensity,
        } => ("point", Some(position), None, intensity),
        PunctualLight::Spot {
            position,
            direction,
            intensity,
            ..
        } => ("spot", Some(position), Some(direction), intensity),
        PunctualLight::Directional {
            direction,
            irradiance,
        } => ("directional", None, Some(direction), irradiance),
    };
    let (color, intensity) = split_color(power);
    let mut light = json!({ "type": ty, "color": color.to_array(), "intensity": intensity });
    if let PunctualLight::Spot {
        cos_inner,
        cos_outer,
        ..
    } = *l
    {
        light["spot"] = json!({
            "innerConeAngle": cos_inner.clamp(-1.0, 1.0).acos(),
            "outerConeAngle": cos_outer.clamp(-1.0, 1.0).acos()
        });
    }
    let mut node = json!({
        "name": format!("light{li}"),
        "extensions": { "KHR_lights_punctual": { "light": li } }
    });
    if let Some(p) = pos {
        node["translation"] = json!(p.to_array());
    }
    if let Some(d) = dir {
        let r = Quat::from_rotation_arc(Vec3::NEG_Z, d.normalize());
        node["rotation"] = json!(r.to_array());
    }
    (light, node)
}

/// Everything [`root_json`] assembles.
struct Parts {
    buffers: Buffers,
    nodes: Vec<Value>,
    meshes: Vec<Value>,
    materials: Vec<Value>,
    cameras: Value,
    lights: Vec<Value>,
    used_ext: Vec<&'static str>,
}

/// (glTF JSON document, binary chunk).
fn root_json(scene: &Scene, p: Parts) -> (Value, Vec<u8>) {
    let (buffers, mut used_ext) = (p.buffers, p.used_ext);
    let s = &scene.settings;
    let mut root = json!({
        "asset": { "version": "2.0", "generator": "refract gltf_export" },
        "scene": 0,
        "scenes": [{
            "name": scene.name,
            "nodes": (0..p.nodes.len()).collect::<Vec<_>>(),
            "extras": {
                "render": {
                    "width": s.width, "height": s.height, "max_depth": s.max_depth,
                    "rr_depth": s.rr_depth, "spp": s.spp
                },
                "environment": environment_json(scene)
            }
        }],
        "nodes": p.nodes,
        "meshes": p.meshes,
        "materials": p.materials,
        "cameras": p.cameras,
        "accessors": buffers.accessors,
        "bufferViews": buffers.views,
        "buffers": [{ "byteLength": buffers.bin.len() }]
    });
    if buffers.bin.is_empty()
        && let Some(o) = root.as_object_mut()
    {
        o.remove("buffers");
    }
    if !p.lights.is_empty() {
        used_ext.push("KHR_lights_punctual");
        root["extensions"] = json!({ "KHR_lights_punctual": { "lights": p.lights } });
    }
    used_ext.sort_unstable();
    used_ext.dedup();
    if !used_ext.is_empty() {
        root["extensionsUsed"] = json!(used_ext);
    }
    (root, buffers.bin)
}

/// (colour with max component 1, intensity) so that colour × intensity = `v`.
fn split_color(v: Vec3) -> (Vec3, f32) {
    let m = v.max_element();
    if m > 0.0 {
        (v / m, m)
    } else {
        (Vec3::ONE, 0.0)
    }
}

/// glTF material of `m` (metallic-roughness + KHR extensions, recorded in `used`).
fn material_json(m: &Material, used: &mut Vec<&'static str>) -> Value {
    let (metallic, roughness) = metallic_roughness(m);
    let bc = m.base_color;
    let mut j = json!({
        "name": m.name,
        "pbrMetallicRoughness": {
            "baseColorFactor": [bc.x, bc.y, bc.z, 1.0],
            "metallicFactor": metallic,
            "roughnessFactor": roughness
        }
    });
    if m.double_sided {
        j["doubleSided"] = json!(true);
    }
    let mut ext = Map::new();
    if m.is_emissive() {
        emission_json(m, &mut j, &mut ext, used);
    }
    if m.is_transmissive() {
        transmission_extensions(m, &mut ext, used);
    }
    specular_extension(m, &mut ext, used);
    if !ext.is_empty() {
        j["extensions"] = Value::Object(ext);
    }
    let extras = material_extras(m);
    if !extras.is_empty() {
        j["extras"] = Value::Object(extras);
    }
    j
}

/// The glTF (metallicFactor, roughnessFactor) that the loader maps back to `m`'s kind.
fn metallic_roughness(m: &Material) -> (f32, f32) {
    match m.kind {
        MaterialKind::Diffuse => (0.0, 1.0),
        MaterialKind::Mirror => (1.0, 0.0),
        MaterialKind::GlossyMetal => (1.0, m.roughness),
        MaterialKind::Glass | MaterialKind::ThinGlass => (0.0, m.roughness),
        MaterialKind::MetalRough => (m.metallic, m.roughness),
    }
}

/// `emissiveFactor` of an emissive material, with KHR_materials_emissive_strength (recorded
/// in `used`) when a component exceeds 1.
fn emission_json(
    m: &Material,
    j: &mut Value,
    ext: &mut Map<String, Value>,
    used: &mut Vec<&'static str>,
) {
    let (c, s) = split_color(m.emission);
    if s <= 1.0 {
        j["emissiveFactor"] = json!(m.emission.to_array());
    } else {
        j["emissiveFactor"] = json!(c.to_array());
        ext.insert(
            "KHR_materials_emissive_strength".into(),
            json!({ "emissiveStrength": s }),
        );
        used.push("KHR_materials_emissive_strength");
    }
}

/// KHR_materials_specular of a metallic-roughness material whose specular factor or colour
/// is not the default, recorded in `used`.
fn specular_extension(m: &Material, ext: &mut Map<String, Value>, used: &mut Vec<&'static str>) {
    if m.kind == MaterialKind::MetalRough
        && (m.specular_factor != 1.0 || m.specular_color != Vec3::ONE)
    {
        ext.insert(
            "KHR_materials_specular".into(),
            json!({
                "specularFactor": m.specular_factor,
                "specularColorFactor": m.specular_color.to_array()
            }),
        );
        used.push("KHR_materials_specular");
    }
}

/// The material's `extras` (the loader's contract): the microfacet distribution of glass and
/// glossy metal, a tabulated `conductor`, and a non-zero `priority` (nested dielectrics).
fn material_extras(m: &Material) -> Map<String, Value> {
    let mut extras = Map::new();
    if matches!(
        m.kind,
        MaterialKind::Glass | MaterialKind::ThinGlass | MaterialKind::GlossyMetal
    ) {
        let d = match m.distribution {
            MicrofacetDistribution::Ggx => "ggx",
            MicrofacetDistribution::Beckmann => "beckmann",
        };
        extras.insert("microfacet_distribution".into(), json!(d));
    }
    if let Some(metal) = m.conductor {
        extras.insert("conductor".into(), json!(metal.symbol()));
    }
    if m.priority != 0 {
        extras.insert("priority".into(), json!(m.priority));
    }
    extras
}

/// KHR_materials_transmission, _ior, _volume (solid glass) and _dispersion of a transmissive
/// material, recorded in `used`.
fn transmission_extensions(
    m: &Material,
    ext: &mut Map<String, Value>,
    used: &mut Vec<&'static str>,
) {
    ext.insert(
        "KHR_materials_transmission".into(),
        json!({ "transmissionFactor": 1.0 }),
    );
    ext.insert("KHR_materials_ior".into(), json!({ "ior": m.ior }));
    used.extend(["KHR_materials_transmission", "KHR_materials_ior"]);
    if m.kind == MaterialKind::Glass {
        let mut v = json!({ "thicknessFactor": 1.0 });
        if m.attenuation_distance.is_finite() {
            v["attenuationDistance"] = json!(m.attenuation_distance);
            v["attenuationColor"] = json!(m.attenuation_color.to_array());
        }
        ext.insert("KHR_materials_volume".into(), v);
        used.push("KHR_materials_volume");
    }
    if let Some(abbe) = m.abbe {
        ext.insert(
            "KHR_materials_dispersion".into(),
            json!({ "dispersion": 20.0 / abbe }),
        );
        used.push("KHR_materials_dispersion");
    }
}

/// Wrap JSON and binary chunks into a GLB container (glTF 2.0 §4.4).
fn glb(json_bytes: &[u8], bin: &[u8]) -> Vec<u8> {
    let mut js = json_bytes.to_vec();
    while !js.len().is_multiple_of(4) {
        js.push(b' ');
    }
    let mut b = bin.to_vec();
    while !b.len().is_multiple_of(4) {
        b.push(0);
    }
    let total = 12 + 8 + js.len() + if b.is_empty() { 0 } else { 8 + b.len() };
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(js.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&js);
    if !b.is_empty() {
        out.extend_from_slice(&(b.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(&b);
    }
    out
}

/// `extras.environment`: `[r, g, b]`, or for an environment image `{"uri", "strength",
/// "rotation"}` naming `<name>.hdr` next to the exported file (the shipped HDRIs are called
/// "builtin NAME": `assets/NAME.hdr`).
fn environment_json(scene: &Scene) -> Value {
    match &scene.env_map {
        Some(e) => {
            let name = e.map.name.strip_prefix("builtin ").unwrap_or(&e.map.name);
            let file = std::path::Path::new(name)
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| "environment".into());
            json!({ "uri": format!("{file}.hdr"), "strength": e.strength, "rotation": e.rotation })
        }
        None => json!(scene.environment.to_array()),
    }
}
