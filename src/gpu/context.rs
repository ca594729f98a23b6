//! The wgpu adapter, device and queue. The device asks for the adapter's own limits
//! (`required_limits = adapter.limits()`): eframe's defaults are WebGL2-level and too small for
//! scene buffers.

use anyhow::{Context, Result};

/// An adapter with its device and queue (cloning shares them: wgpu handles are
/// reference-counted).
#[derive(Clone)]
pub struct GpuContext {
    pub adapter: wgpu::Adapter,
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub info: wgpu::AdapterInfo,
}

impl GpuContext {
    /// Open the best adapter (a hardware GPU if there is one, else a software one such as
    /// lavapipe). A clear error if there is none.
    pub fn new() -> Result<GpuContext> {
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: false,
            compatible_surface: None,
            apply_limit_buckets: false,
        }))
        .context(
            "no GPU adapter found (install a Vulkan driver, e.g. mesa-vulkan-drivers for lavapipe, \
             or use --device cpu)",
        )?;
        Self::from_adapter(adapter)
    }

    /// Open a device on `adapter` with the adapter's own limits.
    pub fn from_adapter(adapter: wgpu::Adapter) -> Result<GpuContext> {
        let info = adapter.get_info();
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("refract"),
            required_features: wgpu::Features::empty(),
            required_limits: adapter.limits(),
            ..Default::default()
        }))
        .with_context(|| format!("cannot open a device on GPU adapter '{}'", info.name))?;
        Ok(GpuContext {
            adapter,
            device,
            queue,
            info,
        })
    }

    /// True for CPU-emulated adapters (lavapipe, SwiftShader, WARP, llvmpipe GL).
    pub fn is_software(&self) -> bool {
        self.info.device_type == wgpu::DeviceType::Cpu
    }

    /// "name (backend, type)".
    pub fn describe(&self) -> String {
        format!(
            "{} ({:?}, {:?})",
            self.info.name, self.info.backend, self.info.device_type
        )
    }

    /// Block until all submitted GPU work is done.
    pub fn wait(&self) -> Result<()> {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| anyhow::anyhow!("GPU device lost while waiting: {e}"))
    }

    /// Copy `size` bytes of `src` back to the CPU (blocking).
    pub fn read_buffer(&self, src: &wgpu::Buffer, size: u64) -> Result<Vec<u8>> {
        let staging = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut enc = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
        enc.copy_buffer_to_buffer(src, 0, &staging, 0, size);
        self.queue.submit([enc.finish()]);
        let slice = staging.slice(..);
        let (tx, rx) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        self.wait()?;
        rx.recv()
            .context("GPU readback callback never ran")?
            .context("cannot map GPU readback buffer")?;
        let data = slice
            .get_mapped_range()
            .map_err(|e| anyhow::anyhow!("cannot read mapped GPU buffer: {e:?}"))?
            .to_vec();
        staging.unmap();
        Ok(data)
    }
}
