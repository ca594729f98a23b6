//! Work coming back from the GPU without waiting: finished batches (their timing sizes the
//! next ones) and the asynchronous readback of the dropped-sample counter.

use super::GpuBackend;
use eframe::wgpu;
use std::sync::atomic::{AtomicU8, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Instant;

/// One queued dispatch.
pub(super) struct Batch {
    /// Samples per pixel of its pass.
    pub(super) k: u32,
    /// Pixels it covers (the whole image, or a band of rows).
    pub(super) pixels: u64,
    /// Samples per pixel it completes for the whole image when it finishes: `k` for a
    /// whole-image batch or a pass's last band, 0 for an earlier band.
    pub(super) completes: u32,
    pub(super) generation: u64,
    pub(super) submitted: Instant,
    /// Set by the `on_submitted_work_done` callback: when the GPU finished.
    pub(super) done: Arc<Mutex<Option<Instant>>>,
}

/// Asynchronous readback of the 16-byte stats header (dropped-sample counter).
pub(super) struct StatsReadback {
    pub(super) staging: wgpu::Buffer,
    /// Generation of the copy in flight; None = the staging buffer is free.
    pub(super) pending: Option<u64>,
    /// Set by the `map_async` callback: [`MAP_PENDING`], [`MAP_OK`] or [`MAP_FAILED`].
    pub(super) state: Arc<AtomicU8>,
}

pub(super) const MAP_PENDING: u8 = 0;
pub(super) const MAP_OK: u8 = 1;
pub(super) const MAP_FAILED: u8 = 2;

impl GpuBackend {
    /// Collect a finished batch and the stats readback (never waits).
    pub(super) fn collect(&mut self) {
        let _ = self.ctx.device.poll(wgpu::PollType::Poll);
        // A GPU error no scope caught (a failed submission, a lost device): the CPU takes over.
        if let Err(e) = self.ctx.check_errors() {
            self.enter_fallback(&e);
            return;
        }
        // Batches finish in submission order.
        while let Some(t) = self
            .in_flight
            .front()
            .and_then(|b| *b.done.lock().unwrap_or_else(|e| e.into_inner()))
            && let Some(b) = self.in_flight.pop_front()
        {
            // A batch queued behind another started when that one finished.
            let began = self.last_done.map_or(b.submitted, |d| d.max(b.submitted));
            self.last_done = Some(t);
            let dt = t.saturating_duration_since(began);
            let per = dt.as_secs_f64() / (b.k as f64 * b.pixels as f64).max(1.0);
            self.sec_per_sample = Some(match self.sec_per_sample {
                Some(s) => 0.5 * s + 0.5 * per,
                None => per,
            });
            if b.generation == self.generation {
                self.done_spp += b.completes as u64;
                self.elapsed += dt;
            }
        }
        // Without a poller thread nobody wakes the UI when the batch finishes: keep stepping.
        if !self.in_flight.is_empty()
            && self.poller.thread.is_none()
            && let Some(c) = &self.repaint
        {
            c.request_repaint();
        }
        let Some(generation) = self.readback.pending else {
            return;
        };
        match self.readback.state.load(Ordering::Acquire) {
            MAP_OK => {
                let slice = self.readback.staging.slice(..);
                if let Ok(view) = slice.get_mapped_range() {
                    let s: crate::gpu::layout::Stats = bytemuck::pod_read_unaligned(&view[..16]);
                    if generation == self.generation {
                        self.dropped = s.dropped_lo as u64 | (s.dropped_hi as u64) << 32;
                    }
                }
                self.readback.staging.unmap();
            }
            MAP_FAILED => {}
            _ => return, // still pending
        }
        self.readback.state.store(MAP_PENDING, Ordering::Release);
        self.readback.pending = None;
    }

    /// Queue the stats header copy after a batch (if the staging buffer is free).
    pub(super) fn start_readback(&mut self) {
        let Some(r) = self.renderer.as_ref() else {
            return;
        };
        if self.readback.pending.is_some() || r.spp() == 0 {
            return;
        }
        let mut enc = self
            .ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
        enc.copy_buffer_to_buffer(r.stats_buffer(), 0, &self.readback.staging, 0, 16);
        self.ctx.queue.submit([enc.finish()]);
        let state = Arc::clone(&self.readback.state);
        self.readback
            .staging
            .slice(..)
            .map_async(wgpu::MapMode::Read, move |res| {
                let s = if res.is_ok() { MAP_OK } else { MAP_FAILED };
                state.store(s, Ordering::Release);
            });
        self.readback.pending = Some(self.generation);
    }
}
