//! Where in the JSON a glTF fails to parse: serde's typed error says only "invalid type …
//! at line 1 column 4560" (a GLB's JSON is one line), so the failing top-level element is
//! found again by parsing each one alone, and the error names its JSON pointer
//! (`/materials/4: invalid type: string "1.5", expected f32`).

use gltf::json;
use serde::de::DeserializeOwned;
use serde_json::Value;

/// A readable message for a JSON chunk `text` that `gltf` could not parse (`err`: its error).
pub(super) fn describe(text: &[u8], err: &dyn std::fmt::Display) -> String {
    let value: Value = match serde_json::from_slice(text) {
        Ok(v) => v,
        Err(e) => return format!("its JSON is malformed: {e}"),
    };
    let Value::Object(top) = &value else {
        return format!("the top level must be a JSON object, not {}", kind(&value));
    };
    for (key, v) in top {
        if let Some(at) = failing_element(key, v) {
            return at;
        }
    }
    err.to_string()
}

/// "/key/i: error" for the first element of a top-level array that does not parse alone.
fn failing_element(key: &str, v: &Value) -> Option<String> {
    let check = match key {
        "accessors" => first_bad::<json::Accessor>,
        "animations" => first_bad::<json::Animation>,
        "buffers" => first_bad::<json::Buffer>,
        "bufferViews" => first_bad::<json::buffer::View>,
        "cameras" => first_bad::<json::Camera>,
        "images" => first_bad::<json::Image>,
        "materials" => first_bad::<json::Material>,
        "meshes" => first_bad::<json::Mesh>,
        "nodes" => first_bad::<json::Node>,
        "samplers" => first_bad::<json::texture::Sampler>,
        "scenes" => first_bad::<json::Scene>,
        "skins" => first_bad::<json::Skin>,
        "textures" => first_bad::<json::Texture>,
        "asset" => {
            return serde_json::from_value::<json::Asset>(v.clone())
                .err()
                .map(|e| format!("/asset: {e}"));
        }
        _ => return None,
    };
    let Value::Array(items) = v else {
        return Some(format!("/{key} must be an array, not {}", kind(v)));
    };
    check(items).map(|(i, e)| format!("/{key}/{i}: {e}"))
}

fn first_bad<T: DeserializeOwned>(items: &[Value]) -> Option<(usize, serde_json::Error)> {
    items
        .iter()
        .enumerate()
        .find_map(|(i, v)| serde_json::from_value::<T>(v.clone()).err().map(|e| (i, e)))
}

fn kind(v: &Value) -> &'static str {
    match v {
        Value::Null => "null",
        Value::Bool(_) => "a boolean",
        Value::Number(_) => "a number",
        Value::String(_) => "a string",
        Value::Array(_) => "an array",
        Value::Object(_) => "an object",
    }
}
