//! The buffers of a glTF, read by us rather than by the `gltf` importer: the GLB binary
//! chunk, a base64 `data:` URI or a file inside the scene's folder, each exactly `byteLength`
//! bytes long (shorter is an error, longer is cut), so a file can neither claim data it does
//! not have nor make us read more than it declares. A meshopt fallback buffer without a URI
//! is empty: only views decoded from compressed data may use it (`meshopt`).

use super::files::{read_regular_file, resolve_uri};
use super::limits::LoadLimits;
use super::uri::{base64_decode, percent_decode};
use crate::text::abbreviate;
use gltf::json;
use std::path::Path;

/// Every buffer's bytes, in order.
pub(super) fn load_buffers(
    root: &json::Root,
    mut blob: Option<Vec<u8>>,
    base: Option<&Path>,
    limits: &LoadLimits,
) -> Result<Vec<Vec<u8>>, String> {
    let max = limits.max_file_bytes;
    let mut out = Vec::with_capacity(root.buffers.len());
    for (i, b) in root.buffers.iter().enumerate() {
        let len = b.byte_length.0;
        if len > max {
            return Err(format!(
                "buffer {i}: byteLength {len} is more than the {max} bytes allowed"
            ));
        }
        let mut data = match b.uri.as_deref() {
            // EXT_meshopt_compression: a fallback buffer may hold no data (only compressed views,
            // decoded from another buffer, point into it); it never takes the GLB chunk.
            None if super::meshopt::is_fallback(b) => {
                out.push(Vec::new());
                continue;
            }
            None => blob.take().ok_or_else(|| {
                format!("buffer {i} has no URI and the file has no GLB binary chunk")
            })?,
            Some(uri) => buffer_from_uri(uri, base, i, limits)?,
        };
        if (data.len() as u64) < len {
            return Err(format!(
                "buffer {i} has {} bytes but its byteLength is {len} (missing or short buffer)",
                data.len()
            ));
        }
        data.truncate(len as usize);
        out.push(data);
    }
    Ok(out)
}

/// A buffer's bytes from a `data:` URI or a file next to the scene.
fn buffer_from_uri(
    uri: &str,
    base: Option<&Path>,
    i: usize,
    limits: &LoadLimits,
) -> Result<Vec<u8>, String> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let (head, data) = rest
            .split_once(',')
            .ok_or_else(|| format!("buffer {i}: malformed data URI (no ',' before the data)"))?;
        if !head.ends_with(";base64") {
            return Err(format!("buffer {i}: data URI is not base64 ('{head}')"));
        }
        return base64_decode(data)
            .ok_or_else(|| format!("buffer {i}: data URI holds invalid base64"));
    }
    if uri.contains(':') && !uri.starts_with("file:") {
        return Err(format!(
            "buffer {i}: unsupported URI scheme in '{}'",
            abbreviate(uri)
        ));
    }
    let rel = uri
        .strip_prefix("file://")
        .or(uri.strip_prefix("file:"))
        .unwrap_or(uri);
    let rel = percent_decode(rel).ok_or_else(|| {
        format!(
            "buffer {i}: URI '{}' is not valid percent-encoded UTF-8",
            abbreviate(uri)
        )
    })?;
    let base = base.ok_or_else(|| {
        format!("buffer {i}: external file '{rel}' but no folder to read it from")
    })?;
    let what = format!("buffer {i}");
    let path = resolve_uri(base, &rel, &what, limits.allow_absolute_uris)?;
    read_regular_file(&path, limits.max_file_bytes, &what)
}
