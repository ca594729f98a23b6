//! Cameras: the first perspective camera in traversal order, or a default framing.

use super::Loader;
use crate::scene::{Camera, Mesh, RenderSettings};
use anyhow::{Context, bail};
use glam::{Mat4, Vec3};
use gltf::json;
use gltf::json::validation::Checked;

impl Loader<'_> {
    pub(super) fn camera_node(&mut self, ni: usize, ci: usize, world: Mat4) -> anyhow::Result<()> {
        if self.camera.is_some() {
            return Ok(());
        }
        let Some(cam) = self.root.cameras.get(ci) else {
            self.warnings.push(format!(
                "node {ni}: camera {ci} does not exist (index out of range)"
            ));
            return Ok(());
        };
        match (&cam.type_, &cam.perspective) {
            (Checked::Valid(json::camera::Type::Perspective), Some(p))
            | (Checked::Invalid, Some(p)) => {
                let yfov = p.yfov;
                if !(yfov.is_finite() && yfov > 1e-4 && yfov < std::f32::consts::PI - 1e-3) {
                    bail!("camera {ci}: yfov {yfov} is outside (0, π) radians");
                }
                self.check_clip_planes(ci, p.znear, p.zfar);
                self.camera_aspect = p
                    .aspect_ratio
                    .filter(|a| a.is_finite() && (1.0 / 64.0..=64.0).contains(a));
                let c = Camera::from_matrix(world, yfov);
                c.validate()
                    .with_context(|| format!("camera {ci} on node {ni}"))?;
                self.camera = Some(c);
            }
            _ => self.warnings.push(format!(
                "camera {ci}: only perspective cameras are supported; ignored"
            )),
        }
        if matches!(cam.type_, Checked::Invalid) {
            self.warnings.push(format!(
                "camera {ci}: unknown camera type (glTF knows perspective and orthographic); \
                 read as perspective"
            ));
        }
        Ok(())
    }

    /// glTF requires 0 < znear < zfar; a path tracer has no clip planes, so invalid ones only
    /// warn (the file is broken, the render is not).
    fn check_clip_planes(&mut self, ci: usize, znear: f32, zfar: Option<f32>) {
        let far_ok = zfar.is_none_or(|f| f > znear);
        if !(znear > 0.0 && znear.is_finite() && far_ok) {
            self.warnings.push(format!(
                "camera {ci}: clip planes znear {znear}, zfar {zfar:?} are invalid (glTF needs \
                 0 < znear < zfar); ignored, as a path tracer does not clip"
            ));
        }
    }
}

/// The image size for a camera of aspect ratio `a` (width / height) when the file gives no
/// size: the longer side 512, the default's, the other rounded (at least 1).
pub(super) fn size_for_aspect(a: f32) -> (u32, u32) {
    let short = |x: f32| (x.round() as u32).max(1);
    if a >= 1.0 {
        (512, short(512.0 / a))
    } else {
        (short(512.0 * a), 512)
    }
}

/// No camera in the file: look down −Z at the bounding sphere, framing it in the smaller FOV.
pub fn default_camera(mesh: &Mesh, settings: &RenderSettings) -> Camera {
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    for p in &mesh.positions {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    let (center, mut radius) = if lo.is_finite() && hi.is_finite() {
        (0.5 * (lo + hi), 0.5 * (hi - lo).length())
    } else {
        (Vec3::ZERO, 1.0)
    };
    if !(radius.is_finite() && radius > 0.0) {
        radius = 1.0;
    }
    let yfov = 0.6911_f32; // 39.6°, the Cornell box camera
    let aspect = settings.width.max(1) as f32 / settings.height.max(1) as f32;
    let half_x = ((0.5 * yfov).tan() * aspect).atan();
    let half = (0.5 * yfov).min(half_x);
    let dist = radius / half.sin() * 1.05;
    Camera::look_at(center + Vec3::Z * dist, center, Vec3::Y, yfov)
}
