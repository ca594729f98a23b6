//! The Khronos-style built-ins `ior-grid` and `transmission-roughness` (studio-lit glass
//! spheres): their layout, and the index-matched column (IOR 1.0) vanishing at every
//! roughness, the rough dielectric's degenerate case η = 1.

mod common_scenes;

use common_scenes::{assert_blocks_agree, cpu_block_runs};
use glam::Vec3;
use refract::cpu::Renderer;
use refract::render::Estimator;
use refract::scene::builtin::khronos::{
    IOR_COLUMNS, ROUGHNESS_ROWS, TRANSMISSION_ROUGHNESS, sphere_name,
};
use refract::scene::{Camera, Scene};

#[test]
fn the_grids_hold_one_studio_lit_sphere_per_ior_and_roughness() {
    let grid = Scene::load("builtin:ior-grid").unwrap();
    assert!(grid.env_map.is_some() && grid.emissive_triangles().is_empty());
    for &r in &ROUGHNESS_ROWS {
        for &n in &IOR_COLUMNS {
            let m = grid
                .materials
                .iter()
                .find(|m| m.name == sphere_name(n, r))
                .unwrap_or_else(|| panic!("no sphere n {n} r {r}"));
            assert_eq!((m.ior, m.roughness), (n, r));
            assert!(m.is_transmissive());
        }
    }
    let row = Scene::load("builtin:transmission-roughness").unwrap();
    for &r in &TRANSMISSION_ROUGHNESS {
        assert!(row.materials.iter().any(|m| m.name == sphere_name(1.5, r)));
    }
}

/// `ior-grid`'s IOR 1.0 column filling a 48×80 image, with or without those spheres (their
/// triangles removed).
fn small_grid(drop_index_matched: bool) -> Scene {
    let mut s = Scene::load("builtin:ior-grid").unwrap();
    (s.settings.width, s.settings.height) = (48, 80);
    s.settings.max_depth = 12;
    let (x, mid) = (-1.75, s.camera.position.y);
    s.camera = Camera::look_at(
        Vec3::new(x, mid, 4.0),
        Vec3::new(x, mid, 0.0),
        Vec3::Y,
        0.65,
    );
    if drop_index_matched {
        let matched: Vec<bool> = s
            .materials
            .iter()
            .map(|m| m.is_transmissive() && m.ior == 1.0)
            .collect();
        let keep: Vec<usize> = (0..s.mesh.indices.len())
            .filter(|&t| !matched[s.mesh.tri_material[t] as usize])
            .collect();
        s.mesh.indices = keep.iter().map(|&t| s.mesh.indices[t]).collect();
        s.mesh.tri_material = keep.iter().map(|&t| s.mesh.tri_material[t]).collect();
    }
    s
}

#[test]
fn index_matched_spheres_vanish_at_every_roughness() {
    let with = Renderer::new(small_grid(false)).unwrap();
    let without = Renderer::new(small_grid(true)).unwrap();
    assert!(without.scene.mesh.indices.len() < with.scene.mesh.indices.len());
    let a = cpu_block_runs(&with, Estimator::Path, 16, None, 11, 6);
    let b = cpu_block_runs(&without, Estimator::Path, 16, None, 31, 6);
    let t = assert_blocks_agree("ior-grid with vs without the IOR 1.0 column", &a, &b);
    assert!(
        t.mean_a > 0.05,
        "the studio lights the grid: mean {}",
        t.mean_a
    );
}
