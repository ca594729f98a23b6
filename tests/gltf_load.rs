//! glTF loader, exporter and built-in scene tests (scene contract, docs/design.md).

use glam::{Mat3, Vec2, Vec3};
use refract::bsdf::MicrofacetDistribution;
use refract::gltf_io::export::export_glb;
use refract::gltf_io::load::load_slice;
use refract::scene::builtin::{self, NAMES};
use refract::scene::{Features, MaterialKind, Mesh, PunctualLight, Scene, Wrap};
use serde_json::{Value, json};
use std::collections::HashMap;

// ---------------------------------------------------------------- helpers

fn b64(data: &[u8]) -> String {
    const T: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::new();
    for c in data.chunks(3) {
        let n = (c[0] as u32) << 16
            | (*c.get(1).unwrap_or(&0) as u32) << 8
            | *c.get(2).unwrap_or(&0) as u32;
        for k in 0..4 {
            if k <= c.len() {
                s.push(T[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                s.push('=');
            }
        }
    }
    s
}

/// Builds the binary side of a hand-written glTF: accessors over one data: URI buffer.
#[derive(Default)]
struct Bin {
    bytes: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Bin {
    fn add(&mut self, raw: &[u8], count: usize, ty: &str, ctype: u32) -> usize {
        while !self.bytes.len().is_multiple_of(4) {
            self.bytes.push(0);
        }
        self.views
            .push(json!({"buffer": 0, "byteOffset": self.bytes.len(), "byteLength": raw.len()}));
        self.bytes.extend_from_slice(raw);
        self.accessors.push(json!({
            "bufferView": self.views.len() - 1, "componentType": ctype, "count": count, "type": ty
        }));
        self.accessors.len() - 1
    }
    fn vec3(&mut self, v: &[[f32; 3]]) -> usize {
        let f: Vec<f32> = v.iter().flatten().copied().collect();
        self.add(bytemuck::cast_slice(&f), v.len(), "VEC3", 5126)
    }
    fn vec2(&mut self, v: &[[f32; 2]]) -> usize {
        let f: Vec<f32> = v.iter().flatten().copied().collect();
        self.add(bytemuck::cast_slice(&f), v.len(), "VEC2", 5126)
    }
    fn idx(&mut self, v: &[u32]) -> usize {
        self.add(bytemuck::cast_slice(v), v.len(), "SCALAR", 5125)
    }
    fn raw_view(&mut self, raw: &[u8]) -> usize {
        while !self.bytes.len().is_multiple_of(4) {
            self.bytes.push(0);
        }
        self.views
            .push(json!({"buffer": 0, "byteOffset": self.bytes.len(), "byteLength": raw.len()}));
        self.bytes.extend_from_slice(raw);
        self.views.len() - 1
    }
    /// Insert buffers/bufferViews/accessors into `doc` and serialise it.
    fn finish(self, mut doc: Value) -> String {
        doc["asset"] = json!({"version": "2.0"});
        doc["buffers"] = json!([{
            "byteLength": self.bytes.len(),
            "uri": format!("data:application/octet-stream;base64,{}", b64(&self.bytes))
        }]);
        doc["bufferViews"] = json!(self.views);
        doc["accessors"] = json!(self.accessors);
        doc.to_string()
    }
}

const TRI: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];

/// A one-triangle mesh 0 (normal +Z) plus whatever `extra` adds (nodes, materials, …).
fn one_triangle(extra: Value) -> String {
    let mut b = Bin::default();
    let p = b.vec3(&TRI);
    let n = b.vec3(&[[0.0, 0.0, 1.0]; 3]);
    let i = b.idx(&[0, 1, 2]);
    let mut doc = json!({
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": p, "NORMAL": n}, "indices": i}]}]
    });
    merge(&mut doc, extra);
    b.finish(doc)
}

fn merge(doc: &mut Value, extra: Value) {
    if let (Some(d), Value::Object(e)) = (doc.as_object_mut(), extra) {
        for (k, v) in e {
            d.insert(k, v);
        }
    }
}

fn load(text: &str) -> anyhow::Result<Scene> {
    load_slice(text.as_bytes(), None, "test")
}

fn has_warning(s: &Scene, needle: &str) -> bool {
    s.warnings.iter().any(|w| w.contains(needle))
}

fn close(a: Vec3, b: Vec3, tol: f32) -> bool {
    (a - b).abs().max_element() <= tol
}

fn find_vertex(m: &Mesh, p: Vec3) -> Option<usize> {
    m.positions.iter().position(|q| close(*q, p, 1e-5))
}

fn geometric_normal(m: &Mesh, t: usize) -> Vec3 {
    let [a, b, c] = m.tri(t);
    (b - a).cross(c - a).normalize()
}

// ---------------------------------------------------------------- built-ins

#[test]
fn every_builtin_loads_and_validates() {
    for name in NAMES {
        let s = Scene::load(&format!("builtin:{name}")).unwrap();
        s.validate().unwrap();
        assert!(
            s.mesh.triangle_count() >= 12,
            "{name}: {} triangles",
            s.mesh.triangle_count()
        );
        assert_eq!(s.name, *name);
        assert!(s.has_light(), "{name} has no light");
        // Every shading normal is unit length and on the front side of its triangle.
        for t in 0..s.mesh.triangle_count() {
            let g = geometric_normal(&s.mesh, t);
            for v in s.mesh.indices[t] {
                let n = s.mesh.normals[v as usize];
                assert!((n.length() - 1.0).abs() < 1e-4, "{name}: normal {n}");
                assert!(
                    n.dot(g) > 0.0,
                    "{name}: triangle {t} shading normal {n} opposes {g}"
                );
            }
        }
    }
    assert!(
        Scene::load("builtin:nope")
            .unwrap_err()
            .to_string()
            .contains("cornell-glass")
    );
}

#[test]
fn builtin_contents_match_the_brief() {
    let c = Scene::load("builtin:cornell-glass").unwrap();
    let f = c.features();
    assert!(f.contains(
        Features::SMOOTH_GLASS | Features::MIRROR | Features::DIFFUSE | Features::AREA_LIGHTS
    ));
    let g = c
        .materials
        .iter()
        .find(|m| m.kind == MaterialKind::Glass)
        .unwrap();
    assert_eq!((g.ior, g.roughness), (1.5, 0.0));
    // The light faces down into the box.
    let lt = c.emissive_triangles();
    assert!(!lt.is_empty());
    for &t in &lt {
        assert!(geometric_normal(&c.mesh, t as usize).y < -0.999);
    }

    let r = Scene::load("builtin:rough-glass").unwrap();
    let g = r
        .materials
        .iter()
        .find(|m| m.kind == MaterialKind::Glass)
        .unwrap();
    assert_eq!(
        (g.roughness, g.distribution),
        (0.3, MicrofacetDistribution::Ggx)
    );
    assert!(r.features().contains(Features::ROUGH_GLASS));

    let p = Scene::load("builtin:prism").unwrap();
    assert!(p.features().contains(Features::DISPERSION));
    let g = p.materials.iter().find(|m| m.abbe.is_some()).unwrap();
    assert_eq!((g.ior, g.abbe), (1.5168, Some(20.0)));

    let fu = Scene::load("builtin:furnace").unwrap();
    assert_eq!(fu.environment, Vec3::ONE);
    assert!(fu.emissive_triangles().is_empty() && fu.punctual_lights.is_empty());

    let m = Scene::load("builtin:materials").unwrap();
    let rough: Vec<(MaterialKind, f32)> = m
        .materials
        .iter()
        .filter(|x| !x.is_emissive() && x.kind != MaterialKind::Diffuse)
        .map(|x| (x.kind, x.roughness))
        .collect();
    assert_eq!(
        rough,
        vec![
            (MaterialKind::Mirror, 0.0),
            (MaterialKind::GlossyMetal, 0.1),
            (MaterialKind::GlossyMetal, 0.3),
            (MaterialKind::GlossyMetal, 0.6),
            (MaterialKind::MetalRough, 0.05),
            (MaterialKind::MetalRough, 0.2),
            (MaterialKind::MetalRough, 0.45),
            (MaterialKind::MetalRough, 0.8),
        ]
    );
}

/// Every undirected edge is shared by exactly two triangles that traverse it in opposite
/// directions (closed, consistently oriented, no cracks). Edges keyed by vertex bit patterns.
fn assert_closed(m: &Mesh, what: &str) {
    let key = |v: u32| m.positions[v as usize].to_array().map(f32::to_bits);
    let mut edges: HashMap<([u32; 3], [u32; 3]), i32> = HashMap::new();
    for t in &m.indices {
        for k in 0..3 {
            let (a, b) = (key(t[k]), key(t[(k + 1) % 3]));
            *edges.entry((a, b)).or_default() += 1;
        }
    }
    for ((a, b), n) in &edges {
        assert_eq!(*n, 1, "{what}: directed edge used {n} times");
        assert_eq!(
            edges.get(&(*b, *a)),
            Some(&1),
            "{what}: open or flipped edge"
        );
    }
}

#[test]
fn helper_solids_are_watertight_and_outward() {
    let c = Vec3::new(0.3, -0.2, 1.0);
    let mut m = Mesh::default();
    builtin::sphere(&mut m, c, 0.7, 12, 24, 0);
    assert_closed(&m, "sphere");
    assert_eq!(
        m.positions.len(),
        2 + 11 * 24,
        "poles and seam share vertices"
    );
    assert_eq!(m.triangle_count(), 2 * 24 * 11);
    for t in 0..m.triangle_count() {
        let [a, b, cc] = m.tri(t);
        assert!(geometric_normal(&m, t).dot((a + b + cc) / 3.0 - c) > 0.0);
    }
    for (p, n) in m.positions.iter().zip(&m.normals) {
        assert!(((*p - c).length() - 0.7).abs() < 1e-5);
        assert!(close(*n, (*p - c) / 0.7, 1e-5));
    }

    let mut b = Mesh::default();
    builtin::oriented_box(
        &mut b,
        Vec3::new(1.0, 2.0, 3.0),
        Vec3::new(0.3, 0.5, 0.7),
        glam::Quat::from_rotation_y(0.3) * glam::Quat::from_rotation_x(0.4),
        0,
    );
    assert_closed(&b, "box");
    assert_eq!(b.triangle_count(), 12);
    let area: f32 = (0..12).map(|t| b.area(t)).sum();
    assert!((area - 8.0 * (0.3 * 0.5 + 0.5 * 0.7 + 0.3 * 0.7)).abs() < 1e-4);

    let mut p = Mesh::default();
    let tri = [
        Vec2::new(0.0, 0.0),
        Vec2::new(1.0, 0.0),
        Vec2::new(0.5, 0.8),
    ];
    builtin::triangular_prism(&mut p, tri, 0.0, 0.5, 0);
    assert_closed(&p, "prism");
    assert_eq!(p.triangle_count(), 8);
}

// ---------------------------------------------------------------- round trips

fn assert_same_scene(a: &Scene, b: &Scene) {
    let n = &a.name;
    assert_eq!(
        a.mesh.triangle_count(),
        b.mesh.triangle_count(),
        "{n}: triangles"
    );
    assert_eq!(a.materials.len(), b.materials.len(), "{n}: materials");
    for (x, y) in a.materials.iter().zip(&b.materials) {
        assert_eq!(x.name, y.name);
        assert_eq!(x.kind, y.kind, "{n}: {}", x.name);
        assert!(
            close(x.base_color, y.base_color, 1e-6),
            "{n}: {} colour",
            x.name
        );
        assert_eq!(x.ior, y.ior, "{n}: {} ior", x.name);
        assert_eq!(x.roughness, y.roughness, "{n}: {} roughness", x.name);
        assert_eq!(x.conductor, y.conductor, "{n}: {} conductor", x.name);
        assert!(
            close(
                x.emission,
                y.emission,
                1e-5 * x.emission.max_element().max(1.0)
            ),
            "{n}: {} emission {} vs {}",
            x.name,
            x.emission,
            y.emission
        );
        assert_eq!(
            x.abbe.map(|v| (v * 1e4).round()),
            y.abbe.map(|v| (v * 1e4).round())
        );
        assert_eq!(x.distribution, y.distribution);
        assert_eq!(x.double_sided, y.double_sided);
        assert_eq!(x.attenuation_distance, y.attenuation_distance);
        assert_eq!(x.priority, y.priority, "{n}: {} priority", x.name);
        // A film round-trips without its thickness texture (the exporter writes none).
        let film = |m: &refract::scene::Material| {
            m.iridescence
                .map(|i| (i.factor, i.ior, i.thickness_min, i.thickness_max))
        };
        assert_eq!(film(x), film(y), "{n}: {} film", x.name);
    }
    // Same area per material.
    let areas = |s: &Scene| {
        let mut v = vec![0f64; s.materials.len()];
        for t in 0..s.mesh.triangle_count() {
            v[s.mesh.tri_material[t] as usize] += s.mesh.area(t) as f64;
        }
        v
    };
    for (x, y) in areas(a).iter().zip(areas(b)) {
        assert!((x - y).abs() <= 1e-5 * x.max(1.0), "{n}: area {x} vs {y}");
    }
    let (ca, cb) = (&a.camera, &b.camera);
    assert!(
        close(ca.position, cb.position, 1e-5),
        "{n}: camera position"
    );
    for k in 0..3 {
        assert!(
            close(ca.rotation.col(k), cb.rotation.col(k), 1e-5),
            "{n}: camera rotation"
        );
    }
    assert!((ca.yfov - cb.yfov).abs() < 1e-5);
    assert_eq!(a.settings, b.settings, "{n}: settings");
    assert_eq!(a.environment, b.environment, "{n}: environment");
    assert_eq!(
        a.env_map
            .as_ref()
            .map(|e| (e.strength, e.rotation, e.map.width, e.map.height)),
        b.env_map
            .as_ref()
            .map(|e| (e.strength, e.rotation, e.map.width, e.map.height)),
        "{n}: environment image"
    );
    assert_eq!(a.punctual_lights.len(), b.punctual_lights.len());
}

#[test]
fn builtins_round_trip_through_glb() {
    for name in NAMES {
        let a = Scene::load(&format!("builtin:{name}")).unwrap();
        let glb = export_glb(&a).unwrap();
        // An environment image is referenced as `<name>.hdr` next to the file: the shipped
        // HDRIs in assets/.
        let assets = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets");
        let base = a.env_map.as_ref().map(|_| assets.as_path());
        let b = load_slice(&glb, base, name).unwrap();
        assert_same_scene(&a, &b);
        assert!(
            !b.warnings
                .iter()
                .any(|w| w.contains("unsupported") || w.contains("dropped")),
            "{name}: {:?}",
            b.warnings
        );
    }
}

#[test]
fn committed_assets_match_the_code() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets");
    for name in NAMES {
        let path = dir.join(format!("{name}.glb"));
        let b = Scene::load(path.to_str().unwrap()).unwrap();
        let a = Scene::load(&format!("builtin:{name}")).unwrap();
        assert_same_scene(&a, &b);
    }
}

#[test]
fn lights_and_specular_round_trip() {
    let mut s = Scene::load("builtin:cornell-glass").unwrap();
    s.punctual_lights = vec![
        PunctualLight::Point {
            position: Vec3::new(0.1, 1.5, 0.2),
            intensity: Vec3::new(3.0, 2.0, 1.0),
        },
        PunctualLight::Spot {
            position: Vec3::new(0.0, 1.9, 0.0),
            direction: Vec3::new(0.3, -1.0, 0.1).normalize(),
            intensity: Vec3::splat(5.0),
            cos_inner: 0.9,
            cos_outer: 0.8,
        },
        PunctualLight::Directional {
            direction: Vec3::new(0.0, -1.0, -1.0).normalize(),
            irradiance: Vec3::splat(2.0),
        },
    ];
    s.materials[0].kind = MaterialKind::MetalRough;
    s.materials[0].roughness = 0.4;
    s.materials[0].specular_factor = 0.5;
    s.materials[0].specular_color = Vec3::new(1.0, 0.5, 0.25);
    let b = load_slice(&export_glb(&s).unwrap(), None, "x").unwrap();
    assert_eq!(b.materials[0].specular_factor, 0.5);
    assert_eq!(b.materials[0].specular_color, Vec3::new(1.0, 0.5, 0.25));
    for (x, y) in s.punctual_lights.iter().zip(&b.punctual_lights) {
        match (x, y) {
            (
                PunctualLight::Point {
                    position: p,
                    intensity: i,
                },
                PunctualLight::Point {
                    position: q,
                    intensity: j,
                },
            ) => {
                assert!(close(*p, *q, 1e-6) && close(*i, *j, 1e-5))
            }
            (
                PunctualLight::Spot {
                    direction: d,
                    cos_inner: ci,
                    cos_outer: co,
                    ..
                },
                PunctualLight::Spot {
                    direction: e,
                    cos_inner: di,
                    cos_outer: dout,
                    ..
                },
            ) => assert!(close(*d, *e, 1e-5) && (ci - di).abs() < 1e-5 && (co - dout).abs() < 1e-5),
            (
                PunctualLight::Directional {
                    direction: d,
                    irradiance: i,
                },
                PunctualLight::Directional {
                    direction: e,
                    irradiance: j,
                },
            ) => {
                assert!(close(*d, *e, 1e-5) && close(*i, *j, 1e-5))
            }
            _ => panic!("light kinds differ: {x:?} vs {y:?}"),
        }
    }
}

// ---------------------------------------------------------------- transforms

#[test]
fn trs_hierarchy_transforms_vertices() {
    // parent: T(1,2,3) · R_y(90°) · S(2); child: T(1,0,0). Vertex (1,0,0) → (1, 2, −1).
    let h = std::f32::consts::FRAC_1_SQRT_2;
    let s = load(&one_triangle(json!({
        "scenes": [{"nodes": [0]}],
        "nodes": [
            {"children": [1], "translation": [1, 2, 3], "rotation": [0, h, 0, h], "scale": [2, 2, 2]},
            {"mesh": 0, "translation": [1, 0, 0]}
        ]
    })))
    .unwrap();
    assert!(
        find_vertex(&s.mesh, Vec3::new(1.0, 2.0, -1.0)).is_some(),
        "{:?}",
        s.mesh.positions
    );
    assert!(find_vertex(&s.mesh, Vec3::new(1.0, 2.0, 1.0)).is_some()); // origin → (1,2,3)−(0,0,2)
    // Normal +Z rotated by 90° about Y → +X; winding agrees.
    assert!(close(s.mesh.normals[0], Vec3::X, 1e-6));
    assert!(close(geometric_normal(&s.mesh, 0), Vec3::X, 1e-6));
}

#[test]
fn matrix_node_is_column_major() {
    // Translation (5,0,0), scale y by 2 → vertex (0,1,0) lands at (5,2,0).
    let s = load(&one_triangle(json!({
        "nodes": [{"mesh": 0, "matrix": [1,0,0,0, 0,2,0,0, 0,0,1,0, 5,0,0,1]}]
    })))
    .unwrap();
    assert!(
        find_vertex(&s.mesh, Vec3::new(5.0, 2.0, 0.0)).is_some(),
        "{:?}",
        s.mesh.positions
    );
    assert!(find_vertex(&s.mesh, Vec3::new(6.0, 0.0, 0.0)).is_some());
}

#[test]
fn non_uniform_scale_uses_inverse_transpose_for_normals() {
    // Triangle in the plane x + z = 1 (normal (1,0,1)/√2), scaled x by 2: the plane becomes
    // x/2 + z = 1 with normal ∝ (1/2, 0, 1).
    let mut b = Bin::default();
    let p = b.vec3(&[[1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
    let nn = std::f32::consts::FRAC_1_SQRT_2;
    let n = b.vec3(&[[nn, 0.0, nn]; 3]);
    let doc = json!({
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "scale": [2, 1, 1]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": p, "NORMAL": n}}]}]
    });
    let s = load(&b.finish(doc)).unwrap();
    let want = Vec3::new(0.5, 0.0, 1.0).normalize();
    assert!(
        close(s.mesh.normals[0], want, 1e-6),
        "{}",
        s.mesh.normals[0]
    );
    assert!(close(geometric_normal(&s.mesh, 0), want, 1e-6));
}

#[test]
fn mirrored_node_keeps_ccw_front_and_outward_normals() {
    // A closed tetrahedron with outward normals, mirrored by scale (−1, 1, 1).
    let v = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    let faces = [[0u32, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
    let mut pos = vec![];
    let mut nrm = vec![];
    for f in faces {
        let [a, b, c] = f.map(|i| Vec3::from(v[i as usize]));
        let n = (b - a).cross(c - a).normalize();
        for p in [a, b, c] {
            pos.push(p.to_array());
            nrm.push(n.to_array());
        }
    }
    let mut b = Bin::default();
    let p = b.vec3(&pos);
    let n = b.vec3(&nrm);
    let doc = json!({
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "scale": [-1, 1, 1], "translation": [3, 0, 0]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": p, "NORMAL": n}}]}]
    });
    let s = load(&b.finish(doc)).unwrap();
    assert_eq!(s.mesh.triangle_count(), 4);
    let centroid = Vec3::new(3.0 - 0.25, 0.25, 0.25);
    for t in 0..4 {
        let [a, bb, c] = s.mesh.tri(t);
        let g = geometric_normal(&s.mesh, t);
        assert!(
            g.dot((a + bb + c) / 3.0 - centroid) > 0.0,
            "triangle {t} faces inward"
        );
        for vi in s.mesh.indices[t] {
            assert!(
                close(s.mesh.normals[vi as usize], g, 1e-5),
                "shading normal disagrees"
            );
        }
    }
}

// ---------------------------------------------------------------- camera

#[test]
fn camera_yfov_and_minus_z() {
    let h = std::f32::consts::FRAC_1_SQRT_2;
    let s = load(&one_triangle(json!({
        "scenes": [{"nodes": [0, 1, 3]}],
        "nodes": [
            {"children": [2]},
            {"mesh": 0},
            {"camera": 1, "translation": [0, 1, 5], "rotation": [0, h, 0, h]},
            {"camera": 0}
        ],
        "cameras": [
            {"type": "perspective", "perspective": {"yfov": 0.9, "znear": 0.1}},
            {"type": "perspective", "perspective": {"yfov": 0.5, "znear": 0.1}}
        ]
    })))
    .unwrap();
    // Pre-order traversal reaches node 2 (camera 1) before node 3 (camera 0).
    assert_eq!(s.camera.yfov, 0.5);
    assert!(close(s.camera.position, Vec3::new(0.0, 1.0, 5.0), 1e-6));
    // −Z rotated by +90° about Y is −X.
    assert!(
        close(s.camera.forward(), Vec3::NEG_X, 1e-6),
        "{}",
        s.camera.forward()
    );
    assert!(close(s.camera.rotation.col(1), Vec3::Y, 1e-6));
    // The centre pixel looks along forward.
    assert!(close(s.camera.ray_dir(0.5, 0.5, 1.0), Vec3::NEG_X, 1e-6));
}

#[test]
fn no_camera_frames_the_bounds() {
    let s = load(&one_triangle(
        json!({"nodes": [{"mesh": 0, "translation": [10, 0, -3]}]}),
    ))
    .unwrap();
    let (lo, hi) = s.bounds();
    let cam = &s.camera;
    let inv: Mat3 = cam.rotation.transpose();
    let tan_half = (0.5 * cam.yfov).tan();
    for k in 0..8 {
        let p = Vec3::new(
            if k & 1 == 0 { lo.x } else { hi.x },
            if k & 2 == 0 { lo.y } else { hi.y },
            if k & 4 == 0 { lo.z } else { hi.z },
        );
        let q = inv * (p - cam.position);
        assert!(q.z < 0.0, "corner behind the default camera");
        assert!((q.y / -q.z).abs() < tan_half && (q.x / -q.z).abs() < tan_half);
    }
}

#[test]
fn bad_camera_is_a_clear_error() {
    let e = load(&one_triangle(json!({
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0}, {"camera": 0}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.0, "znear": 0.1}}]
    })))
    .unwrap_err();
    assert!(format!("{e:#}").contains("yfov"), "{e:#}");
}

// ---------------------------------------------------------------- geometry details

#[test]
fn missing_normals_give_flat_normals() {
    let mut b = Bin::default();
    // Two triangles sharing an edge, folded: flat normals must not be averaged.
    let p = b.vec3(&[
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, -1.0],
    ]);
    let i = b.idx(&[0, 1, 2, 0, 1, 3]);
    let doc = json!({
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": p}, "indices": i}]}]
    });
    let s = load(&b.finish(doc)).unwrap();
    assert_eq!(s.mesh.triangle_count(), 2);
    for t in 0..2 {
        let g = geometric_normal(&s.mesh, t);
        for v in s.mesh.indices[t] {
            assert_eq!(s.mesh.normals[v as usize], g);
        }
    }
    assert!(close(geometric_normal(&s.mesh, 0), Vec3::Z, 1e-6));
    assert!(close(geometric_normal(&s.mesh, 1), Vec3::Y, 1e-6));
}

#[test]
fn broken_normals_fall_back_to_geometric() {
    let mut b = Bin::default();
    let p = b.vec3(&TRI);
    let n = b.vec3(&[[0.0, 0.0, 2.0], [0.0, 0.0, 0.0], [f32::NAN, 0.0, 1.0]]);
    let doc = json!({
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": p, "NORMAL": n}}]}]
    });
    let s = load(&b.finish(doc)).unwrap();
    for v in s.mesh.indices[0] {
        assert_eq!(
            s.mesh.normals[v as usize],
            Vec3::Z,
            "renormalised / replaced"
        );
    }
    assert!(has_warning(&s, "2 vertex normals"), "{:?}", s.warnings);
}

#[test]
fn texcoords_are_loaded() {
    let mut b = Bin::default();
    let p = b.vec3(&TRI);
    let t = b.vec2(&[[0.0, 0.0], [1.0, 0.0], [0.25, 0.75]]);
    let doc = json!({
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": p, "TEXCOORD_0": t}}]}]
    });
    let s = load(&b.finish(doc)).unwrap();
    let v = find_vertex(&s.mesh, Vec3::new(0.0, 1.0, 0.0)).unwrap();
    assert_eq!(s.mesh.uvs[v], Vec2::new(0.25, 0.75));
}

#[test]
fn non_triangle_modes_are_skipped_with_a_warning() {
    let mut b = Bin::default();
    let p = b.vec3(&TRI);
    let doc = json!({
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [
            {"attributes": {"POSITION": p}, "mode": 1},
            {"attributes": {"POSITION": p}}
        ]}]
    });
    let s = load(&b.finish(doc)).unwrap();
    assert_eq!(s.mesh.triangle_count(), 1);
    assert!(has_warning(&s, "Lines"), "{:?}", s.warnings);
}

