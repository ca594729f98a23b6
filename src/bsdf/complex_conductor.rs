//! Conductors with a complex IOR η − ik (tabulated metals, `bsdf::metal_ior`) and the exact
//! conductor Fresnel term: a smooth one (delta reflection, [`Lobe::S`]) and a rough one (the
//! microfacet lobe of [`RoughConductor`] with F at the microfacet normal, [`Lobe::G`]).

use super::MicrofacetDistribution;
use super::fresnel::fresnel_conductor_color;
use super::fresnel_polarized::{MuellerLanes, all, conductor_mueller, half_vector};
use super::metal_ior::Metal;
use super::{BsdfSample, BxDF, Event, Lobe, RoughConductor, TransportMode};
use crate::math::Color;
use crate::math::mueller::depolarizer;
use glam::{Vec2, Vec3};

/// Complex relative IOR per colour lane (RGB channels, or the path's hero wavelengths) and the
/// metal it came from (to re-evaluate it at wavelengths: [`ComplexIor::at_wavelengths`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ComplexIor {
    pub eta: Color,
    pub k: Color,
    pub metal: Metal,
}

impl ComplexIor {
    /// The metal's linear-sRGB η, k (`Metal::rgb`).
    pub fn rgb(metal: Metal) -> ComplexIor {
        let (eta, k) = metal.rgb();
        ComplexIor {
            eta: eta.extend(0.0),
            k: k.extend(0.0),
            metal,
        }
    }

    /// η, k at four wavelengths (hero-wavelength spectral mode).
    pub fn at_wavelengths(self, lambdas: [f32; 4]) -> ComplexIor {
        let ek = lambdas.map(|l| self.metal.ior_at(l));
        ComplexIor {
            eta: Color::from_array(ek.map(|(e, _)| e)),
            k: Color::from_array(ek.map(|(_, k)| k)),
            metal: self.metal,
        }
    }

    /// Fresnel reflectance per lane at incidence cosine `cos_i`.
    #[inline]
    pub fn fresnel(&self, cos_i: f32) -> Color {
        fresnel_conductor_color(cos_i, self.eta, self.k)
    }
}

/// Smooth conductor: f = T F(θo) δ(wi − reflect(wo)) / |cos θi| (PBR 4th ed. §9.4 specular
/// reflection with the conductor Fresnel term of §9.3.6). T = base colour (Mitsuba's
/// `specular_reflectance`).
#[derive(Clone, Copy, Debug)]
pub struct SmoothConductor {
    pub ior: ComplexIor,
    pub tint: Color,
}

impl BxDF for SmoothConductor {
    #[inline]
    fn can_transmit(&self) -> bool {
        false
    }

    /// Fresnel reflection with η − ik per colour lane at the normal.
    fn mueller(&self, _wo: Vec3, wi: Vec3, _event: Event, _lobe: Lobe) -> MuellerLanes {
        conductor_mueller(wi.z, self.ior.eta, self.ior.k)
    }

    #[inline]
    fn map_colors(self, f: impl Fn(Color) -> Color) -> Self {
        SmoothConductor {
            tint: f(self.tint),
            ..self
        }
    }

    #[inline]
    fn at_wavelengths(self, lambdas: [f32; 4]) -> Self {
        SmoothConductor {
            ior: self.ior.at_wavelengths(lambdas),
            ..self
        }
    }

    #[inline]
    fn eval(&self, _wo: Vec3, _wi: Vec3, _mode: TransportMode) -> Color {
        Color::ZERO
    }
    #[inline]
    fn pdf(&self, _wo: Vec3, _wi: Vec3) -> f32 {
        0.0
    }
    #[inline]
    fn sample(&self, wo: Vec3, _uc: f32, _u2: Vec2, _mode: TransportMode) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        Some(BsdfSample::delta(
            Vec3::new(-wo.x, -wo.y, wo.z),
            self.tint * self.ior.fresnel(wo.z),
            1.0,
            Event::Reflect,
            1.0,
        ))
    }
}

/// Rough conductor with the exact Fresnel term:
/// f = T F(wo·m) D(m) G2(wo, wi) / (4 cosθo cosθi), m = normalize(wo + wi)
/// (Walter et al. 2007 eq. 20; Heitz 2014 height-correlated G2). `lobe.reflectance` is the
/// tint T (base colour); the lobe supplies D G2/(4 cos cos), its pdf and its sampling.
#[derive(Clone, Copy, Debug)]
pub struct RoughFresnelConductor {
    pub ior: ComplexIor,
    pub lobe: RoughConductor,
}

