//! How large the emitters look from the surfaces that cast caustics: the `auto` estimator's
//! measure of "a small light" (`render::estimator`).
//!
//! A path tracer finds a caustic L S+ D only when a direction it samples at the diffuse
//! vertex is carried by the specular chain onto an emitter; the chance of that is about the
//! emitter's solid angle as seen from the specular surface, so caustics of lights that look
//! small from the glass or the mirror are what photon mapping renders better (Jensen 2001,
//! *Realistic Image Synthesis Using Photon Mapping*, §9; Hachisuka & Jensen 2009). The light's
//! size next to the scene's does not decide it: a Cornell box and a glass slab under a light
//! of the same 1 % of the bounding box differ fivefold in which estimator wins (README,
//! "Choosing the estimator").

use super::Scene;
use super::features::{Features, bsdf_features};
use glam::Vec3;
use std::f32::consts::TAU;

/// The BSDFs whose surfaces focus light into caustics: specular ones and rough glass.
pub const CASTERS: Features = Features::SMOOTH_GLASS
    .union(Features::THIN_GLASS)
    .union(Features::MIRROR)
    .union(Features::SMOOTH_CONDUCTOR)
    .union(Features::ROUGH_GLASS);

/// At most this many triangles of each kind enter the estimate (an even stride through the
/// list), so that the estimate costs at most 256² point pairs (the viewer's
/// estimator panel asks for it every frame).
const MAX_POINTS: usize = 256;

/// The solid angle (sr) that the emissive triangles subtend, summed over emitters (at most
/// 2π) and averaged over the caster surfaces by area; `None` when the scene has no caster or
/// no emissive triangle. Each emitter triangle counts as a point at its centroid: A |cos θ| /
/// d² from each caster triangle's centroid.
pub fn emitter_solid_angle_at_casters(scene: &Scene) -> Option<f32> {
    let mesh = &scene.mesh;
    let caster_material: Vec<bool> = scene
        .materials
        .iter()
        .map(|m| bsdf_features(scene, m).intersects(CASTERS) && !m.is_emissive())
        .collect();
    let casters: Vec<usize> = (0..mesh.triangle_count())
        .filter(|&t| {
            let m = mesh.tri_material[t] as usize;
            caster_material.get(m).copied().unwrap_or(false) && mesh.area(t) > 0.0
        })
        .collect();
    let lights = scene.emissive_triangles();
    if casters.is_empty() || lights.is_empty() {
        return None;
    }
    // Each sampled emitter stands for `stride` of them: (centroid, normal × area × stride).
    let stride = lights.len().div_ceil(MAX_POINTS);
    let emitters: Vec<(Vec3, Vec3)> = lights
        .iter()
        .step_by(stride)
        .map(|&t| {
            let (c, n2a) = centroid_and_normal(scene, t as usize);
            (c, n2a * (0.5 * stride as f32))
        })
        .collect();
    let (mut sum, mut weight) = (0.0f64, 0.0f64);
    for &t in casters.iter().step_by(casters.len().div_ceil(MAX_POINTS)) {
        let (p, _) = centroid_and_normal(scene, t);
        let omega: f32 = emitters
            .iter()
            .map(|&(c, n_a)| {
                let w = p - c;
                let d2 = w.length_squared();
                let term = n_a.dot(w).abs() / (d2 * d2.sqrt());
                if term.is_finite() { term } else { 0.0 }
            })
            .sum();
        let a = mesh.area(t) as f64;
        sum += a * omega.min(TAU) as f64;
        weight += a;
    }
    (weight > 0.0).then(|| (sum / weight) as f32)
}

/// Triangle `t`'s centroid and (p1 − p0) × (p2 − p0), whose length is twice its area.
fn centroid_and_normal(scene: &Scene, t: usize) -> (Vec3, Vec3) {
    let [a, b, c] = scene.mesh.indices[t].map(|i| scene.mesh.positions[i as usize]);
    ((a + b + c) / 3.0, (b - a).cross(c - a))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Mesh;
    use crate::scene::builtin::shapes::rect;

    /// `builtin:caustic`'s materials (0 floor, 1 glass, 2 light) over the mesh `build` makes.
    fn caustic_with(build: impl FnOnce(&mut Mesh)) -> Scene {
        let mut s = Scene::load("builtin:caustic").expect("built-in");
        s.mesh = Mesh::default();
        build(&mut s.mesh);
        s
    }

    /// A small glass square under a 0.1 × 0.1 emitter at height 2 sees it as A / d² =
    /// 0.0025 sr; a second, identical emitter doubles it; light below the glass still counts
    /// (|cos|: which side the caustic forms on is not the question).
    #[test]
    fn a_small_emitter_subtends_area_over_distance_squared() {
        let one = caustic_with(|m| {
            rect(m, Vec3::ZERO, Vec3::Y, 0.01, 0.01, 1);
            rect(m, Vec3::new(0.0, 2.0, 0.0), -Vec3::Y, 0.1, 0.1, 2);
        });
        let sr = emitter_solid_angle_at_casters(&one).expect("caster and emitter");
        assert!((sr / 0.0025 - 1.0).abs() < 1e-3, "{sr}");
        let two = caustic_with(|m| {
            rect(m, Vec3::ZERO, Vec3::Y, 0.01, 0.01, 1);
            rect(m, Vec3::new(0.0, 2.0, 0.0), -Vec3::Y, 0.1, 0.1, 2);
            rect(m, Vec3::new(0.0, -2.0, 0.0), Vec3::Y, 0.1, 0.1, 2);
        });
        let sr2 = emitter_solid_angle_at_casters(&two).expect("caster and emitter");
        assert!((sr2 / sr - 2.0).abs() < 1e-3, "{sr2} against {sr}");
    }

    /// A scene without a caster, or without an emissive triangle, has no such solid angle.
    #[test]
    fn none_without_casters_or_emitters() {
        let no_caster = caustic_with(|m| {
            rect(m, Vec3::ZERO, Vec3::Y, 1.0, 1.0, 0);
            rect(m, Vec3::new(0.0, 2.0, 0.0), -Vec3::Y, 0.1, 0.1, 2);
        });
        assert_eq!(emitter_solid_angle_at_casters(&no_caster), None);
        let no_light = caustic_with(|m| rect(m, Vec3::ZERO, Vec3::Y, 1.0, 1.0, 1));
        assert_eq!(emitter_solid_angle_at_casters(&no_light), None);
    }

    /// A solid angle does not depend on the scene's unit: scaled by 10⁻⁵ … 10⁵ every
    /// built-in with casters and emitters measures the same (so `auto` picks the same).
    #[test]
    fn the_measure_is_scale_free() {
        for name in [
            "cornell-glass",
            "glass-slab",
            "caustic",
            "rough-glass",
            "materials",
        ] {
            let base = Scene::load(&format!("builtin:{name}")).expect("built-in");
            let sr = emitter_solid_angle_at_casters(&base).expect("caster and emitter");
            for k in [1e-5f32, 1e-3, 1e3, 1e5] {
                let mut s = base.clone();
                s.mesh.positions.iter_mut().for_each(|p| *p *= k);
                let got = emitter_solid_angle_at_casters(&s).expect("caster and emitter");
                assert!(
                    (got / sr - 1.0).abs() < 1e-4,
                    "{name} × {k}: {got} against {sr}"
                );
            }
        }
    }
}
