//! The GPU photon store of `sppm` (src/gpu/photon.wgsl): the radius schedule, the two
//! buffers (photons, and the hash grids' counters, links and bucket heads) and the clear at
//! the start of a submission. Twin of `cpu::sppm` (`SppmParams`, `HashGrid`): same radius
//! schedule (`render::photon_radius`, shared by both renderers), same number of photon paths
//! per iteration, same hash and 2r cells.
//!
//! A submission runs several iterations (sample index s = iteration s), each with its own
//! photons and grid: one iteration per submission left a GPU waiting on each iteration's
//! longest photon and camera paths, and, where sppm's camera walk is a wavefront, paid the
//! wavefront's every bounce dispatch (`max_depth` + 1, with nested media + 65 more, × 5) per
//! sample where path tracing pays them once per 16 (docs/performance.md, "sppm's photon
//! pass"). The store holds [`PhotonStore::iterations`] of them.

use super::GpuContext;
use super::layout::{PHOTON_HEADS, Photon};
use crate::gpu::submissions::MAX_SPP_PER_SUBMISSION;
use anyhow::{Result, ensure};

pub use crate::render::photon_radius::{ALPHA, RADIUS_EXPONENT, RADIUS_PIXELS, radius, radius0};

/// The most memory the photon store takes for its iterations together (at least one
/// iteration, whatever it needs): 512×512 fits 16 iterations, 1080p 2.
pub const STORE_BUDGET: u64 = 256 << 20;

/// Buckets of the hash grid for `paths` photon paths (`HashGrid::build` with every path
/// stored: a power of two ≥ 2 × paths, at least 16).
pub fn buckets(paths: u32) -> u32 {
    (2 * paths.max(1)).next_power_of_two().max(16)
}

/// (photon bytes, grid bytes) of a store for `iterations` iterations of `paths` photon paths.
fn store_bytes(paths: u32, iterations: u32) -> (u64, u64) {
    let (p, k) = (u64::from(paths), u64::from(iterations));
    let photons = k * p * std::mem::size_of::<Photon>() as u64;
    let grid = 4 * (u64::from(PHOTON_HEADS) + k * p + k * u64::from(buckets(paths)));
    (photons, grid)
}

/// Iterations a store of `paths` photon paths per iteration holds: as many as fit `cap` bytes
/// per binding and [`STORE_BUDGET`] in all, at most [`MAX_SPP_PER_SUBMISSION`], at least 1.
pub fn iterations_for(paths: u32, cap: u64) -> u32 {
    (1..=MAX_SPP_PER_SUBMISSION)
        .rev()
        .find(|&k| {
            let (p, g) = store_bytes(paths, k);
            p.max(g) <= cap && p + g <= STORE_BUDGET
        })
        .unwrap_or(1)
}

/// The most photon paths per iteration whose store (one iteration) fits `cap` bytes per
/// binding: an image's one slot per pixel is capped to it on devices with small bindings
/// (lavapipe and many laptop GPUs bind 128 MiB: 4K with sppm wanted 379 MiB). Fewer photons
/// per iteration keep sppm consistent (each iteration's estimate is normalised by its own
/// photon count); they only make each iteration noisier.
pub fn max_paths(cap: u64) -> u32 {
    let fits = |p: u32| {
        let (ph, g) = store_bytes(p, 1);
        ph.max(g) <= cap
    };
    let (mut lo, mut hi) = (1u32, u32::MAX / 2);
    if fits(hi) {
        return hi;
    }
    // Invariant: fits(lo) (or lo = 1), !fits(hi).
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        if fits(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// The photon store: `photons` holds one slot per photon path of each of `iterations`
/// iterations (each path stores at most one photon), `grid` the counters, one link per slot and
/// `buckets` heads per iteration.
pub struct PhotonStore {
    pub photons: wgpu::Buffer,
    pub grid: wgpu::Buffer,
    pub buckets: u32,
    /// Photon slots per iteration (photon paths per iteration): `requested`, at most
    /// [`max_paths`] of the device's binding.
    pub paths: u32,
    /// The slots asked for (one per pixel with sppm).
    pub requested: u32,
    /// Iterations one submission may run.
    pub iterations: u32,
}

impl PhotonStore {
    /// A store for `paths` photon paths per iteration (1 for a placeholder: kernels without
    /// photons still bind the buffers), capped to what one binding of the device holds
    /// ([`max_paths`]).
    pub fn new(ctx: &GpuContext, paths: u32) -> Result<PhotonStore> {
        let requested = paths.max(1);
        let cap = ctx.max_binding_bytes();
        let paths = requested.min(max_paths(cap));
        let buckets = buckets(paths);
        let iterations = if paths > 1 {
            iterations_for(paths, cap)
        } else {
            1
        };
        let (photon_bytes, grid_bytes) = store_bytes(paths, iterations);
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
            requested,
            iterations,
        })
    }

    /// Queue the start of a submission of `k` iterations: no photons stored, every bucket of
    /// their grids empty (the overflow counter and the links stay; links are written before
    /// they are read).
    pub fn encode_clear(&self, enc: &mut wgpu::CommandEncoder, k: u32) {
        enc.clear_buffer(&self.grid, 0, Some(4));
        let heads = u64::from(PHOTON_HEADS) + u64::from(self.iterations) * u64::from(self.paths);
        enc.clear_buffer(
            &self.grid,
            4 * heads,
            Some(4 * u64::from(self.buckets) * u64::from(k.min(self.iterations))),
        );
    }

    /// (photons stored by the last submission, all its iterations together; photons refused
    /// by a full store since the last clear of the whole grid).
    pub fn counts(&self, ctx: &GpuContext) -> Result<(u32, u32)> {
        let bytes = ctx.read_buffer(&self.grid, 8)?;
        let w: [u32; 2] = bytemuck::pod_read_unaligned(&bytes);
        Ok((w[0], w[1]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Small images batch the most iterations, large ones fewer, never none; every store
    /// fits the binding and the budget.
    #[test]
    fn iterations_fit_the_bindings() {
        let cap = 128 << 20;
        assert_eq!(iterations_for(32 * 24, cap), MAX_SPP_PER_SUBMISSION);
        assert_eq!(iterations_for(512 * 512, cap), 10);
        assert_eq!(iterations_for(1920 * 1080, cap), 1);
        assert_eq!(iterations_for(3840 * 2160, cap), 1);
        // 4K wants 8.3 M slots: capped to what 128 MiB binds, which then fits.
        let most = max_paths(cap);
        assert!((2_000_000..3_000_000).contains(&most), "{most}");
        let (p, g) = store_bytes(most, 1);
        assert!(p.max(g) <= cap);
        let (p, g) = store_bytes(most + 1, 1);
        assert!(p.max(g) > cap);
        for paths in [1, 1000, 512 * 512, 1920 * 1080] {
            let k = iterations_for(paths, cap);
            let (p, g) = store_bytes(paths, k);
            assert!(
                k == 1 || (p.max(g) <= cap && p + g <= STORE_BUDGET),
                "{paths}"
            );
        }
    }
}
