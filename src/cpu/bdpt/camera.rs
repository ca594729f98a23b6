//! Pinhole camera geometry for importance and raster positions (the t = 1 strategy).

use crate::scene::camera::CameraRays;
use glam::Vec3;

#[derive(Clone, Copy)]
pub(super) struct CameraModel {
    pub pos: Vec3,
    /// World → camera (the camera's rotation transposed once, not per raster query).
    pub rot_t: glam::Mat3,
    /// The optical axis (world, unit): the camera looks along it.
    pub axis: Vec3,
    /// The camera's primary rays (`CameraRays::dir`).
    pub rays: CameraRays,
    pub tan_half: f32,
    pub aspect: f32,
    /// Area of the image plane at distance 1.
    pub a_plane: f32,
    pub width: u32,
    pub height: u32,
}

impl CameraModel {
    pub fn new(c: &crate::scene::Camera, width: u32, height: u32) -> CameraModel {
        let tan_half = (0.5 * c.yfov).tan();
        let aspect = width as f32 / height as f32;
        CameraModel {
            pos: c.position,
            rot_t: c.rotation.transpose(),
            axis: -c.rotation.transpose().row(2),
            rays: CameraRays::new(c),
            tan_half,
            aspect,
            a_plane: 4.0 * tan_half * tan_half * aspect,
            width,
            height,
        }
    }

    /// (pixel x, y, cosθ) of the direction `w` from the camera, if it lands on the film.
    pub fn raster(&self, w: Vec3) -> Option<(u32, u32, f32)> {
        let l = self.rot_t * w;
        if l.z >= 0.0 {
            return None;
        }
        let x = l.x / -l.z / (self.tan_half * self.aspect);
        let y = l.y / -l.z / self.tan_half;
        let sx = 0.5 * (x + 1.0);
        let sy = 0.5 * (1.0 - y);
        if !(0.0..1.0).contains(&sx) || !(0.0..1.0).contains(&sy) {
            return None;
        }
        let px = ((sx * self.width as f32) as u32).min(self.width - 1);
        let py = ((sy * self.height as f32) as u32).min(self.height - 1);
        Some((px, py, -l.z / l.length()))
    }

    /// Solid-angle density of the camera's primary direction `w` (uniform on the image plane):
    /// p(ω) = 1 / (A_plane cos³θ) (PBR 3rd ed. §16.1.1, `PerspectiveCamera::Pdf_We`); 0 off
    /// the film. The estimator itself knows when a direction is on the film (`pdf_at_cos`);
    /// the tests' direct MIS forms use this.
    #[cfg(test)]
    pub fn pdf_dir(&self, w: Vec3) -> f32 {
        self.raster(w).map_or(0.0, |(_, _, c)| self.pdf_at_cos(c))
    }

    /// `pdf_dir` of a direction known to land on the film, from its cosine to the optical
    /// axis (`raster`'s third value, or the primary ray's): no projection needed.
    #[inline]
    pub fn pdf_at_cos(&self, cos: f32) -> f32 {
        1.0 / (self.a_plane * cos * cos * cos)
    }

    /// Cosine between the unit direction `w` and the optical axis.
    #[inline]
    pub fn cos_to_axis(&self, w: Vec3) -> f32 {
        self.axis.dot(w)
    }
}
