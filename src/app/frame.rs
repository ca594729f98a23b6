//! The per-frame `show` and its steps: before drawing, the side panels, the central image
//! with its interaction and overlays, following the viewport size, and after drawing.

use super::{Edit, VIEWPORT_SETTLE, ViewerApp, inspect_overlay, lecture, panels, viewport};
use eframe::egui;
use std::time::{Duration, Instant};

impl ViewerApp {
    /// Draw the whole viewer into `ui` (window or test harness).
    pub fn show(&mut self, ui: &mut egui::Ui) {
        let t0 = Instant::now();
        let ctx = ui.ctx().clone();
        self.begin_frame(&ctx);
        self.side_panels(ui);
        egui::CentralPanel::no_frame().show(ui, |ui| self.central_image(&ctx, ui));
        self.apply_queued();
        self.end_frame(&ctx, t0.elapsed());
    }

    /// Before drawing: dialog result, keys, lecture zoom, a slice of rendering, its message.
    fn begin_frame(&mut self, ctx: &egui::Context) {
        self.poll_dialog();
        self.handle_input(ctx);
        if let Some(zoom) = self.lecture.zoom_change() {
            ctx.set_zoom_factor(zoom);
        }
        self.backend.step(Duration::from_millis(8));
        if let Some(m) = self.backend.take_message() {
            self.messages.info = Some(m);
        }
    }

    /// The status bar, the controls panel and the inspector panel (before the central image,
    /// which takes the space they leave).
    fn side_panels(&mut self, ui: &mut egui::Ui) {
        egui::Panel::bottom("status").show(ui, |ui| self.status_bar(ui));
        egui::Panel::left("controls")
            .default_size(340.0)
            .resizable(true)
            .show(ui, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| panels::side_panel(self, ui));
            });
        self.apply_queued();
        self.lecture_follow();
        self.inspect_follow();
        panels::inspect::side(self, ui);
    }

    /// The central panel: the rendered image with orbit, picking and inspection, and its
    /// overlays.
    fn central_image(&mut self, ctx: &egui::Context, ui: &mut egui::Ui) {
        self.viewport_follow(ctx, ui.available_size() * ctx.pixels_per_point());
        let tex = self.backend.display_texture(ctx, &self.display_params());
        let res = self.settings.resolution(&self.scene);
        let yfov = self.scene.camera.yfov;
        let mut orbit = self.orbit;
        let r = viewport::show(ui, tex, res, &mut orbit, yfov);
        let (display, scene) = (self.display_params(), &self.scene);
        self.denoise
            .step(ctx, self.backend.as_ref(), scene, display);
        if tex.is_some() {
            self.denoise
                .paint(ui, r.image_rect, self.backend.generation());
        }
        if r.camera_changed {
            self.push(Edit::Orbit(orbit));
        }
        self.viewport_interaction(ctx, &r);
        self.inspector.image_rect = Some(r.image_rect);
        self.image_overlays(ui, r.image_rect);
    }

    /// React to a drag starting or ending and to a click on the image (inspect or pick).
    /// Any drag is interactive — the camera's, and a slider's (IOR, roughness, light): the
    /// backend renders at a lower resolution until it ends, so each step shows at once.
    fn viewport_interaction(&mut self, ctx: &egui::Context, r: &viewport::ViewportResponse) {
        let dragging = r.dragging || ctx.dragged_id().is_some() || self.scripted_drag;
        if dragging != self.dragging {
            self.dragging = dragging;
            self.backend.set_interactive(dragging);
        }
        if let Some((sx, sy)) = r.clicked {
            if r.alt || self.inspector.enabled {
                self.lecture.inspect_point = None;
                self.inspector.request((sx, sy));
                ctx.request_repaint();
            } else {
                self.selected = self.pick(sx, sy);
            }
        }
    }

    /// Draw the lecture caption and the inspected path over the image at `rect`.
    fn image_overlays(&self, ui: &egui::Ui, rect: egui::Rect) {
        if let (Some(caption), Some((k, n))) = (self.lecture_caption(), self.lecture_position()) {
            let line = format!("{k} / {n}  ·  {caption}");
            lecture::draw_caption(&ui.painter_at(rect), rect, &line);
        }
        if let Some(t) = &self.inspector.traced {
            let painter = ui.painter_at(rect);
            inspect_overlay::draw(&painter, rect, t, self.inspector.highlight);
        }
    }

    /// After drawing: record the frame's UI time and keep repainting while work is under way.
    fn end_frame(&mut self, ctx: &egui::Context, ui_time: Duration) {
        self.record_frame(ui_time);
        if self.backend.is_rendering() || self.dialog.is_some() || self.inspector.is_tracing() {
            ctx.request_repaint_after(Duration::from_millis(100));
        }
    }

    /// The image area measures `physical` pixels: with `fit_viewport`, a new size restarts
    /// accumulation at that size (× render scale) once it has held for [`VIEWPORT_SETTLE`]
    /// (the first size at once). The settle time keeps a window drag from restarting every
    /// frame and breaks layout feedback: the inspector's panel re-laid after each restart's
    /// re-trace changed the image width by a few pixels, which restarted it again, forever.
    /// Sizes under 16 pixels (a collapsed layout) are ignored.
    fn viewport_follow(&mut self, ctx: &egui::Context, physical: egui::Vec2) {
        let px = (physical.x.round() as u32, physical.y.round() as u32);
        if px.0 < 16 || px.1 < 16 || self.settings.viewport == Some(px) {
            self.viewport_pending = None;
            return;
        }
        let now = Instant::now();
        let settled = match self.viewport_pending {
            _ if self.settings.viewport.is_none() => true,
            Some((p, since)) if p == px => now - since >= VIEWPORT_SETTLE,
            _ => {
                self.viewport_pending = Some((px, now));
                false
            }
        };
        if !settled {
            ctx.request_repaint_after(VIEWPORT_SETTLE);
            return;
        }
        self.viewport_pending = None;
        let before = self.settings.resolution(&self.scene);
        self.settings.viewport = Some(px);
        if self.settings.resolution(&self.scene) != before {
            self.options_follow();
        }
    }

    /// Start or collect the inspector's trace for the scene and options as they are now.
    fn inspect_follow(&mut self) {
        let generation = self.backend.generation();
        let (settings, scene) = (&self.settings, &self.scene);
        self.inspector
            .update(scene, generation, || settings.render_options(scene));
    }
}
