//! The status bar and the frame timing behind it: each frame recorded, the summary line
//! printed at exit and the `--frames`/`--exit-after` exit rule.

use super::ViewerApp;
use eframe::egui;
use std::time::{Duration, Instant};

impl ViewerApp {
    pub(super) fn record_frame(&mut self, ui_time: Duration) {
        let now = Instant::now();
        let s = &mut self.stats;
        if let Some(last) = s.last {
            let dt = now - last;
            s.interval_sum += dt;
            s.interval_ema = 0.9 * s.interval_ema + 0.1 * dt.as_secs_f64();
        }
        s.last = Some(now);
        s.frames += 1;
        s.ui_sum += ui_time;
        s.ui_ema = 0.9 * s.ui_ema + 0.1 * ui_time.as_secs_f64();
    }

    pub(super) fn status_bar(&mut self, ui: &mut egui::Ui) {
        let b = self.backend.as_ref();
        let (w, h) = self.settings.resolution(&self.scene);
        ui.horizontal_wrapped(|ui| {
            let spp = b.spp();
            let target = self.settings.render.spp_target;
            let state = if self.paused {
                "paused"
            } else if b.is_rendering() {
                "rendering"
            } else {
                "done"
            };
            ui.label(if target > 0 {
                format!("{spp} / {target} spp")
            } else {
                format!("{spp} spp")
            })
            .on_hover_text("Samples per pixel averaged so far; noise falls as 1/√spp.");
            ui.separator();
            ui.label(format!("{:.2} M samples/s", b.samples_per_sec() / 1e6))
                .on_hover_text("Camera paths traced per second (pixels × spp / render time).");
            ui.separator();
            ui.label(format!("{:.1} s", b.elapsed().as_secs_f64()))
                .on_hover_text("Render time spent on the current image.");
            ui.separator();
            let dropped = b.dropped();
            let text = format!("{dropped} NaN/dropped");
            if dropped > 0 {
                ui.colored_label(egui::Color32::from_rgb(255, 160, 60), text)
            } else {
                ui.label(text)
            }
            .on_hover_text(
                "Samples refused by the film's firewall (NaN, infinite or negative radiance).",
            );
            ui.separator();
            ui.label(format!("{w}×{h} · {state}"));
            ui.separator();
            let mut dev = format!("render: {}", b.device_name());
            if !self.display_device.is_empty() {
                dev.push_str(&format!(" · display: {}", self.display_device));
            }
            ui.label(dev);
            ui.separator();
            ui.label(format!(
                "frame {:.1} ms (UI {:.1} ms)",
                self.stats.interval_ema * 1e3,
                self.stats.ui_ema * 1e3
            ))
            .on_hover_text("Time between UI frames and the part of it spent building the UI.");
        });
    }

    /// One line summarising the frame times (printed when `--frames`/`--exit-after` ends).
    pub fn frame_summary(&self) -> String {
        let s = &self.stats;
        let n = s.frames.max(1);
        let display = if self.display_device.is_empty() {
            String::new()
        } else {
            format!("; display: {}", self.display_device)
        };
        format!(
            "{} frames in {:.2} s: mean frame interval {:.2} ms, mean UI build {:.2} ms; {} spp at {}x{}; render: {}{display}",
            s.frames,
            s.started.elapsed().as_secs_f64(),
            s.interval_sum.as_secs_f64() * 1e3 / (n.saturating_sub(1)).max(1) as f64,
            s.ui_sum.as_secs_f64() * 1e3 / n as f64,
            self.backend.spp(),
            self.settings.resolution(&self.scene).0,
            self.settings.resolution(&self.scene).1,
            self.backend.device_name(),
        )
    }

    /// `--frames N`: after N frames — and, when `--exit-after` bounds the wait, not before the
    /// image has its first sample (a GPU pipeline still compiling in the background would
    /// otherwise leave a black window for the screenshot). `--exit-after`: after that time.
    pub(super) fn should_exit(&self) -> bool {
        let sampled = self.exit_after.is_none() || self.backend.spp() >= 1;
        self.exit_frames
            .is_some_and(|n| self.stats.frames >= n && sampled)
            || self
                .exit_after
                .is_some_and(|d| self.stats.started.elapsed() >= d)
    }
}
