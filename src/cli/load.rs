//! The flags every subcommand that loads a glTF shares: its budgets and URI permission
//! (`refract::gltf_io::load::LoadLimits`).

use refract::gltf_io::load::LoadLimits;
use refract::gltf_io::load::limits::{DEFAULT_MAX_TEXTURE_PIXELS, DEFAULT_MAX_TRIANGLES};

#[derive(clap::Args, Clone, Debug)]
pub struct LoadArgs {
    /// Most triangles a glTF scene may have after instancing (refused before it is built).
    #[arg(long, default_value_t = DEFAULT_MAX_TRIANGLES, value_name = "N")]
    pub max_triangles: u64,
    /// Most texels over all of a glTF scene's textures (16 bytes each once loaded).
    #[arg(long, default_value_t = DEFAULT_MAX_TEXTURE_PIXELS, value_name = "N")]
    pub max_texture_pixels: u64,
    /// Let a glTF's buffer and image URIs be absolute or point outside its folder (by
    /// default they are refused: a downloaded scene must not read other local files).
    #[arg(long)]
    pub allow_absolute_uris: bool,
}

impl Default for LoadArgs {
    /// The flags' defaults (the viewer opened without a subcommand).
    fn default() -> Self {
        let d = LoadLimits::default();
        Self {
            max_triangles: d.max_triangles,
            max_texture_pixels: d.max_texture_pixels,
            allow_absolute_uris: d.allow_absolute_uris,
        }
    }
}

impl LoadArgs {
    pub fn limits(&self) -> LoadLimits {
        LoadLimits {
            max_triangles: self.max_triangles,
            max_texture_pixels: self.max_texture_pixels,
            allow_absolute_uris: self.allow_absolute_uris,
            ..LoadLimits::default()
        }
    }
}