// ---------------------------------------------------------------- materials

#[test]
fn material_classification_follows_the_contract() {
    let pbr = |m: f32, r: f32| json!({"baseColorFactor": [0.5, 0.25, 0.125, 1.0], "metallicFactor": m, "roughnessFactor": r});
    let s = load(&one_triangle(json!({
        "extensionsUsed": ["KHR_materials_transmission", "KHR_materials_volume", "KHR_materials_ior",
                           "KHR_materials_dispersion", "KHR_materials_emissive_strength", "KHR_materials_specular"],
        "extensionsRequired": ["KHR_materials_volume", "KHR_materials_dispersion"],
        "materials": [
            {"name": "diffuse", "pbrMetallicRoughness": pbr(0.0, 1.0)},
            {"name": "mirror", "pbrMetallicRoughness": pbr(1.0, 0.0)},
            {"name": "glossy", "pbrMetallicRoughness": pbr(1.0, 0.4)},
            {"name": "glass", "pbrMetallicRoughness": pbr(0.0, 0.0), "extensions": {
                "KHR_materials_transmission": {"transmissionFactor": 1.0},
                "KHR_materials_volume": {"thicknessFactor": 0.5, "attenuationColor": [0.5, 0.8, 1.0], "attenuationDistance": 2.0}}},
            {"name": "thin", "pbrMetallicRoughness": pbr(0.0, 0.0), "extensions": {
                "KHR_materials_transmission": {"transmissionFactor": 1.0}}},
            {"name": "thin0", "extensions": {
                "KHR_materials_transmission": {"transmissionFactor": 1.0},
                "KHR_materials_volume": {"thicknessFactor": 0.0}}},
            {"name": "plastic", "pbrMetallicRoughness": pbr(0.5, 0.5), "extensions": {
                "KHR_materials_specular": {"specularFactor": 0.5, "specularColorFactor": [1.0, 0.5, 0.5]}}},
            {"name": "partial", "pbrMetallicRoughness": pbr(0.0, 1.0), "extensions": {
                "KHR_materials_transmission": {"transmissionFactor": 0.2}}},
            {"name": "rough-beckmann", "pbrMetallicRoughness": pbr(0.0, 0.3), "extras": {"microfacet_distribution": "beckmann"},
             "extensions": {
                "KHR_materials_transmission": {"transmissionFactor": 1.0},
                "KHR_materials_ior": {"ior": 1.33},
                "KHR_materials_volume": {"thicknessFactor": 1.0},
                "KHR_materials_dispersion": {"dispersion": 0.5}}},
            {"name": "no-dispersion", "extensions": {
                "KHR_materials_transmission": {"transmissionFactor": 1.0},
                "KHR_materials_volume": {"thicknessFactor": 1.0},
                "KHR_materials_dispersion": {"dispersion": 0.0}}},
            {"name": "emitter", "doubleSided": true, "emissiveFactor": [1.0, 0.5, 0.25], "pbrMetallicRoughness": pbr(0.0, 1.0),
             "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4.0}}},
            {"name": "emit-plain", "emissiveFactor": [0.5, 0.5, 0.5]}
        ]
    })))
    .unwrap();
    let m = |name: &str| s.materials.iter().find(|x| x.name == name).unwrap();
    use MaterialKind::*;
    assert_eq!(m("diffuse").kind, Diffuse);
    assert_eq!(m("diffuse").base_color, Vec3::new(0.5, 0.25, 0.125));
    assert_eq!(m("mirror").kind, Mirror);
    assert_eq!(m("glossy").kind, GlossyMetal);
    assert_eq!(m("glossy").roughness, 0.4);
    let g = m("glass");
    assert_eq!(
        (g.kind, g.ior, g.roughness, g.abbe),
        (Glass, 1.5, 0.0, None)
    );
    assert_eq!(
        (g.attenuation_color, g.attenuation_distance),
        (Vec3::new(0.5, 0.8, 1.0), 2.0)
    );
    assert!((g.sigma_a().x - 2f32.ln() / 2.0).abs() < 1e-6);
    assert_eq!(m("thin").kind, ThinGlass);
    assert_eq!(m("thin0").kind, ThinGlass);
    assert!(has_warning(&s, "thin-walled"));
    assert_eq!(
        s.warnings
            .iter()
            .filter(|w| w.contains("thin-walled"))
            .count(),
        1,
        "warned once"
    );
    let p = m("plastic");
    assert_eq!((p.kind, p.metallic, p.roughness), (MetalRough, 0.5, 0.5));
    assert_eq!(
        (p.specular_factor, p.specular_color),
        (0.5, Vec3::new(1.0, 0.5, 0.5))
    );
    assert_eq!(m("partial").kind, MetalRough);
    assert!(has_warning(&s, "partial transmission"));
    let r = m("rough-beckmann");
    assert_eq!((r.kind, r.ior, r.roughness), (Glass, 1.33, 0.3));
    assert_eq!(r.distribution, MicrofacetDistribution::Beckmann);
    assert_eq!(r.abbe, Some(40.0)); // V_d = 20 / dispersion
    assert_eq!(m("no-dispersion").abbe, None);
    let e = m("emitter");
    assert_eq!(e.emission, Vec3::new(4.0, 2.0, 1.0));
    assert!(e.double_sided && e.base_color == Vec3::ZERO && e.kind == Diffuse);
    assert_eq!(m("emit-plain").emission, Vec3::splat(0.5));
    assert!(!has_warning(&s, "unsupported"), "{:?}", s.warnings);
    // The triangle has no material: the glTF default (metallic 1, roughness 1) is appended.
    let d = &s.materials[s.mesh.tri_material[0] as usize];
    assert_eq!(
        (d.kind, d.base_color, d.roughness),
        (GlossyMetal, Vec3::ONE, 1.0)
    );
}

fn png_bytes(px: &[[u8; 4]], w: u32, h: u32) -> Vec<u8> {
    let img = image::RgbaImage::from_raw(w, h, px.iter().flatten().copied().collect()).unwrap();
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).unwrap();
    out.into_inner()
}

