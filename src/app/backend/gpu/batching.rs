//! Sizing and queueing the next batch: samples per pixel from the measured time per pixel
//! sample, bands of rows where one pass would overrun the frame budget.

use super::completion::Batch;
use super::poller::Poller;
use super::{GpuBackend, MAX_BATCH_SPP};
use crate::gpu::GpuRenderer;
use std::sync::atomic::Ordering;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// Pixels of the first, untimed band of a viewer pass.
const PROBE_PIXELS: u32 = 1 << 14;

impl GpuBackend {
    /// Queue the next batch (a whole image, or the next band of a pass); false when there is
    /// nothing to render (paused, the spp target reached, no renderer).
    pub(super) fn queue_batch(&mut self, frame_budget: Duration) -> bool {
        let (generation, budget, per) = (self.generation, frame_budget, self.sec_per_sample);
        let Some(r) = self.renderer.as_mut() else {
            return false;
        };
        let queued = r.spp();
        if self.paused || (self.spp_target > 0 && queued >= self.spp_target) {
            return false;
        }
        let band_time = band_time(self.poller.thread.is_none(), r, budget);
        let band_rows = band_rows(r, per, band_time);
        if self.pass.is_some() || band_rows.is_some() {
            let (batch, before) = queue_band(r, &self.poller, &mut self.pass, band_rows);
            self.track(batch, generation, before);
            return true;
        }
        let o = r.options();
        let pixels = o.width as u64 * o.height as u64;
        let k = whole_image_spp(per, queued, budget, pixels, self.spp_target);
        // Mark busy before the callback can possibly run.
        self.poller.kick();
        let before = Instant::now();
        r.dispatch(k);
        self.track((k, pixels, k), generation, before);
        true
    }

    /// Follow the submission just made: (samples per pixel, pixels covered, samples per pixel
    /// it completes), submitted at `before`.
    fn track(&mut self, (k, pixels, completes): (u32, u64, u32), generation: u64, before: Instant) {
        let done = Arc::new(Mutex::new(None));
        {
            let done = Arc::clone(&done);
            let busy = Arc::clone(&self.poller.busy);
            let repaint = self.repaint.clone();
            self.ctx.queue.on_submitted_work_done(move || {
                *done.lock().unwrap_or_else(|e| e.into_inner()) = Some(Instant::now());
                busy.fetch_sub(1, Ordering::AcqRel);
                if let Some(c) = repaint {
                    c.request_repaint();
                }
            });
        }
        self.in_flight.push_back(Batch {
            k,
            pixels,
            completes,
            generation,
            // Without a poller thread (GL) the driver may run the batch inside the submission.
            submitted: match self.poller.thread {
                Some(_) => Instant::now(),
                None => before,
            },
            done,
        });
    }
}

/// The longest a band of rows may take, or None to render whole images: with synchronous
/// submissions (GL: the batch runs inside `submit`, which froze the UI for 0.7 s on
/// llvmpipe) the frame budget; on a hardware GPU (watchdogs) at least `SUBMISSION_BUDGET`.
/// A software Vulkan device runs asynchronously and has no watchdog: whole images.
fn band_time(synchronous: bool, r: &GpuRenderer, budget: Duration) -> Option<Duration> {
    if synchronous {
        Some(budget)
    } else if r.is_software() {
        None
    } else {
        Some(budget.max(crate::gpu::SUBMISSION_BUDGET))
    }
}

/// Rows per band (a multiple of 8, at least 8) where one sample of the whole image would take
/// longer than `band_time` at `per` seconds per pixel sample; None for whole images. Untimed,
/// a first band of ~2¹⁴ pixels measures the device.
fn band_rows(r: &GpuRenderer, per: Option<f64>, band_time: Option<Duration>) -> Option<u32> {
    let o = r.options();
    let (w, h) = (o.width, o.height);
    match (per, band_time) {
        _ if r.needs_whole_image() => None,
        (_, None) => None,
        (Some(s), Some(t)) => {
            let rows = (t.as_secs_f64() / (s * w.max(1) as f64)) as u32 / 8 * 8;
            (rows < h).then_some(rows.max(8))
        }
        (None, Some(_)) => {
            let rows = (PROBE_PIXELS / w.max(1)) / 8 * 8;
            (rows < h).then_some(rows.max(8))
        }
    }
}

/// Dispatch the next band of the pass in `pass` (or of a new one-sample pass) of at most
/// `band_rows` rows, ending the pass at the last row; returns the batch for
/// [`GpuBackend::track`] and when it was submitted.
fn queue_band(
    r: &mut GpuRenderer,
    poller: &Poller,
    pass: &mut Option<(u32, u32)>,
    band_rows: Option<u32>,
) -> ((u32, u64, u32), Instant) {
    let o = r.options();
    let (w, h) = (o.width, o.height);
    let (k, y0) = pass.unwrap_or((1, 0));
    let rows = band_rows.unwrap_or(h).min(h - y0);
    let last = y0 + rows >= h;
    poller.kick();
    let before = Instant::now();
    r.dispatch_band(k, y0, rows);
    if last {
        r.end_pass(k);
    }
    *pass = (!last).then_some((k, y0 + rows));
    (
        (k, w as u64 * rows as u64, if last { k } else { 0 }),
        before,
    )
}

/// Samples per pixel of the next whole-image batch: one for the first batch of a
/// generation (to show the edit at once) or when untimed, else what fits `budget` at `per`
/// seconds per pixel sample, at most `MAX_BATCH_SPP` and what `spp_target` still needs.
fn whole_image_spp(
    per: Option<f64>,
    queued: u64,
    budget: Duration,
    pixels: u64,
    spp_target: u64,
) -> u32 {
    let mut k = match per {
        // The first batch of a generation: one sample, to show the edit at once.
        _ if queued == 0 => 1,
        Some(s) => {
            let fit = budget.as_secs_f64() / (s * pixels.max(1) as f64);
            fit.clamp(1.0, MAX_BATCH_SPP as f64) as u32
        }
        None => 1,
    };
    if spp_target > 0 {
        k = k.min((spp_target - queued).min(MAX_BATCH_SPP as u64) as u32);
    }
    k.max(1)
}
