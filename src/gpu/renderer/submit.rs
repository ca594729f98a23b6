//! Dispatch and submission: planning batches and row bands, encoding the kernels, queueing
//! submissions and retiring them, and the pipelines' readiness.

use super::{GpuImage, GpuRenderer, photon_paths, wavefront};
use crate::gpu::layout::{FilterWords, Params};
use crate::gpu::photons;
use crate::gpu::pipeline::Kernel;
use crate::render::photon_aim;
use anyhow::Result;
use std::time::{Duration, Instant};

/// A submission of [`GpuRenderer::render_with`] not yet known to be finished.
struct Queued {
    index: wgpu::SubmissionIndex,
    submitted: Instant,
    /// Pixel samples it adds.
    samples: u64,
    /// The spp accumulated once it finishes, where it completes a pass.
    completes: Option<u64>,
}

impl GpuRenderer {
    /// Collect pipelines compiled on a worker thread (never waits): Ok(true) once those of
    /// the current specialisation are ready, an `Err` if their compilation failed.
    ///
    /// With background compilation, the general kernel of the specialisation's family
    /// counts: it renders while the specialised one compiles ([`GpuRenderer::kernel_spec`]).
    pub fn pipelines_ready(&mut self) -> Result<bool> {
        self.pipelines.poll()?;
        Ok(self.kernel_spec().is_some())
    }

    /// True while the current specialisation's pipelines are not compiled yet (its family's
    /// general kernel's, with [`GpuRenderer::set_general_kernel`]).
    pub fn is_compiling(&self) -> bool {
        !self.pipelines.is_ready(self.wanted_spec())
    }

    /// The specialisation this renderer compiles for the current scene and options: its own,
    /// or its family's general kernel with [`GpuRenderer::set_general_kernel`].
    fn wanted_spec(&self) -> crate::gpu::pipeline::Specialization {
        if self.general_only {
            self.spec.general()
        } else {
            self.spec
        }
    }

    /// True while some specialisation compiles on a worker thread.
    pub fn background_compiles_pending(&self) -> bool {
        self.pipelines.is_compiling()
    }

    /// True while the next dispatch runs the general kernel (the specialised one compiles).
    pub fn is_general(&self) -> bool {
        self.kernel_spec()
            .is_some_and(|k| k != self.spec && k == self.spec.general())
    }

    /// The specialisation whose pipelines run the next dispatch: the scene's own once
    /// compiled; meanwhile, with background compilation, the general kernel of its family
    /// once that is (`Specialization::general`: same estimator and maths, every kind of part
    /// compiled in); None while neither is.
    pub(super) fn kernel_spec(&self) -> Option<crate::gpu::pipeline::Specialization> {
        let general = self.spec.general();
        if self.general_only {
            return self.pipelines.is_ready(general).then_some(general);
        }
        if self.pipelines.is_ready(self.spec) {
            return Some(self.spec);
        }
        (self.background_compile && self.pipelines.is_ready(general)).then_some(general)
    }

    /// Compile general kernels ahead of need (`on`; the default except on software
    /// drivers), starting with this specialisation's family.
    pub fn set_compile_ahead(&mut self, on: bool) {
        self.pipelines.set_compile_ahead(on);
        if on && self.background_compile {
            self.request_pipelines();
        }
    }

    /// Run the general kernel of the specialisation's family even where the specialised
    /// one is compiled (`on`), or the specialised one again: to compare the two (they
    /// render the same image) and to measure what specialising buys. Accumulation goes on.
    pub fn set_general_kernel(&mut self, on: bool) {
        self.general_only = on;
        self.request_pipelines();
    }

    /// Submissions [`GpuRenderer::render_with`] keeps queued (at least 1; default
    /// [`BATCHES_IN_FLIGHT`]).
    ///
    /// [`BATCHES_IN_FLIGHT`]: super::BATCHES_IN_FLIGHT
    pub fn set_batches_in_flight(&mut self, n: usize) {
        self.batches_in_flight = n.max(1);
    }

