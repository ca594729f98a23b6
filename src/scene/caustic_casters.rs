//! How large the light (emissive triangles and the environment) looks from the surfaces that
//! cast caustics: the `auto` estimator's measure of "a small light" (`render::estimator`).
//!
//! A path tracer finds a caustic L S+ D only when a direction it samples at the diffuse
//! vertex is carried by the specular chain onto an emitter; the chance of that is about the
//! emitter's solid angle as seen from the specular surface, so caustics of lights that look
//! small from the glass or the mirror are what photon mapping renders better (Jensen 2001,
//! *Realistic Image Synthesis Using Photon Mapping*, §9; Hachisuka & Jensen 2009). The light's
//! size next to the scene's does not decide it: a Cornell box and a glass slab under a light
//! of the same 1 % of the bounding box differ fivefold in which estimator wins (docs/estimators.md,
//! "Choosing the estimator").

use super::Scene;
use super::features::{Features, bsdf_features};
use crate::math::color::luminance;
use glam::Vec3;

/// The BSDFs whose surfaces focus light into caustics: specular ones and rough glass.
pub const CASTERS: Features = Features::SMOOTH_GLASS
    .union(Features::THIN_GLASS)
    .union(Features::MIRROR)
    .union(Features::SMOOTH_CONDUCTOR)
    .union(Features::ROUGH_GLASS);

/// At most this many triangles of each kind enter the estimate (casters at their area
/// quantiles, emitters at an even stride): at most 256² point pairs, since the viewer's
/// estimator panel asks for it every frame (finding the triangles still walks the mesh).
const MAX_POINTS: usize = 256;

/// The solid angle (sr) of the scene's light as seen from its caster surfaces, averaged
/// over their area; `None` when the scene has no caster or no emitter (emissive triangle
/// or environment). At each caster point every emitter is a luminance L over a solid angle
/// Ω — an emissive triangle A |cos θ| / d² at its centroid, each texel of the environment
/// its own — and the light's solid angle is their participation ratio (Σ L Ω)² / Σ L² Ω: Ω
/// itself for one uniform emitter, the sum for equal ones, about the sun's for a sky whose
/// power the sun carries (at most 4π).
pub fn emitter_solid_angle_at_casters(scene: &Scene) -> Option<f32> {
    let casters = caster_triangles(scene);
    let emitters = emitter_points(scene);
    let (env, env_sq) = environment_moments(scene);
    if casters.is_empty() || (emitters.is_empty() && env <= 0.0) {
        return None;
    }
    let (mut sum, mut weight) = (0.0f64, 0.0f64);
    for t in area_quantiles(&casters) {
        let (p, _) = centroid_and_normal(scene, t);
        let (mut s1, mut s2) = (env, env_sq);
        for &(c, n_a, l) in &emitters {
            let w = p - c;
            let d2 = w.length_squared();
            let omega = (n_a.dot(w).abs() / (d2 * d2.sqrt())) as f64;
            if omega.is_finite() {
                s1 += l * omega;
                s2 += l * l * omega;
            }
        }
        if s2 > 0.0 {
            sum += (s1 * s1 / s2).min(4.0 * std::f64::consts::PI);
            weight += 1.0;
        }
    }
    (weight > 0.0).then(|| (sum / weight) as f32)
}

/// Up to [`MAX_POINTS`] of the triangles `(t, area)` at the area quantiles (i + ½)/n:
/// equally weighted points for an area-weighted mean (large triangles are never skipped, as
/// an even stride would).
fn area_quantiles(tris: &[(usize, f32)]) -> Vec<usize> {
    let cdf: Vec<f64> = tris
        .iter()
        .scan(0.0f64, |total, &(_, a)| {
            *total += a as f64;
            Some(*total)
        })
        .collect();
    let total = cdf.last().copied().unwrap_or(0.0);
    let n = tris.len().min(MAX_POINTS);
    (0..n)
        .map(|i| {
            let u = (i as f64 + 0.5) / n as f64 * total;
            tris[cdf.partition_point(|&c| c < u).min(tris.len() - 1)].0
        })
        .collect()
}

