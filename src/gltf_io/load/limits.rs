//! The budgets and permissions of one load: what a glTF may make us allocate and read.
//!
//! The defaults fit large real scenes (a 100 M-triangle scene, textures of 256 M texels in
//! all, 4 GiB files) and refuse what would only exhaust memory; the CLI's `--max-triangles`,
//! `--max-texture-pixels` and `--allow-absolute-uris` change them. Every refusal names the
//! budget, the value and the flag that raises it.

/// Budgets and permissions of a load (`Default`: the documented defaults).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LoadLimits {
    /// Most triangles after instancing (`--max-triangles`).
    pub max_triangles: u64,
    /// Most texels over all textures of the scene (`--max-texture-pixels`); each texel is
    /// stored as four f32 (16 bytes).
    pub max_texture_pixels: u64,
    /// Most bytes of the scene file, one buffer or one image file.
    pub max_file_bytes: u64,
    /// Let URIs be absolute or leave the scene's folder (`--allow-absolute-uris`); they are
    /// still read only from regular files.
    pub allow_absolute_uris: bool,
}

/// Default of `max_triangles`.
pub const DEFAULT_MAX_TRIANGLES: u64 = 100_000_000;
/// Default of `max_texture_pixels` (4 GiB of texels).
pub const DEFAULT_MAX_TEXTURE_PIXELS: u64 = 1 << 28;
pub use crate::files::DEFAULT_MAX_FILE_BYTES;

impl Default for LoadLimits {
    fn default() -> Self {
        Self {
            max_triangles: DEFAULT_MAX_TRIANGLES,
            max_texture_pixels: DEFAULT_MAX_TEXTURE_PIXELS,
            max_file_bytes: DEFAULT_MAX_FILE_BYTES,
            allow_absolute_uris: false,
        }
    }
}
