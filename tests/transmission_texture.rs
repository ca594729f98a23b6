//! `KHR_materials_transmission.transmissionTexture` as a per-texel glass mask: where
//! transmissionFactor × texel.r ≥ 0.5 (the loader's glass threshold for the factor) the surface
//! is the material's glass, elsewhere its opaque metal-rough base. A thin glass pane whose
//! 2 × 1 mask is glass on the left and opaque on the right, in front of an emissive wall under a
//! uniform environment, renders its left half exactly as the all-glass pane and its right half
//! exactly as the opaque pane (same seed: the mask draws no random number), and the two
//! references differ there. Also the loader's warnings and the GPU's refusal.

mod common_scenes;
use common_scenes::*;
use glam::Vec3;
use refract::cpu::Renderer;
use refract::gltf_io::load::load_slice;
use refract::render::RenderOptions;
use refract::scene::{Camera, MaterialKind, Scene};
use serde_json::json;

const W: u32 = 40;
const H: u32 = 20;

/// The pane (x, y ∈ [−1, 1] at z = 0, uv u = 0 on the left) with `transmission` and, when
/// given, the grey-level mask texture `mask` (w × 1, nearest); an emissive wall (radiance 1)
/// at z = −1 behind it; environment 0.5.
fn pane(transmission: f32, mask: Option<&[u8]>) -> Scene {
    let pos: [[f32; 3]; 8] = [
        [-1.0, -1.0, 0.0],
        [1.0, -1.0, 0.0],
        [1.0, 1.0, 0.0],
        [-1.0, 1.0, 0.0],
        [-4.0, -4.0, -1.0],
        [4.0, -4.0, -1.0],
        [4.0, 4.0, -1.0],
        [-4.0, 4.0, -1.0],
    ];
    let uv: [[f32; 2]; 8] = [
        [0.0, 1.0],
        [1.0, 1.0],
        [1.0, 0.0],
        [0.0, 0.0],
        [0.0, 0.0],
        [0.0, 0.0],
        [0.0, 0.0],
        [0.0, 0.0],
    ];
    let idx: [u32; 6] = [0, 1, 2, 0, 2, 3];
    let png = mask
        .map(|m| grey_png(m.len() as u32, 1, m))
        .unwrap_or_default();
    let mut bytes: Vec<u8> = Vec::new();
    let mut views = vec![];
    for raw in [
        bytemuck::cast_slice::<_, u8>(&pos),
        bytemuck::cast_slice(&uv),
        bytemuck::cast_slice(&idx),
        &png,
    ] {
        while !bytes.len().is_multiple_of(4) {
            bytes.push(0);
        }
        views.push(json!({"buffer": 0, "byteOffset": bytes.len(), "byteLength": raw.len().max(1)}));
        bytes.extend_from_slice(raw);
    }
    bytes.push(0);
    let mut transmission_ext = json!({"transmissionFactor": transmission});
    if mask.is_some() {
        transmission_ext["transmissionTexture"] = json!({"index": 0});
    }
    let doc = json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_materials_transmission", "KHR_materials_emissive_strength"],
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [
            {"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0},
            {"attributes": {"POSITION": 3}, "indices": 2, "material": 1}
        ]}],
        "materials": [
            {"name": "pane", "doubleSided": true,
             "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.9, 0.9, 1.0],
                "metallicFactor": 0.0, "roughnessFactor": 0.5},
             "extensions": {"KHR_materials_transmission": transmission_ext}},
            {"name": "wall", "emissiveFactor": [1.0, 1.0, 1.0]}
        ],
        "samplers": [{"magFilter": 9728, "minFilter": 9728}],
        "images": [{"bufferView": 3, "mimeType": "image/png"}],
        "textures": [{"source": 0, "sampler": 0}],
        "buffers": [{"byteLength": bytes.len(),
            "uri": format!("data:application/octet-stream;base64,{}", base64(&bytes))}],
        "bufferViews": views,
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [-1.0, -1.0, 0.0], "max": [1.0, 1.0, 0.0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 2, "componentType": 5125, "count": 6, "type": "SCALAR"},
            {"bufferView": 0, "byteOffset": 48, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [-4.0, -4.0, -1.0], "max": [4.0, 4.0, -1.0]}
        ],
    });
    let mut s = load_slice(doc.to_string().as_bytes(), None, "pane").expect("the pane loads");
    s.environment = Vec3::splat(0.5);
    s.env_map = None;
    s.camera = Camera::look_at(Vec3::new(0.0, 0.0, 2.0), Vec3::ZERO, Vec3::Y, 0.55);
    (s.settings.width, s.settings.height) = (W, H);
    s.settings.max_depth = 6;
    s
}

