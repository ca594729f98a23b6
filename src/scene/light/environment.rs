//! Uniform environment: the same radiance from every direction (PBR 4th ed. §12.5.1
//! `UniformInfiniteLight`). Escaping rays add it; it is not in the NEE distribution (the
//! walks add it with MIS weight 1 on escape), so `sample_li` serves tests and light tracing
//! from the environment. The image environment (`image_environment.rs`) is in it.

use super::{LeSample, LiSample};
use crate::math::{Frame, sampling};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UniformEnvironment {
    /// Radiance of every direction (RGB).
    pub radiance: Vec3,
    /// The scene's bounding sphere (emitted rays start on a disk of this radius).
    pub center: Vec3,
    pub radius: f32,
}

impl UniformEnvironment {
    /// Uniform direction on the sphere (PBR 4th ed. §12.5.1).
    #[inline]
    pub fn sample_li(&self, u: Vec2, pick: f32) -> Option<LiSample> {
        Some(LiSample {
            l: self.radiance,
            wi: sampling::uniform_sphere(u),
            pdf: pick * sampling::UNIFORM_SPHERE_PDF,
            p_light: Vec3::ZERO,
            n_light: Vec3::ZERO,
            is_delta: false,
            infinite: true,
        })
    }

    #[inline]
    pub fn pdf_li(&self, pick: f32) -> f32 {
        pick * sampling::UNIFORM_SPHERE_PDF
    }

    /// A uniform direction and a point on the disk perpendicular to it that covers the
    /// bounding sphere, behind the scene (PBR 4th ed. §12.5.1 `UniformInfiniteLight::SampleLe`).
    #[inline]
    pub fn sample_le(&self, u_pos: Vec2, u_dir: Vec2, pick: f32) -> LeSample {
        let dir = -sampling::uniform_sphere(u_dir);
        let frame = Frame::from_normal(dir);
        let d = sampling::concentric_disk(u_pos) * self.radius;
        let p = self.center - self.radius * dir + frame.to_world(d.extend(0.0));
        LeSample {
            p,
            n: dir,
            dir,
            l: self.radiance,
            pdf_pos: pick / (PI * self.radius * self.radius),
            pdf_dir: sampling::UNIFORM_SPHERE_PDF,
            delta_pos: false,
            infinite: true,
        }
    }

    /// (area density of the disk point, solid-angle density of the direction).
    #[inline]
    pub fn pdf_le(&self, pick: f32) -> (f32, f32) {
        (
            pick / (PI * self.radius * self.radius),
            sampling::UNIFORM_SPHERE_PDF,
        )
    }

    /// Power 4π²r²L (luminance; pbrt-v4 `UniformInfiniteLight::Phi`).
    pub fn power(&self) -> f32 {
        4.0 * PI * PI * self.radius * self.radius * super::luminance(self.radiance)
    }
}
