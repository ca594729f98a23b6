//! Isotropic point light (PBR 4th ed. §12.1 `PointLight`; glTF KHR_lights_punctual "point":
//! intensity in the scene's radiometric unit per steradian).

use super::{LeSample, LiSample};
use crate::math::sampling;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointLight {
    pub position: Vec3,
    /// Radiant intensity (RGB).
    pub intensity: Vec3,
}

impl PointLight {
    /// Delta position: L = I/d² from the one point, pdf = selection probability.
    #[inline]
    pub fn sample_li(&self, p: Vec3, pick: f32) -> Option<LiSample> {
        let (wi, d2) = super::towards_position(p, self.position)?;
        Some(LiSample::delta_position(
            self.intensity / d2,
            wi,
            pick,
            self.position,
        ))
    }

    /// Uniform direction on the sphere (PBR 4th ed. §12.1 `PointLight::SampleLe`).
    #[inline]
    pub fn sample_le(&self, u_dir: Vec2, pick: f32) -> LeSample {
        LeSample {
            p: self.position,
            n: Vec3::ZERO,
            dir: sampling::uniform_sphere(u_dir),
            l: self.intensity,
            pdf_pos: pick,
            pdf_dir: sampling::UNIFORM_SPHERE_PDF,
            delta_pos: true,
            infinite: false,
        }
    }

    /// Power 4π·I (luminance).
    pub fn power(&self) -> f32 {
        4.0 * PI * super::luminance(self.intensity)
    }
}
