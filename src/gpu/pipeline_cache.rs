//! wgpu's driver pipeline cache, kept on disk between runs: where the device has
//! `Features::PIPELINE_CACHE` (Vulkan), every compute pipeline is created with one
//! `wgpu::PipelineCache` whose initial data is read from a file under the user's cache
//! directory, named by `wgpu::util::pipeline_cache_key` (vendor and device; wgpu and the
//! driver also check the driver version in the data's header and start empty on a mismatch).
//! The data is written back after each compilation. Without the feature (wgpu's GL backend)
//! there is no cache and no error. A missing, unreadable or corrupt file only means a cold
//! start; a failed write is reported by the caller as a warning, never an error.

use super::GpuContext;
use anyhow::{Context, Result};
use std::path::{Path, PathBuf};

/// The directory cache files go to: `$REFRACT_CACHE_DIR`, else `$XDG_CACHE_HOME/refract`,
/// else `$HOME/.cache/refract` (the XDG base directory specification's default). None where
/// none of these is set.
pub fn default_dir() -> Option<PathBuf> {
    let env = |k: &str| {
        std::env::var_os(k)
            .filter(|v| !v.is_empty())
            .map(PathBuf::from)
    };
    env("REFRACT_CACHE_DIR")
        .or_else(|| env("XDG_CACHE_HOME").map(|d| d.join("refract")))
        .or_else(|| env("HOME").map(|h| h.join(".cache").join("refract")))
}

/// A driver pipeline cache with the file it was loaded from and is saved to.
pub struct DiskPipelineCache {
    pub cache: wgpu::PipelineCache,
    /// The cache file (None: kept in memory only).
    pub path: Option<PathBuf>,
    /// Bytes of cache data read at creation (0: a cold start).
    pub loaded_bytes: usize,
}

impl DiskPipelineCache {
    /// The cache for `ctx`'s device with the data of `dir`'s file for this adapter, or None
    /// where the device has no `PIPELINE_CACHE` feature or wgpu no cache key for its backend.
    pub fn open(ctx: &GpuContext, dir: Option<&Path>) -> Option<DiskPipelineCache> {
        if !ctx
            .device
            .features()
            .contains(wgpu::Features::PIPELINE_CACHE)
        {
            return None;
        }
        let key = wgpu::util::pipeline_cache_key(&ctx.info)?;
        let path = dir.map(|d| d.join(key));
        let data = path.as_ref().and_then(|p| std::fs::read(p).ok());
        // SAFETY: `data` is what `PipelineCache::get_data` returned for a cache of an adapter
        // with the same `pipeline_cache_key` (the file is named by it and only `save` writes
        // it). wgpu validates its header (wgpu version, vendor, device, driver) and, with
        // `fallback: true`, starts an empty cache when the data does not fit, as the driver
        // does for data it does not accept.
        let cache = unsafe {
            ctx.device
                .create_pipeline_cache(&wgpu::PipelineCacheDescriptor {
                    label: Some("refract pipelines"),
                    data: data.as_deref(),
                    fallback: true,
                })
        };
        Some(DiskPipelineCache {
            cache,
            path,
            loaded_bytes: data.map_or(0, |d| d.len()),
        })
    }

    /// Write the cache's data to its file (through a temporary file and a rename, so a
    /// concurrent reader never sees half a file). Ok(false): nothing to write.
    pub fn save(&self) -> Result<bool> {
        let (Some(path), Some(data)) = (&self.path, self.cache.get_data()) else {
            return Ok(false);
        };
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir)
                .with_context(|| format!("cannot create the cache directory {}", dir.display()))?;
        }
        let tmp = path.with_extension(format!("tmp{}", std::process::id()));
        std::fs::write(&tmp, &data)
            .with_context(|| format!("cannot write the pipeline cache {}", tmp.display()))?;
        std::fs::rename(&tmp, path)
            .with_context(|| format!("cannot write the pipeline cache {}", path.display()))?;
        Ok(true)
    }
}
