//! Image environment: radiance from an equirectangular map at infinity, importance-sampled
//! ∝ luminance × sinθ with a piecewise-constant 2D distribution (PBR 4th ed. §12.5.2
//! `ImageInfiniteLight`, which uses an equal-area octahedral map; the equirectangular
//! Jacobian is that of 3rd ed. §14.2.4: p(ω) = p(u, t) / (2π² sinθ)).

use super::{LeSample, LiSample};
use crate::math::{Frame, sampling};
use crate::scene::env_map::{EnvImage, dir_to_uv, rotate_y, uv_to_dir};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

#[derive(Clone, Debug, PartialEq)]
pub struct ImageEnvironment {
    pub image: EnvImage,
    /// cos and sin of the rotation about +Y.
    pub cos_rot: f32,
    pub sin_rot: f32,
    /// The scene's bounding sphere (emitted rays start on a disk of this radius).
    pub center: Vec3,
    pub radius: f32,
}

impl ImageEnvironment {
    pub fn new(image: EnvImage, center: Vec3, radius: f32) -> ImageEnvironment {
        let r = image.rotation.to_radians();
        ImageEnvironment {
            image,
            cos_rot: r.cos(),
            sin_rot: r.sin(),
            center,
            radius,
        }
    }

    /// World direction → image (u, t).
    #[inline]
    fn to_image(&self, wi: Vec3) -> Vec2 {
        dir_to_uv(rotate_y(wi, self.cos_rot, -self.sin_rot))
    }

    /// Radiance arriving from the world direction `wi` (towards the environment).
    #[inline]
    pub fn radiance(&self, wi: Vec3) -> Vec3 {
        self.image.strength * self.image.map.lookup_uv(self.to_image(wi))
    }

    /// Solid-angle density of `sample_dir` for `wi` (without the selection probability).
    #[inline]
    pub fn pdf_dir(&self, wi: Vec3) -> f32 {
        if !self.image.importance {
            return sampling::UNIFORM_SPHERE_PDF;
        }
        let uv = self.to_image(wi);
        let sin_t = (uv.y * PI).sin();
        if sin_t <= 0.0 {
            return 0.0;
        }
        self.image.map.dist.pdf(uv) / (2.0 * PI * PI * sin_t)
    }

    /// A direction towards the environment and its solid-angle density (PBR 4th ed.
    /// §12.5.2 `ImageInfiniteLight::SampleLi`); uniform on the sphere when importance
    /// sampling is off.
    #[inline]
    pub fn sample_dir(&self, u: Vec2) -> Option<(Vec3, f32)> {
        self.sample_dir_radiance(u).map(|(wi, pdf, _)| (wi, pdf))
    }

    /// [`ImageEnvironment::sample_dir`] and the radiance from the sampled direction, read at
    /// the sampled image coordinates themselves (no round trip through atan2 and acos; the
    /// GPU twin does the same, whose round trip was imprecise on some drivers).
    #[inline]
    fn sample_dir_radiance(&self, u: Vec2) -> Option<(Vec3, f32, Vec3)> {
        if !self.image.importance {
            let wi = sampling::uniform_sphere(u);
            return Some((wi, sampling::UNIFORM_SPHERE_PDF, self.radiance(wi)));
        }
        let (uv, pdf_uv) = self.image.map.dist.sample(u);
        let sin_t = (uv.y * PI).sin();
        if pdf_uv <= 0.0 || sin_t <= 0.0 {
            return None;
        }
        let wi = rotate_y(uv_to_dir(uv), self.cos_rot, self.sin_rot);
        let l = self.image.strength * self.image.map.lookup_uv(uv);
        Some((wi, pdf_uv / (2.0 * PI * PI * sin_t), l))
    }

    #[inline]
    pub fn sample_li(&self, u: Vec2, pick: f32) -> Option<LiSample> {
        let (wi, pdf, l) = self.sample_dir_radiance(u)?;
        Some(LiSample {
            l,
            wi,
            pdf: pick * pdf,
            p_light: Vec3::ZERO,
            n_light: Vec3::ZERO,
            is_delta: false,
            infinite: true,
        })
    }

    #[inline]
    pub fn pdf_li(&self, pick: f32, wi: Vec3) -> f32 {
        pick * self.pdf_dir(wi)
    }

    /// A sampled direction and a point on the disk perpendicular to it that covers the
    /// bounding sphere, behind the scene (PBR 4th ed. §12.5.2 `ImageInfiniteLight::SampleLe`).
    #[inline]
    pub fn sample_le(&self, u_pos: Vec2, u_dir: Vec2, pick: f32) -> Option<LeSample> {
        let (wi, pdf_dir, l) = self.sample_dir_radiance(u_dir)?;
        let dir = -wi;
        let frame = Frame::from_normal(dir);
        let d = sampling::concentric_disk(u_pos) * self.radius;
        let p = self.center - self.radius * dir + frame.to_world(d.extend(0.0));
        Some(LeSample {
            p,
            n: dir,
            dir,
            l,
            pdf_pos: pick / (PI * self.radius * self.radius),
            pdf_dir,
            delta_pos: false,
            infinite: true,
        })
    }

    /// (area density of the disk point, solid-angle density of emitting along `w`).
    #[inline]
    pub fn pdf_le(&self, pick: f32, w: Vec3) -> (f32, f32) {
        (pick / (PI * self.radius * self.radius), self.pdf_dir(-w))
    }

    /// Power πr² · ∫L dω (luminance; pbrt-v4 `ImageInfiniteLight::Phi`).
    pub fn power(&self) -> f32 {
        PI * self.radius * self.radius * self.image.strength * self.image.map.luminance_integral()
    }
}
