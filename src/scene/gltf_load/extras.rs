//! `extras` JSON: `scenes[0].extras.render` (render settings) and `extras.environment`.

use crate::scene::RenderSettings;
use anyhow::{anyhow, bail};
use glam::Vec3;
use gltf::json;
use serde_json::Value;

/// The `extras` object at JSON pointer `at`, parsed; an error naming `at` when it cannot be
/// (it nests deeper than serde_json's 128 levels, say) instead of silently losing every
/// setting in it.
pub(super) fn extras_value(extras: &json::Extras, at: &str) -> anyhow::Result<Option<Value>> {
    let Some(raw) = extras.as_ref() else {
        return Ok(None);
    };
    serde_json::from_str::<Value>(raw.get())
        .map(Some)
        .map_err(|e| anyhow!("{at} cannot be read: {e}"))
}

fn get_u32(obj: &Value, key: &str) -> anyhow::Result<Option<u32>> {
    match obj.get(key) {
        None | Some(Value::Null) => Ok(None),
        Some(v) => {
            let x = v
                .as_f64()
                .filter(|x| x.fract() == 0.0 && *x >= 0.0 && *x <= u32::MAX as f64);
            match x {
                Some(x) => Ok(Some(x as u32)),
                None => bail!("extras.render.{key} must be a non-negative integer, got {v}"),
            }
        }
    }
}

/// `scenes[0].extras.render` → settings (defaults for what is missing).
pub(super) fn parse_render_settings(extras: Option<&Value>) -> anyhow::Result<RenderSettings> {
    let mut s = RenderSettings::default();
    let Some(r) = extras.and_then(|e| e.get("render")) else {
        return Ok(s);
    };
    if !r.is_object() {
        bail!("extras.render must be an object, got {r}");
    }
    if let Some(v) = get_u32(r, "width")? {
        s.width = v;
    }
    if let Some(v) = get_u32(r, "height")? {
        s.height = v;
    }
    if let Some(v) = get_u32(r, "max_depth")? {
        s.max_depth = v;
    }
    if let Some(v) = get_u32(r, "rr_depth")? {
        s.rr_depth = v;
    }
    if let Some(v) = get_u32(r, "spp")? {
        s.spp = v;
    }
    Ok(s)
}

/// `scenes[0].extras.environment` → uniform radiance `[r, g, b]` (a single number = grey).
pub(super) fn parse_environment(extras: Option<&Value>) -> anyhow::Result<Vec3> {
    let Some(e) = extras.and_then(|e| e.get("environment")) else {
        return Ok(Vec3::ZERO);
    };
    let bad = || anyhow!("extras.environment must be [r, g, b] with finite values ≥ 0, got {e}");
    let v = match e {
        Value::Number(n) => Vec3::splat(n.as_f64().ok_or_else(bad)? as f32),
        Value::Array(a) if a.len() == 3 => {
            let c: Option<Vec<f64>> = a.iter().map(|x| x.as_f64()).collect();
            let c = c.ok_or_else(bad)?;
            Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32)
        }
        _ => return Err(bad()),
    };
    if !(v.is_finite() && v.min_element() >= 0.0) {
        return Err(bad());
    }
    Ok(v)
}
