//! `scenes[0].extras.environment`: uniform `[r, g, b]` (or one number) or an image
//! `{"uri": "sky.hdr", "strength": 1.0, "rotation": 0.0}` read through the same safe-file
//! rules as buffers and textures (a regular file inside the scene's folder); and the
//! fallback for a file with no light at all: the built-in studio environment, with a warning.

use super::limits::LoadLimits;
use super::{Warnings, extras, files, uri};
use crate::scene::Scene;
use crate::scene::env_map::{EnvImage, EnvMap};
use anyhow::{anyhow, bail};
use glam::Vec3;
use serde_json::Value;
use std::path::Path;
use std::sync::Arc;

/// The uniform radiance and the image (if the environment is an object).
pub(super) fn parse(
    extras: Option<&Value>,
    base: Option<&Path>,
    limits: &LoadLimits,
    warnings: &mut Warnings,
) -> anyhow::Result<(Vec3, Option<EnvImage>)> {
    match extras.and_then(|e| e.get("environment")) {
        Some(obj @ Value::Object(_)) => {
            Ok((Vec3::ZERO, Some(parse_image(obj, base, limits, warnings)?)))
        }
        _ => Ok((extras::parse_environment(extras)?, None)),
    }
}

/// A finite number at `key` of the environment object (default `dflt`).
fn number(obj: &Value, key: &str, dflt: f32, min: f32) -> anyhow::Result<f32> {
    match obj.get(key) {
        None | Some(Value::Null) => Ok(dflt),
        Some(v) => v
            .as_f64()
            .map(|x| x as f32)
            .filter(|x| x.is_finite() && *x >= min)
            .ok_or_else(|| {
                anyhow!("extras.environment.{key} must be a finite number ≥ {min}, got {v}")
            }),
    }
}

fn parse_image(
    obj: &Value,
    base: Option<&Path>,
    limits: &LoadLimits,
    warnings: &mut Warnings,
) -> anyhow::Result<EnvImage> {
    let Some(raw) = obj.get("uri").and_then(|u| u.as_str()) else {
        bail!("extras.environment must be [r, g, b] or an object with a string \"uri\", got {obj}");
    };
    let strength = number(obj, "strength", 1.0, 0.0)?;
    let rotation = number(obj, "rotation", 0.0, f32::MIN)?;
    let what = format!("extras.environment.uri '{raw}'");
    if raw.contains(':') && !raw.starts_with("file:") {
        bail!("{what}: only relative file URIs are supported");
    }
    let rel = raw
        .strip_prefix("file://")
        .or(raw.strip_prefix("file:"))
        .unwrap_or(raw);
    let rel = uri::percent_decode(rel).ok_or_else(|| anyhow!("{what}: bad URI"))?;
    let base = base.ok_or_else(|| anyhow!("{what}: an external file but no scene folder"))?;
    let path = files::resolve_uri(base, &rel, &what, limits.allow_absolute_uris)
        .map_err(|e| anyhow!(e))?;
    let bytes =
        files::read_regular_file(&path, limits.max_file_bytes, &what).map_err(|e| anyhow!(e))?;
    let ext = Path::new(&rel)
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("");
    let (mut map, w) = EnvMap::decode(&bytes, ext, &what)?;
    map.name = rel.clone();
    for m in w {
        warnings.push(m);
    }
    Ok(EnvImage::new(Arc::new(map), strength, rotation))
}

/// A scene with no emissive triangle, punctual light or environment is lit by the built-in
/// studio environment (Khronos' test scenes rely on image-based lighting), with a warning.
pub(super) fn light_the_lightless(scene: &mut Scene, warnings: &mut Warnings) {
    if scene.has_light() {
        return;
    }
    scene.env_map = Some(crate::scene::hdri::studio_env());
    warnings.push(format!(
        "'{}' has no light (no emissive material, KHR_lights_punctual light or environment): \
         lit by the built-in studio environment",
        scene.name
    ));
}
