//! The wgpu adapter, device and queue. The device asks for the adapter's own limits
//! (`required_limits = adapter.limits()`): eframe's defaults are WebGL2-level and too small for
//! scene buffers.
//!
//! GPU errors never panic: every device gets an uncaptured-error handler and a device-lost
//! callback that record the error (wgpu's default handler panics); [`GpuContext::scoped`]
//! turns validation and out-of-memory errors of resource and pipeline creation into an `Err`,
//! and [`GpuContext::wait`] returns the recorded error, or one after [`WAIT_TIMEOUT`].

use anyhow::{Context, Result};
use std::sync::{Arc, Mutex};
use std::time::Duration;

/// The longest [`GpuContext::wait`] waits for submitted work before giving up.
pub const WAIT_TIMEOUT: Duration = Duration::from_secs(120);

/// The first GPU error that no error scope caught (validation, out of memory, device lost).
pub type ErrorLog = Arc<Mutex<Option<String>>>;

/// Record uncaptured errors and device loss of `device` in the returned log instead of
/// panicking (wgpu's default handler).
pub fn install_error_handlers(device: &wgpu::Device) -> ErrorLog {
    let log: ErrorLog = Arc::default();
    let l = Arc::clone(&log);
    device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
        // The description names the call and the cause; `Display` says only "Validation Error".
        let text = match &e {
            wgpu::Error::Validation { description, .. }
            | wgpu::Error::Internal { description, .. } => description.clone(),
            other => other.to_string(),
        };
        record(&l, format!("GPU error: {text}"));
    }));
    let l = Arc::clone(&log);
    device.set_device_lost_callback(move |reason, msg| {
        record(&l, format!("GPU device lost ({reason:?}): {msg}"));
    });
    log
}

/// Record `msg` in `log` as an uncaptured error would be (the first one is kept).
pub fn record(log: &ErrorLog, msg: String) {
    let mut slot = log.lock().unwrap_or_else(|e| e.into_inner());
    if slot.is_none() {
        eprintln!("refract: {msg}");
        *slot = Some(msg);
    }
}

/// Run `f` on this thread in validation and out-of-memory error scopes of `device` (wgpu's
/// error scopes are per thread): an error there is an `Err` naming `what`, never a panic.
pub fn scoped_on<T>(device: &wgpu::Device, what: &str, f: impl FnOnce() -> T) -> Result<T> {
    let oom = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
    let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let value = f();
    let v = pollster::block_on(validation.pop());
    let o = pollster::block_on(oom.pop());
    match v.or(o) {
        Some(e) => Err(anyhow::anyhow!("{what}: {e}")),
        None => Ok(value),
    }
}

/// An adapter with its device and queue (cloning shares them: wgpu handles are
/// reference-counted).
#[derive(Clone)]
pub struct GpuContext {
    pub adapter: wgpu::Adapter,
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub info: wgpu::AdapterInfo,
    /// Errors no scope caught (see [`install_error_handlers`]).
    pub errors: ErrorLog,
    /// Where the driver pipeline cache is kept between runs (`pipeline_cache::default_dir`;
    /// None: in memory only). Used by renderers created on this context.
    pub pipeline_cache_dir: Option<std::path::PathBuf>,
}

/// The instance flags refract's devices use: wgpu's defaults and environment variables,
/// except that indirect dispatches are not validated unless `WGPU_VALIDATION_INDIRECT_CALL`
/// asks for it. wgpu's validation runs a one-thread check (and its barriers) before every
/// indirect dispatch; refract's only indirect dispatches are the wavefront's bounce kernels,
/// whose size `wf_advance` computes as ⌈queued paths / 64⌉ ≤ 2¹⁹ / 64 = 8192 workgroups, within
/// every adapter's limit by construction. (On lavapipe the check cost the wavefront a third of
/// its time: docs/gpu.md "Live-path queues".)
pub fn instance_flags(defaults: wgpu::InstanceFlags) -> wgpu::InstanceFlags {
    let mut flags = defaults;
    if std::env::var_os("WGPU_VALIDATION_INDIRECT_CALL").is_none() {
        flags.remove(wgpu::InstanceFlags::VALIDATION_INDIRECT_CALL);
    }
    flags
}

impl GpuContext {
    /// Open the best adapter (a hardware GPU if there is one, else a software one such as
    /// lavapipe). A clear error if there is none.
    pub fn new() -> Result<GpuContext> {
        Self::on_backends(None).context(
            "no GPU adapter found (install a Vulkan driver, e.g. mesa-vulkan-drivers for lavapipe, \
             or use --device cpu)",
        )
    }

