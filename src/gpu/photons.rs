//! The GPU photon store of `sppm` (src/shaders/photon.wgsl): the radius schedule, the two
//! buffers (photons, and the hash grid's counters, bucket heads and links) and the per-iteration
//! clear. Twin of `cpu::sppm` (`SppmParams`, `HashGrid`): same radius schedule, same number of
//! photon paths per iteration (one per pixel), same hash and 2r cells; the radius schedule
//! is `render::photon_radius`, shared by both renderers.

use super::GpuContext;
use super::layout::{PHOTON_HEADS, Photon};
use anyhow::{Result, ensure};

pub use crate::render::photon_radius::{ALPHA, RADIUS_PIXELS, radius, radius0};

/// Buckets of the hash grid for `paths` photon paths (`HashGrid::build` with every path
/// stored: a power of two ≥ 2 × paths, at least 16).
pub fn buckets(paths: u32) -> u32 {
    (2 * paths.max(1)).next_power_of_two().max(16)
}

/// The photon store: `photons` holds one slot per photon path of an iteration (each path
/// stores at most one photon), `grid` the counters, `buckets` heads and one link per slot.
pub struct PhotonStore {
    pub photons: wgpu::Buffer,
    pub grid: wgpu::Buffer,
    pub buckets: u32,
    /// Photon slots (photon paths per iteration).
    pub paths: u32,
}

impl PhotonStore {
    /// A store for `paths` photon paths per iteration (1 for a placeholder: kernels without
    /// photons still bind the buffers). Errors if a buffer exceeds the device's binding size.
    pub fn new(ctx: &GpuContext, paths: u32) -> Result<PhotonStore> {
        let paths = paths.max(1);
        let buckets = buckets(paths);
        let photon_bytes = u64::from(paths) * std::mem::size_of::<Photon>() as u64;
        let grid_bytes = 4 * (u64::from(PHOTON_HEADS) + u64::from(buckets) + u64::from(paths));
        let cap = ctx.max_binding_bytes();
        ensure!(
            photon_bytes.max(grid_bytes) <= cap,
            "{paths} photon paths per iteration need a {} MiB photon store; the device binds at \
             most {} MiB per buffer (render smaller images with sppm, or use --device cpu)",
            photon_bytes.max(grid_bytes) >> 20,
            cap >> 20
        );
        let buffer = |label, size| {
            ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_DST
                    | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            })
        };
        Ok(PhotonStore {
            photons: buffer("photons", photon_bytes),
            grid: buffer("photon grid", grid_bytes),
            buckets,
            paths,
        })
    }

    /// Queue the start of an iteration: no photons stored, every bucket empty (the overflow
    /// counter and the links stay; links are written before they are read).
    pub fn encode_clear(&self, enc: &mut wgpu::CommandEncoder) {
        enc.clear_buffer(&self.grid, 0, Some(4));
        enc.clear_buffer(
            &self.grid,
            4 * u64::from(PHOTON_HEADS),
            Some(4 * u64::from(self.buckets)),
        );
    }

    /// (photons stored by the last iteration, photons refused by a full store since the last
    /// clear of the whole grid).
    pub fn counts(&self, ctx: &GpuContext) -> Result<(u32, u32)> {
        let bytes = ctx.read_buffer(&self.grid, 8)?;
        let w: [u32; 2] = bytemuck::pod_read_unaligned(&bytes);
        Ok((w[0], w[1]))
    }
}
