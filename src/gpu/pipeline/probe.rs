//! The probe kernels: one dispatch over a case buffer, read back (BSDF and light probes).

use super::{create_module, probe_source};
use crate::gpu::GpuContext;
use crate::gpu::layout::{GpuLayout, ProbeCase, ProbeOut};
use anyhow::Result;

/// Run the probe kernel (src/gpu/probe.wgsl) on `cases`.
pub fn run_probe(ctx: &GpuContext, cases: &[ProbeCase]) -> Result<Vec<ProbeOut>> {
    use wgpu::util::DeviceExt;
    anyhow::ensure!(!cases.is_empty(), "no probe cases");
    let module = create_module(ctx, "probe.wgsl", probe_source())?;
    let input = ctx
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("probe cases"),
            contents: bytemuck::cast_slice(cases),
            usage: wgpu::BufferUsages::STORAGE,
        });
    let out_size = (cases.len() * ProbeOut::size() as usize) as u64;
    let output = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("probe out"),
        size: out_size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    dispatch_once(
        ctx,
        &module,
        "probe",
        &[(0, &input), (1, &output)],
        cases.len() as u32,
    );
    let bytes = ctx.read_buffer(&output, out_size)?;
    Ok(bytemuck::pod_collect_to_vec(&bytes))
}

/// Run entry point `entry` of `module` once over `threads` invocations (workgroups of 64)
/// with `buffers` bound at their binding numbers of group 0 (the layout derived from the
/// shader), and submit it (the probe kernels; the caller reads its output buffer back).
pub(crate) fn dispatch_once(
    ctx: &GpuContext,
    module: &wgpu::ShaderModule,
    entry: &str,
    buffers: &[(u32, &wgpu::Buffer)],
    threads: u32,
) {
    let pipeline = ctx
        .device
        .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(entry),
            layout: None,
            module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            cache: None,
        });
    let entries: Vec<wgpu::BindGroupEntry> = buffers
        .iter()
        .map(|&(binding, b)| wgpu::BindGroupEntry {
            binding,
            resource: b.as_entire_binding(),
        })
        .collect();
    let bg = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(entry),
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
        pass.dispatch_workgroups(threads.div_ceil(64), 1, 1);
    }
    ctx.queue.submit([enc.finish()]);
}
