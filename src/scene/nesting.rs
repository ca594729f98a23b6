//! Nested dielectrics (Schmidt & Budge 2002, "Simple nested dielectrics in ray traced
//! images"): the limits the CPU (`cpu::medium`) and GPU (interaction.wgsl) medium stacks
//! share, and the test that decides whether a scene needs the stack at all.

use super::{MaterialKind, Scene};
use glam::Vec3;

/// The most volumes a path tracks at once; a push onto a full stack forgets the outermost.
pub const MEDIUM_STACK_DEPTH: usize = 4;

/// More false hits than this on one path end it (a ray trapped between coincident
/// surfaces of nested volumes cannot loop for ever).
pub const FALSE_HIT_LIMIT: u32 = 64;

/// Do the dielectric volumes of `scene` (materials marked in `used`) possibly nest: the
/// bounds of a solid-glass material overlap those of another solid or thin glass, or a solid
/// sets a priority?
pub(super) fn nested_volumes(scene: &Scene, used: &[bool]) -> bool {
    let kind = |m: usize| used[m].then_some(scene.materials[m].kind);
    let solid = |m: usize| kind(m) == Some(MaterialKind::Glass);
    if (0..scene.materials.len()).any(|m| solid(m) && scene.materials[m].priority != 0) {
        return true;
    }
    let mut bounds: Vec<Option<(Vec3, Vec3)>> = vec![None; scene.materials.len()];
    for (t, &m) in scene.mesh.tri_material.iter().enumerate() {
        let m = m as usize;
        if m >= bounds.len() || !scene.materials[m].is_transmissive() || kind(m).is_none() {
            continue;
        }
        for &i in &scene.mesh.indices[t] {
            let p = scene.mesh.positions[i as usize];
            let b = bounds[m].get_or_insert((p, p));
            *b = (b.0.min(p), b.1.max(p));
        }
    }
    let boxes: Vec<(usize, (Vec3, Vec3))> = bounds
        .into_iter()
        .enumerate()
        .filter_map(|(m, b)| b.map(|b| (m, b)))
        .collect();
    boxes.iter().enumerate().any(|(i, (ma, a))| {
        boxes[i + 1..].iter().any(|(mb, b)| {
            (solid(*ma) || solid(*mb)) && a.0.cmple(b.1).all() && b.0.cmple(a.1).all()
        })
    })
}
