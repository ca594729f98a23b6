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
        let tan_half = (0.5 * self.yfov).tan();
        let x = (2.0 * sx - 1.0) * tan_half * aspect;
        let y = (1.0 - 2.0 * sy) * tan_half;
        (self.rotation * Vec3::new(x, y, -1.0)).normalize()
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
