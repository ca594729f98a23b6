//! Photons aimed at what can focus them. A photon is stored only where a path L S^k D
//! (k ≥ 1) first reaches a diffuse surface, so its first hit must be a surface whose BSDF
//! can be specular — a mirror, smooth or thin glass, a smooth metal. Every other emitted
//! direction carries nothing into the photon map. A finite light therefore emits its photons
//! only into the cones from the light point towards bounding spheres of those surfaces (the
//! projection maps of Jensen 1996, "Global Illumination Using Photon Maps", §2.1, and
//! Jensen 2001, *Realistic Image Synthesis Using Photon Mapping*, §5.2, made exact by
//! weighting): with the emitted direction's density p(ω) = N(ω) / Σ_j Ω_j, where Ω_j is cone
//! j's solid angle and N(ω) the number of cones holding ω, the photon's weight
//! Le cosθ / (p_pos p(ω)) is the same estimator restricted to where its integrand is not
//! zero — unbiased, with every photon path now reaching a caster instead of the few percent
//! a cosine-weighted hemisphere sends there.
//!
//! The targets are the connected pieces of those surfaces (triangles sharing a vertex), each
//! in a bounding sphere, clustered into at most [`MAX_TARGETS`] spheres. Lights at infinity
//! keep their own emission (from the disk over the scene).
//!
//! Since every aimed photon path now meets a caster, an iteration needs fewer of them for as
//! many stored photons: [`photon_paths`].

use crate::bsdf;
use crate::math::color::luminance;
use crate::math::{Frame, rng::Sampler};
use crate::scene::light::LightSet;
use crate::scene::{Material, MaterialKind, Scene};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// At most this many target spheres (each photon looks at all of them).
pub const MAX_TARGETS: usize = 32;

/// Aimed photon paths per iteration, as a multiple of the caster-bound ones an unaimed pass
/// of one path per pixel would trace: 4 × as many caustic photons per iteration, since the
/// caustic's noise is what photon mapping is for (docs/estimators.md, "Photons aimed at the casters",
/// measured at equal time on `caustic`, a variant with its light 8 m away, `cornell-glass`).
pub const AIM_BOOST: f32 = 4.0;

/// At most this many aimed photon paths per pixel: where the casters take much of the
/// light (`cornell-glass`: 29 %), more photons than this cost more time than their noise
/// is worth next to the path-traced rest of the image (same measurements).
pub const MAX_PATHS_PER_PIXEL: f32 = 0.5;

/// Photon paths of one iteration of an image of `pixels` pixels whose lights send
/// `aimed_fraction` of their power towards the targets (`PhotonTargets::aimed_fraction`):
/// [`AIM_BOOST`] times the caster-bound share of one path per pixel, at most
/// [`MAX_PATHS_PER_PIXEL`] per pixel — or one per pixel when nothing is aimed
/// (`aimed_fraction` = 1: lights at infinity only) — and at least one.
pub fn photon_paths(pixels: u32, aimed_fraction: f32) -> u32 {
    let share = if aimed_fraction >= 1.0 {
        1.0
    } else {
        (aimed_fraction * AIM_BOOST).clamp(0.0, MAX_PATHS_PER_PIXEL)
    };
    ((pixels as f32 * share).ceil() as u32).clamp(1, pixels.max(1))
}

/// A bounding sphere of caster surfaces.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    pub center: Vec3,
    pub radius: f32,
}

/// The spheres photons from finite lights are aimed at (none when no surface can be
/// specular: then no photon can be stored either).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PhotonTargets {
    pub spheres: Vec<Sphere>,
}

/// Materials whose BSDF can be a delta lobe (`Bsdf::is_delta`) somewhere: only these can be
/// a photon's first vertex (a superset is safe, a subset would lose caustics). Mirrors
/// always; thin glass, glass and glossy metal only when smooth (`Material::bsdf`), or, for
/// rough glass, where an interface can be index-matched (η = 1 is a smooth pass-through):
/// IOR 1 or the IOR of another dielectric of the scene (`iors`). Rough glass and rough metal
/// scatter every photon off a glossy lobe, which stores nothing: aimed at them, photon paths
/// are traced for nothing (`transmission-roughness`: 120 photons stored from 128,000 paths
/// an iteration; docs/performance.md, "sppm's photon pass").
fn can_be_specular(m: &Material, iors: &[f32]) -> bool {
    let smooth = bsdf::effectively_smooth(bsdf::roughness_to_alpha(m.roughness));
    match m.kind {
        MaterialKind::Mirror => true,
        // A rough sheet scatters off a glossy lobe (`bsdf::RoughThinDielectric`) unless it
        // is index-matched or filmed (then `Material::bsdf` keeps the smooth sheet).
        MaterialKind::ThinGlass => m.sheet_is_smooth(m.ior),
        MaterialKind::GlossyMetal => smooth,
        MaterialKind::Glass => {
            smooth || m.ior == 1.0 || iors.iter().filter(|&&n| n == m.ior).count() > 1
        }
        MaterialKind::MetalRough | MaterialKind::Diffuse => false,
    }
}