    /// [`GpuContext::new`] for a process that also draws a window: the primary backends (or
    /// `WGPU_BACKEND`'s) first; wgpu's GL backend only where they have no adapter, and its
    /// probe guarded, since on some drivers it panics (an NVIDIA EGL without an X11
    /// display): the panic becomes the error.
    pub fn headless() -> Result<GpuContext> {
        let gl = wgpu::Backends::GL;
        let allowed = wgpu::Backends::from_env().unwrap_or(wgpu::Backends::PRIMARY | gl);
        let primary = allowed - gl;
        let mut last = anyhow::anyhow!("WGPU_BACKEND names no backend");
        if !primary.is_empty() {
            match Self::on_backends(Some(primary)) {
                Ok(ctx) => return Ok(ctx),
                Err(e) => last = e,
            }
        }
        if allowed.contains(gl) {
            let probe = std::panic::catch_unwind(|| Self::on_backends(Some(gl)));
            return probe.unwrap_or_else(|_| {
                Err(anyhow::anyhow!("wgpu's GL backend panicked while probing"))
            });
        }
        Err(last)
    }

    /// The best adapter among `backends` (None: `WGPU_BACKEND`'s, else wgpu's default set).
    fn on_backends(backends: Option<wgpu::Backends>) -> Result<GpuContext> {
        let mut descriptor = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
        if let Some(b) = backends {
            descriptor.backends = b;
        }
        descriptor.flags = instance_flags(descriptor.flags);
        let instance = wgpu::Instance::new(descriptor);
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: false,
            compatible_surface: None,
            apply_limit_buckets: false,
        }))
        .context("no GPU adapter found")?;
        Self::from_adapter(adapter)
    }

    /// The largest buffer one storage binding may hold on this device (from its limits, not a
    /// fixed cap: 128 MiB is the WebGPU default, desktop GPUs bind 2–4 GiB).
    pub fn max_binding_bytes(&self) -> u64 {
        let l = self.device.limits();
        l.max_storage_buffer_binding_size.min(l.max_buffer_size)
    }

    /// Open a device on `adapter` with the adapter's own limits.
    pub fn from_adapter(adapter: wgpu::Adapter) -> Result<GpuContext> {
        let limits = adapter.limits();
        Self::with_limits(adapter, limits)
    }

    /// Open a device on `adapter` with `limits` (an `Err` where the adapter has less).
    pub fn with_limits(adapter: wgpu::Adapter, limits: wgpu::Limits) -> Result<GpuContext> {
        let info = adapter.get_info();
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("refract"),
            // The driver pipeline cache where the adapter has one (Vulkan): `pipeline_cache`.
            required_features: adapter.features() & wgpu::Features::PIPELINE_CACHE,
            required_limits: limits,
            ..Default::default()
        }))
        .with_context(|| format!("cannot open a device on GPU adapter '{}'", info.name))?;
        Ok(Self::from_parts(adapter, device, queue))
    }

    /// A context on an existing device (e.g. eframe's), with the error handlers installed.
    pub fn from_parts(adapter: wgpu::Adapter, device: wgpu::Device, queue: wgpu::Queue) -> Self {
        let errors = install_error_handlers(&device);
        GpuContext {
            info: adapter.get_info(),
            adapter,
            device,
            queue,
            errors,
            pipeline_cache_dir: super::pipeline_cache::default_dir(),
        }
    }

    /// The recorded uncaptured error, if any, as an `Err` (cleared: reported once).
    pub fn check_errors(&self) -> Result<()> {
        match self.errors.lock().unwrap_or_else(|e| e.into_inner()).take() {
            Some(msg) => Err(anyhow::anyhow!(msg)),
            None => Ok(()),
        }
    }

    /// Run `f` (resource or pipeline creation) in validation and out-of-memory error scopes:
    /// an error there is an `Err` naming `what`, never a panic.
    pub fn scoped<T>(&self, what: &str, f: impl FnOnce() -> T) -> Result<T> {
        scoped_on(&self.device, what, f)
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

    /// Block until all submitted GPU work is done: an `Err` after [`WAIT_TIMEOUT`], when the
    /// device is lost, or when a GPU error was recorded.
    pub fn wait(&self) -> Result<()> {
        self.device
            .poll(wgpu::PollType::Wait {
                submission_index: None,
                timeout: Some(WAIT_TIMEOUT),
            })
            .map_err(|e| anyhow::anyhow!("GPU wait failed: {e}"))?;
        self.check_errors()
    }

    /// Block until submission `index` (and all before it) is done: errors as
    /// [`GpuContext::wait`].
    pub fn wait_for(&self, index: wgpu::SubmissionIndex) -> Result<()> {
        self.device
            .poll(wgpu::PollType::Wait {
                submission_index: Some(index),
                timeout: Some(WAIT_TIMEOUT),
            })
            .map_err(|e| anyhow::anyhow!("GPU wait failed: {e}"))?;
        self.check_errors()
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
