//! Directional (distant) light (PBR 4th ed. §12.4 `DistantLight`; glTF KHR_lights_punctual
//! "directional": irradiance in lux used as given).

use super::{LeSample, LiSample};
use crate::math::{Frame, sampling};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectionalLight {
    /// The direction light travels (unit).
    pub direction: Vec3,
    /// Irradiance on a surface facing the light (RGB).
    pub irradiance: Vec3,
    /// The scene's bounding sphere: emitted rays start on a disk of this radius.
    pub center: Vec3,
    pub radius: f32,
}

impl DirectionalLight {
    /// Delta direction: wi = −direction, pdf = selection probability, shadow ray to infinity.
    #[inline]
    pub fn sample_li(&self, pick: f32) -> Option<LiSample> {
        Some(LiSample {
            l: self.irradiance,
            wi: -self.direction,
            pdf: pick,
            p_light: Vec3::ZERO,
            n_light: Vec3::ZERO,
            is_delta: true,
            infinite: true,
        })
    }

    /// Area density of the bounding disk, 1/(πr²).
    #[inline]
    pub fn pdf_pos(&self) -> f32 {
        1.0 / (PI * self.radius * self.radius)
    }

    /// A ray along `direction` through a uniform point of the disk that covers the scene's
    /// bounding sphere, placed behind it (PBR 4th ed. §12.4 `DistantLight::SampleLe`).
    #[inline]
    pub fn sample_le(&self, u_pos: Vec2, pick: f32) -> LeSample {
        let frame = Frame::from_normal(self.direction);
        let d = sampling::concentric_disk(u_pos) * self.radius;
        let p = self.center + self.radius * (-self.direction) + frame.to_world(d.extend(0.0));
        LeSample {
            p,
            n: self.direction,
            dir: self.direction,
            l: self.irradiance,
            pdf_pos: pick * self.pdf_pos(),
            pdf_dir: 1.0,
            delta_pos: false,
            infinite: true,
        }
    }

    /// Power π r² E (luminance) over the scene's bounding disk.
    pub fn power(&self) -> f32 {
        PI * self.radius * self.radius * super::luminance(self.irradiance)
    }
}