/// Per material of `scene`: can it be a photon's specular vertex ([`can_be_specular`])?
fn specular_materials(scene: &Scene) -> Vec<bool> {
    let iors: Vec<f32> = scene
        .materials
        .iter()
        .filter(|m| matches!(m.kind, MaterialKind::Glass | MaterialKind::ThinGlass))
        .map(|m| m.ior)
        .collect();
    scene
        .materials
        .iter()
        .map(|m| can_be_specular(m, &iors))
        .collect()
}

impl PhotonTargets {
    /// The targets of `scene` and the share of the power of `lights` (the scene's) sent
    /// towards them: what an `sppm` render aims with.
    pub fn with_fraction(scene: &Scene, lights: &LightSet) -> (PhotonTargets, f32) {
        let targets = PhotonTargets::new(scene);
        let fraction = targets.aimed_fraction(lights);
        (targets, fraction)
    }

    /// The target spheres of `scene` (none when nothing can be specular).
    pub fn new(scene: &Scene) -> PhotonTargets {
        let pieces = caster_pieces(scene);
        PhotonTargets {
            spheres: cluster(pieces, MAX_TARGETS),
        }
    }

    /// Cone j from `p`: (axis, 1 − cos θ_max, solid angle); the whole sphere of directions
    /// when `p` is inside the sphere.
    #[inline]
    fn cone(s: &Sphere, p: Vec3) -> (Vec3, f32, f32) {
        let to = s.center - p;
        let d2 = to.length_squared();
        let r2 = s.radius * s.radius;
        if d2 <= r2 {
            return (Vec3::Z, 2.0, 4.0 * PI);
        }
        let sin2 = r2 / d2;
        // 1 − √(1 − sin²) without cancellation for small cones.
        let omc = sin2 / (1.0 + (1.0 - sin2).sqrt());
        (to / d2.sqrt(), omc, 2.0 * PI * omc)
    }

    /// A direction from `p` towards the targets and its solid-angle density, from one
    /// uniform number (which cone) and a 2D one (where in it); `None` without targets.
    pub fn sample_dir(&self, p: Vec3, u_pick: f32, u: Vec2) -> Option<(Vec3, f32)> {
        let n = self.spheres.len();
        if n == 0 {
            return None;
        }
        let mut cones = [(Vec3::ZERO, 0.0f32, 0.0f32); MAX_TARGETS];
        let mut total = 0.0;
        for (c, s) in cones.iter_mut().zip(&self.spheres) {
            *c = Self::cone(s, p);
            total += c.2;
        }
        if !(total > 0.0 && total.is_finite()) {
            return None;
        }
        let mut target = u_pick * total;
        let mut j = n - 1;
        for (i, c) in cones[..n].iter().enumerate() {
            if target < c.2 {
                j = i;
                break;
            }
            target -= c.2;
        }
        let (axis, omc, _) = cones[j];
        let w = if omc >= 2.0 {
            crate::math::sampling::uniform_sphere(u)
        } else {
            // Uniform in the cone: 1 − cos θ = u₀ (1 − cos θ_max).
            let one_minus_cos = u.x * omc;
            let cos = 1.0 - one_minus_cos;
            let sin = (one_minus_cos * (2.0 - one_minus_cos)).max(0.0).sqrt();
            let phi = 2.0 * PI * u.y;
            Frame::from_normal(axis).to_world(Vec3::new(sin * phi.cos(), sin * phi.sin(), cos))
        };
        // The density of the mixture: every cone holding w counts (cone j by construction).
        let mut holding = 1u32;
        for (i, &(a, omc, _)) in cones[..n].iter().enumerate() {
            if i != j && (omc >= 2.0 || 1.0 - w.dot(a) <= omc) {
                holding += 1;
            }
        }
        Some((w, holding as f32 / total))
    }
}

/// Light-sample pairs in [`PhotonTargets::aimed_fraction`]'s estimate.
const FRACTION_SAMPLES: u32 = 1024;

