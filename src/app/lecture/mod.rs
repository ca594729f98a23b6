//! Lecture mode: one-click demonstrations, each a built-in scene set up to show one effect
//! (a path filter, the inspector on a telling pixel, a selected material) with a one-line
//! caption drawn over the image, and large type (egui zoom) for the back row.
//!
//! A demo is data ([`Demo`]); [`ViewerApp::start_demo`] turns it into ordinary edits, so a
//! demo is exactly what a user could set up by hand and every control keeps working in it.

mod ahead;
mod clicker;
mod demos;
mod toggle;

pub use ahead::Ahead;
pub use demos::{DEMOS, Demo, Toggle};

use super::{Edit, ViewerApp};

/// The demo called `key`, or an error listing the names.
pub fn find(key: &str) -> anyhow::Result<&'static Demo> {
    DEMOS.iter().find(|d| d.key == key).ok_or_else(|| {
        let names: Vec<&str> = DEMOS.iter().map(|d| d.key).collect();
        anyhow::anyhow!(
            "--lecture: no demo '{key}'; the demos are {}",
            names.join(", ")
        )
    })
}

/// Zoom factor of large type.
pub const LARGE_ZOOM: f32 = 1.4;

/// Lecture-mode state of the viewer.
#[derive(Clone, Debug, Default)]
pub struct Lecture {
    /// The demo shown (its caption is drawn while its scene is open).
    pub active: Option<usize>,
    /// Large type (egui zoom [`LARGE_ZOOM`]).
    pub large_type: bool,
    /// The zoom factor last given to egui (None = never set: leave the user's zoom alone).
    applied_zoom: Option<f32>,
    /// The demo's inspected scene point, followed until the user inspects elsewhere.
    pub inspect_point: Option<glam::Vec3>,
    /// The image size the point was last projected at.
    inspected_size: Option<(u32, u32)>,
    /// The neighbouring demos being prepared (`ahead`).
    pub ahead: Ahead,
}

impl Lecture {
    /// The zoom to give egui now, when it differs from what was given last.
    pub fn zoom_change(&mut self) -> Option<f32> {
        let want = if self.large_type { LARGE_ZOOM } else { 1.0 };
        if self.applied_zoom == Some(want) || (self.applied_zoom.is_none() && !self.large_type) {
            return None;
        }
        self.applied_zoom = Some(want);
        Some(want)
    }
}

impl ViewerApp {
    /// Open demo `index` of [`DEMOS`]: its scene, filter, inspector pixel and selection, as
    /// edits applied now. A scene that fails to open leaves the current one and its message.
    pub fn start_demo(&mut self, index: usize) {
        let Some(demo) = DEMOS.get(index) else { return };
        self.apply(Edit::OpenScene(demo.scene.to_owned()));
        if self.settings.scene != demo.scene {
            return;
        }
        self.filter_text = demo.filter.to_owned();
        self.apply(Edit::PathFilter(demo.filter.to_owned()));
        self.inspector.clear();
        self.inspector.enabled = demo.inspect.is_some();
        self.lecture.inspect_point = demo.inspect.map(glam::Vec3::from);
        self.lecture.inspected_size = None;
        self.selected = demo
            .select
            .and_then(|name| self.scene.materials.iter().position(|m| m.name == name));
        if demo.view != self.view {
            self.set_view(demo.view);
        }
        if demo.polarizer != self.polarizer {
            self.set_polarizer(demo.polarizer);
        }
        self.lecture.active = Some(index);
        self.lecture.ahead.start(index, &self.settings);
        self.lecture_follow();
    }

    /// Hand the neighbouring demos that finished loading to the backend to prepare for, and
    /// keep the demo's inspected scene point under the inspector when the image changes size
    /// (Fit viewport: the inspector's own panel narrows the image when it opens).
    pub fn lecture_follow(&mut self) {
        for (scene, opts) in self.lecture.ahead.take_ready() {
            self.backend.prepare_for(&scene, &opts);
        }
        let Some(p) = self.lecture.inspect_point else {
            return;
        };
        if self.lecture_caption().is_none() {
            self.lecture.inspect_point = None;
            return;
        }
        let size = self.settings.resolution(&self.scene);
        if self.lecture.inspected_size == Some(size) {
            return;
        }
        self.lecture.inspected_size = Some(size);
        if let Some(film) = self.scene.camera.to_film(p, size.0 as f32 / size.1 as f32) {
            self.inspector.request(film);
        }
    }

    /// The caption of the demo on screen, if its scene is still the open one.
    pub fn lecture_caption(&self) -> Option<&'static str> {
        let demo = DEMOS.get(self.lecture.active?)?;
        (self.settings.scene == demo.scene).then_some(demo.caption)
    }
}

/// The caption across the top of the image: wrapped white text on a dark band.
pub fn draw_caption(painter: &eframe::egui::Painter, rect: eframe::egui::Rect, caption: &str) {
    use eframe::egui::{Align2, Color32, FontId, Rect, pos2, vec2};
    let margin = 10.0;
    let font = FontId::proportional(17.0);
    let galley = painter.layout(
        caption.to_owned(),
        font,
        Color32::WHITE,
        (rect.width() - 2.0 * margin).max(50.0),
    );
    let band = Rect::from_min_size(rect.min, vec2(rect.width(), galley.size().y + 2.0 * margin));
    painter.rect_filled(band, 0.0, Color32::from_black_alpha(170));
    let at = Align2::LEFT_TOP.align_size_within_rect(galley.size(), band.shrink(margin));
    painter.galley(pos2(at.min.x, at.min.y), galley, Color32::WHITE);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn demos_are_found_by_key_and_unknown_keys_list_them() {
        for d in &DEMOS {
            assert_eq!(find(d.key).unwrap().key, d.key);
            assert!(crate::scene::Scene::load(d.scene).is_ok(), "{}", d.scene);
        }
        let e = find("laser").unwrap_err().to_string();
        assert!(
            e.contains("--lecture") && e.contains("energy, brdf-types") && e.contains("wine-glass"),
            "{e}"
        );
    }

    #[test]
    fn zoom_is_given_once_per_change_and_never_unasked() {
        let mut l = Lecture::default();
        assert_eq!(l.zoom_change(), None);
        l.large_type = true;
        assert_eq!(l.zoom_change(), Some(LARGE_ZOOM));
        assert_eq!(l.zoom_change(), None);
        l.large_type = false;
        assert_eq!(l.zoom_change(), Some(1.0));
    }
}
