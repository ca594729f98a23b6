//! The tone-mapped display image: rerun only when something shown changed, registered with
//! egui-wgpu under a stable id.

use super::GpuBackend;
use crate::gpu::GpuContext;
use crate::gpu::tonemap::ToneMapper;
use eframe::egui;
use eframe::egui::mutex::RwLock;
use eframe::egui_wgpu;

impl GpuBackend {
    /// Re-run the tone map if the generation, the spp or the display settings changed, and
    /// only while no batch is in flight (otherwise the next `step` does it, right after the
    /// batch finishes: the image and a new exposure appear within one batch).
    pub(super) fn refresh_display(&mut self) {
        if self.in_flight.len() >= self.depth {
            return;
        }
        let (Some(r), Some(display)) = (self.renderer.as_ref(), self.display) else {
            return;
        };
        let size = [r.options().width, r.options().height];
        let key = (self.generation, r.spp(), size, display);
        // While a new specialisation compiles the film still holds the last image (its clear
        // waits for the first batch): tone-map it on display changes.
        let stale = r.spp() == 0 && r.is_compiling() && self.shown.is_some_and(|s| s.2 == size);
        // Nothing rendered for this generation yet: keep showing the previous image.
        if (r.spp() > 0 || stale) && self.shown != Some(key) {
            if self.tonemap.ensure_target(&self.ctx, size)
                && let Some(egui_renderer) = &self.egui_renderer
            {
                register_image(&self.ctx, egui_renderer, &self.tonemap, &mut self.image_id);
            }
            self.tonemap.run(
                &self.ctx,
                r.accum_buffer(),
                display.tone_map,
                display.exposure,
            );
            self.shown = Some(key);
            self.start_cpu_copy();
        }
    }
}

/// Register the (new) tone-map target's sRGB view with egui-wgpu, under the old id if there
/// is one.
pub(super) fn register_image(
    ctx: &GpuContext,
    egui_renderer: &RwLock<egui_wgpu::Renderer>,
    tonemap: &ToneMapper,
    image_id: &mut Option<egui::TextureId>,
) {
    let Some(view) = tonemap.srgb_view() else {
        return;
    };
    let filter = wgpu::FilterMode::Linear;
    let mut r = egui_renderer.write();
    *image_id = Some(match *image_id {
        Some(id) => {
            r.update_egui_texture_from_wgpu_texture(&ctx.device, &view, filter, id);
            id
        }
        None => r.register_native_texture(&ctx.device, &view, filter),
    });
}
