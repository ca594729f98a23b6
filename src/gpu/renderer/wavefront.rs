//! The camera walk and lt+pt's light subpaths as wavefronts on the host side
//! (src/gpu/wavefront.wgsl, light_wavefront.wgsl): the path-state buffers, the chunk table
//! read at a dynamic offset, and the dispatches of one submission — every chunk's light
//! subpaths first (`lt_wf_start`, per bounce `lt_wf_extend`, `lt_wf_shade`, `lt_wf_splat`,
//! then `lt_wf_finish`: their splats land anywhere in the film), then per chunk of whole
//! pixels `wf_start`, per bounce `wf_extend`, `wf_nee`, `wf_shade`, `wf_connect`, then
//! `wf_finish`, which folds each pixel's samples and splats into the film.
//!
//! Each bounce's kernels run one thread per path still live (the `WfQueue` of
//! wavefront.wgsl): `wf_advance` writes the next bounce's dispatch size into the buffer the
//! bounce's kernels are dispatched from indirectly — once every path has ended, the
//! remaining bounces dispatch no workgroups. A chunk's walk is one compute pass. Without
//! indirect dispatch (`DownlevelFlags::INDIRECT_EXECUTION`) they dispatch the whole chunk,
//! whose threads past the queue's end return at once.

use super::GpuRenderer;
use crate::gpu::GpuContext;
use crate::gpu::pipeline::Kernel;
use wgpu::util::DeviceExt;

/// Bytes of one `WfPath` (wavefront.wgsl) and of one `LtPath` (light_wavefront.wgsl);
/// `tests/gpu.rs` checks both against the WGSL layouts.
pub const PATH_BYTES: u64 = 240;
pub const LIGHT_PATH_BYTES: u64 = 240;
/// Stride of the chunk table's entries: the largest `min_uniform_buffer_offset_alignment`
/// WebGPU allows.
pub const CHUNK_STRIDE: u64 = 256;
/// Chunks one submission may have (a larger one is split into submissions of fewer samples).
pub const MAX_CHUNKS: usize = 1024;
/// Bytes of `WfQueue`'s header (two counts, the running parity, padding).
pub const QUEUE_HEADER: u64 = 16;
/// Paths in flight at most (120 MiB of state; fewer, larger chunks cost the host less per
/// submission: `examples/wavefront_encode`, docs/gpu.md "Live-path queues").
const MAX_PATHS: u64 = 1 << 19;
// The bounce kernels' indirect sizes are at most MAX_PATHS / 64 workgroups, which must stay
// within WebGPU's least `max_compute_workgroups_per_dimension` (65535): wgpu does not check
// them (`gpu::context::instance_flags`).
const _: () = assert!(MAX_PATHS / 64 <= 65535);

/// The wavefront's buffers: path states for up to `max_paths` camera paths (and as many
/// light subpaths with lt+pt) and the chunk table.
pub struct WavefrontBuffers {
    pub paths: wgpu::Buffer,
    pub light_paths: wgpu::Buffer,
    pub chunks: wgpu::Buffer,
    /// `WfQueue`: its header (`QUEUE_HEADER` bytes) and two queues of `max_paths` path
    /// indices.
    pub queue: wgpu::Buffer,
    pub max_paths: u32,
    /// `light_paths` holds `max_paths` subpaths (else a placeholder).
    pub light: bool,
}

impl WavefrontBuffers {
    /// Buffers for `max_paths` paths (0: placeholders for a megakernel specialisation), with
    /// light subpaths when `light`.
    fn with_paths(ctx: &GpuContext, max_paths: u32, light: bool) -> WavefrontBuffers {
        let chunks = if max_paths == 0 { 1 } else { MAX_CHUNKS as u64 };
        let light_paths = if light { u64::from(max_paths) } else { 0 };
        let storage = |label, bytes: u64| {
            ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes,
                usage: wgpu::BufferUsages::STORAGE,
                mapped_at_creation: false,
            })
        };
        WavefrontBuffers {
            paths: storage(
                "wavefront paths",
                (u64::from(max_paths) * PATH_BYTES).max(PATH_BYTES),
            ),
            light_paths: storage(
                "wavefront light subpaths",
                (light_paths * LIGHT_PATH_BYTES).max(LIGHT_PATH_BYTES),
            ),
            chunks: ctx
                .device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("wavefront chunks"),
                    contents: &vec![0u8; (chunks * CHUNK_STRIDE) as usize],
                    usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                }),
            queue: ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("wavefront queues"),
                size: QUEUE_HEADER + 2 * 4 * u64::from(max_paths.max(1)),
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            max_paths,
            light,
        }
    }

    pub fn placeholder(ctx: &GpuContext) -> WavefrontBuffers {
        Self::with_paths(ctx, 0, false)
    }

    /// Buffers for as many paths as fit one binding, at most `MAX_PATHS`.
    pub fn sized(ctx: &GpuContext, light: bool) -> WavefrontBuffers {
        let paths = (ctx.max_binding_bytes() / PATH_BYTES.max(LIGHT_PATH_BYTES)).min(MAX_PATHS);
        Self::with_paths(ctx, paths as u32, light)
    }
}

