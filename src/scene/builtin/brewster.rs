//! Brewster's angle (issue 38, docs/polarization.md): a bright panel seen in a glass plate
//! at θB = atan(1.5) ≈ 56.3° of incidence. Light reflected there is polarised entirely
//! along s (horizontal in the image: the plate is level, the camera upright), so a
//! polarising filter with a vertical axis (`refract render --polarizer 90`) removes the
//! panel's reflection and one with a horizontal axis (`--polarizer 0`) passes all of it.

use super::{checkerboard, cuboid, rect, scene, settings};
use crate::scene::{Camera, Material, Mesh, Scene};
use glam::Vec3;

/// IOR of the plate.
pub const BREWSTER_IOR: f32 = 1.5;

/// Height of the plate's top face.
pub const PLATE_TOP: f32 = 0.045;

/// The glass plate (1.6 × 1.6 m, 4 cm thick, n = 1.5) on a black base on a dark
/// checkerboard, 5 mm above them;
/// the camera 2.6 m from the plate's centre at θB from the vertical, looking at that centre,
/// so the image's centre sees the plate at Brewster's angle; a 1.2 × 0.5 m panel (radiance
/// 6) at the mirrored direction, facing the plate; a red and a white diffuse box beside the
/// plate, whose light a filter only halves.
pub fn brewster() -> Scene {
    let theta = BREWSTER_IOR.atan();
    let centre = Vec3::new(0.0, PLATE_TOP, 0.0);
    let (sin, cos) = theta.sin_cos();
    let eye = centre + 2.6 * Vec3::new(0.0, cos, sin);
    let panel = centre + 2.2 * Vec3::new(0.0, cos, -sin);
    let mut m = Mesh::default();
    checkerboard(&mut m, Vec3::ZERO, 8.0, 16, 0, 1);
    cuboid(
        &mut m,
        Vec3::new(-0.8, PLATE_TOP - 0.04, -0.8),
        Vec3::new(0.8, PLATE_TOP, 0.8),
        2,
    );
    // Black glass: a black base under the plate (the classic Brewster experiment), so
    // what is seen in the plate is its reflection only.
    rect(&mut m, Vec3::new(0.0, 0.002, 0.0), Vec3::Y, 1.6, 1.6, 6);
    rect(&mut m, panel, centre - panel, 1.2, 0.5, 3);
    cuboid(
        &mut m,
        Vec3::new(-1.3, 0.0, -0.3),
        Vec3::new(-0.9, 0.4, 0.1),
        4,
    );
    cuboid(
        &mut m,
        Vec3::new(0.9, 0.0, -0.5),
        Vec3::new(1.2, 0.3, -0.2),
        5,
    );
    let materials = vec![
        Material::diffuse("floor-light", Vec3::splat(0.35)),
        Material::diffuse("floor-dark", Vec3::splat(0.05)),
        Material::glass("glass-plate", BREWSTER_IOR),
        Material::emitter("panel", Vec3::splat(6.0)),
        Material::diffuse("red-box", Vec3::new(0.7, 0.12, 0.1)),
        Material::diffuse("white-box", Vec3::splat(0.75)),
        Material::diffuse("black-base", Vec3::ZERO),
    ];
    let cam = Camera::look_at(eye, centre, Vec3::Y, 0.75);
    scene(
        "brewster",
        m,
        materials,
        cam,
        Vec3::splat(0.03),
        settings(480, 320),
    )
}
