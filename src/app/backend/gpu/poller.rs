//! [`Poller`]: completion polling for the batches in flight (see the module above).

use eframe::wgpu;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Duration;

/// Polls the device (never waits on it) while a batch is in flight. A blocking
/// `PollType::Wait` would hold the device's fence lock and stall the UI thread's submissions.
pub(super) struct Poller {
    /// Batches in flight (their callbacks decrement it).
    pub(super) busy: Arc<AtomicUsize>,
    quit: Arc<AtomicBool>,
    pub(super) thread: Option<std::thread::JoinHandle<()>>,
}

impl Poller {
    /// A poller with a helper thread, or (`threaded` false, for GL) without one.
    pub(super) fn new(device: wgpu::Device, threaded: bool) -> Poller {
        let busy = Arc::new(AtomicUsize::new(0));
        let quit = Arc::new(AtomicBool::new(false));
        let (b, q) = (Arc::clone(&busy), Arc::clone(&quit));
        if !threaded {
            return Poller {
                busy,
                quit,
                thread: None,
            };
        }
        let thread = std::thread::Builder::new()
            .name("refract-gpu-poll".into())
            .spawn(move || {
                while !q.load(Ordering::Acquire) {
                    if b.load(Ordering::Acquire) > 0 {
                        let _ = device.poll(wgpu::PollType::Poll);
                        std::thread::sleep(Duration::from_micros(500));
                    } else {
                        std::thread::park_timeout(Duration::from_millis(100));
                    }
                }
            })
            .ok();
        Poller { busy, quit, thread }
    }

    /// A batch was queued: poll until its callback decrements `busy`.
    pub(super) fn kick(&self) {
        self.busy.fetch_add(1, Ordering::AcqRel);
        if let Some(t) = &self.thread {
            t.thread().unpark();
        }
    }
}

impl Drop for Poller {
    fn drop(&mut self) {
        self.quit.store(true, Ordering::Release);
        if let Some(t) = self.thread.take() {
            t.thread().unpark();
            let _ = t.join();
        }
    }
}
