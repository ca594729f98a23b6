//! Built-in scenes (`builtin:NAME`). Placeholder geometry builders; see the scene loader.

use super::{Camera, Material, Mesh, RenderSettings, Scene};
use glam::{Vec2, Vec3};

/// Names accepted by [`load`].
pub const NAMES: &[&str] = &["cornell-glass", "furnace"];

pub fn load(name: &str) -> anyhow::Result<Scene> {
    match name {
        "cornell-glass" => Ok(cornell_glass()),
        "furnace" => Ok(furnace()),
        _ => anyhow::bail!(
            "unknown built-in scene '{name}' (available: {})",
            NAMES.join(", ")
        ),
    }
}

/// Append a quad (p, p+u, p+u+v, p+v), CCW seen from the side `u × v` points to.
pub fn quad(mesh: &mut Mesh, p: Vec3, u: Vec3, v: Vec3, material: u32) {
    let n = u.cross(v).normalize();
    let base = mesh.positions.len() as u32;
    for (q, uv) in [
        (p, Vec2::new(0.0, 0.0)),
        (p + u, Vec2::new(1.0, 0.0)),
        (p + u + v, Vec2::new(1.0, 1.0)),
        (p + v, Vec2::new(0.0, 1.0)),
    ] {
        mesh.positions.push(q);
        mesh.normals.push(n);
        mesh.uvs.push(uv);
    }
    mesh.indices.push([base, base + 1, base + 2]);
    mesh.indices.push([base, base + 2, base + 3]);
    mesh.tri_material.extend([material, material]);
}

/// Append a UV sphere with smooth normals, CCW from outside.
pub fn sphere(mesh: &mut Mesh, c: Vec3, r: f32, rings: u32, segments: u32, material: u32) {
    let base = mesh.positions.len() as u32;
    for i in 0..=rings {
        let theta = std::f32::consts::PI * i as f32 / rings as f32;
        for j in 0..=segments {
            let phi = 2.0 * std::f32::consts::PI * j as f32 / segments as f32;
            let n = Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                -theta.sin() * phi.sin(),
            );
            mesh.positions.push(c + r * n);
            mesh.normals.push(n);
            mesh.uvs.push(Vec2::new(
                j as f32 / segments as f32,
                i as f32 / rings as f32,
            ));
        }
    }
    let w = segments + 1;
    for i in 0..rings {
        for j in 0..segments {
            let a = base + i * w + j;
            let b = a + w;
            if i != 0 {
                mesh.indices.push([a, b, a + 1]);
                mesh.tri_material.push(material);
            }
            if i != rings - 1 {
                mesh.indices.push([a + 1, b, b + 1]);
                mesh.tri_material.push(material);
            }
        }
    }
}

/// Axis-aligned box with outward normals.
pub fn cuboid(mesh: &mut Mesh, lo: Vec3, hi: Vec3, material: u32) {
    let d = hi - lo;
    let (x, y, z) = (Vec3::X * d.x, Vec3::Y * d.y, Vec3::Z * d.z);
    quad(mesh, lo, y, x, material); // back (-z)
    quad(mesh, lo + z, x, y, material); // front (+z)
    quad(mesh, lo, z, y, material); // left (-x)
    quad(mesh, lo + x, y, z, material); // right (+x)
    quad(mesh, lo, x, z, material); // bottom (-y)
    quad(mesh, lo + y, z, x, material); // top (+y)
}

pub fn cornell_glass() -> Scene {
    let materials = vec![
        Material::diffuse("white", Vec3::splat(0.75)),
        Material::diffuse("red", Vec3::new(0.63, 0.065, 0.05)),
        Material::diffuse("green", Vec3::new(0.14, 0.45, 0.091)),
        Material::emitter("light", Vec3::splat(17.0)),
        Material::glass("glass", 1.5),
        Material::mirror("mirror", Vec3::splat(0.95)),
    ];
    let mut m = Mesh::default();
    let s = 1.0;
    quad(
        &mut m,
        Vec3::new(-s, 0.0, -s),
        Vec3::Z * 2.0 * s,
        Vec3::X * 2.0 * s,
        0,
    ); // floor
    quad(
        &mut m,
        Vec3::new(-s, 2.0 * s, -s),
        Vec3::X * 2.0 * s,
        Vec3::Z * 2.0 * s,
        0,
    ); // ceiling
    quad(
        &mut m,
        Vec3::new(-s, 0.0, -s),
        Vec3::X * 2.0 * s,
        Vec3::Y * 2.0 * s,
        0,
    ); // back
    quad(
        &mut m,
        Vec3::new(-s, 0.0, -s),
        Vec3::Y * 2.0 * s,
        Vec3::Z * 2.0 * s,
        1,
    ); // left red
    quad(
        &mut m,
        Vec3::new(s, 0.0, -s),
        Vec3::Z * 2.0 * s,
        Vec3::Y * 2.0 * s,
        2,
    ); // right green
    let l = 0.25;
    quad(
        &mut m,
        Vec3::new(-l, 1.999, -l),
        Vec3::X * 2.0 * l,
        Vec3::Z * 2.0 * l,
        3,
    );
    sphere(&mut m, Vec3::new(0.35, 0.35, 0.3), 0.35, 48, 96, 4);
    // rotate the mirror box slightly? keep axis aligned for the placeholder
    cuboid(
        &mut m,
        Vec3::new(-0.75, 0.0, -0.6),
        Vec3::new(-0.2, 1.1, -0.1),
        5,
    );
    Scene {
        name: "cornell-glass".into(),
        mesh: m,
        materials,
        textures: vec![],
        punctual_lights: vec![],
        camera: Camera::look_at(
            Vec3::new(0.0, 1.0, 3.9),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::Y,
            0.6911,
        ),
        environment: Vec3::ZERO,
        settings: RenderSettings::default(),
        warnings: vec![],
    }
}

pub fn furnace() -> Scene {
    let materials = vec![
        Material::diffuse("white", Vec3::ONE),
        Material::mirror("mirror", Vec3::ONE),
        Material::glass("glass", 1.5),
    ];
    let mut m = Mesh::default();
    sphere(&mut m, Vec3::new(-1.1, 0.0, 0.0), 0.5, 32, 64, 0);
    sphere(&mut m, Vec3::new(0.0, 0.0, 0.0), 0.5, 32, 64, 1);
    sphere(&mut m, Vec3::new(1.1, 0.0, 0.0), 0.5, 32, 64, 2);
    Scene {
        name: "furnace".into(),
        mesh: m,
        materials,
        textures: vec![],
        punctual_lights: vec![],
        camera: Camera::look_at(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, Vec3::Y, 0.7),
        environment: Vec3::ONE,
        settings: RenderSettings {
            width: 256,
            height: 128,
            ..Default::default()
        },
        warnings: vec![],
    }
}