#[test]
fn textures_samplers_and_texture_transform() {
    let mut b = Bin::default();
    let p = b.vec3(&TRI);
    let png = png_bytes(&[[128, 255, 0, 255], [0, 0, 255, 255]], 2, 1);
    let good = b.raw_view(&png);
    let corrupt = b.raw_view(&png[..png.len() / 2]);
    let doc = json!({
        "extensionsUsed": ["KHR_texture_transform"],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": p}, "material": 0}]}],
        "images": [{"bufferView": good, "mimeType": "image/png"}, {"bufferView": corrupt, "mimeType": "image/png"}],
        "samplers": [{"magFilter": 9728, "wrapS": 33071, "wrapT": 33648}],
        "textures": [{"source": 0, "sampler": 0}, {"source": 1}],
        "materials": [
            {"name": "tex", "pbrMetallicRoughness": {
                "baseColorTexture": {"index": 0, "extensions": {"KHR_texture_transform": {
                    "offset": [0.5, 0.0], "rotation": std::f32::consts::FRAC_PI_2, "scale": [2.0, 3.0]}}},
                "metallicRoughnessTexture": {"index": 0},
                "metallicFactor": 0.0, "roughnessFactor": 1.0}},
            {"name": "broken", "pbrMetallicRoughness": {"baseColorTexture": {"index": 1}}}
        ]
    });
    let s = load(&b.finish(doc)).unwrap();
    let m = &s.materials[0];
    // A metallic-roughness texture makes it MetalRough even with factors 0 / 1.
    assert_eq!(m.kind, MaterialKind::MetalRough);
    let bt = m.base_color_texture.unwrap();
    let mt = m.metallic_roughness_texture.unwrap();
    assert_ne!(
        bt.texture, mt.texture,
        "sRGB and linear decodes are separate textures"
    );
    let t = &s.textures[bt.texture as usize];
    assert_eq!((t.width, t.height, t.linear), (2, 1, false));
    assert_eq!(
        (t.wrap_s, t.wrap_t),
        (Wrap::ClampToEdge, Wrap::MirroredRepeat)
    );
    // sRGB 128/255 → linear 0.2158605; alpha and the linear texture are not converted.
    assert!(
        (t.texels[0].x - 0.215_860_5).abs() < 1e-5,
        "{}",
        t.texels[0]
    );
    assert_eq!(t.texels[0].y, 1.0);
    assert!((s.textures[mt.texture as usize].texels[0].x - 128.0 / 255.0).abs() < 1e-6);
    // uv' = T · R · S · uv: (1, 0) → S (2, 0) → R(π/2) (0, −2) → T (0.5, −2).
    let q = bt.transform.transform_point2(Vec2::new(1.0, 0.0));
    assert!((q - Vec2::new(0.5, -2.0)).abs().max_element() < 1e-6, "{q}");
    // The corrupt image is a warning and no texture.
    assert!(s.materials[1].base_color_texture.is_none());
    assert!(
        has_warning(&s, "texture 1 cannot be used"),
        "{:?}",
        s.warnings
    );
}