/// The triangles of materials whose BSDF is a caster and that do not emit, with their
/// (positive) areas.
fn caster_triangles(scene: &Scene) -> Vec<(usize, f32)> {
    let mesh = &scene.mesh;
    let caster_material: Vec<bool> = scene
        .materials
        .iter()
        .map(|m| bsdf_features(scene, m).intersects(CASTERS) && !m.is_emissive())
        .collect();
    (0..mesh.triangle_count())
        .filter(|&t| {
            let m = mesh.tri_material[t] as usize;
            caster_material.get(m).copied().unwrap_or(false)
        })
        .map(|t| (t, mesh.area(t)))
        .filter(|&(_, a)| a > 0.0)
        .collect()
}

/// Up to [`MAX_POINTS`] emissive triangles, each standing for `stride` of them: (centroid,
/// normal × area × stride, luminance of its material's emission).
fn emitter_points(scene: &Scene) -> Vec<(Vec3, Vec3, f64)> {
    let lights = scene.emissive_triangles();
    let stride = lights.len().div_ceil(MAX_POINTS).max(1);
    lights
        .iter()
        .step_by(stride)
        .map(|&t| {
            let (c, n2a) = centroid_and_normal(scene, t as usize);
            let m = scene
                .materials
                .get(scene.mesh.tri_material[t as usize] as usize);
            let l = m.map_or(0.0, |m| luminance(m.emission).max(0.0) as f64);
            (c, n2a * (0.5 * stride as f32), l)
        })
        .filter(|e| e.2 > 0.0)
        .collect()
}

/// ∫ L dω and ∫ L² dω of the environment's luminance over the sphere (the image's, with its
/// strength, or the uniform colour's).
fn environment_moments(scene: &Scene) -> (f64, f64) {
    match &scene.env_map {
        Some(img) => {
            let k = img.strength.max(0.0) as f64;
            (
                img.map.lum_integral as f64 * k,
                img.map.lum_sq_integral as f64 * k * k,
            )
        }
        None => {
            let l = luminance(scene.environment).max(0.0) as f64;
            let four_pi = 4.0 * std::f64::consts::PI;
            (l * four_pi, l * l * four_pi)
        }
    }
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

    /// The environment is light too: a uniform sky alone fills 4π; the generated sun-and-sky
    /// image, whose power the sun's 1.2° disk carries, looks smaller than any built-in lamp;
    /// a dim uniform sky next to a bright small emitter leaves the emitter's solid angle
    /// (the participation ratio weighs by power).
    #[test]
    fn the_environment_counts_by_how_concentrated_it_is() {
        let mut sky = caustic_with(|m| rect(m, Vec3::ZERO, Vec3::Y, 0.01, 0.01, 1));
        sky.environment = Vec3::splat(0.5);
        let sr = emitter_solid_angle_at_casters(&sky).expect("lit by the sky");
        assert!(
            (sr / (4.0 * std::f32::consts::PI) - 1.0).abs() < 1e-4,
            "{sr}"
        );
        sky.env_map = Some(crate::scene::hdri::sun_sky_env());
        let sun = emitter_solid_angle_at_casters(&sky).expect("lit by the sky");
        assert!(sun < 0.01, "sun and sky: {sun} sr");
        let mut both = caustic_with(|m| {
            rect(m, Vec3::ZERO, Vec3::Y, 0.01, 0.01, 1);
            rect(m, Vec3::new(0.0, 2.0, 0.0), -Vec3::Y, 0.1, 0.1, 2);
        });
        both.environment = Vec3::splat(0.01);
        let sr = emitter_solid_angle_at_casters(&both).expect("lit");
        let four_pi = 4.0 * std::f32::consts::PI;
        let (s1, s2) = (
            1000.0 * 0.0025 + 0.01 * four_pi,
            1e6 * 0.0025 + 1e-4 * four_pi,
        );
        let expect = s1 * s1 / s2; // 0.00276: the lamp's 0.0025 sr, a tenth more for the sky
        assert!(
            (sr / expect - 1.0).abs() < 2e-3,
            "lamp 1000 in a sky of 0.01: {sr}"
        );
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
