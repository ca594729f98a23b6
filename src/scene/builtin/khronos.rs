//! Test grids in the manner of the Khronos glTF sample models IORTestGrid and
//! TransmissionRoughnessTest, built in code and lit only by the project's studio HDRI
//! (`assets/studio.hdr`): solid glass spheres in front of a checkered wall, so each sphere's
//! refracted and reflected image of the wall and the studio's soft boxes shows its IOR and
//! roughness.
//!
//! - `ior-grid`: IOR 1.0, 1.2, …, 2.4 left to right × roughness 0, 0.25, 0.5, 0.75, 1 top to
//!   bottom (α = roughness², GGX). IOR 1.0 is index-matched: its spheres must vanish at every
//!   roughness (a stress case for the rough dielectric at η = 1).
//! - `transmission-roughness`: one row of IOR 1.5 spheres, roughness 0, 0.2, …, 1.
//! - `frosted-panes`: one row of thin-walled IOR 1.5 panes (glTF transmission without volume),
//!   roughness 0, 0.1, 0.2, 0.35, 0.6, 1, half a metre in front of the wall: the smooth pane
//!   shows the checks sharp, the rough ones blur them more and more (the rough thin-walled
//!   dielectric, `bsdf::RoughThinDielectric`).

use super::{checkerboard, rect, rough_glass_material, scene, settings, sphere};
use crate::scene::{Camera, Material, MaterialKind, Mesh, Scene};
use glam::{Quat, Vec3};

/// IORs of the grid's columns.
pub const IOR_COLUMNS: [f32; 8] = [1.0, 1.2, 1.4, 1.6, 1.8, 2.0, 2.2, 2.4];
/// Roughness of the grid's rows, top to bottom.
pub const ROUGHNESS_ROWS: [f32; 5] = [0.0, 0.25, 0.5, 0.75, 1.0];
/// Roughness of the transmission row, left to right.
pub const TRANSMISSION_ROUGHNESS: [f32; 6] = [0.0, 0.2, 0.4, 0.6, 0.8, 1.0];
/// Roughness of the frosted panes, left to right.
pub const PANE_ROUGHNESS: [f32; 6] = [0.0, 0.1, 0.2, 0.35, 0.6, 1.0];

/// Sphere radius and centre spacing (m).
const RADIUS: f32 = 0.2;
const SPACING: f32 = 0.5;
/// Tessellation of each sphere (rings, segments): smooth normals hide the facets.
const TESS: (u32, u32) = (16, 32);

/// Materials 0 and 1: the wall's light and dark squares.
fn wall_materials() -> Vec<Material> {
    vec![
        Material::diffuse("wall-light", Vec3::splat(0.8)),
        Material::diffuse("wall-dark", Vec3::splat(0.1)),
    ]
}

/// A checkered wall in the plane z = `z`, facing +z, `size` m square, centred at height `y`.
fn wall(m: &mut Mesh, y: f32, z: f32, size: f32) {
    let mut w = Mesh::default();
    checkerboard(&mut w, Vec3::ZERO, size, 24, 0, 1);
    // The board faces +Y; a quarter turn about +X makes it face +Z.
    let rot = Quat::from_rotation_x(std::f32::consts::FRAC_PI_2);
    let base = m.positions.len() as u32;
    m.positions
        .extend(w.positions.iter().map(|&p| rot * p + Vec3::new(0.0, y, z)));
    m.normals.extend(w.normals.iter().map(|&n| rot * n));
    m.uvs.extend(w.uvs);
    m.indices
        .extend(w.indices.iter().map(|t| t.map(|i| i + base)));
    m.tri_material.extend(w.tri_material);
}

/// The material name of the sphere of `ior` and `roughness`.
pub fn sphere_name(ior: f32, roughness: f32) -> String {
    format!("glass-n{ior:.1}-r{roughness:.2}")
}