impl RoughFresnelConductor {
    /// F at the half vector of (wo, wi) (0 where the lobe is 0 anyway).
    #[inline]
    fn fresnel_half(&self, wo: Vec3, wi: Vec3) -> Color {
        let h = wo + wi;
        let len2 = h.length_squared();
        if len2 <= 0.0 {
            return Color::ZERO;
        }
        self.ior.fresnel(wo.dot(h) / len2.sqrt())
    }
}

impl BxDF for RoughFresnelConductor {
    #[inline]
    fn can_transmit(&self) -> bool {
        false
    }

    /// Fresnel reflection with η − ik per colour lane at the microfacet normal (the
    /// depolariser where it is degenerate).
    fn mueller(&self, wo: Vec3, wi: Vec3, _event: Event, _lobe: Lobe) -> MuellerLanes {
        match half_vector(wo, wi, Event::Reflect, 1.0) {
            Some(m) => conductor_mueller(wi.dot(m), self.ior.eta, self.ior.k),
            None => all(depolarizer()),
        }
    }

    #[inline]
    fn map_colors(self, f: impl Fn(Color) -> Color) -> Self {
        RoughFresnelConductor {
            lobe: self.lobe.map_colors(f),
            ..self
        }
    }

    #[inline]
    fn at_wavelengths(self, lambdas: [f32; 4]) -> Self {
        RoughFresnelConductor {
            ior: self.ior.at_wavelengths(lambdas),
            ..self
        }
    }

    #[inline]
    fn distribution(&self) -> Option<MicrofacetDistribution> {
        Some(self.lobe.dist)
    }

    #[inline]
    fn eval(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> Color {
        let (f, _) = self.lobe.eval_pdf(wo, wi);
        if f == 0.0 {
            return Color::ZERO;
        }
        self.lobe.reflectance * self.fresnel_half(wo, wi) * f
    }

    #[inline]
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.lobe.eval_pdf(wo, wi).1
    }

    /// Visible-normal sampling + mirror reflection about m (Heitz 2018), as
    /// [`RoughConductor`]; the weight is T F(wo·m) G2/G1(wo), computed as f·cos/pdf.
    #[inline]
    fn sample(&self, wo: Vec3, _uc: f32, u2: Vec2, _mode: TransportMode) -> Option<BsdfSample> {
        let (wi, f, pdf) = self.lobe.sample_reflection(wo, u2)?;
        // F at the half vector rebuilt from (wo, wi), as `eval` computes it (equal to m up to
        // rounding), so that sample and eval agree to the last bit.
        let f = self.lobe.reflectance * self.fresnel_half(wo, wi) * f;
        Some(BsdfSample::new(
            wi,
            f,
            f * (wi.z / pdf),
            pdf,
            Event::Reflect,
            Lobe::G,
            1.0,
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::{Bsdf, MicrofacetDistribution};

    #[test]
    fn spectral_lanes_take_the_tabulated_values() {
        let l = [400.0, 500.0, 600.0, 700.0];
        for metal in Metal::ALL {
            let smooth = Bsdf::SmoothConductor(SmoothConductor {
                ior: ComplexIor::rgb(metal),
                tint: Color::ONE,
            });
            let rough = Bsdf::RoughFresnelConductor(RoughFresnelConductor {
                ior: ComplexIor::rgb(metal),
                lobe: RoughConductor {
                    reflectance: Color::ONE,
                    alpha: 0.2,
                    dist: MicrofacetDistribution::Ggx,
                },
            });
            for b in [smooth, rough] {
                let ior = match b.at_wavelengths(l) {
                    Bsdf::SmoothConductor(c) => c.ior,
                    Bsdf::RoughFresnelConductor(c) => c.ior,
                    other => panic!("{other:?}"),
                };
                for (i, &lambda) in l.iter().enumerate() {
                    assert_eq!((ior.eta[i], ior.k[i]), metal.ior_at(lambda));
                }
            }
        }
        // Gold: its blue end absorbs (η > 1, low k), its red end reflects (η ≪ 1, high k).
        let gold = ComplexIor::rgb(Metal::Au).at_wavelengths(l);
        let f = gold.fresnel(1.0);
        assert!(f.x < 0.5 && f.w > 0.95, "{f:?}");
    }
}
