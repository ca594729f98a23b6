//! `extras` JSON: `scenes[0].extras.render` (render settings) and `extras.environment`.

use crate::scene::RenderSettings;
use crate::text::abbreviate;
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
                None => bail!(
                    "extras.render.{key} must be a non-negative integer, got {}",
                    abbreviate(&v.to_string())
                ),
            }
        }
    }
}

/// `scenes[0].extras.render` → settings (defaults for what is missing).
/// The keys `extras.render` may have.
const RENDER_KEYS: [&str; 6] = [
    "width",
    "height",
    "max_depth",
    "rr_depth",
    "spp",
    "light_line_nm",
];

/// Unknown keys of `extras.render` (a typo such as `sp` would otherwise silently keep the
/// default) go to `warnings`.
pub(super) fn parse_render_settings(
    extras: Option<&Value>,
    warnings: &mut Vec<String>,
) -> anyhow::Result<RenderSettings> {
    let mut s = RenderSettings::default();
    let Some(r) = extras.and_then(|e| e.get("render")) else {
        return Ok(s);
    };
    let Some(obj) = r.as_object() else {
        bail!(
            "/scenes/0/extras/render (extras.render) must be an object, got {}",
            abbreviate(&r.to_string())
        );
    };
    for k in obj.keys().filter(|k| !RENDER_KEYS.contains(&k.as_str())) {
        warnings.push(format!(
            "extras.render.{} is not a render setting (known: {}); ignored",
            abbreviate(k),
            RENDER_KEYS.join(", ")
        ));
    }
    let side = 1..=crate::scene::MAX_IMAGE_SIDE;
    for (key, field, range) in [
        ("width", &mut s.width, side.clone()),
        ("height", &mut s.height, side),
        ("max_depth", &mut s.max_depth, 0..=u32::MAX),
        ("rr_depth", &mut s.rr_depth, 0..=u32::MAX),
        ("spp", &mut s.spp, 1..=u32::MAX),
    ] {
        if let Some(v) = get_u32(r, key)? {
            if !range.contains(&v) {
                bail!(
                    "extras.render.{key} is {v}, outside {}..={}",
                    range.start(),
                    range.end()
                );
            }
            *field = v;
        }
    }
    s.light_line_nm = parse_light_line(r)?;
    Ok(s)
}

/// `extras.render.light_line_nm`: one wavelength (nm) every emitter radiates at
/// (`RenderSettings::light_line_nm`); null or missing = white light.
fn parse_light_line(r: &Value) -> anyhow::Result<Option<f32>> {
    const AT: &str = "/scenes/0/extras/render/light_line_nm (extras.render.light_line_nm)";
    match r.get("light_line_nm") {
        None | Some(Value::Null) => Ok(None),
        Some(v) => {
            let Some(nm) = v.as_f64() else {
                bail!(
                    "{AT} must be a wavelength in nm, got {}",
                    abbreviate(&v.to_string())
                );
            };
            crate::math::spectrum::check_light_line(nm as f32, AT)
                .map(Some)
                .map_err(anyhow::Error::msg)
        }
    }
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

/// True when `extras.render` sets the image's width or height (else the camera's aspect
/// ratio may shape it).
pub(super) fn has_image_size(extras: Option<&Value>) -> bool {
    extras
        .and_then(|e| e.get("render"))
        .is_some_and(|r| r.get("width").is_some() || r.get("height").is_some())
}
