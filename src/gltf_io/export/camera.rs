//! The scene camera as a glTF camera and its node.

use crate::scene::Scene;
use glam::Quat;
use serde_json::{Value, json};

/// (camera node, `cameras` array). Camera: local −Z is the view direction, rotation columns
/// right/up/back.
pub(super) fn camera_json(scene: &Scene) -> (Value, Value) {
    let cam = &scene.camera;
    let q = Quat::from_mat3(&cam.rotation).normalize();
    let node = json!({
        "name": "camera", "camera": 0,
        "translation": cam.position.to_array(), "rotation": q.to_array()
    });
    let s = &scene.settings;
    let cameras = json!([{
        "type": "perspective",
        "perspective": {
            "yfov": cam.yfov, "znear": 0.001,
            "aspectRatio": s.width as f32 / s.height.max(1) as f32
        }
    }]);
    (node, cameras)
}
