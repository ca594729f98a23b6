//! The viewer's wgpu device setup, shared by the window (`window`) and the presenters that
//! try the wgpu backends one by one (`present`).

/// The wgpu setup: our own device with the adapter's full limits (eframe's default asks for
/// WebGL2-level limits, too small for compute). The GPU backend renders on this device.
/// Backends: `WGPU_BACKEND`'s, else the primary ones and GL.
pub fn wgpu_configuration() -> eframe::egui_wgpu::WgpuConfiguration {
    let backends = eframe::wgpu::Backends::from_env()
        .unwrap_or(eframe::wgpu::Backends::PRIMARY | eframe::wgpu::Backends::GL);
    wgpu_configuration_on(backends)
}

/// [`wgpu_configuration`] on exactly `backends` (`present::Presenter::Wgpu`).
pub fn wgpu_configuration_on(
    backends: eframe::wgpu::Backends,
) -> eframe::egui_wgpu::WgpuConfiguration {
    use eframe::egui_wgpu::{WgpuConfiguration, WgpuSetup, WgpuSetupCreateNew};
    use eframe::wgpu;
    let mut create = WgpuSetupCreateNew::without_display_handle();
    create.instance_descriptor.backends = backends;
    create.instance_descriptor.flags =
        crate::gpu::context::instance_flags(create.instance_descriptor.flags);
    create.device_descriptor =
        std::sync::Arc::new(|adapter: &wgpu::Adapter| wgpu::DeviceDescriptor {
            label: Some("refract device"),
            required_limits: adapter.limits(),
            // The driver pipeline cache where there is one (gpu::pipeline_cache).
            required_features: adapter.features() & wgpu::Features::PIPELINE_CACHE,
            ..Default::default()
        });
    WgpuConfiguration {
        wgpu_setup: WgpuSetup::CreateNew(create),
        ..Default::default()
    }
}
