//! Read-only views of a [`GpuRenderer`] (device, scene, options, pipelines, BVH) and the
//! viewer's accessors.

use super::GpuRenderer;
use crate::gpu::GpuContext;
use crate::gpu::pipeline::Specialization;
use crate::paths::DfaTable;
use crate::render::RenderOptions;
use crate::scene::Scene;
use std::time::Duration;

impl GpuRenderer {
    pub fn adapter_info(&self) -> &wgpu::AdapterInfo {
        &self.ctx.info
    }
    /// True on a CPU-emulated adapter (lavapipe …).
    pub fn is_software(&self) -> bool {
        self.ctx.is_software()
    }
    pub fn context(&self) -> &GpuContext {
        &self.ctx
    }
    pub fn scene(&self) -> &Scene {
        &self.scene
    }
    pub fn options(&self) -> &RenderOptions {
        &self.opts
    }
    /// Samples per pixel accumulated since the last reset.
    pub fn spp(&self) -> u64 {
        self.spp
    }
    /// Pipelines compiled so far (parameter edits must not add any).
    pub fn pipelines_compiled(&self) -> u32 {
        self.pipelines.compiled
    }
    /// Specialisations whose pipelines are compiled now (at most the cache's capacity).
    pub fn cached_specializations(&self) -> usize {
        self.pipelines.cached_specializations()
    }
    /// Keep at most `n` specialisations compiled (`Pipelines::set_capacity`).
    pub fn set_pipeline_capacity(&mut self, n: usize) {
        self.pipelines.set_capacity(n);
    }
    /// Wall time of the last specialisation's pipeline creation.
    pub fn last_compile_time(&self) -> Option<Duration> {
        self.pipelines.last_compile
    }
    /// Bytes of driver pipeline cache data loaded from disk when the renderer was created
    /// (None: the device has no pipeline cache; 0: a cold cache).
    pub fn pipeline_cache_loaded(&self) -> Option<usize> {
        self.pipelines.disk_cache().map(|c| c.loaded_bytes)
    }
    /// The pipeline cache file (None: no cache, or no cache directory).
    pub fn pipeline_cache_path(&self) -> Option<&std::path::Path> {
        self.pipelines.disk_cache().and_then(|c| c.path.as_deref())
    }
    pub fn specialization(&self) -> Specialization {
        self.spec
    }
    /// The tree's build time, depth and node count.
    pub fn bvh_info(&self) -> (Duration, u32, usize) {
        (self.bvh.build_time, self.bvh.depth, self.bvh.node_count())
    }
    /// Which tree the kernels traverse.
    pub fn bvh_layout(&self) -> crate::gpu::upload::BvhLayout {
        self.bvh.layout
    }

    // ---- BEGIN viewer accessors (used by app::backend::gpu; keep this block last) ----------

    /// The accumulation buffer: `array<vec4<f32>>`, per-pixel MEAN radiance (linear Rec.709),
    /// row-major, top row first, `width × height` entries. The viewer tone-maps it on the GPU.
    pub fn accum_buffer(&self) -> &wgpu::Buffer {
        &self.buffers.accum
    }

    /// The stats buffer; its first 16 bytes are the [`layout::Stats`] counters.
    ///
    /// [`layout::Stats`]: crate::gpu::layout::Stats
    pub fn stats_buffer(&self) -> &wgpu::Buffer {
        &self.buffers.stats
    }

    /// Set the path filter from an eye→light table (as [`RenderOptions::filter`]; None =
    /// every path; the GPU has no use for the light→eye table). Like
    /// [`GpuRenderer::set_filter`]; accumulation restarts.
    pub fn set_filter_table(&mut self, table: Option<DfaTable>) {
        self.opts.filter = table;
        if table.is_some() {
            self.polarization = None; // polarised transport renders every path
        }
        self.respecialize();
        self.reset();
    }

    // ---- END viewer accessors ---------------------------------------------------------------
}
