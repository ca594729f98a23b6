//! Camera edits: the upright [`Orbit`] camera and [`CameraEdit`] (orbit and field of view
//! over the scene's camera).

use crate::scene::{Camera, Scene};
use glam::Vec3;
use serde::{Deserialize, Serialize};

/// An orbit camera: position on a sphere around `target`, always upright (+Y up).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Orbit {
    pub target: [f32; 3],
    pub distance: f32,
    /// Rotation about +Y of the camera position seen from the target (0 = on +Z).
    pub yaw_deg: f32,
    /// Elevation of the camera position seen from the target.
    pub pitch_deg: f32,
}

impl Orbit {
    pub const MAX_PITCH: f32 = 89.0;

    /// The orbit that reproduces `cam`'s position and viewing direction (roll is dropped),
    /// pivoting at the point along the view direction nearest the scene centre.
    pub fn from_camera(cam: &Camera, scene_centre: Vec3, scene_radius: f32) -> Orbit {
        let fwd = cam.forward().normalize_or(Vec3::NEG_Z);
        let t = (scene_centre - cam.position)
            .dot(fwd)
            .max(0.1 * scene_radius.max(1e-3));
        let back = -fwd;
        Orbit {
            target: (cam.position + fwd * t).to_array(),
            distance: t,
            yaw_deg: back.x.atan2(back.z).to_degrees(),
            pitch_deg: back
                .y
                .clamp(-1.0, 1.0)
                .asin()
                .to_degrees()
                .clamp(-Self::MAX_PITCH, Self::MAX_PITCH),
        }
    }

    pub fn position(&self) -> Vec3 {
        let (y, p) = (self.yaw_deg.to_radians(), self.pitch_deg.to_radians());
        let dir = Vec3::new(p.cos() * y.sin(), p.sin(), p.cos() * y.cos());
        Vec3::from_array(self.target) + dir * self.distance
    }

    pub fn camera(&self, yfov: f32) -> Camera {
        Camera::look_at(
            self.position(),
            Vec3::from_array(self.target),
            Vec3::Y,
            yfov,
        )
    }

    /// Keep the orbit usable whatever was typed or dragged.
    pub fn sanitize(&mut self, fallback: &Orbit) {
        let ok = Vec3::from_array(self.target).is_finite()
            && self.distance.is_finite()
            && self.distance > 0.0
            && self.yaw_deg.is_finite()
            && self.pitch_deg.is_finite();
        if !ok {
            *self = *fallback;
        }
        self.distance = self.distance.clamp(1e-4, 1e6);
        self.pitch_deg = self.pitch_deg.clamp(-Self::MAX_PITCH, Self::MAX_PITCH);
        self.yaw_deg = self.yaw_deg.rem_euclid(360.0);
    }
}

/// Camera edits; all None = the scene's camera exactly.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct CameraEdit {
    pub orbit: Option<Orbit>,
    /// Full vertical field of view in degrees.
    pub yfov_deg: Option<f32>,
}

impl CameraEdit {
    /// The camera: the scene's, or the edited orbit, with the edited field of view.
    pub fn camera(&self, base: &Scene) -> Camera {
        let yfov = self
            .yfov_deg
            .filter(|f| f.is_finite())
            .map(|f| f.clamp(1.0, 170.0).to_radians())
            .unwrap_or(base.camera.yfov);
        match self.orbit {
            Some(o) => {
                let cam = o.camera(yfov);
                if cam.validate().is_ok() {
                    cam
                } else {
                    base.camera
                }
            }
            None => Camera {
                yfov,
                ..base.camera
            },
        }
    }

    /// The orbit the camera controls start from.
    pub fn orbit(&self, base: &Scene) -> Orbit {
        self.orbit.unwrap_or_else(|| {
            let (lo, hi) = base.bounds();
            Orbit::from_camera(&base.camera, 0.5 * (lo + hi), 0.5 * (hi - lo).length())
        })
    }
}
