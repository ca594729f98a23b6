//! The central viewport: shows the backend's image (aspect kept, letterboxed), turns mouse
//! input into orbit / pan / zoom of the camera, and clicks into picking rays.

use super::backend::DisplayTexture;
use crate::scene::edits::Orbit;
use eframe::egui::{self, Color32, PointerButton, Pos2, Rect, Sense, Vec2};
use glam::Vec3;

/// What happened in the viewport this frame.
#[derive(Clone, Copy, Debug)]
pub struct ViewportResponse {
    /// The orbit was changed (drag or scroll).
    pub camera_changed: bool,
    /// A click at film coordinates (sx, sy) ∈ [0,1]², (0,0) = top-left.
    pub clicked: Option<(f32, f32)>,
    /// A drag is in progress (the backend may render at lower resolution meanwhile).
    pub dragging: bool,
    /// Alt was held during the click (inspect the pixel's paths).
    pub alt: bool,
    /// Where the image is drawn (overlays draw into it).
    pub image_rect: Rect,
}

impl Default for ViewportResponse {
    fn default() -> Self {
        ViewportResponse {
            camera_changed: false,
            clicked: None,
            dragging: false,
            alt: false,
            image_rect: Rect::NOTHING,
        }
    }
}

/// Degrees of orbit per point of drag.
const ORBIT_DEG_PER_POINT: f32 = 0.3;

/// The largest rectangle of aspect `w/h` centred in `outer`.
pub fn fit_rect(outer: Rect, w: u32, h: u32) -> Rect {
    let aspect = w.max(1) as f32 / h.max(1) as f32;
    let mut size = outer.size();
    if size.x / size.y.max(1.0) > aspect {
        size.x = size.y * aspect;
    } else {
        size.y = size.x / aspect;
    }
    Rect::from_center_size(outer.center(), size)
}

/// Show the image and handle camera input. `image_size` is the rendered resolution (for the
/// aspect ratio even before the first image arrives), `yfov` the current field of view.
pub fn show(
    ui: &mut egui::Ui,
    texture: Option<DisplayTexture>,
    image_size: (u32, u32),
    orbit: &mut Orbit,
    yfov: f32,
) -> ViewportResponse {
    let mut out = ViewportResponse::default();
    let (outer, response) = ui.allocate_exact_size(ui.available_size(), Sense::click_and_drag());
    let response = response.on_hover_text(
        "Drag: orbit · right/middle drag: pan · scroll: zoom · click: select the object's material · Alt+click: inspect the paths through a pixel",
    );
    let rect = fit_rect(outer, image_size.0, image_size.1);
    out.image_rect = rect;
    paint_image(ui, outer, rect, texture);

    // Orbit with the primary button, pan with the secondary or middle one.
    out.camera_changed |= orbit_by_drag(&response, orbit);
    out.camera_changed |= pan_by_drag(&response, orbit, yfov, rect);
    out.dragging = response.dragged();
    out.camera_changed |= zoom_by_scroll(ui, &response, orbit);
    if let Some((at, alt)) = click_in_image(ui, &response, rect) {
        out.clicked = Some(at);
        out.alt = alt;
    }
    if out.camera_changed {
        let fallback = *orbit;
        orbit.sanitize(&fallback);
    }
    out
}

/// Paint the dark background over `outer` and the image (or a "rendering…" placeholder
/// while there is none) into `rect`.
fn paint_image(ui: &egui::Ui, outer: Rect, rect: Rect, texture: Option<DisplayTexture>) {
    let painter = ui.painter_at(outer);
    painter.rect_filled(outer, 0.0, Color32::from_gray(16));
    match texture {
        Some(t) => {
            let uv = Rect::from_min_max(Pos2::ZERO, Pos2::new(1.0, 1.0));
            painter.image(t.id, rect, uv, Color32::WHITE);
        }
        None => {
            painter.rect_filled(rect, 0.0, Color32::BLACK);
            painter.text(
                rect.center(),
                egui::Align2::CENTER_CENTER,
                "rendering…",
                egui::FontId::proportional(16.0),
                Color32::GRAY,
            );
        }
    }
}

/// Orbit (yaw and pitch) by a drag with the primary button; true when the orbit changed.
fn orbit_by_drag(response: &egui::Response, orbit: &mut Orbit) -> bool {
    if response.dragged_by(PointerButton::Primary) {
        let d = response.drag_delta();
        if d != Vec2::ZERO {
            orbit.yaw_deg -= d.x * ORBIT_DEG_PER_POINT;
            orbit.pitch_deg += d.y * ORBIT_DEG_PER_POINT;
            return true;
        }
    }
    false
}

/// Pan the pivot by a drag with the secondary or middle button, so the point under the
/// cursor follows it (at the pivot's depth) in the image drawn in `rect`; true when the orbit
/// changed.
fn pan_by_drag(response: &egui::Response, orbit: &mut Orbit, yfov: f32, rect: Rect) -> bool {
    if response.dragged_by(PointerButton::Secondary) || response.dragged_by(PointerButton::Middle) {
        let d = response.drag_delta();
        if d != Vec2::ZERO {
            // Move the pivot so the point under the cursor follows it (at the pivot's depth).
            let world_per_point =
                2.0 * orbit.distance * (0.5 * yfov).tan() / rect.height().max(1.0);
            let cam = orbit.camera(yfov);
            let right = cam.rotation.x_axis;
            let up = cam.rotation.y_axis;
            let t = Vec3::from_array(orbit.target) + (-d.x * right + d.y * up) * world_per_point;
            orbit.target = t.to_array();
            return true;
        }
    }
    false
}

/// Zoom (the orbit distance) by scrolling over the viewport; true when the orbit changed.
fn zoom_by_scroll(ui: &egui::Ui, response: &egui::Response, orbit: &mut Orbit) -> bool {
    if response.hovered() {
        let scroll = ui.input(|i| i.smooth_scroll_delta.y);
        if scroll != 0.0 {
            orbit.distance *= (-scroll * 0.0015).exp();
            return true;
        }
    }
    false
}

/// A click inside the image drawn in `rect`: its film coordinates (see
/// [`ViewportResponse::clicked`]) and whether Alt was held.
fn click_in_image(
    ui: &egui::Ui,
    response: &egui::Response,
    rect: Rect,
) -> Option<((f32, f32), bool)> {
    if response.clicked()
        && let Some(p) = response.interact_pointer_pos()
        && rect.contains(p)
    {
        let sx = (p.x - rect.min.x) / rect.width();
        let sy = (p.y - rect.min.y) / rect.height();
        return Some(((sx, sy), ui.input(|i| i.modifiers.alt)));
    }
    None
}
