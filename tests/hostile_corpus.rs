//! A generated corpus of hostile glTF inputs (issue 16, part 7), each with its asserted
//! outcome: built in the test from the shipped `assets/*.glb` (no binary fixtures) by editing
//! their JSON at a JSON pointer, or their GLB container. Every case must end in its expected
//! error (whose text names the source: JSON pointer, index or file) or load with its expected
//! warning — never a panic, and every scene that loads validates.

use refract::gltf_io::load::load_slice;
use serde_json::{Value, json};

/// What a case must do.
enum Expect {
    /// `load_slice` fails and the error chain contains every word.
    Fails(&'static [&'static str]),
    /// It loads (and validates) with a warning containing every word.
    Warns(&'static [&'static str]),
    /// It loads and validates (a hostile-looking but legal value).
    Loads,
}
use Expect::{Fails, Loads, Warns};

/// One edit of a shipped file.
enum Edit {
    /// Set the value at a JSON pointer (creating missing objects on the way).
    Set(&'static str, Value),
    /// Remove the value at a JSON pointer.
    Remove(&'static str),
    /// Replace the JSON chunk's text as a whole.
    Json(&'static str),
    /// Change the GLB container's bytes: (offset, new little-endian u32).
    Header(usize, u32),
    /// Keep only the first n bytes of the file.
    Truncate(usize),
}
use Edit::{Header, Json, Remove, Set, Truncate};

struct Case {
    asset: &'static str,
    edits: Vec<Edit>,
    expect: Expect,
}

fn case(asset: &'static str, edits: Vec<Edit>, expect: Expect) -> Case {
    Case {
        asset,
        edits,
        expect,
    }
}

/// The JSON chunk and the binary chunk of a GLB (glTF 2.0 §4.4).
fn split_glb(bytes: &[u8]) -> (Value, Vec<u8>) {
    let u32_at = |o: usize| u32::from_le_bytes(bytes[o..o + 4].try_into().expect("4 bytes"));
    let json_len = u32_at(12) as usize;
    let json = serde_json::from_slice(&bytes[20..20 + json_len]).expect("shipped JSON");
    let bin_at = 20 + json_len;
    let bin_len = u32_at(bin_at) as usize;
    (json, bytes[bin_at + 8..bin_at + 8 + bin_len].to_vec())
}

/// A GLB from a JSON text and a binary chunk, each padded to 4 bytes.
fn join_glb(json: &[u8], bin: &[u8]) -> Vec<u8> {
    let mut j = json.to_vec();
    while !j.len().is_multiple_of(4) {
        j.push(b' ');
    }
    let mut b = bin.to_vec();
    while !b.len().is_multiple_of(4) {
        b.push(0);
    }
    let total = 12 + 8 + j.len() + 8 + b.len();
    let mut out = Vec::with_capacity(total);
    out.extend(b"glTF");
    out.extend(2u32.to_le_bytes());
    out.extend((total as u32).to_le_bytes());
    out.extend((j.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(j);
    out.extend((b.len() as u32).to_le_bytes());
    out.extend(b"BIN\0");
    out.extend(b);
    out
}

/// Set `v` at JSON pointer `ptr`, creating objects (or growing arrays) on the way.
fn set(doc: &mut Value, ptr: &str, v: Value) {
    let mut cur = doc;
    let keys: Vec<&str> = ptr.split('/').skip(1).collect();
    for (i, k) in keys.iter().enumerate() {
        let last = i + 1 == keys.len();
        let next = if last { v.clone() } else { json!({}) };
        cur = match cur {
            Value::Array(a) => {
                let idx: usize = k.parse().expect("array index");
                while a.len() <= idx {
                    a.push(next.clone());
                }
                &mut a[idx]
            }
            other => {
                if !other.is_object() {
                    *other = json!({});
                }
                let o = other.as_object_mut().expect("object");
                o.entry(k.to_string()).or_insert(next)
            }
        };
        if last {
            *cur = v.clone();
            return;
        }
    }
}

fn remove(doc: &mut Value, ptr: &str) {
    let (parent, key) = ptr.rsplit_once('/').expect("pointer");
    match doc.pointer_mut(parent) {
        Some(Value::Object(o)) => {
            o.remove(key);
        }
        Some(Value::Array(a)) => {
            a.remove(key.parse::<usize>().expect("index"));
        }
        _ => panic!("no {parent}"),
    }
}

/// The bytes of a case.
fn build(c: &Case) -> Vec<u8> {
    let path = format!("{}/assets/{}.glb", env!("CARGO_MANIFEST_DIR"), c.asset);
    let shipped = std::fs::read(&path).expect("shipped asset");
    let (mut doc, bin) = split_glb(&shipped);
    let mut raw_json: Option<&str> = None;
    for e in &c.edits {
        match e {
            Set(p, v) => set(&mut doc, p, v.clone()),
            Remove(p) => remove(&mut doc, p),
            Json(t) => raw_json = Some(t),
            _ => {}
        }
    }
    let text = raw_json.map_or_else(|| serde_json::to_vec(&doc).expect("json"), |t| t.into());
    let mut bytes = join_glb(&text, &bin);
    for e in &c.edits {
        match e {
            Header(o, v) => bytes[*o..*o + 4].copy_from_slice(&v.to_le_bytes()),
            Truncate(n) => bytes.truncate(*n),
            _ => {}
        }
    }
    bytes
}

/// A 2×2 PNG as a base64 `data:` URI (made here, not shipped).
fn png_data_uri() -> String {
    let mut png = Vec::new();
    image::RgbaImage::from_pixel(2, 2, image::Rgba([255, 128, 0, 255]))
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .expect("png");
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::from("data:image/png;base64,");
    for chunk in png.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(ALPHABET[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

/// Material 0 of cornell-glass textured with image 0 = `uri`.
fn textured(uri: Value, mut more: Vec<Edit>) -> Vec<Edit> {
    let mut e = vec![
        Set("/images", json!([{"uri": uri}])),
        Set("/textures", json!([{"source": 0}])),
        Set(
            "/materials/0/pbrMetallicRoughness/baseColorTexture",
            json!({"index": 0}),
        ),
    ];
    e.append(&mut more);
    e
}

/// A punctual light (KHR_lights_punctual) on a new node of cornell-glass.
fn with_light(light: Value) -> Vec<Edit> {
    vec![
        Set("/extensionsUsed/4", json!("KHR_lights_punctual")),
        Set("/extensions/KHR_lights_punctual/lights", json!([light])),
        Set(
            "/nodes/7",
            json!({"translation": [0, 1, 0], "extensions": {"KHR_lights_punctual": {"light": 0}}}),
        ),
        Set("/scenes/0/nodes/7", json!(7)),
    ]
}

const C: &str = "cornell-glass";

/// Index fields pointing nowhere: each an error or a skipped primitive naming the index.
fn dangling_indices() -> Vec<Case> {
    let big = || json!(9999);
    vec![
        case(
            C,
            vec![Set("/scenes/0/nodes/0", big())],
            Warns(&["node 9999"]),
        ),
        case(C, vec![Set("/scene", big())], Fails(&["scene 9999"])),
        case(C, vec![Set("/nodes/0/mesh", big())], Warns(&["mesh 9999"])),
        case(
            C,
            vec![Set("/nodes/0/children", json!([9999]))],
            Warns(&["node 9999"]),
        ),
        case(
            C,
            vec![Set("/nodes/6/camera", big())],
            Warns(&["camera 9999"]),
        ),
        case(
            C,
            vec![Set("/meshes/0/primitives/0/attributes/POSITION", big())],
            Warns(&["accessor 9999"]),
        ),
        case(
            C,
            vec![Set("/meshes/0/primitives/0/attributes/NORMAL", big())],
            Warns(&["accessor 9999"]),
        ),
        case(
            C,
            vec![Set("/meshes/0/primitives/0/attributes/TEXCOORD_0", big())],
            Warns(&["accessor 9999"]),
        ),
        case(
            C,
            vec![Set("/meshes/0/primitives/0/indices", big())],
            Warns(&["accessor 9999"]),
        ),
        case(
            C,
            vec![Set("/meshes/0/primitives/0/material", big())],
            Warns(&["material 9999"]),
        ),
        case(
            C,
            vec![Set("/accessors/0/bufferView", big())],
            Warns(&["buffer view 9999"]),
        ),
        case(
            C,
            vec![Set("/accessors/3/bufferView", big())],
            Warns(&["buffer view 9999"]),
        ),
        case(
            C,
            vec![Set("/bufferViews/0/buffer", big())],
            Warns(&["buffer 9999"]),
        ),
        case(
            C,
            textured(
                json!(png_data_uri()),
                vec![Set("/textures/0/source", big())],
            ),
            Warns(&["image 9999"]),
        ),
        case(
            C,
            textured(
                json!(png_data_uri()),
                vec![Set(
                    "/materials/0/pbrMetallicRoughness/baseColorTexture/index",
                    big(),
                )],
            ),
            Warns(&["texture 9999"]),
        ),
        case(
            C,
            textured(
                json!(png_data_uri()),
                vec![Set("/textures/0/sampler", big())],
            ),
            Loads,
        ),
        case(C, textured(json!(png_data_uri()), vec![]), Loads),
    ]
}

const GLASS: &str = "/materials/4";

/// Material values that break energy conservation or physics.
fn materials() -> Vec<Case> {
    let ior = "/materials/4/extensions/KHR_materials_ior/ior";
    let m = |p: &'static str, v: Value, e: Expect| case(C, vec![Set(p, v)], e);
    let _ = GLASS;
    vec![
        m(
            ior,
            json!(0),
            Fails(&["/materials/4/extensions/KHR_materials_ior/ior"]),
        ),
        m(
            ior,
            json!(-1.5),
            Fails(&["/materials/4/extensions/KHR_materials_ior/ior"]),
        ),
        m(ior, json!(1e-30), Warns(&["IOR", "not ≥ 1", "using 1.5"])),
        m(ior, json!(0.5), Warns(&["IOR", "not ≥ 1", "using 1.5"])),
        m(
            ior,
            json!(1e30),
            Fails(&["/materials/4/extensions/KHR_materials_ior/ior"]),
        ),
        m(
            ior,
            json!(1e39),
            Fails(&["/materials/4/extensions/KHR_materials_ior/ior"]),
        ),
        m(ior, json!("1.5"), Fails(&["/materials/4", "expected f32"])),
        m(ior, json!(1.0), Loads),
        m(ior, json!(2.42), Loads),
        m(
            "/materials/4/extensions/KHR_materials_transmission/transmissionFactor",
            json!(2.0),
            Warns(&["transmission"]),
        ),
        m(
            "/materials/4/extensions/KHR_materials_transmission/transmissionFactor",
            json!(-1.0),
            Warns(&["transmission"]),
        ),
        m(
            "/materials/4/extensions/KHR_materials_volume/thicknessFactor",
            json!(-1.0),
            Warns(&["thicknessFactor -1", "thin-walled"]),
        ),
        m(
            "/materials/4/extensions/KHR_materials_volume/attenuationDistance",
            json!(0.0),
            Warns(&["attenuationDistance"]),
        ),
        m(
            "/materials/4/extensions/KHR_materials_volume/attenuationDistance",
            json!(-2.0),
            Warns(&["attenuationDistance"]),
        ),
        m(
            "/materials/4/extensions/KHR_materials_volume/attenuationColor",
            json!([2.0, 0.5, 0.5]),
            Warns(&["attenuationColor"]),
        ),
        m(
            "/materials/4/extensions/KHR_materials_volume/attenuationColor",
            json!([-1.0, 0.5, 0.5]),
            Warns(&["attenuationColor"]),
        ),
        case(
            "prism",
            vec![Set(
                "/materials/2/extensions/KHR_materials_dispersion/dispersion",
                json!(-1.0),
            )],
            Warns(&["dispersion"]),
        ),
        case(
            "prism",
            vec![Set(
                "/materials/2/extensions/KHR_materials_dispersion/dispersion",
                json!(1e30),
            )],
            Warns(&["dispersion", "clamped to 20"]),
        ),
        m(
            "/materials/3/emissiveFactor",
            json!([1e30, 1e30, 1e30]),
            Fails(&["/materials/3/emissiveFactor", "overflows"]),
        ),
        m(
            "/materials/3/extensions/KHR_materials_emissive_strength/emissiveStrength",
            json!(3e38),
            Fails(&["/materials/3", "overflows"]),
        ),
        m(
            "/materials/3/extensions/KHR_materials_emissive_strength/emissiveStrength",
            json!(-1.0),
            Warns(&["emissive"]),
        ),
        m(
            "/materials/3/emissiveFactor",
            json!([-1.0, 0.0, 0.0]),
            Warns(&["emissive"]),
        ),
        m(
            "/materials/0/pbrMetallicRoughness/baseColorFactor",
            json!([1e30, 1.0, 1.0, 1.0]),
            Warns(&["baseColorFactor"]),
        ),
        m(
            "/materials/0/pbrMetallicRoughness/baseColorFactor",
            json!([2.0, 0.5, 0.5, 1.0]),
            Warns(&["baseColorFactor"]),
        ),
        m(
            "/materials/0/pbrMetallicRoughness/baseColorFactor",
            json!([-0.5, 0.5, 0.5, 1.0]),
            Warns(&["baseColorFactor"]),
        ),
        m(
            "/materials/0/pbrMetallicRoughness/baseColorFactor",
            json!([1.0, 1.0]),
            Fails(&["/materials/0", "length"]),
        ),
        m(
            "/materials/0/pbrMetallicRoughness/metallicFactor",
            json!(2.0),
            Warns(&["metallic"]),
        ),
        m(
            "/materials/0/pbrMetallicRoughness/metallicFactor",
            json!(-1.0),
            Warns(&["metallic"]),
        ),
        m(
            "/materials/0/pbrMetallicRoughness/roughnessFactor",
            json!(7.0),
            Warns(&["roughness"]),
        ),
        m(
            "/materials/0/pbrMetallicRoughness/roughnessFactor",
            json!(-7.0),
            Warns(&["roughness"]),
        ),
        m(
            "/materials/4/extras/microfacet_distribution",
            json!("phong"),
            Warns(&["phong", "using GGX"]),
        ),
        m(
            "/materials/4/extras/microfacet_distribution",
            json!(3),
            Warns(&["microfacet_distribution 3"]),
        ),
        m("/materials/4/extras", json!("not an object"), Loads),
        m(
            "/materials/0/doubleSided",
            json!("yes"),
            Fails(&["/materials/0", "boolean"]),
        ),
        m("/materials/0/alphaMode", json!("BLEND"), Loads),
        m("/materials/0/name", json!("x".repeat(100_000)), Loads),
    ]
}

/// Node transforms and hierarchies.
fn nodes() -> Vec<Case> {
    let n = |p: &'static str, v: Value, e: Expect| case(C, vec![Set(p, v)], e);
    let chain: Vec<Value> = (0..2000)
        .map(|i| {
            if i < 1999 {
                json!({"children": [i + 1 + 7]})
            } else {
                json!({"mesh": 0})
            }
        })
        .collect();
    let mut deep = vec![Set("/scenes/0/nodes/7", json!(7))];
    let mut doc_nodes = vec![];
    for (i, c) in chain.into_iter().enumerate() {
        doc_nodes.push((i + 7, c));
    }
    for (i, c) in doc_nodes {
        deep.push(Set(Box::leak(format!("/nodes/{i}").into_boxed_str()), c));
    }
    vec![
        n(
            "/nodes/0/translation",
            json!([1e39, 0, 0]),
            Warns(&["node 0"]),
        ),
        n(
            "/nodes/0/scale",
            json!([0, 0, 0]),
            Warns(&["(node 0)", "singular"]),
        ),
        n(
            "/nodes/0/scale",
            json!([1e30, 1e30, 1e30]),
            Warns(&["node 0", "singular"]),
        ),
        n(
            "/nodes/0/rotation",
            json!([0, 0, 0, 0]),
            Warns(&["node 0", "quaternion", "skipped"]),
        ),
        n("/nodes/0/rotation", json!([0, 0, 0, 2]), Loads),
        n(
            "/nodes/0/matrix",
            json!([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0.5, 0, 0, 0, 1]),
            Warns(&["node 0", "not affine"]),
        ),
        n(
            "/nodes/0/matrix",
            json!([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0]),
            Fails(&["/nodes/0", "length 16"]),
        ),
        n(
            "/nodes/0/matrix",
            json!([0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1]),
            Warns(&["node 0", "singular"]),
        ),
        n("/nodes/0/children", json!([0]), Warns(&["node 0"])),
        n(
            "/nodes/1/children",
            json!([0, 0, 0]),
            Warns(&["reached twice"]),
        ),
        n("/nodes/0/children", json!([-1]), Fails(&["/nodes/0"])),
        n("/scenes/0/nodes", json!([]), Fails(&["no triangles"])),
        n("/scenes", json!([]), Fails(&["scene 0", "does not exist"])),
        case(C, deep, Fails(&["deep"])),
    ]
}

/// Cameras.
fn cameras() -> Vec<Case> {
    let p = |k: &'static str, v: Value, e: Expect| case(C, vec![Set(k, v)], e);
    vec![
        p(
            "/cameras/0/perspective/yfov",
            json!(0.0),
            Fails(&["camera 0", "yfov"]),
        ),
        p(
            "/cameras/0/perspective/yfov",
            json!(-1.0),
            Fails(&["camera 0", "yfov"]),
        ),
        p(
            "/cameras/0/perspective/yfov",
            json!(3.2),
            Fails(&["camera 0", "yfov"]),
        ),
        p(
            "/cameras/0/perspective/yfov",
            json!(1e39),
            Fails(&["camera 0", "yfov"]),
        ),
        p(
            "/cameras/0/perspective/znear",
            json!(0.0),
            Warns(&["camera 0"]),
        ),
        p(
            "/cameras/0/perspective/znear",
            json!(-1.0),
            Warns(&["camera 0"]),
        ),
        p(
            "/cameras/0/perspective/zfar",
            json!(0.0001),
            Warns(&["camera 0"]),
        ),
        p("/cameras/0/perspective/aspectRatio", json!(0.0), Loads),
        p(
            "/cameras/0/type",
            json!("orthographic"),
            Warns(&["camera 0"]),
        ),
        p("/cameras/0/type", json!("fisheye"), Warns(&["camera 0"])),
        case(
            C,
            vec![Remove("/cameras/0/perspective")],
            Warns(&["camera 0"]),
        ),
        p(
            "/cameras/0/orthographic",
            json!({"xmag": 1, "ymag": 1, "znear": 0.1, "zfar": 10}),
            Loads,
        ),
    ]
}

/// `scenes[0].extras`: render settings and environment.
fn extras() -> Vec<Case> {
    let r = |k: &'static str, v: Value, e: Expect| case(C, vec![Set(k, v)], e);
    let mut nest = json!(1);
    for _ in 0..200 {
        nest = json!([nest]);
    }
    vec![
        r(
            "/scenes/0/extras/render/width",
            json!(0),
            Fails(&["extras.render.width"]),
        ),
        r(
            "/scenes/0/extras/render/width",
            json!(1_000_000_000u64),
            Fails(&["extras.render.width"]),
        ),
        r(
            "/scenes/0/extras/render/width",
            json!(-5),
            Fails(&["extras.render.width"]),
        ),
        r(
            "/scenes/0/extras/render/width",
            json!("big"),
            Fails(&["extras.render.width"]),
        ),
        r(
            "/scenes/0/extras/render/height",
            json!(16385),
            Fails(&["extras.render.height"]),
        ),
        r(
            "/scenes/0/extras/render/spp",
            json!(0),
            Fails(&["extras.render.spp"]),
        ),
        r(
            "/scenes/0/extras/render/spp",
            json!(1e30),
            Fails(&["extras.render.spp"]),
        ),
        r(
            "/scenes/0/extras/render/max_depth",
            json!(-1),
            Fails(&["extras.render.max_depth"]),
        ),
        r(
            "/scenes/0/extras/render/max_depth",
            json!(1e12),
            Fails(&["extras.render.max_depth"]),
        ),
        r(
            "/scenes/0/extras/render/rr_depth",
            json!("x"),
            Fails(&["extras.render.rr_depth"]),
        ),
        r(
            "/scenes/0/extras/render",
            json!([1, 2]),
            Fails(&["extras.render"]),
        ),
        r(
            "/scenes/0/extras/render/unknown_key",
            json!(1),
            Warns(&["unknown_key"]),
        ),
        r(
            "/scenes/0/extras/environment",
            json!([-1.0, 0.0, 0.0]),
            Fails(&["environment"]),
        ),
        r(
            "/scenes/0/extras/environment",
            json!([1e39, 0.0, 0.0]),
            Fails(&["environment"]),
        ),
        r(
            "/scenes/0/extras/environment",
            json!([1.0]),
            Fails(&["environment"]),
        ),
        // A single number is a grey environment (documented).
        r("/scenes/0/extras/environment", json!(7), Loads),
        r("/scenes/0/extras/deep", nest, Fails(&["/scenes/0/extras"])),
        r("/scenes/0/extras", json!("text"), Loads),
    ]
}

/// Accessors, buffer views and buffers.
fn data() -> Vec<Case> {
    let a = |k: &'static str, v: Value, e: Expect| case(C, vec![Set(k, v)], e);
    vec![
        a("/accessors/0/count", json!(0), Warns(&["POSITION count 0"])),
        a(
            "/accessors/0/count",
            json!(268_435_457u64),
            Warns(&["accessor 0", "too large"]),
        ),
        a("/accessors/0/count", json!(13), Warns(&["accessor 0"])),
        a(
            "/accessors/0/count",
            json!(-1),
            Fails(&["/accessors/0", "u64"]),
        ),
        a(
            "/accessors/0/byteOffset",
            json!(1_000_000),
            Warns(&["accessor 0"]),
        ),
        a("/accessors/0/byteOffset", json!(2), Warns(&["accessor 0"])),
        // Byte positions are read as KHR_mesh_quantization defines them (integers).
        a("/accessors/0/componentType", json!(5120), Loads),
        a(
            "/accessors/0/componentType",
            json!(9999),
            Warns(&["accessor 0"]),
        ),
        a("/accessors/0/type", json!("SCALAR"), Warns(&["accessor 0"])),
        a("/accessors/0/type", json!("MAT4"), Warns(&["accessor 0"])),
        a("/accessors/0/type", json!("VEC9"), Warns(&["accessor 0"])),
        a(
            "/accessors/3/componentType",
            json!(5126),
            Warns(&["accessor 3"]),
        ),
        a("/accessors/3/bufferView", json!(0), Warns(&["index"])),
        a("/accessors/1/normalized", json!(true), Loads),
        a(
            "/accessors/0/sparse",
            json!({"count": 5, "indices": {"bufferView": 9999, "componentType": 5125}, "values": {"bufferView": 0}}),
            Warns(&["accessor 0"]),
        ),
        a(
            "/accessors/0/sparse",
            json!({"count": 1_000_000_000u64, "indices": {"bufferView": 3, "componentType": 5125}, "values": {"bufferView": 0}}),
            Warns(&["accessor 0"]),
        ),
        case(
            C,
            vec![Remove("/accessors/0/bufferView")],
            Warns(&["dropped"]),
        ),
        a(
            "/bufferViews/0/byteStride",
            json!(3),
            Warns(&["accessor 0"]),
        ),
        a(
            "/bufferViews/0/byteStride",
            json!(1000),
            Warns(&["accessor 0"]),
        ),
        a(
            "/bufferViews/0/byteLength",
            json!(1_000_000_000_000u64),
            Warns(&["buffer view 0"]),
        ),
        a(
            "/bufferViews/0/byteOffset",
            json!(1_000_000_000),
            Warns(&["buffer view 0"]),
        ),
        a(
            "/buffers/0/byteLength",
            json!(1_000_000_000_000u64),
            Fails(&["buffer 0", "byteLength"]),
        ),
        a(
            "/buffers/0/byteLength",
            json!(10),
            Fails(&[
                "no usable triangles",
                "buffer view 0",
                "buffer 0 of 10 bytes",
            ]),
        ),
        a(
            "/buffers/0/byteLength",
            json!(10_000_000),
            Fails(&["buffer 0", "byteLength"]),
        ),
        a(
            "/buffers/0/uri",
            json!("data:application/octet-stream;base64,!!!!"),
            Fails(&["buffer 0", "base64"]),
        ),
        a(
            "/buffers/0/uri",
            json!("data:application/octet-stream,plain"),
            Fails(&["buffer 0", "not base64"]),
        ),
        a(
            "/buffers/0/uri",
            json!("http://example.com/x.bin"),
            Fails(&["buffer 0", "scheme"]),
        ),
        a(
            "/buffers/0/uri",
            json!("x.bin"),
            Fails(&["buffer 0", "no folder"]),
        ),
        a(
            "/buffers/0/uri",
            json!("%FF%FE.bin"),
            Fails(&["buffer 0", "percent"]),
        ),
        a(
            "/buffers/0/uri",
            json!(format!("x{}.bin", "y".repeat(100_000))),
            Fails(&["buffer 0"]),
        ),
        a(
            "/meshes/0/primitives/0/mode",
            json!(0),
            Warns(&["mode Points", "skipped"]),
        ),
        a(
            "/meshes/0/primitives/0/mode",
            json!(1),
            Warns(&["mode Lines", "skipped"]),
        ),
        a("/meshes/0/primitives/0/mode", json!(99), Warns(&["mesh 0"])),
        a("/meshes/0/primitives", json!([]), Loads),
        a(
            "/meshes/0/primitives/0/targets",
            json!([{"POSITION": 0}]),
            Loads,
        ),
    ]
}

/// Punctual lights, extensions and images.
fn lights_extensions_images() -> Vec<Case> {
    let light = |l: Value, e: Expect| case(C, with_light(l), e);
    vec![
        light(json!({"type": "point", "intensity": 10}), Loads),
        light(json!({"type": "directional", "intensity": 2}), Loads),
        light(
            json!({"type": "spot", "intensity": 10, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.5}}),
            Loads,
        ),
        light(
            json!({"type": "point", "intensity": -1}),
            Warns(&["light 0"]),
        ),
        light(
            json!({"type": "point", "intensity": 1e39}),
            Fails(&["light 0"]),
        ),
        light(
            json!({"type": "point", "color": [-1, 1, 1]}),
            Warns(&["light 0"]),
        ),
        light(
            json!({"type": "spot", "spot": {"innerConeAngle": 0.9, "outerConeAngle": 0.1}}),
            Warns(&["light 0"]),
        ),
        light(
            json!({"type": "spot", "spot": {"outerConeAngle": 3.0}}),
            Warns(&["light 0"]),
        ),
        light(json!({"type": "area"}), Warns(&["light 0"])),
        light(json!({"type": "point", "range": 0}), Loads),
        case(
            C,
            vec![Set(
                "/nodes/0/extensions/KHR_lights_punctual/light",
                json!(5),
            )],
            Warns(&["light 5"]),
        ),
        case(
            C,
            vec![Set("/extensionsRequired", json!(["KHR_texture_basisu"]))],
            Fails(&["/extensionsRequired/0", "KHR_texture_basisu"]),
        ),
        // Declared required but used by no buffer view: supported, so it loads as is.
        case(
            C,
            vec![Set(
                "/extensionsRequired",
                json!(["EXT_meshopt_compression", "KHR_mesh_quantization"]),
            )],
            Loads,
        ),
        case(
            C,
            vec![Set(
                "/extensionsRequired",
                json!(["KHR_materials_volume", "KHR_draco_mesh_compression"]),
            )],
            Fails(&["/extensionsRequired/1", "KHR_draco_mesh_compression"]),
        ),
        case(
            C,
            vec![Set("/extensionsRequired", json!(["KHR_materials_ior"]))],
            Loads,
        ),
        case(
            C,
            vec![Set("/extensionsUsed/4", json!("EXT_unknown"))],
            Warns(&["EXT_unknown"]),
        ),
        case(
            C,
            vec![Set(
                "/materials/0/extensions/KHR_materials_clearcoat",
                json!({}),
            )],
            Warns(&["KHR_materials_clearcoat"]),
        ),
        case(
            C,
            textured(json!("data:image/png;base64,@@@@"), vec![]),
            Warns(&["image 0", "base64"]),
        ),
        case(
            C,
            textured(json!("data:image/png;base64,"), vec![]),
            Warns(&["image 0"]),
        ),
        case(
            C,
            textured(json!("data:image/png"), vec![]),
            Warns(&["image 0", "data URI"]),
        ),
        case(
            C,
            textured(json!("http://example.com/t.png"), vec![]),
            Warns(&["image 0", "scheme"]),
        ),
        case(
            C,
            textured(json!("t.png"), vec![]),
            Warns(&["image 0", "no base directory"]),
        ),
        case(
            C,
            textured(json!("data:image/png;base64,AAAAAAAA"), vec![]),
            Warns(&["image 0"]),
        ),
        case(
            C,
            textured(
                json!(png_data_uri()),
                vec![Set(
                    "/materials/0/pbrMetallicRoughness/baseColorTexture/texCoord",
                    json!(1),
                )],
            ),
            Warns(&["TEXCOORD_0"]),
        ),
        case(
            C,
            textured(
                json!(png_data_uri()),
                vec![Set(
                    "/materials/0/pbrMetallicRoughness/baseColorTexture/extensions/KHR_texture_transform",
                    json!({"scale": [1e39, 1]}),
                )],
            ),
            Warns(&["KHR_texture_transform"]),
        ),
        case(
            C,
            textured(
                json!(png_data_uri()),
                vec![
                    Set("/samplers", json!([{"wrapS": 1234}])),
                    Set("/textures/0/sampler", json!(0)),
                ],
            ),
            Loads,
        ),
        case(
            C,
            vec![
                Set("/images", json!([{"bufferView": 9999}])),
                Set("/textures", json!([{"source": 0}])),
                Set(
                    "/materials/0/pbrMetallicRoughness/baseColorTexture",
                    json!({"index": 0}),
                ),
            ],
            Warns(&["image 0"]),
        ),
        case(
            C,
            vec![
                Set("/images", json!([{}])),
                Set("/textures", json!([{"source": 0}])),
                Set(
                    "/materials/0/pbrMetallicRoughness/baseColorTexture",
                    json!({"index": 0}),
                ),
            ],
            Warns(&["image 0"]),
        ),
    ]
}

/// The GLB container and the JSON text.
fn container() -> Vec<Case> {
    let mut deep = "[".repeat(100_000);
    deep.push_str(&"]".repeat(100_000));
    let deep: &'static str = Box::leak(deep.into_boxed_str());
    vec![
        case(C, vec![Header(0, 0x1234_5678)], Fails(&["glTF"])),
        case(C, vec![Header(4, 1)], Fails(&["version"])),
        case(C, vec![Header(8, 10)], Fails(&["length"])),
        case(
            C,
            vec![Header(8, 0xffff_fff0)],
            Fails(&["truncated .glb", "header declares 4294967280"]),
        ),
        case(C, vec![Header(12, 1_000_000_000)], Fails(&["JSON chunk"])),
        case(
            C,
            vec![Header(12, 3)],
            Fails(&[
                "chunk after the JSON chunk",
                "JSON chunk's length (3 bytes)",
            ]),
        ),
        case(
            C,
            vec![Header(16, u32::from_le_bytes(*b"XXXX"))],
            Fails(&["first chunk must be JSON", "'XXXX'"]),
        ),
        case(
            C,
            vec![Header(16, 7)],
            Fails(&["first chunk must be JSON", "0x00000007"]),
        ),
        case(
            C,
            vec![Truncate(10)],
            Fails(&["truncated .glb", "10 bytes"]),
        ),
        case(C, vec![Truncate(30)], Fails(&["truncated .glb", "has 30"])),
        case(
            C,
            vec![Truncate(5000)],
            Fails(&["truncated .glb", "has 5000"]),
        ),
        case(
            C,
            vec![Json("[]")],
            Fails(&[
                "not valid glTF",
                "top level must be a JSON object, not an array",
            ]),
        ),
        case(C, vec![Json("{}")], Fails(&["not valid glTF", "asset"])),
        case(
            C,
            vec![Json("null")],
            Fails(&[
                "not valid glTF",
                "top level must be a JSON object, not null",
            ]),
        ),
        case(
            C,
            vec![Json("not json at all")],
            Fails(&["not valid glTF", "JSON is malformed"]),
        ),
        case(
            C,
            vec![Json(deep)],
            Fails(&["not valid glTF", "recursion limit"]),
        ),
        case(
            C,
            vec![Json(r#"{"asset":{"version":"2.0","minVersion":"2.1"}}"#)],
            Fails(&["/asset/minVersion", "2.1"]),
        ),
        case(
            C,
            vec![Json(r#"{"asset":{"version":"2.0"},"materials":{}}"#)],
            Fails(&["/materials must be an array"]),
        ),
        case(
            C,
            vec![Json(r#"{"asset":{"version":"2.0"}}"#)],
            Fails(&["no triangles"]),
        ),
        case(
            C,
            vec![Json(r#"{"asset":{"version":"3.0"},"scenes":[]}"#)],
            Fails(&["/asset/version", "3.0"]),
        ),
        case(
            C,
            vec![Json("{\"asset\":{\"version\":\"2.0\"},\"x\":\"\u{fffd}\"}")],
            Fails(&["no triangles"]),
        ),
    ]
}

fn corpus() -> Vec<Case> {
    let mut all = dangling_indices();
    all.extend(materials());
    all.extend(nodes());
    all.extend(cameras());
    all.extend(extras());
    all.extend(data());
    all.extend(lights_extensions_images());
    all.extend(container());
    all
}

/// The outcome of one case, as text for the report: Ok(warnings) or Err(error chain).
fn outcome(bytes: &[u8]) -> Result<Vec<String>, String> {
    match std::panic::catch_unwind(|| load_slice(bytes, None, "corpus")) {
        Ok(Ok(s)) => match s.validate() {
            Ok(()) => Ok(s.warnings),
            Err(e) => Err(format!("loaded but does not validate: {e:#}")),
        },
        Ok(Err(e)) => Err(format!("{e:#}")),
        Err(_) => Err("PANIC".into()),
    }
}

fn check(c: &Case, got: &Result<Vec<String>, String>) -> Result<(), String> {
    let has = |text: &str, words: &[&str]| words.iter().all(|w| text.contains(w));
    match (&c.expect, got) {
        (_, Err(e)) if e == "PANIC" || e.starts_with("loaded but") => Err(e.clone()),
        (Fails(words), Err(e)) if has(e, words) => Ok(()),
        (Warns(words), Ok(w)) if w.iter().any(|w| has(w, words)) => Ok(()),
        (Loads, Ok(_)) => Ok(()),
        (_, got) => Err(format!("{got:?}")),
    }
}

#[test]
fn every_hostile_input_has_its_asserted_outcome() {
    let cases = corpus();
    assert!(cases.len() >= 100, "only {} cases", cases.len());
    let mut failures = Vec::new();
    for (i, c) in cases.iter().enumerate() {
        let got = outcome(&build(c));
        if std::env::var_os("REFRACT_CORPUS_SHOW").is_some() {
            eprintln!("case {i}: {:?}", got.as_ref().map(|w| w.join(" | ")));
        }
        if let Err(why) = check(c, &got) {
            let short: String = why.chars().take(300).collect();
            failures.push(format!("case {i} ({}): {short}", c.asset));
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} cases:\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n")
    );
}
