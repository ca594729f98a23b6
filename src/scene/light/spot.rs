//! Spot light with the glTF KHR_lights_punctual smooth cone falloff (PBR 4th ed. §12.1.1
//! `SpotLight` structure, glTF's falloff curve).

use super::{LeSample, LiSample};
use crate::math::{Frame, sampling};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpotLight {
    pub position: Vec3,
    /// Where the spot points (unit).
    pub direction: Vec3,
    /// Radiant intensity on the axis (RGB).
    pub intensity: Vec3,
    pub cos_inner: f32,
    pub cos_outer: f32,
}

/// The narrowest ramp of cosθ [`spot_falloff`] divides by (inner and outer cones that
/// coincide would divide by zero).
pub const SPOT_MIN_RAMP_COS: f32 = 1e-3;

/// glTF spot-light angular falloff (KHR_lights_punctual spec, "Spot"): smooth, squared
/// linear ramp of cosθ between the outer and inner cone.
#[inline]
pub fn spot_falloff(cos_theta: f32, cos_inner: f32, cos_outer: f32) -> f32 {
    let scale = 1.0 / (cos_inner - cos_outer).max(SPOT_MIN_RAMP_COS);
    let offset = -cos_outer * scale;
    let a = (cos_theta * scale + offset).clamp(0.0, 1.0);
    a * a
}

impl SpotLight {
    /// Delta position: L = I·falloff/d², pdf = selection probability.
    #[inline]
    pub fn sample_li(&self, p: Vec3, pick: f32) -> Option<LiSample> {
        let (wi, d2) = super::towards_position(p, self.position)?;
        let fall = spot_falloff((-wi).dot(self.direction), self.cos_inner, self.cos_outer);
        if fall <= 0.0 {
            return None;
        }
        Some(LiSample::delta_position(
            self.intensity * fall / d2,
            wi,
            pick,
            self.position,
        ))
    }

    /// Intensity towards `w` (unit, away from the light).
    #[inline]
    pub fn le(&self, w: Vec3) -> Vec3 {
        self.intensity * spot_falloff(w.dot(self.direction), self.cos_inner, self.cos_outer)
    }

    /// Solid-angle density of `sample_le`'s uniform cone.
    #[inline]
    pub fn pdf_dir(&self, w: Vec3) -> f32 {
        if w.dot(self.direction) >= self.cos_outer {
            self.cone_pdf()
        } else {
            0.0
        }
    }

    #[inline]
    fn cone_pdf(&self) -> f32 {
        1.0 / (2.0 * PI * (1.0 - self.cos_outer).max(1e-7))
    }

    /// Uniform direction in the outer cone (PBR 4th ed. §A.5.4), weighted by the falloff.
    #[inline]
    pub fn sample_le(&self, u_dir: Vec2, pick: f32) -> LeSample {
        let local = sampling::uniform_cone(u_dir, self.cos_outer);
        LeSample {
            p: self.position,
            n: Vec3::ZERO,
            dir: Frame::from_normal(self.direction).to_world(local),
            l: self.intensity * spot_falloff(local.z, self.cos_inner, self.cos_outer),
            pdf_pos: pick,
            pdf_dir: self.cone_pdf(),
            delta_pos: true,
            infinite: false,
        }
    }

    /// Power 2π(1 − ½(cosθ_inner + cosθ_outer))·I (luminance; pbrt-v4 `SpotLight::Phi`).
    pub fn power(&self) -> f32 {
        2.0 * PI
            * (1.0 - 0.5 * (self.cos_inner + self.cos_outer))
            * super::luminance(self.intensity)
    }
}
