//! glTF files as web pipelines write them (issue 43): `KHR_mesh_quantization` and
//! `EXT_meshopt_compression` are decoded, Draco and unknown required extensions are refused by
//! name. The files in `tests/assets/gltf-transform/` were written by gltf-transform 4.5.1 from
//! the built-ins' own assets (the commands are in that folder's README.md).

mod common_scenes;

use glam::Vec3;
use refract::cpu::Renderer;
use refract::gltf_io::load::{load_path, load_slice};
use refract::render::{Estimator, RenderOptions};
use refract::scene::Scene;
use serde_json::{Value, json};
use std::path::PathBuf;

fn asset(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(name)
}

fn load(name: &str) -> Scene {
    load_path(&asset(name)).unwrap_or_else(|e| panic!("{name}: {e:#}"))
}

/// Order-independent geometry figures: triangle count, bounding box, total area and the
/// area-weighted sum of the triangles' mean shading normals.
struct Shape {
    triangles: usize,
    lo: Vec3,
    hi: Vec3,
    area: f64,
    normal_sum: Vec3,
}

fn shape(s: &Scene) -> Shape {
    let m = &s.mesh;
    let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
    let (mut area, mut normal_sum) = (0.0f64, Vec3::ZERO);
    for t in &m.indices {
        let p = t.map(|i| m.positions[i as usize]);
        for q in p {
            lo = lo.min(q);
            hi = hi.max(q);
        }
        let a = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).length();
        area += a as f64;
        let n: Vec3 = t.iter().map(|&i| m.normals[i as usize]).sum();
        normal_sum += n / 3.0 * a;
    }
    Shape {
        triangles: m.indices.len(),
        lo,
        hi,
        area,
        normal_sum,
    }
}

/// The compressed file holds the original's geometry within its quantization error: 16-bit
/// positions (2⁻¹⁶ of the extent) and 8-bit octahedral normals (≈ 1/127).
fn assert_same_shape(name: &str, orig: &Scene, comp: &Scene) {
    let (a, b) = (shape(orig), shape(comp));
    assert_eq!(a.triangles, b.triangles, "{name}: triangle count");
    let extent = (a.hi - a.lo).max_element();
    let box_err = (a.lo - b.lo).abs().max(a.hi - b.hi).max_element();
    assert!(
        box_err <= 1e-3 * extent,
        "{name}: bounding box moved by {box_err} (extent {extent})"
    );
    let area_err = (a.area - b.area).abs() / a.area;
    assert!(area_err < 1e-3, "{name}: total area differs by {area_err}");
    let n_err = (a.normal_sum - b.normal_sum).length() as f64 / a.area;
    assert!(
        n_err < 1e-2,
        "{name}: area-weighted normals differ by {n_err} of the area ({:?} vs {:?})",
        a.normal_sum,
        b.normal_sum
    );
}

#[test]
fn quantized_and_meshopt_files_hold_the_original_geometry() {
    let cornell = load("assets/cornell-glass.glb");
    for v in ["quantized", "meshopt"] {
        let name = format!("tests/assets/gltf-transform/cornell-glass.{v}.glb");
        assert_same_shape(&name, &cornell, &load(&name));
    }
    let metals = load("assets/metals.glb");
    let name = "tests/assets/gltf-transform/metals.meshopt.glb";
    assert_same_shape(name, &metals, &load(name));
}

/// The scene at 48 × 48 for the block tests.
fn small(mut s: Scene) -> Scene {
    s.settings.width = 48;
    s.settings.height = 48;
    s
}

#[test]
fn quantized_and_meshopt_files_render_as_the_original_on_the_cpu() {
    let (spp, runs) = (16, 8);
    let runs_of = |s: Scene, seed0| {
        let r = Renderer::new(small(s)).expect("renderer");
        common_scenes::cpu_block_runs(&r, Estimator::Path, spp, None, seed0, runs)
    };
    let orig = runs_of(load("assets/cornell-glass.glb"), 10);
    for (i, v) in ["quantized", "meshopt"].into_iter().enumerate() {
        let name = format!("tests/assets/gltf-transform/cornell-glass.{v}.glb");
        let comp = runs_of(load(&name), 100 + 10 * i as u32);
        common_scenes::assert_blocks_agree(&format!("CPU, {v} vs original"), &comp, &orig);
    }
}

