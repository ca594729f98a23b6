//! URIs: percent-decoding of relative paths and base64 `data:` payloads; image files are
//! read through `files` (regular files inside the scene's folder only).

use anyhow::bail;
use gltf::json;
use std::path::Path;

/// Relative URIs must percent-decode to UTF-8 (the `gltf` importer would panic otherwise).
pub(super) fn check_uris(root: &json::Root) -> anyhow::Result<()> {
    for (i, b) in root.buffers.iter().enumerate() {
        if let Some(uri) = &b.uri
            && !uri.contains(':')
            && percent_decode(uri).is_none()
        {
            bail!("buffer {i}: URI '{uri}' is not valid percent-encoded UTF-8");
        }
    }
    Ok(())
}

/// Percent-decode a relative URI (invalid escapes are kept literally); None if not UTF-8.
pub(super) fn percent_decode(s: &str) -> Option<String> {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%'
            && let Some(h) = b.get(i + 1..i + 3)
            && let Ok(hs) = std::str::from_utf8(h)
            && let Ok(v) = u8::from_str_radix(hs, 16)
        {
            out.push(v);
            i += 3;
            continue;
        }
        out.push(b[i]);
        i += 1;
    }
    String::from_utf8(out).ok()
}

/// Minimal standard base64 decoder for `data:` image URIs (padding and whitespace tolerated).
pub(super) fn base64_decode(s: &str) -> Option<Vec<u8>> {
    let mut out = Vec::with_capacity(s.len() / 4 * 3);
    let mut acc = 0u32;
    let mut bits = 0u32;
    for c in s.bytes() {
        let v = match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' | b'-' => 62,
            b'/' | b'_' => 63,
            b'=' | b' ' | b'\n' | b'\r' | b'\t' => continue,
            _ => return None,
        };
        acc = (acc << 6) | v as u32;
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
            acc &= (1 << bits) - 1;
        }
    }
    Some(out)
}

/// The bytes of image `ii` from its URI: a base64 `data:` URI or a file relative to `base`.
pub(super) fn image_bytes(
    uri: &str,
    base: Option<&Path>,
    ii: usize,
    limits: &super::limits::LoadLimits,
) -> Result<Vec<u8>, String> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let data = rest
            .split_once(',')
            .map(|(_, d)| d)
            .ok_or_else(|| format!("image {ii}: malformed data URI"))?;
        base64_decode(data).ok_or_else(|| format!("image {ii}: bad base64 data"))
    } else if uri.contains(':') && !uri.starts_with("file:") {
        Err(format!("image {ii}: unsupported URI scheme"))
    } else {
        let rel = uri
            .strip_prefix("file://")
            .or(uri.strip_prefix("file:"))
            .unwrap_or(uri);
        let rel = percent_decode(rel).ok_or_else(|| format!("image {ii}: bad URI"))?;
        let base =
            base.ok_or_else(|| format!("image {ii}: external file '{rel}' but no base directory"))?;
        let what = format!("image {ii}");
        let path = super::files::resolve_uri(base, &rel, &what, limits.allow_absolute_uris)?;
        super::files::read_regular_file(&path, limits.max_file_bytes, &what)
    }
}
