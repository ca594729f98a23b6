//! [`Backend`] for [`GpuBackend`]: what the viewer calls (edits, steps, queries).

use super::GpuBackend;
use crate::app::backend::{Accumulated, Backend, DisplayParams, DisplayTexture};
use crate::render::RenderOptions;
use crate::scene::{Camera, Checked, Material, Scene};
use eframe::egui;
use std::time::Duration;

impl Backend for GpuBackend {
    fn set_scene(&mut self, scene: &Scene) {
        self.bump();
        self.scene = Some(scene.clone());
        if let Some(cpu) = self.fallback.as_mut() {
            cpu.set_scene(scene);
            self.retry_gpu();
            return;
        }
        if let Err(e) = self.sync_full() {
            self.enter_fallback(&e);
        }
    }

    fn update_material(&mut self, index: usize, material: &Checked<Material>) {
        self.bump();
        if let Some(slot) = self.scene.as_mut().and_then(|s| s.materials.get_mut(index)) {
            *slot = Material::clone(material);
        }
        if let Some(cpu) = self.fallback.as_mut() {
            cpu.update_material(index, material);
            return;
        }
        let m = material.clone();
        self.with_renderer(|r| r.set_checked_material(index, m));
    }

    fn update_lights(&mut self, scene: &Scene, geometry_changed: bool) {
        self.bump();
        let old = self.scene.replace(scene.clone());
        if let Some(cpu) = self.fallback.as_mut() {
            cpu.update_lights(scene, geometry_changed);
            return;
        }
        let scene = scene.clone();
        self.with_renderer(|r| {
            let rebuild = geometry_changed
                || old.as_ref().is_none_or(|o| {
                    o.punctual_lights != scene.punctual_lights
                        || o.materials.len() != scene.materials.len()
                        || o.env_map != scene.env_map
                });
            if rebuild {
                let opts = *r.options();
                return r.set_scene(scene, opts);
            }
            // Same geometry: rewrite the changed materials (emission → light CDF) in place.
            for (i, m) in scene.materials.iter().enumerate() {
                if r.scene().materials.get(i) != Some(m) {
                    r.set_material(i, m.clone())?;
                }
            }
            r.set_environment(scene.environment)?;
            Ok(())
        });
    }

    fn update_camera(&mut self, camera: &Checked<Camera>) {
        self.bump();
        if let Some(s) = self.scene.as_mut() {
            s.camera = **camera;
        }
        if let Some(cpu) = self.fallback.as_mut() {
            cpu.update_camera(camera);
            return;
        }
        let c = camera.clone();
        self.with_renderer(|r| r.set_checked_camera(c));
    }

    fn set_options(&mut self, options: &RenderOptions) {
        self.bump();
        // The estimator is applied by `sync_options`/`sync_full` (`wanted_estimator`).
        self.options = Some(*options);
        if let Some(cpu) = self.fallback.as_mut() {
            cpu.set_options(options);
            self.retry_gpu();
            return;
        }
        if let Err(e) = self.sync_options() {
            self.enter_fallback(&e);
        }
    }

    fn set_interactive(&mut self, interactive: bool) {
        if self.interactive == interactive {
            return;
        }
        self.bump();
        self.interactive = interactive;
        if let Some(cpu) = self.fallback.as_mut() {
            cpu.set_interactive(interactive);
            return;
        }
        if let Err(e) = self.sync_options() {
            self.enter_fallback(&e);
        }
    }

    fn set_paused(&mut self, paused: bool) {
        self.paused = paused;
        if let Some(cpu) = self.fallback.as_mut() {
            cpu.set_paused(paused);
        }
    }

    fn set_spp_target(&mut self, spp: u64) {
        self.spp_target = spp;
        if let Some(cpu) = self.fallback.as_mut() {
            cpu.set_spp_target(spp);
        }
    }

    fn reset(&mut self) {
        self.bump();
        if let Some(cpu) = self.fallback.as_mut() {
            cpu.reset();
            return;
        }
        if let Some(r) = self.renderer.as_mut() {
            r.reset();
        }
    }

    fn step(&mut self, frame_budget: Duration) {
        if let Some(cpu) = self.fallback.as_mut() {
            cpu.step(frame_budget);
            return;
        }
        self.budget = frame_budget;
        self.collect();
        if self.fallback.is_some() {
            return; // a GPU error: the CPU renders from the next step on
        }
        if self.in_flight.len() >= self.depth {
            return; // at most `depth` batches in flight
        }
        // The GPU is idle now (or, with two in flight, runs one batch): tone-map and copy the
        // counters before the next batch, so no submission of ours ever queues behind more
        // than one batch (software drivers such as lavapipe block `queue.submit` until the
        // previous submission has finished: there `depth` is 1).
        self.refresh_display();
        self.start_readback();
        // A new specialisation compiles on a worker thread: keep showing the last image.
        match self.renderer.as_mut().map(|r| r.pipelines_ready()) {
            None | Some(Ok(true)) => {}
            Some(Ok(false)) => {
                if let Some(c) = &self.repaint {
                    c.request_repaint_after(Duration::from_millis(10));
                }
                return;
            }
            Some(Err(e)) => {
                self.enter_fallback(&e);
                return;
            }
        }
        while self.in_flight.len() < self.depth && self.queue_batch(frame_budget) {}
    }

