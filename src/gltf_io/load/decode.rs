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
    let kind = word(16).unwrap_or(0);
    if kind != JSON {
        bail!(
            "corrupt .glb: the first chunk must be JSON (glTF 2.0 §4.4.3), its type is {}",
            chunk_name(kind)
        );
    }
    check_bin_chunk(&bytes[..length], 20 + json_len)?;
    Ok(&bytes[..length])
}

const JSON: u32 = 0x4E4F_534A;
const BIN: u32 = 0x004E_4942;

/// The optional second chunk at byte `at` (after the JSON chunk) must be a whole BIN chunk.
fn check_bin_chunk(glb: &[u8], at: usize) -> anyhow::Result<()> {
    let rest = &glb[at..];
    if rest.len() < 8 {
        return Ok(()); // no binary chunk (or only padding)
    }
    let word = |i: usize| u32::from_le_bytes([rest[i], rest[i + 1], rest[i + 2], rest[i + 3]]);
    let (len, kind) = (word(0) as usize, word(4));
    if kind != BIN {
        bail!(
            "corrupt .glb: the chunk after the JSON chunk (at byte {at}) has type {} instead of \
             BIN — is the JSON chunk's length ({} bytes) right?",
            chunk_name(kind),
            at - 20
        );
    }
    if len > rest.len() - 8 {
        bail!(
            "truncated .glb: BIN chunk of {len} bytes at byte {at} does not fit in the file's {} \
             bytes",
            glb.len()
        );
    }
    Ok(())
}

/// A chunk type for messages: its four characters when printable, else hex.
fn chunk_name(kind: u32) -> String {
    let b = kind.to_le_bytes();
    if b.iter().all(|c| c.is_ascii_graphic() || *c == 0) {
        format!("'{}'", String::from_utf8_lossy(&b).trim_end_matches('\0'))
    } else {
        format!("0x{kind:08x}")
    }
}

/// The JSON text of a glTF: a GLB's JSON chunk (after `check_glb_header`), else the whole file.
pub(super) fn json_text(bytes: &[u8]) -> &[u8] {
    if bytes.starts_with(b"glTF") && bytes.len() >= 20 {
        let len = u32::from_le_bytes([bytes[12], bytes[13], bytes[14], bytes[15]]) as usize;
        return bytes.get(20..20 + len).unwrap_or(&[]);
    }
    bytes
}
