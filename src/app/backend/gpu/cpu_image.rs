//! The image of a headless GPU backend (a window egui-wgpu does not draw, such as glow's):
//! each new tone-mapped image is copied into a mappable buffer right after the tone map (so
//! the copy never queues behind a batch), mapped without waiting, and uploaded as an egui
//! texture when the map completes. One copy is in flight at a time; an image tone-mapped
//! meanwhile is copied as soon as that one is back.

use super::GpuBackend;
use super::completion::{MAP_FAILED, MAP_OK, MAP_PENDING};
use crate::gpu::tonemap::unpad_rows;
use eframe::egui;
use eframe::wgpu;
use std::sync::Arc;
use std::sync::atomic::{AtomicU8, Ordering};

/// The read-back image's state.
#[derive(Default)]
pub(super) struct CpuImage {
    /// The copy in flight: its buffer and image size.
    pending: Option<(wgpu::Buffer, [u32; 2])>,
    /// Set by the `map_async` callback.
    state: Arc<AtomicU8>,
    /// A newer image was tone-mapped while a copy was in flight.
    again: bool,
    texture: Option<egui::TextureHandle>,
}

impl GpuBackend {
    /// After a tone map: copy the image back (or remember to, once the copy in flight is done).
    pub(super) fn start_cpu_copy(&mut self) {
        if self.egui_renderer.is_some() {
            return;
        }
        if self.cpu_image.pending.is_some() {
            self.cpu_image.again = true;
            return;
        }
        match self.tonemap.queue_readback(&self.ctx, true) {
            Ok((buf, size)) => {
                let state = Arc::clone(&self.cpu_image.state);
                state.store(MAP_PENDING, Ordering::Release);
                buf.slice(..).map_async(wgpu::MapMode::Read, move |res| {
                    state.store(
                        if res.is_ok() { MAP_OK } else { MAP_FAILED },
                        Ordering::Release,
                    );
                });
                self.cpu_image.pending = Some((buf, size));
                self.cpu_image.again = false;
            }
            Err(e) => self.message = Some(format!("cannot read the GPU image back: {e:#}")),
        }
    }

    /// The texture showing the last image read back (uploading a finished copy first).
    pub(super) fn cpu_texture(&mut self, ctx: &egui::Context) -> Option<egui::TextureId> {
        let _ = self.ctx.device.poll(wgpu::PollType::Poll);
        let state = self.cpu_image.state.load(Ordering::Acquire);
        if state != MAP_PENDING
            && let Some((buf, size)) = self.cpu_image.pending.take()
        {
            if state == MAP_OK {
                self.upload(ctx, &buf, size);
            }
            buf.unmap();
            if self.cpu_image.again {
                self.start_cpu_copy();
            }
        }
        if self.cpu_image.pending.is_some()
            && let Some(c) = &self.repaint
        {
            c.request_repaint();
        }
        self.cpu_image.texture.as_ref().map(egui::TextureHandle::id)
    }

    /// Upload the mapped `buf` (an image of `size`) as the shown texture.
    fn upload(&mut self, ctx: &egui::Context, buf: &wgpu::Buffer, size: [u32; 2]) {
        let Ok(view) = buf.slice(..).get_mapped_range() else {
            return;
        };
        let pixels = unpad_rows(&view, size);
        drop(view);
        let image =
            egui::ColorImage::from_rgba_unmultiplied([size[0] as usize, size[1] as usize], &pixels);
        let options = egui::TextureOptions::LINEAR;
        match self.cpu_image.texture.as_mut() {
            Some(t) => t.set(image, options),
            None => self.cpu_image.texture = Some(ctx.load_texture("gpu image", image, options)),
        }
    }
}