    /// Drop all accumulated samples and counters (the next sample index is 0 again). While
    /// the specialisation's pipelines compile, the film keeps the last image until the first
    /// submission clears it (the viewer shows it meanwhile).
    pub fn reset(&mut self) {
        if self.pipelines.is_ready(self.spec) {
            let mut enc = self
                .ctx
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
            self.encode_clear(&mut enc);
            self.ctx.queue.submit([enc.finish()]);
            self.clear_pending = false;
        } else {
            self.clear_pending = true;
        }
        self.spp = 0;
        self.elapsed = Duration::ZERO;
        self.photon_r0 = self.sppm_radius0();
        if let Some(mean) = &mut self.tiled {
            mean.fill([0.0; 4]);
        }
    }

    /// Zero the film, the counters, the splats and the photon grid.
    fn encode_clear(&self, enc: &mut wgpu::CommandEncoder) {
        enc.clear_buffer(&self.buffers.accum, 0, None);
        enc.clear_buffer(&self.buffers.stats, 0, None);
        enc.clear_buffer(&self.buffers.splats, 0, None);
        enc.clear_buffer(&self.buffers.photon_store.grid, 0, None);
    }

    /// The uniforms of a dispatch adding `batch` samples per pixel to the `first` accumulated.
    fn params(&self, first: u64, batch: u32) -> Params {
        let cam = &self.scene.camera;
        let (w, h) = (self.opts.width, self.opts.height);
        let n = first as f64;
        let k = batch as f64;
        let rot = cam.rotation;
        // sppm: iteration s = sample index s, `batch` iterations per submission.
        let mut targets = [[0.0; 4]; photon_aim::MAX_TARGETS];
        let (mut aimed, mut target_count) = (1, 0);
        if self.spec.sppm {
            let (aim, fraction) = self.photon_aim();
            // At most the store's slots (capped to the device's binding: `photons::max_paths`).
            aimed = photon_aim::photon_paths(photon_paths(true, &self.opts), *fraction)
                .min(self.buffers.photon_store.paths);
            target_count = aim.spheres.len() as u32;
            for (t, s) in targets.iter_mut().zip(&aim.spheres) {
                *t = s.center.extend(s.radius).to_array();
            }
        }
        let paths = f64::from(aimed);
        Params {
            cam_pos: cam.position.extend((0.5 * cam.yfov).tan()).to_array(),
            cam_right: rot.x_axis.extend(w as f32 / h as f32).to_array(),
            cam_up: rot.y_axis.extend(0.0).to_array(),
            cam_back: rot.z_axis.extend(0.0).to_array(),
            environment: self.scene.environment.extend(0.0).to_array(),
            polarizer: self
                .analyzer
                .unwrap_or_else(|| self.polarization.unwrap_or_default().filter_row())
                .to_array(),
            width: w,
            height: h,
            seed: self.opts.seed,
            max_depth: self.opts.max_depth.max(1),
            rr_depth: self.opts.rr_depth,
            // A shard of a split render draws from its first sample index on (`first` counts
            // the samples accumulated, which weigh the running mean).
            sample_offset: u64::from(self.opts.first_sample).saturating_add(first) as u32,
            batch,
            light_count: self.light_count,
            w_old: (n / (n + k)) as f32,
            w_new: (1.0 / (n + k)) as f32,
            debug_pixel: self.debug_pixel,
            offset_scale: self.bvh.offset_scale,
            tile_y0: 0,
            film_y0: self.film_y0,
            photon_radius0: self.photon_r0,
            photon_norm0: (1.0 / (paths * std::f64::consts::PI)) as f32,
            grid_mask: self.buffers.photon_store.buckets - 1,
            photon_paths: aimed,
            target_count,
            photon_radius_exp: photons::RADIUS_EXPONENT,
            targets,
            path_filter: FilterWords::of(self.opts.filter.as_ref()),
        }
    }

    /// r₁ of `sppm` for the current camera, scene and image size.
    pub(super) fn sppm_radius0(&self) -> f32 {
        photons::radius0(&self.scene.camera, self.scene.bounds(), self.opts.height)
    }

    /// Samples per pixel per dispatch: [`RenderOptions::pass_spp`] until a submission has
    /// been timed, then what [`GpuRenderer::render_with`] last planned.
    ///
    /// [`RenderOptions::pass_spp`]: crate::render::RenderOptions::pass_spp
    pub fn batch_spp(&self) -> u32 {
        self.submissions
            .last_k
            .unwrap_or_else(|| self.opts.pass_spp())
    }

    /// Submissions queued since the renderer was made (every estimator, every band).
    pub fn submissions_made(&self) -> u64 {
        self.submissions.submitted
    }

