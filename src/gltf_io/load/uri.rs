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

/// Percent-decode a relative URI (invalid escapes are kept literally, RFC 3986 §2.1 as the
/// `percent-encoding` crate reads it); None if the bytes are not UTF-8.
pub(super) fn percent_decode(s: &str) -> Option<String> {
    percent_encoding::percent_decode_str(s)
        .decode_utf8()
        .ok()
        .map(|c| c.into_owned())
}

/// Decode the base64 payload of a `data:` URI (RFC 4648): the standard alphabet, or the
/// URL-safe one some exporters write; padding optional, whitespace (line breaks in
/// hand-edited files) ignored. None if it is not base64.
pub(super) fn base64_decode(s: &str) -> Option<Vec<u8>> {
    use base64::Engine as _;
    use base64::alphabet::{STANDARD, URL_SAFE};
    use base64::engine::{DecodePaddingMode, GeneralPurpose, GeneralPurposeConfig};
    let config = GeneralPurposeConfig::new()
        .with_decode_padding_mode(DecodePaddingMode::Indifferent)
        .with_decode_allow_trailing_bits(true);
    let compact: String = s.chars().filter(|c| !c.is_ascii_whitespace()).collect();
    GeneralPurpose::new(&STANDARD, config)
        .decode(&compact)
        .or_else(|_| GeneralPurpose::new(&URL_SAFE, config).decode(&compact))
        .ok()
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percent_decoding_keeps_invalid_escapes_and_rejects_non_utf8() {
        assert_eq!(percent_decode("a%20b.bin").as_deref(), Some("a b.bin"));
        assert_eq!(percent_decode("100%.bin").as_deref(), Some("100%.bin"));
        assert_eq!(percent_decode("%C3%A9").as_deref(), Some("é"));
        assert_eq!(percent_decode("%FF"), None);
    }

    #[test]
    fn base64_tolerates_padding_whitespace_and_the_url_safe_alphabet() {
        assert_eq!(base64_decode("aGVsbG8=").as_deref(), Some(&b"hello"[..]));
        assert_eq!(base64_decode("aGVs\nbG8").as_deref(), Some(&b"hello"[..]));
        assert_eq!(base64_decode("-_8=").as_deref(), Some(&[0xfb, 0xff][..]));
        assert_eq!(base64_decode("+/8=").as_deref(), Some(&[0xfb, 0xff][..]));
        assert_eq!(base64_decode("a$b"), None);
    }
}
