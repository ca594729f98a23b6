//! The Cornell-box family: `cornell-glass`, `glass-slab`, `rough-glass`, and the white
//! `furnace`.

use super::{
    checkerboard, oriented_box, quad, rect, rough_glass_material, scene, settings, sphere,
};
use crate::bsdf::MicrofacetDistribution;
use crate::scene::{Camera, Material, Mesh, Scene};
use glam::{Quat, Vec3};

/// Cornell box materials 0..=3 (white, red, green, light) and geometry: x, z ∈ [−1, 1],
/// y ∈ [0, 2], open towards +z; a 0.5 × 0.5 m light 1 mm under the ceiling facing down.
pub(super) fn cornell_box(m: &mut Mesh) -> Vec<Material> {
    let s = 1.0;
    quad(
        m,
        Vec3::new(-s, 0.0, -s),
        Vec3::Z * 2.0 * s,
        Vec3::X * 2.0 * s,
        0,
    ); // floor, +Y
    quad(
        m,
        Vec3::new(-s, 2.0 * s, -s),
        Vec3::X * 2.0 * s,
        Vec3::Z * 2.0 * s,
        0,
    ); // ceiling, −Y
    quad(
        m,
        Vec3::new(-s, 0.0, -s),
        Vec3::X * 2.0 * s,
        Vec3::Y * 2.0 * s,
        0,
    ); // back, +Z
    quad(
        m,
        Vec3::new(-s, 0.0, -s),
        Vec3::Y * 2.0 * s,
        Vec3::Z * 2.0 * s,
        1,
    ); // left red, +X
    quad(
        m,
        Vec3::new(s, 0.0, -s),
        Vec3::Z * 2.0 * s,
        Vec3::Y * 2.0 * s,
        2,
    ); // right green, −X
    let l = 0.25;
    quad(
        m,
        Vec3::new(-l, 1.999, -l),
        Vec3::X * 2.0 * l,
        Vec3::Z * 2.0 * l,
        3,
    ); // light, −Y
    vec![
        Material::diffuse("white", Vec3::splat(0.75)),
        Material::diffuse("red", Vec3::new(0.63, 0.065, 0.05)),
        Material::diffuse("green", Vec3::new(0.14, 0.45, 0.091)),
        Material::emitter("light", Vec3::splat(17.0)),
    ]
}

pub(super) fn cornell_camera() -> Camera {
    Camera::look_at(
        Vec3::new(0.0, 1.0, 3.9),
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::Y,
        0.6911,
    )
}

/// Default scene: Cornell box, smooth solid glass sphere (IOR 1.5, r = 0.35 m) and a mirror
/// box (0.55 × 1.1 × 0.5 m) turned 15° about Y.
pub fn cornell_glass() -> Scene {
    let mut m = Mesh::default();
    let mut materials = cornell_box(&mut m);
    materials.push(Material::glass("glass", 1.5));
    materials.push(Material::mirror("mirror", Vec3::splat(0.95)));
    sphere(&mut m, Vec3::new(0.35, 0.35, 0.3), 0.35, 48, 96, 4);
    oriented_box(
        &mut m,
        Vec3::new(-0.45, 0.55, -0.35),
        Vec3::new(0.275, 0.55, 0.25),
        Quat::from_rotation_y(15f32.to_radians()),
        5,
    );
    scene(
        "cornell-glass",
        m,
        materials,
        cornell_camera(),
        Vec3::ZERO,
        settings(512, 512),
    )
}

/// A 1.2 × 0.2 × 0.8 m smooth glass slab (IOR 1.5), tilted ~26° about X and turned 20° about
/// Y, 0.3–0.8 m over a 10 × 10 m checkerboard of 0.25 m squares (albedo 0.8 / 0.05), lit by
/// a 2 × 2 m area light (radiance 6) 3 m up.
pub fn glass_slab() -> Scene {
    let materials = vec![
        Material::diffuse("checker-light", Vec3::splat(0.8)),
        Material::diffuse("checker-dark", Vec3::splat(0.05)),
        Material::glass("glass", 1.5),
        Material::emitter("light", Vec3::splat(6.0)),
    ];
    let mut m = Mesh::default();
    checkerboard(&mut m, Vec3::ZERO, 10.0, 40, 0, 1);
    oriented_box(
        &mut m,
        Vec3::new(0.0, 0.55, 0.0),
        Vec3::new(0.6, 0.1, 0.4),
        Quat::from_rotation_y(20f32.to_radians()) * Quat::from_rotation_x(26f32.to_radians()),
        2,
    );
    rect(&mut m, Vec3::new(-0.6, 3.0, 0.4), Vec3::NEG_Y, 2.0, 2.0, 3);
    let cam = Camera::look_at(
        Vec3::new(0.0, 2.2, 2.4),
        Vec3::new(0.0, 0.3, 0.0),
        Vec3::Y,
        0.75,
    );
    scene(
        "glass-slab",
        m,
        materials,
        cam,
        Vec3::ZERO,
        settings(640, 480),
    )
}

/// White furnace: diffuse (albedo 1), mirror (reflectance 1) and smooth glass (IOR 1.5)
/// spheres of radius 0.5 m in a uniform environment of radiance 1; no lights. Every pixel
/// should render exactly 1.
pub fn furnace() -> Scene {
    let materials = vec![
        Material::diffuse("white", Vec3::ONE),
        Material::mirror("mirror", Vec3::ONE),
        Material::glass("glass", 1.5),
    ];
    let mut m = Mesh::default();
    sphere(&mut m, Vec3::new(-1.1, 0.0, 0.0), 0.5, 48, 96, 0);
    sphere(&mut m, Vec3::new(0.0, 0.0, 0.0), 0.5, 48, 96, 1);
    sphere(&mut m, Vec3::new(1.1, 0.0, 0.0), 0.5, 48, 96, 2);
    let cam = Camera::look_at(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, Vec3::Y, 0.7);
    scene("furnace", m, materials, cam, Vec3::ONE, settings(256, 128))
}

/// Cornell box with a rough solid glass sphere (IOR 1.5, roughness 0.3 → α = 0.09, GGX),
/// r = 0.45 m, on the floor in the middle.
pub fn rough_glass() -> Scene {
    let mut m = Mesh::default();
    let mut materials = cornell_box(&mut m);
    let mut g = rough_glass_material("rough-glass", 1.5, 0.3);
    g.distribution = MicrofacetDistribution::Ggx;
    materials.push(g);
    sphere(&mut m, Vec3::new(0.0, 0.45, 0.0), 0.45, 48, 96, 4);
    scene(
        "rough-glass",
        m,
        materials,
        cornell_camera(),
        Vec3::ZERO,
        settings(512, 512),
    )
}
