//! The caustic scenes: `caustic` (ball lens and slab on a floor) and `caustic-mirror`
//! (the same caustic also seen in a mirror).

use super::{oriented_box, rect, scene, settings, sphere};
use crate::scene::{Camera, Material, Mesh, Scene};
use glam::{Quat, Vec3};

/// Caustics: a smooth glass sphere (r = 0.3 m, IOR 1.5) and an upright glass block
/// (0.1 × 0.4 × 0.6 m) on a 4 × 4 m diffuse floor (albedo 0.8) with a back wall, lit by a
/// 0.1 × 0.1 m light of radiance 1000 at 45° elevation, 2 m from the sphere; the sphere
/// focuses it to a bright spot just beyond its contact point.
pub fn caustic() -> Scene {
    let materials = vec![
        Material::diffuse("floor", Vec3::splat(0.8)),
        Material::glass("glass", 1.5),
        Material::emitter("light", Vec3::splat(1000.0)),
        Material::diffuse("wall", Vec3::splat(0.6)),
    ];
    let mut m = Mesh::default();
    rect(&mut m, Vec3::ZERO, Vec3::Y, 4.0, 4.0, 0);
    rect(&mut m, Vec3::new(0.0, 1.0, -1.5), Vec3::Z, 4.0, 2.0, 3);
    let c = Vec3::new(0.0, 0.3, 0.0);
    sphere(&mut m, c, 0.3, 48, 96, 1);
    oriented_box(
        &mut m,
        Vec3::new(0.75, 0.2, -0.6),
        Vec3::new(0.05, 0.2, 0.3),
        Quat::IDENTITY,
        1,
    );
    let to_light = Vec3::new(-1.0, 1.0, 0.0).normalize();
    let lp = c + 2.0 * to_light;
    rect(&mut m, lp, -to_light, 0.1, 0.1, 2);
    let cam = Camera::look_at(
        Vec3::new(0.3, 1.3, 2.6),
        Vec3::new(0.2, 0.15, -0.2),
        Vec3::Y,
        0.6,
    );
    scene("caustic", m, materials, cam, Vec3::ZERO, settings(640, 480))
}

/// The ball-lens caustic seen directly and in a mirror: the glass sphere of [`caustic`]
/// (r = 0.3 m, IOR 1.5) on a 4 × 4 m diffuse floor (albedo 0.8) under a 0.1 × 0.1 m light of
/// radiance 1000 2 m away at about 39° elevation (so the focused spot lies clear of the
/// sphere), and a 1.6 × 0.9 m perfect mirror (reflectance 0.95) standing on the floor 0.45 m
/// behind the sphere, facing the camera. The spot beside the contact point is the path class
/// LS+DE; its reflection in the mirror is LS+DS+E, which no connection of a light subpath to
/// the camera can make.
pub fn caustic_mirror() -> Scene {
    let materials = vec![
        Material::diffuse("floor", Vec3::splat(0.8)),
        Material::glass("glass", 1.5),
        Material::emitter("light", Vec3::splat(1000.0)),
        Material::mirror("mirror", Vec3::splat(0.95)),
    ];
    let mut m = Mesh::default();
    rect(&mut m, Vec3::ZERO, Vec3::Y, 4.0, 4.0, 0);
    let c = Vec3::new(0.0, 0.3, 0.0);
    sphere(&mut m, c, 0.3, 48, 96, 1);
    let to_light = Vec3::new(-1.0, 0.8, 0.0).normalize();
    let lp = c + 2.0 * to_light;
    rect(&mut m, lp, -to_light, 0.1, 0.1, 2);
    rect(&mut m, Vec3::new(0.2, 0.45, -0.45), Vec3::Z, 1.6, 0.9, 3);
    let cam = Camera::look_at(
        Vec3::new(0.9, 1.5, 2.0),
        Vec3::new(0.2, 0.15, -0.35),
        Vec3::Y,
        0.6,
    );
    scene(
        "caustic-mirror",
        m,
        materials,
        cam,
        Vec3::ZERO,
        settings(320, 240),
    )
}
