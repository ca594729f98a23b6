//! glTF 2.0 loader following the scene contract in DESIGN.md.

use super::Scene;
use std::path::Path;

/// Load a `.gltf` or `.glb` file.
pub fn load_path(path: &Path) -> anyhow::Result<Scene> {
    let bytes = std::fs::read(path)
        .map_err(|e| anyhow::anyhow!("cannot read scene '{}': {e}", path.display()))?;
    load_slice(&bytes, path.parent(), &path.display().to_string())
}

/// Load from bytes; `base` resolves relative URIs (None = only embedded data).
pub fn load_slice(_bytes: &[u8], _base: Option<&Path>, name: &str) -> anyhow::Result<Scene> {
    anyhow::bail!("glTF loading is not implemented yet ({name})")
}
