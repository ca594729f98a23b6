//! A demo's teaching switch (`Demo::toggle`): an ordinary material edit that breaks a law
//! on purpose (the furnace's sphere with ρ = π glows) and one that puts it back.

use super::{DEMOS, Toggle};
use crate::app::ViewerApp;
use glam::Vec3;

impl ViewerApp {
    /// The open demo's teaching switch, and whether it is on (its material has the switch's
    /// albedo).
    pub fn lecture_toggle(&self) -> Option<(Toggle, bool)> {
        self.lecture_caption()?;
        let toggle = DEMOS.get(self.lecture.active?)?.toggle?;
        let m = self
            .scene
            .materials
            .iter()
            .find(|m| m.name == toggle.material)?;
        Some((toggle, m.base_color == Vec3::splat(toggle.albedo)))
    }

    /// Turn the open demo's switch on (the material's albedo becomes the switch's) or off
    /// (the albedo of the scene as loaded).
    pub fn set_lecture_toggle(&mut self, on: bool) {
        let Some((toggle, _)) = self.lecture_toggle() else {
            return;
        };
        let Some(index) = self
            .scene
            .materials
            .iter()
            .position(|m| m.name == toggle.material)
        else {
            return;
        };
        let mut m = self.scene.materials[index].clone();
        m.base_color = if on {
            Vec3::splat(toggle.albedo)
        } else {
            self.base
                .materials
                .get(index)
                .map_or(m.base_color, |b| b.base_color)
        };
        self.set_material(index, m);
    }
}
