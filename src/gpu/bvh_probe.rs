//! The traversal probe: runs scene.wgsl's `traverse` (the BVH2 or the CWBVH of cwbvh.wgsl)
//! on a list of rays with its work counted (src/gpu/bvh_probe.wgsl). `tests/gpu_bvh.rs`
//! checks the trees against a one-leaf tree (brute force); `examples/bvh_cost.rs` counts
//! nodes and triangles per ray.

use super::GpuContext;
use super::buffers::{checked_storage, zeroed_storage};
use super::layout::{BvhProbeOut, BvhProbeRay, GpuLayout};
use super::pipeline::{bvh_probe_source, create_module};
use super::upload::{self, BvhLayout, GpuBvh};
use crate::scene::Scene;
use crate::scene::light::LightSet;
use anyhow::{Result, ensure};

/// Trace `rays` through `bvh` over `scene`'s triangles packed in its leaf order (slots map
/// to scene triangles by `bvh.primitive_indices`): each ray's hit and the work it took.
/// `x4`: a CWBVH's children tested four at once (`BVH_CHILDREN_X4`; the renderer's choice is
/// `ctx.is_software()`).
pub fn run_bvh_probe(
    ctx: &GpuContext,
    scene: &Scene,
    bvh: &GpuBvh,
    rays: &[BvhProbeRay],
    x4: bool,
) -> Result<Vec<BvhProbeOut>> {
    ensure!(!rays.is_empty(), "no probe rays");
    let tris = upload::pack_triangles(scene, bvh, &LightSet::build(scene));
    let nodes = checked_storage(ctx, "bvh nodes", "BVH", bvh.node_bytes())?;
    let triangles = checked_storage(ctx, "triangles", "triangles", &tris)?;
    let input = checked_storage(ctx, "bvh probe rays", "probe rays", rays)?;
    let out_size = (rays.len() * BvhProbeOut::size() as usize) as u64;
    let output = zeroed_storage(ctx, "bvh probe out", out_size, wgpu::BufferUsages::COPY_SRC);
    let module = create_module(ctx, "bvh_probe.wgsl", bvh_probe_source())?;
    let constants = [
        ("BVH_STACK_SIZE", f64::from(bvh.stack_words())),
        (
            "BVH_WIDE",
            f64::from(u8::from(bvh.layout == BvhLayout::Cwbvh)),
        ),
        ("BVH_COUNT", 1.0),
        ("BVH_CHILDREN_X4", f64::from(u8::from(x4))),
    ];
    ctx.scoped("bvh probe", || {
        let pipeline = ctx
            .device
            .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("bvh_probe"),
                layout: None,
                module: &module,
                entry_point: Some("bvh_probe"),
                compilation_options: wgpu::PipelineCompilationOptions {
                    constants: &constants,
                    zero_initialize_workgroup_memory: false,
                },
                cache: None,
            });
        let buffers = [(1, &nodes), (2, &triangles), (20, &input), (21, &output)];
        let entries: Vec<wgpu::BindGroupEntry> = buffers
            .iter()
            .map(|&(binding, b)| wgpu::BindGroupEntry {
                binding,
                resource: b.as_entire_binding(),
            })
            .collect();
        let bg = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("bvh probe"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &entries,
        });
        let mut enc = ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
        {
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor::default());
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &bg, &[]);
            pass.dispatch_workgroups((rays.len() as u32).div_ceil(64), 1, 1);
        }
        ctx.queue.submit([enc.finish()]);
    })?;
    let bytes = ctx.read_buffer(&output, out_size)?;
    Ok(bytemuck::pod_collect_to_vec(&bytes))
}
