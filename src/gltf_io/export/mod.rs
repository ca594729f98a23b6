//! Minimal glTF 2.0 (.glb) writer for scenes, following the scene contract in docs/design.md so
//! that [`super::load::load_slice`] reads back the same scene (and Blender can open it).
//!
//! One mesh (and node) per used material with POSITION, NORMAL, TEXCOORD_0 and u32 indices;
//! the camera and the punctual lights as nodes; `scenes[0].extras.render` and
//! `.environment`. Textures are not written (built-in scenes have none).

mod binary;
mod camera;
mod lights;
mod material;
mod mesh;

use crate::scene::Scene;
use binary::{Buffers, glb};
use camera::camera_json;
use glam::Vec3;
use lights::light_json;
use material::material_json;
use mesh::material_mesh;
use serde_json::{Value, json};

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