    /// Bound the wall time of one submission of [`GpuRenderer::render_with`] (default
    /// [`SUBMISSION_BUDGET`]).
    pub fn set_submission_budget(&mut self, budget: Duration) {
        self.submissions.budget = budget;
    }

    /// Queue one dispatch adding `k` samples per pixel to the whole image (does not wait).
    pub fn dispatch(&mut self, k: u32) {
        if k == 0 || self.refuse_tiled() {
            return;
        }
        self.submit(k, 0, self.opts.height);
        self.spp += k as u64;
    }

    /// Queue `k` samples per pixel for the rows `y0 .. y0 + rows` only (does not wait): one
    /// band of a pass the caller completes with [`GpuRenderer::end_pass`] once every row has
    /// its `k` samples (the viewer's bounded frames). Not with light tracing, whose splats need
    /// whole-image passes, nor with sppm, whose iterations are whole-image submissions (the
    /// band is ignored there; [`GpuRenderer::needs_whole_image`]).
    pub fn dispatch_band(&mut self, k: u32, y0: u32, rows: u32) {
        if k > 0 && rows > 0 && y0 < self.opts.height && !self.refuse_tiled() {
            self.submit(k, y0, rows.min(self.opts.height - y0));
        }
    }

    /// Every row of a banded pass now has `k` more samples.
    pub fn end_pass(&mut self, k: u32) {
        self.spp += k as u64;
    }

    /// True when every submission must cover the whole image (light tracing, sppm).
    pub fn needs_whole_image(&self) -> bool {
        self.spec.light_tracing || self.spec.sppm
    }

    /// Queue `k` samples per pixel for image rows `y0 .. y0 + rows` (all rows with light
    /// tracing, whose splats land anywhere, and with sppm, one submission per iteration);
    /// `self.spp` is not advanced.
    /// Returns the last submission's index (None: nothing submitted, the pipelines failed
    /// to compile; the error is recorded for [`GpuContext::check_errors`]).
    ///
    /// [`GpuContext::check_errors`]: crate::gpu::GpuContext::check_errors
    fn submit(&mut self, k: u32, y0: u32, rows: u32) -> Option<wgpu::SubmissionIndex> {
        if self.spec.sppm {
            // Iteration s = sample index s: as many iterations per submission as the photon
            // store holds, their photons first, then their camera paths (one sample each).
            let per = self.buffers.photon_store.iterations.max(1);
            let (mut last, mut done) = (None, 0);
            while done < k {
                let kk = per.min(k - done);
                last = self.submit_pass(self.spp + u64::from(done), kk, 0, self.opts.height);
                done += kk;
            }
            last
        } else if self.spec.wavefront {
            // As many samples per submission as the chunk table holds.
            let pixels = self.opts.width * rows;
            let part =
                wavefront::samples_per_submission(pixels, k, self.buffers.wavefront.max_paths);
            let (mut last, mut done) = (None, 0);
            while done < k {
                let kk = part.min(k - done);
                last = self.submit_pass(self.spp + u64::from(done), kk, y0, rows);
                done += kk;
            }
            last
        } else {
            self.submit_pass(self.spp, k, y0, rows)
        }
    }

    /// The current specialisation's pipelines, waiting for (or doing) their compilation;
    /// false (the error recorded) if it fails.
    fn ensure_pipelines(&mut self) -> bool {
        if self.kernel_spec().is_some() {
            return true;
        }
        match self.pipelines.compile(self.wanted_spec()) {
            Ok(()) => true,
            Err(e) => {
                super::super::context::record(&self.ctx.errors, format!("{e:#}"));
                false
            }
        }
    }

    /// Compile the current specialisation's pipelines (on a worker thread with background
    /// compilation); a failure is recorded for [`GpuContext::check_errors`].
    ///
    /// [`GpuContext::check_errors`]: crate::gpu::GpuContext::check_errors
    pub(super) fn request_pipelines(&mut self) {
        // In use again: least recently used is what the cache drops first. With the general
        // kernel only, the specialised one is never asked for.
        let want = self.wanted_spec();
        self.pipelines.touch(self.spec.general());
        self.pipelines.touch(want);
        let r = if self.background_compile {
            compile_family_in_background(&mut self.pipelines, want)
        } else {
            self.pipelines.compile(want)
        };
        if let Err(e) = r {
            super::super::context::record(&self.ctx.errors, format!("{e:#}"));
        }
    }

