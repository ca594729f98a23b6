//! Reading results back: the image, the counters, the photon counts and the debug path.

use super::{DebugPath, GpuImage, GpuRenderer, STATS_BYTES};
use crate::gpu::layout;
use crate::render::RenderStats;
use anyhow::Result;
use glam::{Vec3, Vec4};

impl GpuRenderer {
    fn read_stats(&self) -> Result<(layout::Stats, Vec<Vec4>)> {
        let bytes = self.ctx.read_buffer(&self.buffers.stats, STATS_BYTES)?;
        let head: layout::Stats = bytemuck::pod_read_unaligned(&bytes[..16]);
        let recs: Vec<[f32; 4]> = bytemuck::pod_collect_to_vec(&bytes[16..]);
        Ok((head, recs.into_iter().map(Vec4::from_array).collect()))
    }

    /// Read the accumulated image back.
    pub fn image(&self) -> Result<GpuImage> {
        let px: Vec<[f32; 4]> = match &self.tiled {
            Some(mean) => mean.clone(),
            None => {
                let pixels = self.opts.width as u64 * self.opts.height as u64;
                let bytes = self.ctx.read_buffer(&self.buffers.accum, pixels * 16)?;
                bytemuck::pod_collect_to_vec(&bytes)
            }
        };
        let (stats, _) = self.read_stats()?;
        Ok(GpuImage {
            width: self.opts.width,
            height: self.opts.height,
            mean: px.iter().map(|p| Vec3::new(p[0], p[1], p[2])).collect(),
            spp: self.spp,
            dropped: stats.dropped_lo as u64 | (stats.dropped_hi as u64) << 32,
        })
    }

    /// `sppm`: (photons the last submission's iterations stored, photons refused by a full
    /// store since the last reset; 0 unless the store is undersized).
    pub fn photon_counts(&self) -> Result<(u32, u32)> {
        self.buffers.photon_store.counts(&self.ctx)
    }

    /// `sppm`: the most iterations (samples per pixel) one submission runs, each with its own
    /// photons (`gpu::photons::PhotonStore::iterations`); 1 for the other estimators.
    pub fn photon_iterations(&self) -> u32 {
        self.buffers.photon_store.iterations
    }

    /// Counters since the last reset.
    pub fn stats(&self) -> Result<RenderStats> {
        let (s, _) = self.read_stats()?;
        Ok(RenderStats {
            spp: self.spp,
            dropped: s.dropped_lo as u64 | (s.dropped_hi as u64) << 32,
            segments: Some(s.segments_lo as u64 | (s.segments_hi as u64) << 32),
            elapsed: self.elapsed,
            pixels: self.opts.pixels(),
        })
    }

    /// Record the first sample of every later batch at `pixel` (linear index); None = off.
    pub fn set_debug_pixel(&mut self, pixel: Option<u32>) {
        self.debug_pixel = pixel.unwrap_or(u32::MAX);
    }

    /// The path recorded at the debug pixel by the last dispatch.
    pub fn debug_path(&self) -> Result<DebugPath> {
        let (_, r) = self.read_stats()?;
        let dims = r[1 + layout::DEBUG_STRIDE * layout::DEBUG_MAX_VERTICES].w as u32;
        let value = r[1 + layout::DEBUG_STRIDE * layout::DEBUG_MAX_VERTICES].truncate();
        let mut p = DebugPath {
            camera_dir: r[0].truncate(),
            value,
            dims,
            ..Default::default()
        };
        for v in 0..layout::DEBUG_MAX_VERTICES {
            let hit = r[1 + layout::DEBUG_STRIDE * v];
            if hit.w <= 0.0 {
                break;
            }
            p.hits.push(hit);
            let b = r[2 + layout::DEBUG_STRIDE * v];
            if b.w as usize == v + 1 {
                p.betas.push(b.truncate());
                let d = r[3 + layout::DEBUG_STRIDE * v];
                p.dirs.push((d.truncate(), d.w as u32));
            }
        }
        Ok(p)
    }

    /// Clear the debug records (so a shorter path does not show an older one's tail).
    pub fn clear_debug(&mut self) {
        let mut enc = self
            .ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
        enc.clear_buffer(&self.buffers.stats, 16, None);
        self.ctx.queue.submit([enc.finish()]);
    }
}
