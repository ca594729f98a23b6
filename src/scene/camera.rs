//! Pinhole perspective camera (glTF: full vertical FOV `yfov`, looks down local −Z).

use glam::{Mat3, Vec3};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub position: Vec3,
    /// Orthonormal camera-to-world rotation: columns right (+X), up (+Y), back (+Z);
    /// the camera looks down −Z.
    pub rotation: Mat3,
    /// Full vertical field of view in radians.
    pub yfov: f32,
}

impl Camera {
    /// Camera at `eye` looking at `target`.
    pub fn look_at(eye: Vec3, target: Vec3, up: Vec3, yfov: f32) -> Camera {
        let back = (eye - target).normalize();
        let right = up.cross(back).normalize();
        let up = back.cross(right);
        Camera {
            position: eye,
            rotation: Mat3::from_cols(right, up, back),
            yfov,
        }
    }

    /// From a node's world matrix (scale and shear removed by Gram–Schmidt).
    pub fn from_matrix(m: glam::Mat4, yfov: f32) -> Camera {
        let back = m.z_axis.truncate().normalize_or(Vec3::Z);
        let up0 = m.y_axis.truncate();
        let right = up0.cross(back).normalize_or(Vec3::X);
        let up = back.cross(right);
        Camera {
            position: m.w_axis.truncate(),
            rotation: Mat3::from_cols(right, up, back),
            yfov,
        }
    }

    /// Direction (world, unit) through the film point (sx, sy) ∈ [0,1]², (0,0) = top-left.
    #[inline]
    pub fn ray_dir(&self, sx: f32, sy: f32, aspect: f32) -> Vec3 {
        CameraRays::new(self).dir(sx, sy, aspect)
    }

    /// The film point (sx, sy) of world point `p` (the inverse of [`Camera::ray_dir`]): its
    /// camera-space position projected by the pinhole; None behind the camera (or on its plane).
    #[inline]
    pub fn to_film(&self, p: Vec3, aspect: f32) -> Option<(f32, f32)> {
        self.film_of_local(self.to_local(p), aspect)
    }

    /// `p` in camera space (right, up, back; the camera looks down −Z).
    #[inline]
    pub fn to_local(&self, p: Vec3) -> Vec3 {
        self.rotation.transpose() * (p - self.position)
    }

    /// The film point of camera-space `q` (None when `q.z ≥ 0`, not in front).
    #[inline]
    pub fn film_of_local(&self, q: Vec3, aspect: f32) -> Option<(f32, f32)> {
        if q.z >= 0.0 {
            return None;
        }
        let tan_half = (0.5 * self.yfov).tan();
        let x = q.x / (-q.z * tan_half * aspect);
        let y = q.y / (-q.z * tan_half);
        Some((0.5 * (x + 1.0), 0.5 * (1.0 - y)))
    }

    pub fn forward(&self) -> Vec3 {
        -self.rotation.z_axis
    }

    pub fn validate(&self) -> anyhow::Result<()> {
        anyhow::ensure!(
            self.position.is_finite() && self.rotation.is_finite(),
            "camera transform is not finite"
        );
        anyhow::ensure!(
            self.yfov.is_finite() && self.yfov > 1e-4 && self.yfov < std::f32::consts::PI - 1e-3,
            "camera yfov {} is outside (0, π)",
            self.yfov
        );
        Ok(())
    }
}

/// A camera prepared for many rays: [`Camera::ray_dir`] without its per-ray tangent (the
/// same operations on the same values, so the same directions bit for bit).
#[derive(Clone, Copy, Debug)]
pub struct CameraRays {
    /// Where every ray starts (`Camera::position`).
    pub position: Vec3,
    rotation: Mat3,
    tan_half: f32,
}

impl CameraRays {
    pub fn new(cam: &Camera) -> CameraRays {
        CameraRays {
            position: cam.position,
            rotation: cam.rotation,
            tan_half: (0.5 * cam.yfov).tan(),
        }
    }

    /// Direction (world, unit) through the film point (sx, sy) ∈ [0,1]², (0,0) = top-left.
    #[inline]
    pub fn dir(&self, sx: f32, sy: f32, aspect: f32) -> Vec3 {
        let x = (2.0 * sx - 1.0) * self.tan_half * aspect;
        let y = (1.0 - 2.0 * sy) * self.tan_half;
        (self.rotation * Vec3::new(x, y, -1.0)).normalize()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn to_film_inverts_ray_dir() {
        let cam = Camera::look_at(Vec3::new(1.0, 2.0, 3.0), Vec3::ZERO, Vec3::Y, 0.7);
        for (sx, sy) in [(0.5, 0.5), (0.1, 0.9), (0.83, 0.27)] {
            let p = cam.position + 4.0 * cam.ray_dir(sx, sy, 1.6);
            let (x, y) = cam.to_film(p, 1.6).expect("in front");
            assert!(
                (x - sx).abs() < 1e-5 && (y - sy).abs() < 1e-5,
                "{x} {y} vs {sx} {sy}"
            );
        }
        assert_eq!(cam.to_film(cam.position - cam.forward(), 1.6), None);
    }
}
