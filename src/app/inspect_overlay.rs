//! Drawing the inspected paths over the image: every vertex projected with the camera the
//! paths were traced with (the pinhole of `Camera::to_film`, segments clipped at a near plane
//! in camera space), each segment coloured by the event that sent light along it, light
//! connections dashed (the legend is in `panels::inspect`).

use super::inspect::Traced;
use crate::cpu::inspect::{PathRecord, VertexEvent};
use eframe::egui::{Color32, Painter, Pos2, Rect, Shape, Stroke};
use glam::Vec3;

/// Camera-space depth in front of which segments are clipped (m).
const NEAR: f32 = 1e-3;

/// The colour of a segment leaving a vertex with `event`.
pub fn event_color(event: VertexEvent) -> Color32 {
    match event {
        VertexEvent::Camera => Color32::from_rgb(235, 235, 235),
        VertexEvent::Refract => Color32::from_rgb(40, 200, 255),
        VertexEvent::Reflect => Color32::from_rgb(255, 215, 0),
        VertexEvent::Tir => Color32::from_rgb(255, 60, 200),
        VertexEvent::Diffuse => Color32::from_rgb(255, 140, 60),
        VertexEvent::Glossy => Color32::from_rgb(120, 230, 100),
        VertexEvent::Emission => Color32::from_rgb(255, 255, 190),
        VertexEvent::Absorbed => Color32::from_rgb(150, 150, 150),
    }
}

/// Colour of a light connection (NEE shadow ray) that reached the light / was blocked.
pub const CONNECTION: Color32 = Color32::from_rgb(255, 250, 150);
pub const BLOCKED: Color32 = Color32::from_rgb(110, 110, 110);

/// The colour key (a camera ray projects onto its pixel: it has no colour to show).
pub const LEGEND: [(&str, VertexEvent); 5] = [
    ("refraction", VertexEvent::Refract),
    ("reflection", VertexEvent::Reflect),
    ("total internal reflection", VertexEvent::Tir),
    ("diffuse", VertexEvent::Diffuse),
    ("glossy", VertexEvent::Glossy),
];

/// Projects world points onto the image rectangle.
struct Projector<'a> {
    traced: &'a Traced,
    rect: Rect,
    aspect: f32,
}

impl Projector<'_> {
    /// The segment a–b on screen, clipped to the part in front of the camera.
    fn segment(&self, a: Vec3, b: Vec3) -> Option<[Pos2; 2]> {
        let cam = &self.traced.camera;
        let (mut qa, mut qb) = (cam.to_local(a), cam.to_local(b));
        if qa.z > -NEAR && qb.z > -NEAR {
            return None;
        }
        // Clip at z = −NEAR (Sutherland–Hodgman against one plane).
        let clip = |p: Vec3, q: Vec3| p + (q - p) * ((-NEAR - p.z) / (q.z - p.z));
        if qa.z > -NEAR {
            qa = clip(qa, qb);
        } else if qb.z > -NEAR {
            qb = clip(qb, qa);
        }
        Some([self.screen(qa)?, self.screen(qb)?])
    }

    /// World point `p` on screen (None behind the camera).
    fn point(&self, p: Vec3) -> Option<Pos2> {
        let q = self.traced.camera.to_local(p);
        if q.z > -NEAR { None } else { self.screen(q) }
    }

    fn screen(&self, q: Vec3) -> Option<Pos2> {
        let (sx, sy) = self.traced.camera.film_of_local(q, self.aspect)?;
        let p = Pos2::new(
            self.rect.min.x + sx * self.rect.width(),
            self.rect.min.y + sy * self.rect.height(),
        );
        // Far outside the image: keep the direction but stay in painter range.
        Some(p.clamp(
            self.rect.min - self.rect.size() * 20.0,
            self.rect.max + self.rect.size() * 20.0,
        ))
    }
}

/// Draw the paths of `traced` over the image at `rect`; `highlight` dims the others.
pub fn draw(painter: &Painter, rect: Rect, traced: &Traced, highlight: Option<usize>) {
    let (w, h) = traced.size;
    let proj = Projector {
        traced,
        rect,
        aspect: w as f32 / h.max(1) as f32,
    };
    for (i, path) in traced.trace.paths.iter().enumerate() {
        let alpha = match highlight {
            Some(k) if k != i => 0.18,
            Some(_) => 1.0,
            None => 0.8,
        };
        draw_path(painter, &proj, path, alpha);
    }
    let [x, y] = traced.trace.pixel;
    let c = Pos2::new(
        rect.min.x + (x as f32 + 0.5) / w as f32 * rect.width(),
        rect.min.y + (y as f32 + 0.5) / h as f32 * rect.height(),
    );
    painter.circle_stroke(c, 5.0, Stroke::new(1.5, Color32::WHITE));
}

fn draw_path(painter: &Painter, proj: &Projector, path: &PathRecord, alpha: f32) {
    let fade = |c: Color32| c.gamma_multiply(alpha);
    for pair in path.vertices.windows(2) {
        let (a, b) = (Vec3::from(pair[0].p), Vec3::from(pair[1].p));
        if let Some(seg) = proj.segment(a, b) {
            painter.line_segment(seg, Stroke::new(1.6, fade(event_color(pair[0].event))));
        }
    }
    for c in &path.connections {
        let Some(from) = path.vertices.get(c.from) else {
            continue;
        };
        let color = if c.occluded { BLOCKED } else { CONNECTION };
        if let Some(seg) = proj.segment(Vec3::from(from.p), Vec3::from(c.p)) {
            let dashes = Shape::dashed_line(&seg, Stroke::new(1.2, fade(color)), 5.0, 4.0);
            painter.extend(dashes);
        }
    }
    if let (Some(d), Some(last)) = (path.escape_dir, path.vertices.last()) {
        let a = Vec3::from(last.p);
        // An arrow a third of the way back to the camera long: the ray leaves the scene.
        let b = a + Vec3::from(d) * 0.3 * (a - proj.traced.camera.position).length();
        if let Some(seg) = proj.segment(a, b) {
            painter.arrow(
                seg[0],
                seg[1] - seg[0],
                Stroke::new(1.2, fade(Color32::GRAY)),
            );
        }
    }
    for v in path.vertices.iter().skip(1) {
        if let Some(p) = proj.point(Vec3::from(v.p)) {
            painter.circle_filled(p, 2.2, fade(event_color(v.event)));
        }
    }
}