// ---------------------------------------------------------------- extras and lights

#[test]
fn extras_render_and_environment() {
    let s = load(&one_triangle(json!({
        "scenes": [{"nodes": [0], "extras": {
            "render": {"width": 320, "height": 200, "max_depth": 8, "rr_depth": 3, "spp": 1024},
            "environment": [0.5, 1.0, 2.0]}}]
    })))
    .unwrap();
    let st = s.settings;
    assert_eq!(
        (st.width, st.height, st.max_depth, st.rr_depth, st.spp),
        (320, 200, 8, 3, 1024)
    );
    assert_eq!(s.environment, Vec3::new(0.5, 1.0, 2.0));

    // Partial settings keep the defaults; a missing environment is black, and a file with no
    // light at all is lit by the built-in studio environment, with a warning.
    let s = load(&one_triangle(
        json!({"scenes": [{"nodes": [0], "extras": {"render": {"spp": 4}}}]}),
    ))
    .unwrap();
    assert_eq!(
        (s.settings.spp, s.settings.width, s.settings.rr_depth),
        (4, 512, 5)
    );
    assert_eq!(s.environment, Vec3::ZERO);
    assert_eq!(
        s.env_map.as_ref().map(|e| e.map.name.as_str()),
        Some("builtin studio")
    );
    assert!(
        s.warnings
            .iter()
            .any(|w| w.contains("no light") && w.contains("studio")),
        "{:?}",
        s.warnings
    );

    let e = load(&one_triangle(
        json!({"scenes": [{"nodes": [0], "extras": {"render": {"width": "big"}}}]}),
    ))
    .unwrap_err();
    assert!(format!("{e:#}").contains("extras.render.width"), "{e:#}");
    let e = load(&one_triangle(
        json!({"scenes": [{"nodes": [0], "extras": {"environment": [1, -1, 0]}}]}),
    ))
    .unwrap_err();
    assert!(format!("{e:#}").contains("extras.environment"), "{e:#}");
    let e = load(&one_triangle(
        json!({"scenes": [{"nodes": [0], "extras": {"render": {"width": 0}}}]}),
    ))
    .unwrap_err();
    // Named by its key, not as the image size it would have become.
    assert!(
        format!("{e:#}").contains("extras.render.width is 0"),
        "{e:#}"
    );
    let s = load(&one_triangle(
        json!({"scenes": [{"nodes": [0], "extras": {"render": {"light_line_nm": 589.3}}}]}),
    ))
    .unwrap();
    assert_eq!(s.settings.light_line_nm, Some(589.3));
    for bad in [json!(0), json!(-1), json!(900), json!("sodium")] {
        let e = load(&one_triangle(
            json!({"scenes": [{"nodes": [0], "extras": {"render": {"light_line_nm": bad}}}]}),
        ))
        .unwrap_err();
        assert!(
            format!("{e:#}").contains("extras.render.light_line_nm"),
            "{e:#}"
        );
    }
}