/// The CPU image of `s` (path tracing, seed 5, 64 spp), row-major RGB means.
fn render(s: &Scene) -> Vec<Vec3> {
    let mut opts = RenderOptions::from_scene(s);
    opts.seed = 5;
    opts.estimator = refract::render::Estimator::Path;
    let (film, _) = Renderer::new(s.clone())
        .expect("valid")
        .render(&opts, 64, None, |_| {});
    film.image()
}

/// The pixel columns well inside the pane's left (glass) and right (opaque) halves.
fn columns(left: bool) -> std::ops::Range<u32> {
    if left { 12..18 } else { 22..28 }
}

#[test]
fn mask_makes_glass_and_opaque_halves() {
    let masked = pane(1.0, Some(&[255, 0]));
    assert_eq!(masked.materials[0].kind, MaterialKind::ThinGlass);
    assert!(masked.materials[0].transmission_texture.is_some());
    assert!(
        !masked
            .warnings
            .iter()
            .any(|w| w.contains("transmissionTexture")),
        "a binary mask needs no warning: {:?}",
        masked.warnings
    );
    let glass = pane(1.0, None);
    let opaque = pane(0.0, None);
    assert_eq!(opaque.materials[0].kind, MaterialKind::MetalRough);
    let (a, g, o) = (render(&masked), render(&glass), render(&opaque));
    let mut differ = 0.0f64;
    for y in 6..14 {
        for left in [true, false] {
            for x in columns(left) {
                let i = (y * W + x) as usize;
                let want = if left { g[i] } else { o[i] };
                assert_eq!(
                    a[i],
                    want,
                    "pixel ({x}, {y}) ({})",
                    if left { "glass" } else { "opaque" }
                );
                if !left {
                    differ = differ.max(f64::from((g[i] - o[i]).x.abs()));
                }
            }
        }
    }
    // The references differ where the mask matters: glass shows the wall (≈ 0.92), the
    // opaque base reflects the environment (≈ 0.5 · albedo).
    assert!(
        differ > 0.2,
        "glass and opaque panes differ by only {differ}"
    );
}

#[test]
fn partial_and_useless_masks_warn() {
    let s = pane(1.0, Some(&[255, 128]));
    assert!(
        s.warnings
            .iter()
            .any(|w| w.contains("'pane'") && w.contains("texels between 0 and 1")),
        "{:?}",
        s.warnings
    );
    let s = pane(0.3, Some(&[255, 0]));
    assert!(s.materials[0].transmission_texture.is_none());
    assert!(
        s.warnings
            .iter()
            .any(|w| w.contains("'pane'") && w.contains("transmissionTexture has no effect")),
        "{:?}",
        s.warnings
    );
}

#[test]
fn gpu_refuses_a_transmission_texture_by_name() {
    let err = refract::gpu::upload::check_supported(&pane(1.0, Some(&[255, 0])))
        .expect_err("the GPU has no transmission texture");
    let msg = format!("{err:#}");
    assert!(
        msg.contains("transmission texture") && msg.contains("'pane'"),
        "{msg}"
    );
    refract::gpu::upload::check_supported(&pane(1.0, None)).expect("plain glass is supported");
}
