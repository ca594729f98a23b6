//! Unit tests of the scene edits: the orbit round trip and refused material edits.

use super::*;

#[test]
fn orbit_reproduces_the_scene_camera() {
    let scene = crate::scene::builtin::cornell_glass();
    let o = CameraEdit::default().orbit(&scene);
    let cam = o.camera(scene.camera.yfov);
    assert!((cam.position - scene.camera.position).length() < 1e-4);
    assert!((cam.forward() - scene.camera.forward()).length() < 1e-4);
}

#[test]
fn edits_that_break_energy_are_skipped_with_a_warning() {
    let mut scene = crate::scene::builtin::cornell_glass();
    let before = scene.materials.clone();
    let mut ior = MaterialEdit::from_material(0, &scene.materials[0]);
    ior.ior = 1e-30;
    let mut albedo = MaterialEdit::from_material(0, &scene.materials[0]);
    albedo.base_color = [1e30; 3];
    let mut warnings = Vec::new();
    apply_materials(&[ior, albedo], &mut scene, &mut warnings);
    assert_eq!(scene.materials, before);
    assert_eq!(warnings.len(), 2, "{warnings:?}");
    assert!(warnings[0].contains("ior"), "{}", warnings[0]);
    assert!(warnings[1].contains("base_color"), "{}", warnings[1]);
}