/// `wf_advance`'s group 1: the running bounce's dispatch size, written by `wf_advance` and
/// read as the indirect argument of the bounce's kernels.
pub struct AdvanceArgs {
    pub buffer: wgpu::Buffer,
    pub group: wgpu::BindGroup,
}

impl AdvanceArgs {
    pub fn new(ctx: &GpuContext, pipelines: &crate::gpu::pipeline::Pipelines) -> AdvanceArgs {
        let buffer = ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("wavefront dispatch size"),
            size: 16,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::INDIRECT,
            mapped_at_creation: false,
        });
        let group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("wavefront dispatch size"),
            layout: &pipelines.advance_group_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: buffer.as_entire_binding(),
            }],
        });
        AdvanceArgs { buffer, group }
    }
}

/// Chunks of whole pixels for `pixels` pixels of `k` samples with at most `max_paths` paths
/// each: (first path, paths).
pub fn chunks(pixels: u32, k: u32, max_paths: u32) -> Vec<(u32, u32)> {
    let per = (max_paths / k.max(1)).max(1);
    (0..pixels)
        .step_by(per as usize)
        .map(|p0| (p0 * k, (per.min(pixels - p0)) * k))
        .collect()
}

/// Samples per pixel (at most `k`) that `pixels` pixels can take in one submission of at
/// most `MAX_CHUNKS` chunks.
pub fn samples_per_submission(pixels: u32, k: u32, max_paths: u32) -> u32 {
    let mut k = k.max(1);
    while k > 1 && chunks(pixels, k, max_paths).len() > MAX_CHUNKS {
        k = k.div_ceil(2);
    }
    k
}

impl GpuRenderer {
    /// Give the wavefront buffers the size the current specialisation needs and rebind when
    /// they change.
    pub(super) fn fit_wavefront(&mut self) {
        let want = self.spec.wavefront;
        let light = want && self.spec.light_tracing;
        let wf = &self.buffers.wavefront;
        if want == (wf.max_paths > 0) && light == wf.light {
            return;
        }
        self.buffers.wavefront = if want {
            WavefrontBuffers::sized(&self.ctx, light)
        } else {
            WavefrontBuffers::placeholder(&self.ctx)
        };
        self.bind_group = Self::bind(&self.ctx, &self.pipelines, &self.buffers);
    }

    /// The bounces a path can take: one per vertex up to `max_depth`, the escape, and with
    /// nested volumes the false hits passed on the way.
    fn wavefront_bounces(&self) -> u32 {
        let false_hits = if self.spec.nested {
            crate::gpu::layout::FALSE_HIT_LIMIT + 1
        } else {
            0
        };
        self.opts.max_depth.max(1) + 1 + false_hits
    }

    /// Record the camera walk of `pixels` pixels (rows from the submission's `tile_y0`) at
    /// `k` samples each, after their light subpaths when `light`: the chunk table written,
    /// then each chunk's dispatches.
    pub(super) fn encode_wavefront(
        &self,
        enc: &mut wgpu::CommandEncoder,
        pixels: u32,
        k: u32,
        light: bool,
    ) {
        let table = self.write_chunk_table(pixels, k);
        if light {
            self.encode_light_chunks(enc, &table);
        }
        let bounce_kernels: &[Kernel] = &[
            Kernel::WfExtend,
            Kernel::WfNee,
            Kernel::WfShade,
            Kernel::WfConnect,
        ];
        for (c, &(_, count)) in table.iter().enumerate() {
            let walk = ChunkWalk {
                offset: (c as u64 * CHUNK_STRIDE) as u32,
                groups: count.div_ceil(64),
                start: Kernel::WfStart,
                bounce: bounce_kernels,
                finish: (Kernel::WfFinish, (count / k.max(1)).div_ceil(64)),
            };
            self.encode_chunk_walk(enc, &walk);
        }
    }

    /// Record the light subpaths alone of `pixels` pixels at `k` samples each (a tile of a
    /// tiled image: the whole image's, in a submission of their own).
    pub(super) fn encode_wavefront_light(
        &self,
        enc: &mut wgpu::CommandEncoder,
        pixels: u32,
        k: u32,
    ) {
        let table = self.write_chunk_table(pixels, k);
        self.encode_light_chunks(enc, &table);
    }

