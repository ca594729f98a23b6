//! Input outside the panels: keys, dropped files, the file dialog and picking a material in
//! the viewport.

use super::{Edit, EnvEdit, ViewerApp};
use eframe::egui;
use std::path::PathBuf;
use std::sync::mpsc;

impl ViewerApp {
    pub fn pick(&self, sx: f32, sy: f32) -> Option<usize> {
        let (w, h) = self.settings.resolution(&self.scene);
        let cam = &self.scene.camera;
        let dir = cam.ray_dir(sx, sy, w as f32 / h as f32);
        let hit = self.pick_bvh.intersect(cam.position, dir, f32::INFINITY)?;
        self.scene
            .mesh
            .tri_material
            .get(hit.tri as usize)
            .map(|&m| m as usize)
    }

    /// Open the system file dialog on a helper thread (xdg-desktop-portal on Linux).
    pub fn open_dialog(&mut self) {
        let (tx, rx) = mpsc::channel();
        let spawned = std::thread::Builder::new()
            .name("refract-file-dialog".into())
            .spawn(move || {
                let picked = rfd::FileDialog::new()
                    .add_filter("glTF scene", &["glb", "gltf"])
                    .pick_file();
                let _ = tx.send(picked);
            });
        match spawned {
            Ok(_) => self.dialog = Some(rx),
            Err(e) => self.messages.error = Some(format!("cannot open a file dialog: {e}")),
        }
    }

    pub(super) fn poll_dialog(&mut self) {
        let Some(rx) = &self.dialog else { return };
        match rx.try_recv() {
            Ok(Some(path)) => {
                self.dialog = None;
                let spec = path.display().to_string();
                self.open_path = spec.clone();
                self.push(Edit::OpenScene(spec));
            }
            Ok(None) => {
                self.dialog = None;
                self.messages.info = Some(
                    "No file chosen. If no dialog appeared, this desktop has no \
                     xdg-desktop-portal: drop a .glb/.gltf on the window or type its path."
                        .into(),
                );
            }
            Err(mpsc::TryRecvError::Empty) => {}
            Err(mpsc::TryRecvError::Disconnected) => self.dialog = None,
        }
    }

    pub(super) fn handle_input(&mut self, ctx: &egui::Context) {
        use egui::{Key, Modifiers};
        // Dropped files: open the first .glb/.gltf.
        let dropped: Vec<PathBuf> = ctx.input(|i| {
            i.raw
                .dropped_files
                .iter()
                .map(|f| f.path().to_path_buf())
                .filter(|p| !p.as_os_str().is_empty())
                .collect()
        });
        if let Some(p) = dropped.first() {
            let spec = p.display().to_string();
            let is_env = p
                .extension()
                .and_then(|e| e.to_str())
                .is_some_and(|e| e.eq_ignore_ascii_case("hdr") || e.eq_ignore_ascii_case("exr"));
            if is_env {
                self.env_path = spec.clone();
                self.push(Edit::Environment(EnvEdit::Load(spec)));
            } else {
                self.open_path = spec.clone();
                self.push(Edit::OpenScene(spec));
            }
        }
        let (f12, ctrl_s) = ctx.input_mut(|i| {
            (
                i.consume_key(Modifiers::NONE, Key::F12),
                i.consume_key(Modifiers::COMMAND, Key::S),
            )
        });
        if f12 || ctrl_s {
            let _ = self.save_screenshot();
        }
        self.handle_clicker(ctx);
        if !ctx.egui_wants_keyboard_input() {
            let (space, r, esc) = ctx.input_mut(|i| {
                (
                    i.consume_key(Modifiers::NONE, Key::Space),
                    i.consume_key(Modifiers::NONE, Key::R),
                    i.consume_key(Modifiers::NONE, Key::Escape),
                )
            });
            if space {
                self.push(Edit::Pause(!self.paused));
            }
            if r {
                self.push(Edit::ResetCamera);
            }
            if esc {
                self.selected = None;
            }
        }
    }
}
