//! The integrator's bind group layouts (bindings 0..=16 but 9, and `wf_advance`'s group 1) and
//! the storage-buffer limit they need.

use super::STORAGE_BUFFERS;
use crate::gpu::GpuContext;
use anyhow::Result;

/// A compute-stage buffer binding of type `ty`.
fn buffer_entry(binding: u32, ty: wgpu::BufferBindingType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

fn storage_entry(binding: u32, read_only: bool) -> wgpu::BindGroupLayoutEntry {
    buffer_entry(binding, wgpu::BufferBindingType::Storage { read_only })
}

/// Fail with a clear message when the adapter allows fewer storage buffers per shader
/// stage than the integrator binds.
pub(super) fn check_storage_buffer_limit(ctx: &GpuContext) -> Result<()> {
    let max = ctx.device.limits().max_storage_buffers_per_shader_stage;
    anyhow::ensure!(
        max >= STORAGE_BUFFERS,
        "GPU adapter '{}' allows {max} storage buffers per shader stage; refract needs \
         {STORAGE_BUFFERS} (use --device cpu)",
        ctx.info.name
    );
    Ok(())
}

/// The integrator bind group's layout entries, bindings 0..=16 in order (9 is unused).
fn integrator_entries() -> Vec<wgpu::BindGroupLayoutEntry> {
    // The parameters are read-only storage (integrator.wgsl says why).
    let mut entries = vec![storage_entry(0, true)];
    for b in 1..=5 {
        entries.push(storage_entry(b, true));
    }
    entries.push(storage_entry(6, false));
    entries.push(storage_entry(7, false));
    // Texture references + texels (8 storage buffers in all). (Binding 9, the path filter's
    // uniform, is gone: its table is in the parameters.)
    entries.push(storage_entry(8, true));
    // Light-tracing splats (fixed-point atomics).
    entries.push(storage_entry(10, false));
    // The photon grid (atomics) and the photons (`sppm`, photon.wgsl).
    entries.push(storage_entry(11, false));
    entries.push(storage_entry(12, false));
    // The wavefront's path states and its chunk table (wavefront.wgsl; placeholders for
    // the megakernel), the latter read at a dynamic offset per dispatch.
    entries.push(storage_entry(13, false));
    entries.push(wgpu::BindGroupLayoutEntry {
        binding: 14,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: true,
            min_binding_size: wgpu::BufferSize::new(16),
        },
        count: None,
    });
    // The light wavefront's subpath states (light_wavefront.wgsl; a placeholder).
    entries.push(storage_entry(15, false));
    // The wavefronts' queues of live paths (wavefront.wgsl's `WfQueue`; a placeholder).
    entries.push(storage_entry(16, false));
    entries
}

/// The bind group and pipeline layouts of the integrator kernels and of `wf_advance`.
pub(super) struct IntegratorLayouts {
    /// The integrator's bind group (group 0 of every kernel).
    pub(super) bind_group: wgpu::BindGroupLayout,
    /// Group 1 of `wf_advance`: the wavefront dispatch size.
    pub(super) advance_group: wgpu::BindGroupLayout,
    /// The pipeline layout of every kernel but `wf_advance`.
    pub(super) layout: wgpu::PipelineLayout,
    /// The pipeline layout of `wf_advance` (groups 0 and 1).
    pub(super) advance: wgpu::PipelineLayout,
}

impl IntegratorLayouts {
    /// Create the layouts on `ctx`'s device (integrator group, its pipeline layout, the
    /// dispatch-size group, the `wf_advance` pipeline layout, in that order).
    pub(super) fn new(ctx: &GpuContext) -> IntegratorLayouts {
        let bind_group = ctx
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("integrator"),
                entries: &integrator_entries(),
            });
        let layout = ctx
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("integrator"),
                bind_group_layouts: &[Some(&bind_group)],
                immediate_size: 0,
            });
        let advance_group = ctx
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("wavefront dispatch size"),
                entries: &[storage_entry(0, false)],
            });
        let advance = ctx
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("wf_advance"),
                bind_group_layouts: &[Some(&bind_group), Some(&advance_group)],
                immediate_size: 0,
            });
        IntegratorLayouts {
            bind_group,
            advance_group,
            layout,
            advance,
        }
    }
}