impl PhotonTargets {
    /// The fraction of the lights' emitted power (luminance) that leaves towards the
    /// targets (lights at infinity count whole: they are not aimed), estimated from
    /// [`FRACTION_SAMPLES`] emissions drawn both ways, with a fixed seed: Σ aimed weights /
    /// Σ own weights, each an unbiased estimate of its power. 1 without finite lights.
    pub fn aimed_fraction(&self, lights: &LightSet) -> f32 {
        let (mut aimed, mut all) = (0.0f64, 0.0f64);
        for i in 0..FRACTION_SAMPLES {
            let mut s = Sampler::new(i, 0, 0x5eed);
            let Some((light, pick)) = lights.pick(s.next_1d()) else {
                return 1.0;
            };
            let (u_pos, u_dir, u_side) = (s.next_2d(), s.next_2d(), s.next_1d());
            let Some(le) = light.sample_le(u_pos, u_dir, u_side, pick) else {
                continue;
            };
            let weight = |l: Vec3, w: Vec3, pdf_dir: f32| {
                let cos = if le.delta_pos || le.infinite {
                    1.0
                } else {
                    le.n.dot(w).abs()
                };
                let x = luminance(l) * cos / (le.pdf_pos * pdf_dir);
                if x.is_finite() && x > 0.0 {
                    x as f64
                } else {
                    0.0
                }
            };
            let own = if le.pdf_dir > 0.0 {
                weight(le.l, le.dir, le.pdf_dir)
            } else {
                0.0
            };
            all += own;
            if le.infinite {
                aimed += own;
            } else if let Some((w, pdf)) = self.sample_dir(le.p, s.next_1d(), s.next_2d()) {
                aimed += weight(light.le(le.p, le.n, w), w, pdf);
            }
        }
        if all > 0.0 {
            (aimed / all).clamp(0.0, 1.0) as f32
        } else {
            1.0
        }
    }
}

/// Bounding spheres of the connected pieces of the surfaces that can be specular (triangles
/// joined by shared vertices). Linear in the mesh but for one sort of the caster triangles:
/// a mesh whose faces share no vertex gives one piece per triangle, which `cluster` merges.
fn caster_pieces(scene: &Scene) -> Vec<Sphere> {
    let mesh = &scene.mesh;
    let specular = specular_materials(scene);
    let tris: Vec<usize> = (0..mesh.triangle_count())
        .filter(|&t| {
            let m = mesh.tri_material[t] as usize;
            specular.get(m).copied().unwrap_or(false)
        })
        .collect();
    if tris.is_empty() {
        return Vec::new();
    }
    // Union–find over the vertices the caster triangles use.
    let mut parent: Vec<usize> = (0..mesh.positions.len()).collect();
    for &t in &tris {
        let [a, b, c] = mesh.indices[t].map(|i| i as usize);
        union(&mut parent, a, b);
        union(&mut parent, a, c);
    }
    let mut by_piece: Vec<(usize, usize)> = tris
        .iter()
        .map(|&t| (find(&mut parent, mesh.indices[t][0] as usize), t))
        .collect();
    by_piece.sort_unstable();
    by_piece
        .chunk_by(|a, b| a.0 == b.0)
        .filter_map(|piece| {
            let points = || piece.iter().flat_map(|&(_, t)| mesh.tri(t));
            let (lo, hi) = points().fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(p), hi.max(p))
            });
            // Centred on the box, as wide as the farthest vertex (a ball's own radius, not
            // its box's half-diagonal, √3 times wider).
            let center = 0.5 * (lo + hi);
            let radius = points().map(|p| p.distance(center)).fold(0.0f32, f32::max);
            // A piece of zero extent cannot be hit (and its cone would have no solid angle).
            let ok = center.is_finite() && radius.is_finite() && radius > 0.0;
            ok.then_some(Sphere { center, radius })
        })
        .collect()
}

fn find(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

fn union(parent: &mut [usize], a: usize, b: usize) {
    let (ra, rb) = (find(parent, a), find(parent, b));
    if ra != rb {
        parent[ra.max(rb)] = ra.min(rb);
    }
}

/// At most `max` spheres covering `pieces`: the group with the widest spread of centres is
/// split at the median of its widest axis until there are `max` groups.
fn cluster(pieces: Vec<Sphere>, max: usize) -> Vec<Sphere> {
    let mut groups = vec![pieces];
    groups.retain(|g| !g.is_empty());
    while groups.len() < max {
        let spread = |g: &Vec<Sphere>| {
            let (lo, hi) = g.iter().fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |b, s| {
                (b.0.min(s.center), b.1.max(s.center))
            });
            hi - lo
        };
        let Some((k, ext)) = groups
            .iter()
            .enumerate()
            .filter(|(_, g)| g.len() > 1)
            .map(|(k, g)| (k, spread(g)))
            .max_by(|a, b| a.1.max_element().total_cmp(&b.1.max_element()))
        else {
            break;
        };
        let axis = ext.max_position();
        let mut g = groups.swap_remove(k);
        g.sort_by(|a, b| a.center[axis].total_cmp(&b.center[axis]));
        let upper = g.split_off(g.len() / 2);
        groups.push(g);
        groups.push(upper);
    }
    groups.iter().map(|g| enclosing(g)).collect()
}

/// A sphere holding every sphere of `g` (centred on their bounding box).
fn enclosing(g: &[Sphere]) -> Sphere {
    if let [one] = g {
        return *one;
    }
    let (lo, hi) = g.iter().fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |b, s| {
        (
            b.0.min(s.center - Vec3::splat(s.radius)),
            b.1.max(s.center + Vec3::splat(s.radius)),
        )
    });
    let center = 0.5 * (lo + hi);
    let radius = g
        .iter()
        .map(|s| s.center.distance(center) + s.radius)
        .fold(0.0f32, f32::max);
    Sphere { center, radius }
}

#[cfg(test)]
mod tests;
