//! The polarising part of every BSDF: for a scattering event (wo, wi) the Mueller matrix in
//! the s/p basis of `bsdf::fresnel_polarized`, normalised to m₀₀ = 1 (issue 38). The
//! scalar BSDF already carries the event's intensity (its value, weight and pdf are
//! unchanged), so a polarised walk multiplies its Stokes chain by the scalar weight times
//! this matrix: for unpolarised input the walk's intensity is the scalar one.
//!
//! - Smooth and rough dielectrics: Fresnel reflection or refraction, for a rough one at the
//!   microfacet normal m (the half vector of Walter et al. 2007, eqs. 13 and 16), where
//!   wo, wi and m share the plane of incidence (Wilkie & Weidlich 2012, §5.3; Mitsuba 3's
//!   polarised `roughdielectric` does the same).
//! - Conductors with a complex IOR: Fresnel reflection with η − ik per colour lane, at the
//!   normal or at the microfacet normal.
//! - The mirror and the constant-reflectance rough conductor: the ideal conductor
//!   (r_s = −1, r_p = 1), their tint being the scalar part.
//! - Thin dielectric sheets: one interface's reflection; transmission through both
//!   interfaces (the inner reflections' polarisation is neglected).
//! - Lambert and the diffuse lobe of glTF metallic-roughness: the depolariser.
//! - A thin film (iridescence) on any of these: its base's matrix (the film's own
//!   polarisation, an Airy sum per polarisation, is not followed).
//! - glTF metallic-roughness's specular lobe: Schlick's F has no phases; its polarisation is
//!   that of dielectric reflection at the material's IOR, blended towards the ideal
//!   conductor by `metallic` (an approximation; documented in docs/polarization.md).

use super::{Bsdf, BsdfSample, BxDF, Event, Lobe, LobeValues};
use crate::math::mueller::depolarizer;
use glam::Vec3;

pub use super::fresnel_polarized::MuellerLanes;

/// The normalised Mueller matrix of the event (wo, wi) of `bsdf` in class `lobe` (local
/// frame, wi = the light's incoming direction, wo = where it leaves to): each variant's own
/// [`BxDF::mueller`], in its file.
#[inline]
pub fn event_mueller(bsdf: &Bsdf, wo: Vec3, wi: Vec3, event: Event, lobe: Lobe) -> MuellerLanes {
    bsdf.mueller(wo, wi, event, lobe)
}

/// The Mueller weight of a sampled event: the sample's scalar weight (per lane) times its
/// normalised matrix.
pub fn sample_mueller(bsdf: &Bsdf, wo: Vec3, s: &BsdfSample) -> MuellerLanes {
    let m = event_mueller(bsdf, wo, s.wi, s.event, s.lobe);
    std::array::from_fn(|l| m[l] * s.weight[l])
}

/// The Mueller BSDF value f(wo, wi) of a connection, from its per-class scalar values `f`
/// (`Bsdf::eval_lobes`, already restricted to the classes a path filter accepts): each
/// class's value times its normalised matrix.
pub fn eval_mueller(bsdf: &Bsdf, wo: Vec3, wi: Vec3, f: LobeValues) -> MuellerLanes {
    let event = if wo.z * wi.z >= 0.0 {
        Event::Reflect
    } else {
        Event::Transmit
    };
    let g = event_mueller(bsdf, wo, wi, event, Lobe::G);
    std::array::from_fn(|l| depolarizer() * f.d[l] + g[l] * f.g[l])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::{MicrofacetDistribution, RoughDielectric, SmoothDielectric};
    use crate::bsdf::{TransportMode, metal_rough::MetalRough};
    use crate::math::Color;
    use glam::Vec2;

    #[test]
    fn unpolarized_intensity_is_the_scalar_weight() {
        let wo = Vec3::new(0.5, 0.1, 0.7).normalize();
        let bsdfs = [
            Bsdf::SmoothDielectric(SmoothDielectric { eta: 1.5 }),
            Bsdf::RoughDielectric(RoughDielectric {
                eta: 1.5,
                alpha: 0.3,
                dist: MicrofacetDistribution::Ggx,
            }),
            Bsdf::MetalRough(MetalRough {
                base_color: Color::new(0.8, 0.5, 0.2, 0.0),
                metallic: 0.3,
                alpha: 0.2,
                ior: 1.5,
                specular_factor: 1.0,
                specular_color: Color::ONE,
            }),
        ];
        for b in bsdfs {
            for i in 0..64 {
                let u = Vec2::new((i % 8) as f32 / 8.0 + 0.05, (i / 8) as f32 / 8.0 + 0.05);
                let Some(s) = b.sample(wo, (i as f32 + 0.5) / 64.0, u, TransportMode::Radiance)
                else {
                    continue;
                };
                let m = sample_mueller(&b, wo, &s);
                for (l, ml) in m.iter().enumerate().take(3) {
                    let i_out = (*ml * Vec4::X).x;
                    assert!((i_out - s.weight[l]).abs() <= 1e-6 * s.weight[l].abs().max(1.0));
                }
            }
        }
    }

    use glam::Vec4;

    #[test]
    fn diffuse_depolarizes() {
        let b = Bsdf::Lambert(crate::bsdf::Lambert {
            albedo: Color::splat(0.5),
            uniform: false,
        });
        let (wo, wi) = (Vec3::Z, Vec3::new(0.3, 0.0, 0.9).normalize());
        let m = event_mueller(&b, wo, wi, Event::Reflect, Lobe::D);
        assert_eq!(m[0] * Vec4::new(1.0, 1.0, 0.0, 0.0), Vec4::X);
    }
}