#[test]
fn a_meshopt_file_renders_as_the_original_on_the_gpu() {
    let test = "a_meshopt_file_renders_as_the_original_on_the_gpu";
    let Some(ctx) = common_scenes::gpu_context(test) else {
        return;
    };
    let (spp, runs) = (16, 8);
    let orig = small(load("assets/cornell-glass.glb"));
    let cpu = common_scenes::cpu_block_runs(
        &Renderer::new(orig).expect("renderer"),
        Estimator::Path,
        spp,
        None,
        10,
        runs,
    );
    let comp = small(load(
        "tests/assets/gltf-transform/cornell-glass.meshopt.glb",
    ));
    let mut opts = RenderOptions::from_scene(&comp);
    opts.estimator = Estimator::Path;
    let mut g = refract::gpu::GpuRenderer::with_context(ctx, comp.clone(), opts).expect("gpu");
    g.set_estimator(Estimator::Path).expect("path on the GPU");
    let gpu: Vec<Vec<f64>> = (0..runs)
        .map(|i| {
            opts.seed = 500 + i;
            g.set_options(opts).expect("options");
            let img = g.render(spp).expect("render");
            assert_eq!(img.dropped, 0);
            common_scenes::block_means(&img.mean, 48, 48)
        })
        .collect();
    common_scenes::assert_blocks_agree("GPU meshopt vs CPU original", &gpu, &cpu);
}

#[test]
fn draco_is_refused_by_name_with_a_way_out() {
    let path = asset("tests/assets/gltf-transform/cornell-glass.draco.glb");
    let e = format!("{:#}", load_path(&path).expect_err("Draco is not decoded"));
    assert!(
        e.contains("requires the extension 'KHR_draco_mesh_compression'"),
        "{e}"
    );
    assert!(e.contains("gltf-transform"), "no way out offered: {e}");
}

/// A one-triangle glTF whose buffer 1 is a meshopt-style fallback without data, requiring
/// `required`; `fallback` = whether buffer 1 says `fallback: true`.
fn requiring(required: &str, fallback: bool) -> Vec<u8> {
    let tri: Vec<u8> = [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
        .iter()
        .flat_map(|f| f.to_le_bytes())
        .collect();
    let mut b1 = json!({"byteLength": 36});
    if fallback {
        b1["extensions"] = json!({"EXT_meshopt_compression": {"fallback": true}});
    }
    let doc = json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": [required],
        "extensionsRequired": [required],
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}],
        "bufferViews": [{"buffer": 1, "byteLength": 36}],
        "buffers": [
            {"byteLength": 36, "uri": format!("data:application/octet-stream;base64,{}",
                common_scenes::base64(&tri))},
            b1
        ]
    });
    serde_json::to_vec(&doc).expect("json")
}

#[test]
fn an_unknown_required_extension_is_named_before_buffers_are_read() {
    for fallback in [false, true] {
        let bytes = requiring("EXT_unknown_compression", fallback);
        let e = format!("{:#}", load_slice(&bytes, None, "t").expect_err("refused"));
        assert!(
            e.contains("requires the extension 'EXT_unknown_compression'"),
            "fallback {fallback}: {e}"
        );
    }
}

#[test]
fn an_uncompressed_view_of_a_data_less_fallback_buffer_is_an_error_naming_it() {
    let bytes = requiring("EXT_meshopt_compression", true);
    let e = format!("{:#}", load_slice(&bytes, None, "t").expect_err("no data"));
    assert!(
        e.contains("buffer view 0 is not compressed but reads meshopt fallback buffer 1"),
        "{e}"
    );
}

/// A UV-sphere-like fan of `n` vertices: positions, unit normals, triangle indices.
fn fan(n: usize) -> (Vec<[f32; 3]>, Vec<[f32; 3]>, Vec<u32>) {
    let mut p = vec![[0.0, 0.0, 1.5]];
    let mut nrm = vec![[0.0, 0.0, 1.0]];
    for i in 0..n - 1 {
        let a = i as f32 / (n - 1) as f32 * std::f32::consts::TAU;
        let v = Vec3::new(a.cos(), a.sin(), 0.3).normalize();
        p.push([3.0 * a.cos(), 3.0 * a.sin(), 0.25]);
        nrm.push(v.to_array());
    }
    let idx = (1..n as u32 - 1).flat_map(|i| [0, i, i + 1]).collect();
    (p, nrm, idx)
}