    fn spp(&self) -> u64 {
        match &self.fallback {
            Some(cpu) => cpu.spp(),
            None => self.done_spp,
        }
    }

    fn samples_per_sec(&self) -> f64 {
        if let Some(cpu) = &self.fallback {
            return cpu.samples_per_sec();
        }
        let pixels = self
            .renderer
            .as_ref()
            .map_or(0, |r| r.options().width as u64 * r.options().height as u64);
        (self.done_spp * pixels) as f64 / self.elapsed.as_secs_f64().max(1e-9)
    }

    fn elapsed(&self) -> Duration {
        match &self.fallback {
            Some(cpu) => cpu.elapsed(),
            None => self.elapsed,
        }
    }

    fn dropped(&self) -> u64 {
        match &self.fallback {
            Some(cpu) => cpu.dropped(),
            None => self.dropped,
        }
    }

    fn device_name(&self) -> String {
        let headless = if self.egui_renderer.is_none() {
            ", headless, image read back"
        } else {
            ""
        };
        let gpu = format!(
            "{} ({:?}{headless})",
            self.ctx.info.name, self.ctx.info.backend
        );
        if let Some(cpu) = &self.fallback {
            return format!("{} (GPU {gpu} cannot render this scene)", cpu.device_name());
        }
        let Some(r) = &self.renderer else {
            return format!("GPU {gpu}");
        };
        let running = if r.is_general() {
            format!(
                "{} (general kernel while its own compiles)",
                r.effective_estimator()
            )
        } else {
            r.effective_estimator().to_string()
        };
        let plan = r.plan();
        if plan.exact {
            format!("GPU {gpu}, {running}")
        } else {
            format!(
                "GPU {gpu}, {running} ({} runs on the CPU backend only)",
                plan.asked
            )
        }
    }

    fn is_rendering(&self) -> bool {
        if let Some(cpu) = &self.fallback {
            return cpu.is_rendering();
        }
        !self.in_flight.is_empty()
            || self
                .renderer
                .as_ref()
                .is_some_and(|r| self.wants_samples(r.spp()))
    }

    fn generation(&self) -> u64 {
        self.generation
    }

    fn material(&self, index: usize) -> Option<Material> {
        match &self.fallback {
            Some(cpu) => cpu.material(index),
            None => self
                .renderer
                .as_ref()
                .and_then(|r| r.scene().materials.get(index).cloned()),
        }
    }

    fn display_texture(
        &mut self,
        ctx: &egui::Context,
        display: &DisplayParams,
    ) -> Option<DisplayTexture> {
        if let Some(cpu) = self.fallback.as_mut() {
            return cpu.display_texture(ctx, display);
        }
        self.display = Some(*display);
        self.refresh_display();
        let size = self.tonemap.target()?.size;
        let id = match self.egui_renderer {
            Some(_) => self.image_id?,
            None => self.cpu_texture(ctx)?,
        };
        Some(DisplayTexture { id, size })
    }

    fn denoise_device(&self) -> Option<crate::gpu::GpuContext> {
        (self.ctx.info.backend != wgpu::Backend::Gl).then(|| self.ctx.clone())
    }

    fn read_image(&self) -> Option<Accumulated> {
        if let Some(cpu) = &self.fallback {
            return cpu.read_image();
        }
        let r = self.renderer.as_ref()?;
        if r.spp() == 0 {
            return None;
        }
        let img = r.image().ok()?;
        Some(Accumulated {
            generation: self.generation,
            width: img.width,
            height: img.height,
            pixels: img.mean,
            spp: img.spp,
            dropped: img.dropped,
            elapsed: self.elapsed,
        })
    }

    fn compiling(&self) -> bool {
        self.is_compiling()
    }

    fn general_kernel(&self) -> bool {
        self.runs_general_kernel()
    }

    fn pipeline_stats(&self) -> Option<(u32, usize)> {
        GpuBackend::pipeline_stats(self)
    }

    fn prepare_for(&mut self, scene: &Scene, options: &RenderOptions) {
        if self.fallback.is_some() {
            return;
        }
        if let Some(r) = self.renderer.as_mut()
            && let Err(e) = r.compile_ahead_for(scene, options)
        {
            self.message = Some(format!("{e:#}"));
        }
    }

    fn take_message(&mut self) -> Option<String> {
        self.message.take()
    }

    fn set_polarizer(&mut self, angle: Option<f32>) -> bool {
        if self.polarizer == angle {
            return true;
        }
        self.bump();
        self.polarizer = angle;
        if let Some(cpu) = self.fallback.as_mut() {
            return cpu.set_polarizer(angle);
        }
        if let Err(e) = self.sync_polarizer() {
            self.enter_fallback(&e);
            if let Some(cpu) = self.fallback.as_mut() {
                cpu.set_polarizer(angle);
            }
        }
        true
    }
}