/// Spheres of (ior, roughness) at their centres; materials appended after the wall's.
fn spheres(m: &mut Mesh, materials: &mut Vec<Material>, items: &[(f32, f32, Vec3)]) {
    for &(ior, roughness, c) in items {
        let idx = materials.len() as u32;
        materials.push(rough_glass_material(
            &sphere_name(ior, roughness),
            ior,
            roughness,
        ));
        sphere(m, c, RADIUS, TESS.0, TESS.1, idx);
    }
}

fn lit_by_studio(mut s: Scene) -> Scene {
    s.env_map = Some(crate::scene::hdri::studio_env());
    s
}

pub fn ior_grid() -> Scene {
    let mut materials = wall_materials();
    let mut m = Mesh::default();
    let (cols, rows) = (IOR_COLUMNS.len() as f32, ROUGHNESS_ROWS.len() as f32);
    let items: Vec<(f32, f32, Vec3)> = ROUGHNESS_ROWS
        .iter()
        .enumerate()
        .flat_map(|(r, &rough)| {
            IOR_COLUMNS.iter().enumerate().map(move |(c, &ior)| {
                let x = (c as f32 - 0.5 * (cols - 1.0)) * SPACING;
                let y = ((rows - 1.0) - r as f32) * SPACING + RADIUS + 0.1;
                (ior, rough, Vec3::new(x, y, 0.0))
            })
        })
        .collect();
    spheres(&mut m, &mut materials, &items);
    let mid = 0.5 * (rows - 1.0) * SPACING + RADIUS + 0.1;
    wall(&mut m, mid, -1.0, 8.0);
    let cam = Camera::look_at(
        Vec3::new(0.0, mid, 7.0),
        Vec3::new(0.0, mid, 0.0),
        Vec3::Y,
        0.42,
    );
    let s = scene(
        "ior-grid",
        m,
        materials,
        cam,
        Vec3::ZERO,
        settings(640, 400),
    );
    lit_by_studio(s)
}

pub fn transmission_roughness() -> Scene {
    let mut materials = wall_materials();
    let mut m = Mesh::default();
    let n = TRANSMISSION_ROUGHNESS.len() as f32;
    let items: Vec<(f32, f32, Vec3)> = TRANSMISSION_ROUGHNESS
        .iter()
        .enumerate()
        .map(|(i, &rough)| {
            let x = (i as f32 - 0.5 * (n - 1.0)) * SPACING;
            (1.5, rough, Vec3::new(x, RADIUS + 0.1, 0.0))
        })
        .collect();
    spheres(&mut m, &mut materials, &items);
    wall(&mut m, RADIUS + 0.1, -0.8, 6.0);
    let cam = Camera::look_at(
        Vec3::new(0.0, RADIUS + 0.1, 4.0),
        Vec3::new(0.0, RADIUS + 0.1, 0.0),
        Vec3::Y,
        0.3,
    );
    let s = scene(
        "transmission-roughness",
        m,
        materials,
        cam,
        Vec3::ZERO,
        settings(640, 200),
    );
    lit_by_studio(s)
}

/// Thin-walled panes of rising roughness in front of the checkered wall.
pub fn frosted_panes() -> Scene {
    let mut materials = wall_materials();
    let mut m = Mesh::default();
    let n = PANE_ROUGHNESS.len() as f32;
    let (side, y) = (0.4, RADIUS + 0.1);
    for (i, &rough) in PANE_ROUGHNESS.iter().enumerate() {
        let idx = materials.len() as u32;
        materials.push(Material {
            kind: MaterialKind::ThinGlass,
            ..rough_glass_material(&format!("pane-r{rough:.2}"), 1.5, rough)
        });
        let x = (i as f32 - 0.5 * (n - 1.0)) * SPACING;
        rect(&mut m, Vec3::new(x, y, 0.0), Vec3::Z, side, side, idx);
    }
    wall(&mut m, y, -0.5, 6.0);
    let cam = Camera::look_at(Vec3::new(0.0, y, 4.0), Vec3::new(0.0, y, 0.0), Vec3::Y, 0.3);
    let s = scene(
        "frosted-panes",
        m,
        materials,
        cam,
        Vec3::ZERO,
        settings(640, 200),
    );
    lit_by_studio(s)
}
