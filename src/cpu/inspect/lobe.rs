//! The BSDF lobe at an inspected vertex, in the plane of incidence: the polar plot of a
//! lecture's "three BRDF types" slide (a diffuse circle, a glossy lobe around the mirror
//! direction, a mirror's single spike), drawn from the BSDF the walk itself scattered with.
//!
//! The plot treats the camera ray as a beam of light arriving along −wo and shows where its
//! energy goes: f(wo, wi)·|cos θ_i| in [`TransportMode::Importance`] (no 1/η² radiance
//! scaling, so a smooth dielectric's reflected and refracted fractions add up to one, Veach
//! 1997 §5.2). By reciprocity the same lobe, in radiance mode up to η², says from where
//! light reaches the camera. Delta lobes have no density: they are drawn as spikes whose
//! length is the fraction of energy they carry, found by sampling the BSDF.

use super::record::ScatterRecord;
use crate::bsdf::{BxDF, TransportMode};
use crate::math::Color;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// Angular samples of the continuous lobe over the full circle.
pub const SLICE_STEPS: usize = 720;
/// Stratified BSDF samples per axis (uc × u2.x × u2.y) for the albedo and the spikes.
const GRID: usize = 24;

/// One delta lobe: its direction in the plot's plane and the energy fraction it carries.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spike {
    /// Angle from the normal (radians): positive on the incoming ray's side, |t| > π/2
    /// below the surface.
    pub angle: f32,
    pub fraction: f32,
    pub transmit: bool,
}

/// The lobe of one vertex's BSDF in its plane of incidence.
#[derive(Clone, Debug)]
pub struct LobeSlice {
    /// Angle of the incoming ray's origin side (wo) from the normal, radians in [0, π].
    pub incident: f32,
    /// (angle, f·|cos θ_i|) over the full circle: the continuous (diffuse and glossy) part.
    pub density: Vec<(f32, f32)>,
    /// Delta lobes (mirror reflection, specular refraction).
    pub spikes: Vec<Spike>,
    /// Directional albedo of the continuous part: the fraction of the incoming energy it
    /// scatters (reflected + transmitted).
    pub continuous_albedo: f32,
}

impl LobeSlice {
    /// Total fraction of the incoming energy scattered (≤ 1 for an energy-conserving BSDF).
    pub fn albedo(&self) -> f32 {
        self.continuous_albedo + self.spikes.iter().map(|s| s.fraction).sum::<f32>()
    }

    /// Largest value of the continuous part.
    pub fn peak(&self) -> f32 {
        self.density.iter().map(|p| p.1).fold(0.0, f32::max)
    }
}

/// A colour as one number: the mean of the RGB channels, or of the four hero wavelengths.
fn intensity(c: Color, spectral: bool) -> f32 {
    if spectral {
        (c.x + c.y + c.z + c.w) * 0.25
    } else {
        (c.x + c.y + c.z) / 3.0
    }
}

/// The plot's plane: the shading normal and wo's tangential direction `u`. A direction at
/// angle t from the normal, on wo's side for t > 0.
struct Plane {
    u: Vec2,
}

impl Plane {
    fn of(wo: Vec3) -> Plane {
        let h = Vec2::new(wo.x, wo.y);
        let u = if h.length() > 1e-6 {
            h.normalize()
        } else {
            Vec2::X
        };
        Plane { u }
    }

    fn dir(&self, t: f32) -> Vec3 {
        let (s, c) = t.sin_cos();
        Vec3::new(self.u.x * s, self.u.y * s, c)
    }

    /// Angle of `w` in the plane (its out-of-plane part is dropped).
    fn angle(&self, w: Vec3) -> f32 {
        let along = w.x * self.u.x + w.y * self.u.y;
        along.atan2(w.z)
    }
}

/// The lobe of `rec`'s BSDF for the direction it recorded.
pub fn lobe_slice(rec: &ScatterRecord) -> LobeSlice {
    let wo = rec.wo.normalize_or(Vec3::Z);
    let plane = Plane::of(wo);
    let density = (0..SLICE_STEPS)
        .map(|i| {
            let t = -PI + 2.0 * PI * (i as f32 + 0.5) / SLICE_STEPS as f32;
            let wi = plane.dir(t);
            let f = rec.bsdf.eval(wo, wi, TransportMode::Importance);
            (t, intensity(f, rec.spectral).max(0.0) * wi.z.abs())
        })
        .collect();
    let (continuous_albedo, spikes) = sampled_energy(rec, wo, &plane);
    LobeSlice {
        incident: plane.angle(wo).abs(),
        density,
        spikes,
        continuous_albedo,
    }
}

