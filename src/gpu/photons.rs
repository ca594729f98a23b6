//! The GPU photon store of `sppm` (src/shaders/photon.wgsl): the radius schedule, the two
//! buffers (photons, and the hash grid's counters, bucket heads and links) and the per-iteration
//! clear. Twin of `cpu::sppm` (`SppmParams`, `HashGrid`): same radius schedule, same number of
//! photon paths per iteration (one per pixel), same hash and 2r cells; the CPU and GPU
//! renderers never import each other, so the schedule is restated here (tests/gpu_sppm.rs
//! checks the two agree).

use super::GpuContext;
use super::layout::{PHOTON_HEADS, Photon};
use crate::scene::Camera;
use anyhow::{Result, ensure};
use glam::Vec3;

/// The radius exponent α of Knaus & Zwicker 2011 (`cpu::sppm::ALPHA`).
pub const ALPHA: f32 = 2.0 / 3.0;
/// r₁ in pixel footprints at the scene's centre (`cpu::sppm::RADIUS_PIXELS`).
pub const RADIUS_PIXELS: f32 = 1.5;

/// r₁ for an image `height` pixels tall of a scene with `bounds` seen by `cam` (twin of
/// `SppmParams::new`): 1.5 pixel footprints at the distance of the scene's centre.
pub fn radius0(cam: &Camera, bounds: (Vec3, Vec3), height: u32) -> f32 {
    let centre = 0.5 * (bounds.0 + bounds.1);
    let mut dist = (centre - cam.position).length();
    let diag = (bounds.1 - bounds.0).length();
    if !(dist.is_finite() && dist > 0.0) {
        dist = diag.max(1.0);
    }
    let footprint = dist * 2.0 * (0.5 * cam.yfov).tan() / height.max(1) as f32;
    let r = RADIUS_PIXELS * footprint;
    if r.is_finite() && r > 0.0 {
        r
    } else {
        1e-3 * diag.max(1e-6)
    }
}

/// The radius of iteration `s` (0-based): r₁ · (s + 1)^((α − 1)/2) (Knaus & Zwicker 2011,
/// eq. 15 in closed form; `SppmParams::radius`).
pub fn radius(r0: f32, s: u32) -> f32 {
    r0 * ((s as f64 + 1.0).powf(0.5 * (ALPHA as f64 - 1.0))) as f32
}

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