    /// One submission: `k` samples per pixel from sample index `first` for rows `y0 ..`.
    pub(super) fn submit_pass(
        &mut self,
        first: u64,
        k: u32,
        y0: u32,
        rows: u32,
    ) -> Option<wgpu::SubmissionIndex> {
        if !self.ensure_pipelines() {
            return None;
        }
        // A tile of a tiled image: the light subpaths of the whole image first, in their own
        // submission (their rows are all the image's, the camera pass's only the tile's).
        let light_apart = self.spec.light_tracing && self.tiled.is_some();
        if light_apart {
            self.submit_light_pass(first, k)?;
        }
        let mut params = self.params(first, k);
        params.tile_y0 = y0;
        self.ctx
            .queue
            .write_buffer(&self.buffers.params, 0, bytemuck::bytes_of(&params));
        let mut enc = self
            .ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
        if std::mem::take(&mut self.clear_pending) {
            self.encode_clear(&mut enc);
        }
        let groups = (self.opts.width.div_ceil(8), rows.div_ceil(8));
        // Light subpaths first: `render` folds their splats into the film; photons first:
        // `render` gathers them (wgpu orders the passes' storage accesses).
        if self.spec.light_tracing && !self.spec.wavefront && !light_apart {
            self.encode_kernel(&mut enc, Kernel::LightTrace, (groups.0, groups.1, 1));
        }
        if self.spec.sppm {
            // The photons of the submission's k iterations (z: the iteration).
            // Every photon path of the iteration, whatever rows the camera pass covers (a
            // tile of a tiled image gathers from all of them).
            let photon_rows = params.photon_paths.div_ceil(self.opts.width.max(1));
            self.buffers.photon_store.encode_clear(&mut enc, k);
            self.encode_kernel(
                &mut enc,
                Kernel::PhotonTrace,
                (groups.0, photon_rows.div_ceil(8), k),
            );
        }
        if self.spec.wavefront {
            let light = self.spec.light_tracing && !light_apart;
            self.encode_wavefront(&mut enc, self.opts.width * rows, k, light);
        } else {
            self.encode_kernel(&mut enc, Kernel::Render, (groups.0, groups.1, 1));
        }
        self.submissions.submitted += 1;
        Some(self.ctx.queue.submit([enc.finish()]))
    }

    /// The light subpaths of `k` samples per pixel from sample index `first` over the whole
    /// image, in submissions of their own (as many as the wavefront's chunk table needs):
    /// a tiled image's tile splats them on its rows before its camera pass takes them.
    fn submit_light_pass(&mut self, first: u64, k: u32) -> Option<wgpu::SubmissionIndex> {
        let (w, h) = (self.opts.width, self.opts.height);
        let part = if self.spec.wavefront {
            wavefront::samples_per_submission(w * h, k, self.buffers.wavefront.max_paths)
        } else {
            k
        };
        let (mut last, mut done) = (None, 0);
        while done < k {
            let kk = part.min(k - done);
            let params = self.params(first + u64::from(done), kk);
            self.ctx
                .queue
                .write_buffer(&self.buffers.params, 0, bytemuck::bytes_of(&params));
            let mut enc = self
                .ctx
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
            if std::mem::take(&mut self.clear_pending) {
                self.encode_clear(&mut enc);
            }
            if self.spec.wavefront {
                self.encode_wavefront_light(&mut enc, w * h, kk);
            } else {
                self.encode_kernel(
                    &mut enc,
                    Kernel::LightTrace,
                    (w.div_ceil(8), h.div_ceil(8), 1),
                );
            }
            self.submissions.submitted += 1;
            last = Some(self.ctx.queue.submit([enc.finish()]));
            done += kk;
        }
        last
    }

