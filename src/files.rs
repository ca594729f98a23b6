//! Reading files safely (a glTF and the files it names, environment images, settings
//! sidecars): only regular files (a FIFO would block forever,
//! `/dev/zero` would never end), never more bytes than the caller allows, and — for URIs —
//! only inside the scene's folder (a downloaded glTF must not read `/etc/passwd` or
//! `../../.ssh/id_rsa` into a texture).

use std::io::Read;
use std::path::{Path, PathBuf};

/// Default of `max_file_bytes`.
pub const DEFAULT_MAX_FILE_BYTES: u64 = 4 << 30;

/// The contents of the regular file `path`, at most `max` bytes; `what` names it in errors.
pub fn read_regular_file(path: &Path, max: u64, what: &str) -> Result<Vec<u8>, String> {
    let shown = path.display();
    let meta = std::fs::metadata(path).map_err(|e| format!("cannot read {what} '{shown}': {e}"))?;
    if !meta.is_file() {
        return Err(format!(
            "cannot read {what} '{shown}': not a regular file (a directory, device or pipe)"
        ));
    }
    if meta.len() > max {
        return Err(format!(
            "{what} '{shown}' is {} bytes, more than the {max} allowed",
            meta.len()
        ));
    }
    let file =
        std::fs::File::open(path).map_err(|e| format!("cannot read {what} '{shown}': {e}"))?;
    let mut bytes = Vec::new();
    file.take(max + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| format!("cannot read {what} '{shown}': {e}"))?;
    if bytes.len() as u64 > max {
        return Err(format!(
            "{what} '{shown}' grew beyond {max} bytes while being read"
        ));
    }
    Ok(bytes)
}

/// The folder a scene file's relative URIs are read from, the same whatever form `path` has
/// (issue 41): a bare file name (`scene.gltf`, whose `Path::parent()` is the empty path) lies
/// in the current directory, and a symbolic link is followed to the file it points at, since
/// the buffers and textures an exporter writes lie beside the real file (the URIs themselves
/// are resolved through links the same way by [`resolve_uri`]).
pub fn scene_folder(path: &Path) -> Result<PathBuf, String> {
    let real = std::fs::canonicalize(path)
        .map_err(|e| format!("cannot resolve the scene path '{}': {e}", path.display()))?;
    Ok(real
        .parent()
        .map_or_else(|| PathBuf::from("/"), Path::to_path_buf))
}

/// The file a URI `rel` (already percent-decoded) names relative to the folder `base` (the
/// empty path is the current directory); unless `allow_outside`, an error if it resolves
/// outside that folder (absolute paths, `..`, symbolic links out of it).
pub fn resolve_uri(
    base: &Path,
    rel: &str,
    what: &str,
    allow_outside: bool,
) -> Result<PathBuf, String> {
    let base = if base.as_os_str().is_empty() {
        Path::new(".")
    } else {
        base
    };
    let full = base.join(rel);
    let canon = std::fs::canonicalize(&full)
        .map_err(|e| format!("cannot read {what} '{}': {e}", full.display()))?;
    if allow_outside {
        return Ok(canon);
    }
    let canon_base = std::fs::canonicalize(base)
        .map_err(|e| format!("cannot read the scene's folder '{}': {e}", base.display()))?;
    if !canon.starts_with(&canon_base) {
        return Err(format!(
            "{what} URI '{rel}' points outside the scene's folder '{}' (refused: a glTF may \
             only read files next to it unless --allow-absolute-uris is given)",
            base.display()
        ));
    }
    Ok(canon)
}