    /// Write the chunk table of `pixels` pixels at `k` samples each and return it.
    fn write_chunk_table(&self, pixels: u32, k: u32) -> Vec<(u32, u32)> {
        let wf = &self.buffers.wavefront;
        let table = chunks(pixels, k, wf.max_paths);
        let mut bytes = vec![0u8; table.len() * CHUNK_STRIDE as usize];
        for (c, &(first, count)) in table.iter().enumerate() {
            let at = c * CHUNK_STRIDE as usize;
            bytes[at..at + 4].copy_from_slice(&first.to_le_bytes());
            bytes[at + 4..at + 8].copy_from_slice(&count.to_le_bytes());
        }
        self.ctx.queue.write_buffer(&wf.chunks, 0, &bytes);
        table
    }

    /// Each chunk's light subpaths (their splats land anywhere in the film).
    fn encode_light_chunks(&self, enc: &mut wgpu::CommandEncoder, table: &[(u32, u32)]) {
        let light = [Kernel::LtWfExtend, Kernel::LtWfShade, Kernel::LtWfSplat];
        for (c, &(_, count)) in table.iter().enumerate() {
            let walk = ChunkWalk {
                offset: (c as u64 * CHUNK_STRIDE) as u32,
                groups: count.div_ceil(64),
                start: Kernel::LtWfStart,
                bounce: &light,
                finish: (Kernel::LtWfFinish, count.div_ceil(64)),
            };
            self.encode_chunk_walk(enc, &walk);
        }
    }

    /// One chunk's walk: its queue reset, then one compute pass: the start kernel, per bounce
    /// the bounce's kernels over the queued paths and `wf_advance`, then the finish kernel.
    fn encode_chunk_walk(&self, enc: &mut wgpu::CommandEncoder, walk: &ChunkWalk) {
        enc.clear_buffer(&self.buffers.wavefront.queue, 0, Some(QUEUE_HEADER));
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("wavefront"),
            timestamp_writes: None,
        });
        pass.set_bind_group(0, &self.bind_group, &[walk.offset]);
        pass.set_bind_group(1, &self.wf_args.group, &[]);
        self.dispatch_in(&mut pass, walk.start, Dispatch::Groups(walk.groups));
        self.dispatch_in(&mut pass, Kernel::WfAdvance, Dispatch::Groups(1));
        let size = if self.wavefront_indirect {
            Dispatch::Indirect
        } else {
            Dispatch::Groups(walk.groups)
        };
        for _ in 0..self.wavefront_bounces() {
            for &kernel in walk.bounce {
                self.dispatch_in(&mut pass, kernel, size);
            }
            self.dispatch_in(&mut pass, Kernel::WfAdvance, Dispatch::Groups(1));
        }
        self.dispatch_in(&mut pass, walk.finish.0, Dispatch::Groups(walk.finish.1));
    }

    /// One kernel of the running specialisation in `pass` (wgpu orders the dispatches of a
    /// pass and makes each one's writes visible to the next; group 1, bound for the pass, is
    /// part of `wf_advance`'s layout only).
    fn dispatch_in(&self, pass: &mut wgpu::ComputePass, kernel: Kernel, size: Dispatch) {
        let Some(pipeline) = self
            .kernel_spec()
            .and_then(|spec| self.pipelines.get_kernel(spec, kernel))
        else {
            return;
        };
        pass.set_pipeline(pipeline);
        match size {
            Dispatch::Groups(n) => pass.dispatch_workgroups(n, 1, 1),
            Dispatch::Indirect => {
                pass.dispatch_workgroups_indirect(&self.wf_args.buffer, 0);
            }
        }
    }
}

/// The kernels of one chunk's walk (camera or light) and their dispatch sizes.
struct ChunkWalk<'k> {
    /// The chunk's dynamic offset in the chunk table.
    offset: u32,
    /// Workgroups covering the chunk's paths.
    groups: u32,
    start: Kernel,
    bounce: &'k [Kernel],
    finish: (Kernel, u32),
}

/// A dispatch's size: workgroups, or the running bounce's from the indirect buffer.
#[derive(Clone, Copy)]
enum Dispatch {
    Groups(u32),
    Indirect,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chunks_cover_every_path_once_in_whole_pixels() {
        for (pixels, k, max) in [(10, 3, 7), (1000, 4, 256), (5, 1, 100), (7, 9, 8)] {
            let c = chunks(pixels, k, max);
            let mut next = 0;
            for &(first, count) in &c {
                assert_eq!(first, next);
                assert_eq!(first % k, 0);
                assert_eq!(count % k, 0);
                assert!(count <= max.max(k));
                next += count;
            }
            assert_eq!(next, pixels * k);
        }
    }
}
