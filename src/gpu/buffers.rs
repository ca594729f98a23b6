//! Storage buffers made from packed scene data (`upload`): each checked against the device's
//! largest binding, so an oversized scene is an error naming what did not fit, not a wgpu
//! validation panic.

use super::GpuContext;
use anyhow::{Result, ensure};
use wgpu::util::DeviceExt;

/// A storage buffer (copy destination too) holding `bytes`.
pub fn storage(ctx: &GpuContext, label: &str, bytes: &[u8]) -> wgpu::Buffer {
    ctx.device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytes,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        })
}

/// A storage buffer holding `data`, or an error naming `what` when it is larger than one
/// binding of this device.
pub fn checked_storage<T: bytemuck::Pod>(
    ctx: &GpuContext,
    label: &str,
    what: &str,
    data: &[T],
) -> Result<wgpu::Buffer> {
    let bytes = checked_bytes(what, data, ctx.max_binding_bytes())?;
    Ok(storage(ctx, label, bytes))
}

/// A zeroed storage buffer of `size` bytes with the `extra` usages.
pub fn zeroed_storage(
    ctx: &GpuContext,
    label: &str,
    size: u64,
    extra: wgpu::BufferUsages,
) -> wgpu::Buffer {
    ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size,
        usage: wgpu::BufferUsages::STORAGE | extra,
        mapped_at_creation: false,
    })
}

/// Bytes of a slice, checked against `cap`, the device's largest storage binding
/// ([`super::GpuContext::max_binding_bytes`]).
pub fn checked_bytes<'a, T: bytemuck::Pod>(
    what: &str,
    data: &'a [T],
    cap: u64,
) -> Result<&'a [u8]> {
    let bytes: &[u8] = bytemuck::cast_slice(data);
    ensure!(
        (bytes.len() as u64) <= cap,
        "scene too large for this GPU: {what} needs {} MiB, the device binds at most {} MiB \
         per buffer",
        bytes.len() >> 20,
        cap >> 20
    );
    Ok(bytes)
}