/// A glTF whose three views are meshopt-compressed: positions with the exponential filter
/// (stride 12), normals with the 16-bit octahedral filter (stride 8, `VEC3` of a 4-lane view),
/// indices as an index sequence (stride 4); `edit` changes the JSON before it is written.
fn meshopt_fan(edit: impl FnOnce(&mut Value)) -> (Vec<u8>, Vec<[f32; 3]>, Vec<u32>) {
    let (p, n, idx) = fan(24);
    let pos = meshopt::encode_filter_exp::<3>(&p, 15, meshopt::EncodeExpMode::Separate);
    let n4: Vec<[f32; 4]> = n.iter().map(|v| [v[0], v[1], v[2], 0.0]).collect();
    let oct = meshopt::encode_filter_oct::<i16>(&n4, 16);
    let views = [
        meshopt::encode_vertex_buffer(&pos).expect("encode positions"),
        meshopt::encode_vertex_buffer(&oct).expect("encode normals"),
        meshopt::encode_index_sequence(&idx, p.len()).expect("encode indices"),
    ];
    let (strides, counts) = ([12, 8, 4], [p.len(), p.len(), idx.len()]);
    let modes = ["ATTRIBUTES", "ATTRIBUTES", "INDICES"];
    let filters = ["EXPONENTIAL", "OCTAHEDRAL", "NONE"];
    let (mut data, mut buffer_views, mut fallback_len) = (Vec::new(), vec![], 0);
    for k in 0..3 {
        let len = strides[k] * counts[k];
        buffer_views.push(json!({
            "buffer": 1, "byteOffset": fallback_len, "byteLength": len, "byteStride": strides[k],
            "extensions": {"EXT_meshopt_compression": {
                "buffer": 0, "byteOffset": data.len(), "byteLength": views[k].len(),
                "byteStride": strides[k], "count": counts[k], "mode": modes[k],
                "filter": filters[k]}}
        }));
        data.extend_from_slice(&views[k]);
        data.resize(data.len().next_multiple_of(4), 0);
        fallback_len += len;
    }
    // Index views carry no byteStride in core glTF.
    buffer_views[2]
        .as_object_mut()
        .expect("view")
        .remove("byteStride");
    let mut doc = json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["EXT_meshopt_compression"],
        "extensionsRequired": ["EXT_meshopt_compression"],
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2}]}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": p.len(), "type": "VEC3"},
            {"bufferView": 1, "componentType": 5122, "normalized": true, "count": p.len(),
             "type": "VEC3"},
            {"bufferView": 2, "componentType": 5125, "count": idx.len(), "type": "SCALAR"}
        ],
        "bufferViews": buffer_views,
        "buffers": [
            {"byteLength": data.len(), "uri": format!("data:application/octet-stream;base64,{}",
                common_scenes::base64(&data))},
            {"byteLength": fallback_len,
             "extensions": {"EXT_meshopt_compression": {"fallback": true}}}
        ]
    });
    edit(&mut doc);
    (serde_json::to_vec(&doc).expect("json"), n, idx)
}

#[test]
fn meshopt_filters_and_index_sequences_decode_to_the_encoded_mesh() {
    let (bytes, normals, idx) = meshopt_fan(|_| {});
    let s = load_slice(&bytes, None, "fan").unwrap_or_else(|e| panic!("{e:#}"));
    let (p, _, _) = fan(24);
    assert_eq!(s.mesh.indices.len(), idx.len() / 3);
    for (f, t) in s.mesh.indices.iter().enumerate() {
        for k in 0..3 {
            let src = idx[3 * f + k] as usize;
            let got = s.mesh.positions[t[k] as usize];
            let want = Vec3::from(p[src]);
            // 15-bit mantissas: relative error ≤ 2⁻¹⁵ of each component's exponent range.
            assert!(
                (got - want).abs().max_element() < 2e-4,
                "vertex {src}: {got} vs {want}"
            );
            let gn = s.mesh.normals[t[k] as usize];
            let wn = Vec3::from(normals[src]);
            assert!(gn.dot(wn) > 0.9999, "normal {src}: {gn} vs {wn}");
        }
    }
}

#[test]
fn hostile_meshopt_views_are_errors_naming_the_view() {
    type Edit = fn(&mut Value);
    let cases: [(Edit, &str); 4] = [
        (
            |d| {
                d["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["byteStride"] =
                    3.into()
            },
            "buffer view 0: EXT_meshopt_compression: byteStride 3 is not allowed",
        ),
        (
            |d| {
                d["bufferViews"][1]["extensions"]["EXT_meshopt_compression"]["byteLength"] =
                    5.into()
            },
            "buffer view 1: EXT_meshopt_compression data does not decode",
        ),
        (
            |d| {
                d["bufferViews"][2]["extensions"]["EXT_meshopt_compression"]["mode"] =
                    "TRIANGLES".into()
            },
            "buffer view 2: EXT_meshopt_compression data does not decode",
        ),
        (
            |d| {
                d["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["filter"] =
                    "QUATERNION".into()
            },
            "buffer view 0: EXT_meshopt_compression: filter Quaternion does not allow byteStride 12",
        ),
    ];
    for (edit, want) in cases {
        let (bytes, _, _) = meshopt_fan(edit);
        let e = format!("{:#}", load_slice(&bytes, None, "fan").expect_err(want));
        assert!(e.contains(want), "want '{want}' in: {e}");
    }
}
