//! Small scenes built in code for the integration tests (independent of the built-ins).
#![allow(dead_code)]

use glam::{Vec2, Vec3};
use refract::scene::{Camera, Material, Mesh, RenderSettings, Scene};

/// Quad p, p+u, p+u+v, p+v (CCW seen from the side u×v points to).
pub fn quad(mesh: &mut Mesh, p: Vec3, u: Vec3, v: Vec3, material: u32) {
    let n = u.cross(v).normalize();
    let base = mesh.positions.len() as u32;
    for q in [p, p + u, p + u + v, p + v] {
        mesh.positions.push(q);
        mesh.normals.push(n);
        mesh.uvs.push(Vec2::ZERO);
    }
    mesh.indices.push([base, base + 1, base + 2]);
    mesh.indices.push([base, base + 2, base + 3]);
    mesh.tri_material.extend([material, material]);
}

/// Closed axis-aligned box with outward normals.
pub fn cuboid(mesh: &mut Mesh, lo: Vec3, hi: Vec3, material: u32) {
    let d = hi - lo;
    let (x, y, z) = (Vec3::X * d.x, Vec3::Y * d.y, Vec3::Z * d.z);
    quad(mesh, lo, y, x, material);
    quad(mesh, lo + z, x, y, material);
    quad(mesh, lo, z, y, material);
    quad(mesh, lo + x, y, z, material);
    quad(mesh, lo, x, z, material);
    quad(mesh, lo + y, z, x, material);
}

/// Watertight icosphere-like UV sphere with shared pole/seam vertices, smooth normals.
pub fn sphere(mesh: &mut Mesh, c: Vec3, r: f32, rings: u32, segs: u32, material: u32) {
    let base = mesh.positions.len() as u32;
    // north pole, ring vertices (rings-1 rings of segs each), south pole
    let mut push = |n: Vec3| {
        mesh.positions.push(c + r * n);
        mesh.normals.push(n);
        mesh.uvs.push(Vec2::ZERO);
    };
    push(Vec3::Y);
    for i in 1..rings {
        let th = std::f32::consts::PI * i as f32 / rings as f32;
        for j in 0..segs {
            let ph = 2.0 * std::f32::consts::PI * j as f32 / segs as f32;
            push(Vec3::new(
                th.sin() * ph.cos(),
                th.cos(),
                -th.sin() * ph.sin(),
            ));
        }
    }
    push(-Vec3::Y);
    let south = base + 1 + (rings - 1) * segs;
    let ring = |i: u32, j: u32| base + 1 + i * segs + (j % segs);
    for j in 0..segs {
        mesh.indices.push([base, ring(0, j), ring(0, j + 1)]);
        mesh.tri_material.push(material);
        mesh.indices
            .push([south, ring(rings - 2, j + 1), ring(rings - 2, j)]);
        mesh.tri_material.push(material);
    }
    for i in 0..rings - 2 {
        for j in 0..segs {
            let (a, b, c2, d) = (
                ring(i, j),
                ring(i, j + 1),
                ring(i + 1, j),
                ring(i + 1, j + 1),
            );
            mesh.indices.push([a, c2, d]);
            mesh.indices.push([a, d, b]);
            mesh.tri_material.extend([material, material]);
        }
    }
}

pub fn scene(name: &str, mesh: Mesh, materials: Vec<Material>, camera: Camera, env: f32) -> Scene {
    Scene {
        name: name.into(),
        mesh,
        materials,
        textures: vec![],
        punctual_lights: vec![],
        camera,
        environment: Vec3::splat(env),
        settings: RenderSettings {
            width: 32,
            height: 32,
            max_depth: 64,
            rr_depth: 5,
            spp: 16,
        },
        warnings: vec![],
    }
}

/// Replace smooth normals by per-triangle geometric normals (vertices are unshared), so the
/// shading normal equals the geometric one everywhere.
pub fn flatten(mesh: &Mesh) -> Mesh {
    let mut out = Mesh::default();
    for (t, tri) in mesh.indices.iter().enumerate() {
        let p = tri.map(|i| mesh.positions[i as usize]);
        let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
        let base = out.positions.len() as u32;
        for q in p {
            out.positions.push(q);
            out.normals.push(n);
            out.uvs.push(Vec2::ZERO);
        }
        out.indices.push([base, base + 1, base + 2]);
        out.tri_material.push(mesh.tri_material[t]);
    }
    out
}

/// A GPU context for test `test`, or None (with a SKIP line) when there is no adapter; with
/// REFRACT_REQUIRE_GPU set (CI installs lavapipe) a missing adapter fails the test instead.
pub fn gpu_context(test: &str) -> Option<refract::gpu::GpuContext> {
    match refract::gpu::GpuContext::new() {
        Ok(c) => {
            eprintln!("{test}: GPU adapter {}", c.describe());
            Some(c)
        }
        Err(e) => {
            if std::env::var_os("REFRACT_REQUIRE_GPU").is_some() {
                panic!("{test}: no GPU adapter although REFRACT_REQUIRE_GPU is set ({e:#})");
            }
            eprintln!("SKIP {test}: no GPU adapter ({e:#})");
            None
        }
    }
}
