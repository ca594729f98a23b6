//! Direct controls for the panels and headless callers: the backend, the view mode, material
//! and option changes, display parameters and screenshots.

use super::backend::{Backend, DisplayParams};
use super::{Edit, ViewerApp, layer_view, screenshot};
use crate::scene::Material;

impl ViewerApp {
    pub fn backend(&self) -> &dyn Backend {
        self.backend.as_ref()
    }

    /// Hold a drag that no pointer makes (a scripted slider drag): the backend renders
    /// interactively while it lasts, as for a real one.
    pub fn hold_drag(&mut self, on: bool) {
        self.scripted_drag = on;
    }

    /// Show `mode`; a backend that cannot (the GPU) keeps the image and says so.
    pub fn set_view(&mut self, mode: layer_view::ViewMode) {
        if self.backend.set_view(mode) {
            self.view = mode;
        } else {
            self.view = layer_view::ViewMode::Beauty;
            self.messages.info = Some(
                "the path-class, heatmap and polarisation views are CPU only: switch the device to CPU"
                    .to_owned(),
            );
        }
    }

    /// Put a polarising filter at `degrees` in front of the sensor (None: take it away); a
    /// backend that cannot keeps the unpolarised image and says so (both can: the GPU's
    /// kernel traces the filtered intensity, `cpu/polarized/chain.wgsl`).
    pub fn set_polarizer(&mut self, degrees: Option<f32>) {
        if self.backend.set_polarizer(degrees.map(f32::to_radians)) {
            self.polarizer = degrees;
        } else {
            self.polarizer = None;
            self.messages.info = Some(
                "this device cannot trace polarised light: switch the device to CPU".to_owned(),
            );
        }
    }

    /// Apply a material edit now (headless callers; the panels push [`Edit::Material`]).
    pub fn set_material(&mut self, index: usize, material: Material) {
        self.apply(Edit::Material {
            index,
            material: Box::new(material),
        });
    }

    /// `settings.render` was changed in place (headless callers): apply it now.
    pub fn options_changed(&mut self) {
        self.options_follow();
    }

    pub fn display_params(&self) -> DisplayParams {
        DisplayParams {
            exposure: self.settings.display.exposure,
            tone_map: self.settings.display.tone_map,
        }
    }

    /// Save the screenshot triple (PNG as shown, linear EXR, JSON sidecar).
    pub fn save_screenshot(&mut self) -> anyhow::Result<screenshot::Saved> {
        let r = screenshot::save(self);
        match &r {
            Ok(s) => {
                self.messages.info = Some(format!("saved {}", s.png.display()));
            }
            Err(e) => self.messages.error = Some(format!("screenshot failed: {e:#}")),
        }
        r
    }
}