    /// Record one compute pass of `kernel` over `groups` workgroups (its pipeline is
    /// compiled: [`GpuRenderer::ensure_pipelines`]; the wavefront's kernels are recorded by
    /// `encode_wavefront`).
    fn encode_kernel(
        &self,
        enc: &mut wgpu::CommandEncoder,
        kernel: Kernel,
        groups: (u32, u32, u32),
    ) {
        let Some(spec) = self.kernel_spec() else {
            return;
        };
        let Some(pipeline) = self.pipelines.get_kernel(spec, kernel) else {
            return;
        };
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(kernel.entry()),
            timestamp_writes: None,
        });
        pass.set_pipeline(pipeline);
        // The chunk table's dynamic offset: only the wavefront's kernels read it.
        pass.set_bind_group(0, &self.bind_group, &[0]);
        pass.dispatch_workgroups(groups.0, groups.1, groups.2);
    }

    /// Add `spp` samples per pixel (in batches) and return the accumulated image. The first
    /// sample index is `opts.first_sample` plus the samples already accumulated.
    pub fn render(&mut self, spp: u32) -> Result<GpuImage> {
        self.render_with(spp, None, |_| {})
    }

    /// Add up to `spp` samples per pixel, stopping early once `budget` is spent (at least one
    /// batch); `progress` gets the spp accumulated after each batch. Up to
    /// [`GpuRenderer::set_batches_in_flight`] submissions are queued at a time: the next is
    /// submitted before waiting for the one running. The submissions, and so the image, are
    /// those of one at a time; only the waiting differs.
    pub fn render_with(
        &mut self,
        spp: u32,
        budget: Option<Duration>,
        mut progress: impl FnMut(u64),
    ) -> Result<GpuImage> {
        if self.tiled.is_some() {
            return self.render_tiled(spp, budget, progress);
        }
        self.pipelines.compile(self.spec)?;
        let start = Instant::now();
        let mut queued = std::collections::VecDeque::new();
        // When the GPU finished the last retired submission (the next one starts then).
        let mut last_done = start;
        let mut done = 0u32;
        while done < spp && !budget.is_some_and(|b| done > 0 && start.elapsed() >= b) {
            let (w, h) = (self.opts.width, self.opts.height);
            let (k, rows) = self
                .submissions
                .plan(w, h, spp - done, self.needs_whole_image());
            for y0 in (0..h).step_by(rows as usize) {
                let band = rows.min(h - y0);
                let submitted = Instant::now();
                let index = self.submit(k, y0, band);
                let last_band = y0 + band >= h;
                let Some(index) = index else {
                    return Err(self
                        .ctx
                        .check_errors()
                        .err()
                        .unwrap_or_else(|| anyhow::anyhow!("the GPU kernels are not compiled")));
                };
                queued.push_back(Queued {
                    index,
                    submitted,
                    samples: u64::from(w) * u64::from(band) * u64::from(k),
                    completes: last_band.then_some(self.spp + u64::from(k)),
                });
                while queued.len() >= self.batches_in_flight {
                    self.retire(&mut queued, &mut last_done, &mut progress)?;
                }
            }
            self.spp += k as u64;
            done += k;
        }
        while !queued.is_empty() {
            self.retire(&mut queued, &mut last_done, &mut progress)?;
        }
        self.elapsed += start.elapsed();
        self.image()
    }

    /// Wait for the oldest queued submission and time it: from its submission, or from when
    /// the one before it finished if that was later (it waited in the queue until then).
    fn retire(
        &mut self,
        queued: &mut std::collections::VecDeque<Queued>,
        last_done: &mut Instant,
        progress: &mut impl FnMut(u64),
    ) -> Result<()> {
        let Some(q) = queued.pop_front() else {
            return Ok(());
        };
        self.ctx.wait_for(q.index)?;
        let now = Instant::now();
        let began = q.submitted.max(*last_done);
        self.submissions
            .observe(now.saturating_duration_since(began), q.samples);
        *last_done = now;
        if let Some(spp) = q.completes {
            progress(spp);
        }
        Ok(())
    }
}

/// Start compiling `spec`'s pipelines on a worker thread now; queue its family's general
/// kernel (which renders while a later edit's specialisation compiles) and the general kernel
/// with the colour representation flipped (what a dispersion toggle asks for next) to compile
/// one at a time after it. Compilations already done or under way are not repeated.
pub(super) fn compile_family_in_background(
    pipelines: &mut crate::gpu::pipeline::Pipelines,
    spec: crate::gpu::pipeline::Specialization,
) -> Result<()> {
    let general = spec.general();
    pipelines.compile_in_background(spec)?;
    pipelines.compile_ahead(general)?;
    pipelines.compile_ahead(crate::gpu::pipeline::Specialization {
        spectral: !general.spectral,
        ..general
    })
}