/// Stratified samples of the BSDF: the continuous part's albedo (the mean weight of its
/// samples) and each delta lobe's energy fraction. A delta sample's weight is the lobe's
/// energy over the probability of choosing it (the `BsdfSample` convention), so weight × pdf
/// is the lobe's energy exactly, not up to the grid's resolution in the lobe choice; a smooth
/// surface's delta directions depend on wo only.
fn sampled_energy(rec: &ScatterRecord, wo: Vec3, plane: &Plane) -> (f32, Vec<Spike>) {
    let n = (GRID * GRID * GRID) as f32;
    let g = |k: usize| (k as f32 + 0.5) / GRID as f32;
    let mut continuous = 0.0;
    let mut spikes: Vec<Spike> = Vec::new();
    for a in 0..GRID {
        for b in 0..GRID {
            for c in 0..GRID {
                let u2 = Vec2::new(g(b), g(c));
                let Some(s) = rec.bsdf.sample(wo, g(a), u2, TransportMode::Importance) else {
                    continue;
                };
                let e = intensity(s.weight, rec.spectral).max(0.0);
                if !s.is_delta {
                    continuous += e / n;
                    continue;
                }
                let transmit = s.event == crate::bsdf::Event::Transmit;
                if !spikes.iter().any(|k| k.transmit == transmit) {
                    spikes.push(Spike {
                        angle: plane.angle(s.wi),
                        fraction: e * s.pdf,
                        transmit,
                    });
                }
            }
        }
    }
    (continuous, spikes)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::fresnel::fresnel_dielectric;
    use crate::bsdf::{Bsdf, Lambert, MicrofacetDistribution, Mirror, RoughConductor};
    use crate::bsdf::{SmoothDielectric, roughness_to_alpha};
    use crate::math::rgb;

    fn at(bsdf: Bsdf, theta_deg: f32) -> LobeSlice {
        let t = theta_deg.to_radians();
        lobe_slice(&ScatterRecord {
            bsdf,
            wo: Vec3::new(t.sin(), 0.0, t.cos()),
            spectral: false,
        })
    }

    #[test]
    fn lambert_is_a_circle_through_the_point() {
        let s = at(Bsdf::Lambert(Lambert::new(rgb(0.8, 0.8, 0.8))), 40.0);
        for &(t, v) in &s.density {
            let want = if t.abs() < PI / 2.0 {
                0.8 / PI * t.cos()
            } else {
                0.0
            };
            assert!((v - want).abs() < 1e-5, "{t}: {v} vs {want}");
        }
        assert!(s.spikes.is_empty());
        assert!(
            (s.continuous_albedo - 0.8).abs() < 5e-3,
            "{}",
            s.continuous_albedo
        );
        assert!((s.incident - 40f32.to_radians()).abs() < 1e-5);
    }

    #[test]
    fn a_mirror_is_one_spike_at_the_reflected_angle() {
        let s = at(
            Bsdf::Mirror(Mirror {
                reflectance: rgb(0.9, 0.9, 0.9),
            }),
            30.0,
        );
        assert!(s.peak() == 0.0 && s.continuous_albedo == 0.0);
        assert_eq!(s.spikes.len(), 1);
        let k = s.spikes[0];
        assert!(!k.transmit && (k.fraction - 0.9).abs() < 1e-4, "{k:?}");
        assert!((k.angle + 30f32.to_radians()).abs() < 1e-4, "{k:?}");
    }

    #[test]
    fn glass_splits_into_fresnel_reflection_and_snell_refraction() {
        let eta = 1.5;
        let s = at(Bsdf::SmoothDielectric(SmoothDielectric { eta }), 60.0);
        let f = fresnel_dielectric(60f32.to_radians().cos(), eta);
        let r = s.spikes.iter().find(|k| !k.transmit).expect("reflection");
        let t = s.spikes.iter().find(|k| k.transmit).expect("refraction");
        assert!((r.fraction - f).abs() < 1e-5, "{r:?} vs F = {f}");
        assert!((t.fraction - (1.0 - f)).abs() < 1e-5, "{t:?}");
        // Snell: sinθ_t = sinθ_i / η, on the far side below the surface (angle −(π − θ_t)).
        let theta_t = (60f32.to_radians().sin() / eta).asin();
        assert!((t.angle + (PI - theta_t)).abs() < 1e-3, "{t:?}");
        assert!((s.albedo() - 1.0).abs() < 1e-5);
    }

    #[test]
    fn a_glossy_lobe_peaks_near_the_mirror_direction() {
        let b = Bsdf::RoughConductor(RoughConductor {
            reflectance: rgb(1.0, 1.0, 1.0),
            alpha: roughness_to_alpha(0.3),
            dist: MicrofacetDistribution::Ggx,
        });
        let s = at(b, 35.0);
        let (t_peak, _) = s
            .density
            .iter()
            .copied()
            .fold((0.0, 0.0), |a, p| if p.1 > a.1 { p } else { a });
        // The peak leans towards grazing (off-specular peak) but stays on the far side,
        // within a few tens of degrees of the mirror direction.
        assert!(t_peak < 0.0, "{t_peak}");
        assert!(
            (t_peak + 35f32.to_radians()).abs() < 25f32.to_radians(),
            "{t_peak}"
        );
        assert!(s.spikes.is_empty());
        assert!(
            s.albedo() <= 1.0 + 1e-3 && s.albedo() > 0.8,
            "{}",
            s.albedo()
        );
    }
}
