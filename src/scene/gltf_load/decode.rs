//! The GLB container: header checks before the `gltf` crate reads it.

use anyhow::bail;

/// Validate the GLB container header ourselves (the `gltf` crate subtracts before checking)
/// and cut the slice to the declared length.
pub(super) fn check_glb_header(bytes: &[u8]) -> anyhow::Result<&[u8]> {
    if !bytes.starts_with(b"glTF") {
        return Ok(bytes);
    }
    let word = |i: usize| -> Option<u32> {
        let b: [u8; 4] = bytes.get(i..i + 4)?.try_into().ok()?;
        Some(u32::from_le_bytes(b))
    };
    let (Some(version), Some(length)) = (word(4), word(8)) else {
        bail!(
            "truncated .glb: {} bytes, the header alone needs 12",
            bytes.len()
        );
    };
    if version != 2 {
        bail!(".glb container version {version} is not supported (only 2)");
    }
    let length = length as usize;
    if length < 20 {
        bail!("corrupt .glb: declared length {length} is too small for a JSON chunk");
    }
    if length > bytes.len() {
        bail!(
            "truncated .glb: header declares {length} bytes but the file has {}",
            bytes.len()
        );
    }
    let json_len = word(12).unwrap_or(0) as usize;
    if json_len > length - 20 {
        bail!("truncated .glb: JSON chunk of {json_len} bytes does not fit in {length} bytes");
    }
    Ok(&bytes[..length])
}