#[test]
fn punctual_lights() {
    let h = std::f32::consts::FRAC_1_SQRT_2;
    let s = load(&one_triangle(json!({
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensionsRequired": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "point", "color": [1.0, 0.5, 0.25], "intensity": 8.0, "range": 10.0},
            {"type": "spot", "intensity": 3.0, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.5}},
            {"type": "directional", "color": [0.5, 0.5, 0.5], "intensity": 2.0}
        ]}},
        "scenes": [{"nodes": [0, 1, 2, 3]}],
        "nodes": [
            {"mesh": 0},
            {"translation": [1, 2, 3], "extensions": {"KHR_lights_punctual": {"light": 0}}},
            {"translation": [0, 4, 0], "rotation": [-h, 0, 0, h], "extensions": {"KHR_lights_punctual": {"light": 1}}},
            {"rotation": [0, h, 0, h], "extensions": {"KHR_lights_punctual": {"light": 2}}}
        ]
    })))
    .unwrap();
    assert_eq!(s.punctual_lights.len(), 3);
    assert_eq!(
        s.punctual_lights[0],
        PunctualLight::Point {
            position: Vec3::new(1.0, 2.0, 3.0),
            intensity: Vec3::new(8.0, 4.0, 2.0)
        }
    );
    match s.punctual_lights[1] {
        PunctualLight::Spot {
            position,
            direction,
            intensity,
            cos_inner,
            cos_outer,
        } => {
            assert_eq!(position, Vec3::new(0.0, 4.0, 0.0));
            // Rotation −90° about X turns −Z into −Y: the spot points down.
            assert!(close(direction, Vec3::NEG_Y, 1e-6), "{direction}");
            assert_eq!(intensity, Vec3::splat(3.0));
            assert!(
                (cos_inner - 0.2f32.cos()).abs() < 1e-7 && (cos_outer - 0.5f32.cos()).abs() < 1e-7
            );
        }
        l => panic!("expected a spot, got {l:?}"),
    }
    match s.punctual_lights[2] {
        PunctualLight::Directional {
            direction,
            irradiance,
        } => {
            assert!(close(direction, Vec3::NEG_X, 1e-6), "{direction}");
            assert_eq!(irradiance, Vec3::splat(1.0));
        }
        l => panic!("expected a directional light, got {l:?}"),
    }
    assert!(has_warning(&s, "range"));
    assert!(!has_warning(&s, "unsupported"));
}

