//! Punctual lights as `KHR_lights_punctual` lights and their nodes.

use super::split_color;
use crate::scene::PunctualLight;
use glam::{Quat, Vec3};
use serde_json::{Value, json};

/// (KHR_lights_punctual light, its node) of punctual light `li`.
pub(super) fn light_json(li: usize, l: &PunctualLight) -> (Value, Value) {
    let (ty, pos, dir, power) = match *l {
        PunctualLight::Point {
            position,
            intensity,
        } => ("point", Some(position), None, intensity),
        PunctualLight::Spot {
            position,
            direction,
            intensity,
            ..
        } => ("spot", Some(position), Some(direction), intensity),
        PunctualLight::Directional {
            direction,
            irradiance,
        } => ("directional", None, Some(direction), irradiance),
    };
    let (color, intensity) = split_color(power);
    let mut light = json!({ "type": ty, "color": color.to_array(), "intensity": intensity });
    if let PunctualLight::Spot {
        cos_inner,
        cos_outer,
        ..
    } = *l
    {
        light["spot"] = json!({
            "innerConeAngle": cos_inner.clamp(-1.0, 1.0).acos(),
            "outerConeAngle": cos_outer.clamp(-1.0, 1.0).acos()
        });
    }
    let mut node = json!({
        "name": format!("light{li}"),
        "extensions": { "KHR_lights_punctual": { "light": li } }
    });
    if let Some(p) = pos {
        node["translation"] = json!(p.to_array());
    }
    if let Some(d) = dir {
        let r = Quat::from_rotation_arc(Vec3::NEG_Z, d.normalize());
        node["rotation"] = json!(r.to_array());
    }
    (light, node)
}
