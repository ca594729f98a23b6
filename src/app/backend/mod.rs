//! The seam between the viewer and a renderer.
//!
//! The viewer owns the scene model and tells a [`Backend`] what changed; the backend
//! accumulates samples without ever blocking the UI thread and hands back a texture to show.
//! Every edit bumps a generation counter: samples rendered for an older generation never reach
//! the accumulated image.
//!
//! [`CpuBackend`] ([`cpu`]) runs the CPU path tracer (`cpu::Renderer`, rayon) on a background
//! thread in short passes that an edit can cancel mid-pass.
//!
//! The GPU backend, [`GpuBackend`] ([`gpu`]), is the second `impl Backend`. It gets
//! the `egui_wgpu::RenderState` from `eframe::CreationContext::wgpu_render_state` (device
//! created in `app::run` with the adapter's own limits so compute works), queues its batches
//! from [`Backend::step`] within the frame budget, tone-maps on the GPU into its own
//! `wgpu::Texture` registered with `render_state.renderer.write().register_native_texture(...)`;
//! [`Backend::display_texture`] returns that id (no CPU readback). Only
//! [`Backend::read_image`] (screenshots) reads the accumulation buffer back. `app::run`
//! chooses the backend (`refract view --device auto|cpu|gpu`).

pub mod cpu;
pub mod gpu;

pub use cpu::CpuBackend;
pub use gpu::GpuBackend;

use crate::film::ToneMap;
use crate::render::RenderOptions;
use crate::scene::{Camera, Checked, Material, Scene};
use glam::Vec3;
use std::time::Duration;

/// How the accumulated radiance is shown.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DisplayParams {
    /// Exposure in stops.
    pub exposure: f32,
    pub tone_map: ToneMap,
}

/// A texture ready to be painted, and the rendered resolution behind it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DisplayTexture {
    pub id: eframe::egui::TextureId,
    pub size: [u32; 2],
}

/// The accumulated mean radiance of one generation (linear Rec.709, row-major, top row first).
#[derive(Clone, Debug)]
pub struct Accumulated {
    pub generation: u64,
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<Vec3>,
    pub spp: u64,
    pub dropped: u64,
    /// Render time spent on these samples.
    pub elapsed: Duration,
}

/// A renderer the viewer can drive. Every method returns at once (work happens elsewhere or
/// within [`Backend::step`]'s budget).
pub trait Backend {
    /// Replace the whole scene (already validated by the caller); restarts accumulation.
    fn set_scene(&mut self, scene: &Scene);
    /// Material `index` of the current scene changed (no geometry rebuild).
    fn update_material(&mut self, index: usize, material: &Checked<Material>);
    /// Lights changed: emitter materials, punctual lights, environment and, when
    /// `geometry_changed`, emitter triangles (the backend rebuilds its BVH).
    fn update_lights(&mut self, scene: &Scene, geometry_changed: bool);
    fn update_camera(&mut self, camera: &Checked<Camera>);
    /// Resolution, depth, seed, path filter.
    fn set_options(&mut self, options: &RenderOptions);
    /// While the user drags, the backend may trade resolution for latency.
    fn set_interactive(&mut self, interactive: bool);
    fn set_paused(&mut self, paused: bool);
    /// Stop accumulating at this many samples per pixel (0 = never).
    fn set_spp_target(&mut self, spp: u64);
    /// Drop every sample and start again.
    fn reset(&mut self);
    /// Called once per UI frame; a synchronous backend may spend up to `frame_budget` here.
    fn step(&mut self, frame_budget: Duration);
    /// Samples per pixel in the current image.
    fn spp(&self) -> u64;
    /// Pixel samples per second of the current generation.
    fn samples_per_sec(&self) -> f64;
    /// Render time of the current generation.
    fn elapsed(&self) -> Duration;
    /// Samples dropped by the film's NaN/Inf/negative firewall (current generation).
    fn dropped(&self) -> u64;
    fn device_name(&self) -> String;
    /// True while samples are still being added (not paused, target not reached).
    fn is_rendering(&self) -> bool;
    /// Edits applied so far (increases with every edit).
    fn generation(&self) -> u64;
    /// The material the backend renders with (last one applied), for tests and the UI.
    fn material(&self, index: usize) -> Option<Material>;
    /// The image to show, tone-mapped with `display`; None before the first pass.
    fn display_texture(
        &mut self,
        ctx: &eframe::egui::Context,
        display: &DisplayParams,
    ) -> Option<DisplayTexture>;
    /// The accumulated mean radiance (for screenshots; a GPU backend reads it back here).
    fn read_image(&self) -> Option<Accumulated>;
    /// True while the kernel for the current scene and options compiles (the GPU; the image
    /// meanwhile comes from the family's general kernel, or stays the last one).
    fn compiling(&self) -> bool {
        false
    }
    /// True while the image comes from the family's general kernel (the GPU, while the
    /// specialised kernel compiles).
    fn general_kernel(&self) -> bool {
        false
    }
    /// (kernel pipelines compiled so far, specialisations cached now): the GPU's; None
    /// where there are none (the CPU).
    fn pipeline_stats(&self) -> Option<(u32, usize)> {
        None
    }
    /// Prepare, in the background, to render `scene` with `options` next (a lecture's next
    /// demo): the GPU compiles the general kernel of its family ahead of need. The CPU has
    /// nothing to prepare.
    fn prepare_for(&mut self, _scene: &Scene, _options: &RenderOptions) {}
    /// The device the live view's denoiser filters on (`denoise::gpu`, the WGSL twin): the
    /// GPU backend's own, except on GL, whose one context the submitting thread holds. None:
    /// the CPU twin filters.
    fn denoise_device(&self) -> Option<crate::gpu::GpuContext> {
        None
    }
    /// A notice for the user since the last call (e.g. "the GPU cannot render this scene,
    /// rendering on the CPU"); the viewer shows it in the side panel.
    fn take_message(&mut self) -> Option<String> {
        None
    }
    /// Show `mode` (`app::layer_view`) instead of the rendered image; false when this
    /// backend cannot (the GPU: the layer views are CPU only).
    fn set_view(&mut self, _mode: crate::app::layer_view::ViewMode) -> bool {
        false
    }
    /// Trace polarised light and show the image behind a linear polariser at `angle`
    /// (radians from the image's horizontal; None: no filter, unpolarised transport;
    /// `cpu::polarized`, on the GPU `cpu/polarized/chain.wgsl`); false when this backend
    /// cannot.
    fn set_polarizer(&mut self, _angle: Option<f32>) -> bool {
        false
    }
}