// ---------------------------------------------------------------- malformed input

fn err_of(bytes: &[u8]) -> String {
    match load_slice(bytes, None, "bad") {
        Ok(s) => panic!("loaded a malformed file: {:?}", s.warnings),
        Err(e) => format!("{e:#}"),
    }
}

#[test]
fn malformed_containers_are_errors() {
    assert!(err_of(b"").contains("empty"));
    assert!(err_of(b"\x00\x01garbage\xff\xfe").contains("not valid glTF"));
    assert!(
        err_of(b"{\"asset\": {\"version\": \"2.0\"}, \"nodes\": \"abc\"}")
            .contains("not valid glTF")
    );
    assert!(err_of(b"glTF\x02\x00").contains("truncated"));
    let glb = export_glb(&Scene::load("builtin:furnace").unwrap()).unwrap();
    assert!(err_of(&glb[..glb.len() / 2]).contains("truncated"));
    assert!(err_of(&glb[..30]).contains("truncated"));
    let mut v1 = glb.clone();
    v1[4] = 1;
    assert!(err_of(&v1).contains("version"));
    // A .gltf whose buffer is an external file, loaded without a base directory.
    let e =
        err_of(br#"{"asset":{"version":"2.0"},"buffers":[{"byteLength":12,"uri":"missing.bin"}]}"#);
    assert!(e.contains("buffers"), "{e}");
    let e =
        err_of(br#"{"asset":{"version":"2.0"},"buffers":[{"byteLength":12,"uri":"%FF%FE.bin"}]}"#);
    assert!(e.contains("URI"), "{e}");
    // A buffer shorter than it claims.
    let e = err_of(br#"{"asset":{"version":"2.0"},"buffers":[{"byteLength":100,"uri":"data:application/octet-stream;base64,AAAA"}]}"#);
    assert!(e.contains("buffers"), "{e}");
}

/// A one-primitive file with a custom index/position setup.
fn tri_file(pos: &[[f32; 3]], idx: &[u32]) -> String {
    let mut b = Bin::default();
    let p = b.vec3(pos);
    let i = b.idx(idx);
    b.finish(json!({
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": p}, "indices": i}]}]
    }))
}

#[test]
fn bad_geometry_is_an_error_or_a_warning() {
    // Out-of-range index in the only primitive: nothing usable → error naming the problem.
    let e = load(&tri_file(&TRI, &[0, 1, 99])).unwrap_err();
    assert!(format!("{e:#}").contains("out of range"), "{e:#}");

    // NaN position and zero-area triangles are dropped with a counted warning.
    let s = load(&tri_file(
        &[
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [f32::NAN, 0.0, 0.0],
            [2.0, 0.0, 0.0],
        ],
        &[0, 1, 2, 0, 1, 3, 0, 1, 4, 1, 1, 2],
    ))
    .unwrap();
    assert_eq!(s.mesh.triangle_count(), 1);
    assert_eq!(
        s.mesh.positions.len(),
        3,
        "unused and NaN vertices are not kept"
    );
    assert!(
        has_warning(&s, "dropped 3 zero-area or non-finite"),
        "{:?}",
        s.warnings
    );
    s.validate().unwrap();

    // A bad primitive next to a good one: the good one loads, the bad one is a warning.
    let mut b = Bin::default();
    let p = b.vec3(&TRI);
    let bad = b.idx(&[0, 1, 7]);
    let doc = json!({
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [
            {"attributes": {"POSITION": p}, "indices": bad},
            {"attributes": {"POSITION": p}},
            {"attributes": {"POSITION": 42}},
            {"attributes": {"NORMAL": p}},
            {"attributes": {"POSITION": p}, "material": 9}
        ]}]
    });
    let s = load(&b.finish(doc)).unwrap();
    assert_eq!(s.mesh.triangle_count(), 1);
    assert!(
        has_warning(&s, "vertex index 7 out of range"),
        "{:?}",
        s.warnings
    );
    assert!(has_warning(&s, "accessor 42 does not exist"));
    assert!(has_warning(&s, "no POSITION"));
    assert!(has_warning(&s, "material 9 does not exist"));
}

#[test]
fn bad_accessors_and_views() {
    let base = || -> (Bin, Value) {
        let mut b = Bin::default();
        let p = b.vec3(&TRI);
        let doc = json!({"nodes": [{"mesh": 0}], "meshes": [{"primitives": [{"attributes": {"POSITION": p}}]}]});
        (b, doc)
    };
    // Accessor reading past its view.
    let (mut b, doc) = base();
    b.accessors[0]["count"] = json!(1000);
    let e = load(&b.finish(doc)).unwrap_err();
    assert!(format!("{e:#}").contains("out of bounds"), "{e:#}");
    // Huge count.
    let (mut b, doc) = base();
    b.accessors[0]["count"] = json!(4_000_000_000u64);
    let e = load(&b.finish(doc)).unwrap_err();
    assert!(format!("{e:#}").contains("too large"), "{e:#}");
    // View pointing to a missing buffer.
    let (mut b, doc) = base();
    b.views[0]["buffer"] = json!(5);
    let e = load(&b.finish(doc)).unwrap_err();
    assert!(format!("{e:#}").contains("missing buffer"), "{e:#}");
    // View past the end of its buffer.
    let (mut b, doc) = base();
    b.views[0]["byteOffset"] = json!(1u64 << 40);
    let e = load(&b.finish(doc)).unwrap_err();
    assert!(format!("{e:#}").contains("exceeds buffer"), "{e:#}");
    // Stride smaller than the element.
    let (mut b, doc) = base();
    b.views[0]["byteStride"] = json!(4);
    let e = load(&b.finish(doc)).unwrap_err();
    assert!(format!("{e:#}").contains("stride"), "{e:#}");
    // Wrong accessor type for POSITION.
    let (mut b, doc) = base();
    b.accessors[0]["type"] = json!("VEC2");
    b.accessors[0]["count"] = json!(4);
    let e = load(&b.finish(doc)).unwrap_err();
    assert!(format!("{e:#}").contains("components"), "{e:#}");
}

#[test]
fn unknown_extensions_and_odd_hierarchies_still_load() {
    let s = load(&one_triangle(json!({
        "extensionsUsed": ["EXT_fancy", "KHR_materials_clearcoat"],
        "scenes": [{"nodes": [0, 7]}],
        "nodes": [{"mesh": 0, "children": [1]}, {"children": [0]}],
        "materials": [{"extensions": {"KHR_materials_sheen": {}}}]
    })))
    .unwrap();
    assert_eq!(s.mesh.triangle_count(), 1);
    assert!(has_warning(&s, "EXT_fancy"), "{:?}", s.warnings);
    assert!(has_warning(&s, "KHR_materials_clearcoat"));
    assert!(has_warning(&s, "KHR_materials_sheen"));
    assert!(
        has_warning(&s, "reached twice"),
        "cycle detected: {:?}",
        s.warnings
    );
    assert!(has_warning(&s, "node 7 does not exist"));
    assert_eq!(
        s.warnings
            .iter()
            .filter(|w| w.contains("EXT_fancy"))
            .count(),
        1
    );
}

/// glTF 2.0 §3.12: an asset whose `extensionsRequired` names an extension the loader does not
/// support must not load; a supported one listed as required loads.
#[test]
fn unknown_required_extensions_are_refused() {
    let gltf = one_triangle(json!({
        "extensionsUsed": ["KHR_materials_ior", "EXT_fancy"],
        "extensionsRequired": ["KHR_materials_ior", "EXT_fancy"]
    }));
    let e = format!("{:#}", load_slice(gltf.as_bytes(), None, "t").unwrap_err());
    assert!(
        e.contains("/extensionsRequired/1") && e.contains("EXT_fancy"),
        "{e}"
    );
    let ok = one_triangle(json!({
        "extensionsUsed": ["KHR_materials_volume"],
        "extensionsRequired": ["KHR_materials_volume"]
    }));
    load(&ok).unwrap();
}

/// Deterministic mutation fuzzing: flipped bytes and truncations of a valid .glb and .gltf
/// must give Ok or Err, never a panic; every Ok scene validates.
#[test]
fn mutated_files_never_panic() {
    let glb = export_glb(&Scene::load("builtin:cornell-glass").unwrap()).unwrap();
    let gltf = one_triangle(json!({"materials": [{"emissiveFactor": [1, 1, 1]}]})).into_bytes();
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut rnd = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    let (mut ok, mut err) = (0, 0);
    for src in [&glb, &gltf] {
        // Concentrate on the JSON chunk / header, where structure lives.
        let hot = src.len().min(4096);
        for _ in 0..300 {
            let mut v = src.clone();
            for _ in 0..1 + rnd() % 4 {
                let i = (rnd() as usize) % hot;
                v[i] = rnd() as u8;
            }
            match load_slice(&v, None, "fuzz") {
                Ok(s) => {
                    s.validate().unwrap();
                    ok += 1
                }
                Err(_) => err += 1,
            }
        }
        for cut in (0..src.len().min(3000)).step_by(37) {
            if let Ok(s) = load_slice(&src[..cut], None, "cut") {
                s.validate().unwrap();
            }
        }
    }
    assert!(ok > 0 && err > 0, "ok {ok}, err {err}");
}

#[test]
fn material_priority_is_read_from_extras() {
    let glass = |name: &str, extras: Value| {
        json!({"name": name, "extras": extras, "extensions": {
            "KHR_materials_transmission": {"transmissionFactor": 1.0},
            "KHR_materials_volume": {"thicknessFactor": 1.0}}})
    };
    let s = load(&one_triangle(json!({
        "extensionsUsed": ["KHR_materials_transmission", "KHR_materials_volume"],
        "materials": [
            glass("high", json!({"priority": 3})),
            glass("negative", json!({"priority": -2})),
            glass("none", json!({})),
            glass("fraction", json!({"priority": 1.5})),
            glass("huge", json!({"priority": 1e12})),
            glass("text", json!({"priority": "high"}))
        ]
    })))
    .unwrap();
    let p = |name: &str| {
        s.materials
            .iter()
            .find(|x| x.name == name)
            .unwrap()
            .priority
    };
    assert_eq!((p("high"), p("negative"), p("none")), (3, -2, 0));
    for bad in ["fraction", "huge", "text"] {
        assert_eq!(p(bad), 0, "{bad}");
        assert!(
            s.warnings
                .iter()
                .any(|w| w.contains(bad) && w.contains("priority")),
            "{bad}: {:?}",
            s.warnings
        );
    }
}

/// Everyday texture formats (issue 18, part 3): JPEG (most glTF files' colour textures) and
/// WebP decode like PNG; the image's own bytes decide the format, whatever `mimeType` says.
#[test]
fn jpeg_and_webp_textures_load() {
    let img = image::RgbImage::from_pixel(8, 4, image::Rgb([200, 100, 50]));
    let encode = |f: image::ImageFormat| {
        let mut out = std::io::Cursor::new(Vec::new());
        match f {
            image::ImageFormat::WebP => image::DynamicImage::ImageRgba8(
                image::DynamicImage::ImageRgb8(img.clone()).to_rgba8(),
            )
            .write_to(&mut out, f)
            .unwrap(),
            _ => img.write_to(&mut out, f).unwrap(),
        }
        out.into_inner()
    };
    for (f, mime, tol) in [
        (image::ImageFormat::Jpeg, "image/jpeg", 0.02),
        (image::ImageFormat::WebP, "image/webp", 1e-6),
    ] {
        let mut b = Bin::default();
        let p = b.vec3(&TRI);
        let view = b.raw_view(&encode(f));
        let doc = json!({
            "nodes": [{"mesh": 0}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": p}, "material": 0}]}],
            "images": [{"bufferView": view, "mimeType": mime}],
            "textures": [{"source": 0}],
            "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]
        });
        let s = load(&b.finish(doc)).unwrap();
        assert!(
            s.warnings.iter().all(|w| !w.contains("texture")),
            "{mime}: {:?}",
            s.warnings
        );
        let t = &s.textures[s.materials[0].base_color_texture.unwrap().texture as usize];
        assert_eq!((t.width, t.height), (8, 4), "{mime}");
        // sRGB 200/255 → linear 0.5776 (lossy JPEG: within a few levels).
        assert!(
            (t.texels[0].x - 0.577_58).abs() < tol * 4.0 + 1e-5,
            "{mime}: {}",
            t.texels[0]
        );
    }
}

/// The camera's `aspectRatio` shapes the image when `extras.render` gives no size (longer
/// side 512); an explicit size wins.
#[test]
fn camera_aspect_ratio_sizes_the_image_without_extras() {
    let cam = |extras: Value| {
        one_triangle(json!({
            "scenes": [{"nodes": [0, 1], "extras": extras}],
            "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0, 0, 3]}],
            "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1, "aspectRatio": 2.0}}]
        }))
    };
    let s = load(&cam(json!({}))).unwrap();
    assert_eq!((s.settings.width, s.settings.height), (512, 256));
    let s = load(&cam(json!({"render": {"width": 300}}))).unwrap();
    assert_eq!((s.settings.width, s.settings.height), (300, 512));
}

#[test]
fn extras_conductor_makes_a_tabulated_metal_and_rejects_unknown_names() {
    let metal = |name: &str, r: f32, c: serde_json::Value| json!({"name": name, "pbrMetallicRoughness": {"metallicFactor": 1.0, "roughnessFactor": r}, "extras": {"conductor": c}});
    let s = load(&one_triangle(json!({
        "materials": [metal("gold", 0.0, json!("Au")), metal("rough-al", 0.4, json!("Al"))]
    })))
    .unwrap();
    let m = |name: &str| s.materials.iter().find(|x| x.name == name).unwrap();
    assert_eq!(m("gold").conductor, Some(refract::bsdf::Metal::Au));
    assert_eq!(m("gold").kind, MaterialKind::Mirror);
    assert_eq!(m("rough-al").conductor, Some(refract::bsdf::Metal::Al));
    assert_eq!(m("rough-al").kind, MaterialKind::GlossyMetal);
    for (c, want) in [
        (json!("Pt"), "extras.conductor \"Pt\" is not a known metal"),
        (json!(3), "extras.conductor must be a string"),
    ] {
        let e = load(&one_triangle(
            json!({"materials": [metal("shiny", 0.0, c)]}),
        ))
        .expect_err("refused");
        let msg = format!("{e:#}");
        assert!(
            msg.contains("material 'shiny'") && msg.contains(want),
            "{msg}"
        );
    }
    // Not metallic: refused, naming the material.
    let e = load(&one_triangle(json!({"materials": [
        {"name": "plastic", "pbrMetallicRoughness": {"metallicFactor": 0.0}, "extras": {"conductor": "Cu"}}
    ]})))
            .expect_err("refused");
    let msg = format!("{e:#}");
    assert!(
        msg.contains("material 'plastic'") && msg.contains("needs a metallic material"),
        "{msg}"
    );
}

/// KHR_materials_iridescence: the factor, film IOR and thickness range are read (defaults
/// where absent), a factor of 0 (the extension's default) is no film, and a film IOR below 1
/// or a negative thickness is an error naming the material and the JSON path.
#[test]
fn iridescence_is_read_and_checked() {
    let material = |ext: Value| {
        json!({"materials": [{"name": "coated", "pbrMetallicRoughness": {"metallicFactor": 1.0,
            "roughnessFactor": 0.0}, "extensions": {"KHR_materials_iridescence": ext}}],
            "extensionsUsed": ["KHR_materials_iridescence"]})
    };
    let with_material = |ext: Value| {
        let mut doc: Value = serde_json::from_str(&one_triangle(material(ext))).unwrap();
        doc["meshes"][0]["primitives"][0]["material"] = json!(0);
        doc.to_string()
    };
    let s = load(&with_material(
        json!({"iridescenceFactor": 1.0, "iridescenceIor": 1.45,
        "iridescenceThicknessMaximum": 550.0}),
    ))
    .unwrap();
    let film = s.materials[0].iridescence.expect("a film");
    assert_eq!((film.factor, film.ior), (1.0, 1.45));
    assert_eq!((film.thickness_min, film.thickness_max), (100.0, 550.0));
    assert!(!has_warning(&s, "unsupported"), "{:?}", s.warnings);
    let none = load(&with_material(json!({"iridescenceIor": 1.45}))).unwrap();
    assert!(none.materials[0].iridescence.is_none(), "factor 0: no film");
    for (bad, field) in [
        (
            json!({"iridescenceFactor": 1.0, "iridescenceIor": 0.5}),
            "film IOR 0.5",
        ),
        (
            json!({"iridescenceFactor": 1.0, "iridescenceThicknessMinimum": -3.0}),
            "minimum -3",
        ),
        (json!({"iridescenceFactor": 2.0}), "factor 2"),
        (json!({"iridescenceFactor": "a lot"}), "iridescenceFactor"),
    ] {
        let e = format!("{:#}", load(&with_material(bad)).unwrap_err());
        assert!(
            e.contains("coated") && e.contains(field) && e.contains("KHR_materials_iridescence"),
            "{e}"
        );
    }
}
