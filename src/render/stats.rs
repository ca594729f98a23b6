//! Counters of one render (CPU or GPU).

use std::time::Duration;

/// Counters since the start of a render (or the last reset of a progressive one).
#[derive(Clone, Copy, Debug, Default)]
pub struct RenderStats {
    /// Samples per pixel accumulated.
    pub spp: u64,
    /// Samples dropped by the NaN/Inf/negative firewall.
    pub dropped: u64,
    /// Render time of the accumulated samples.
    pub elapsed: Duration,
    /// Pixels of the image.
    pub pixels: u64,
    /// Closest-hit rays traced (path segments, shadow rays not included); None where the
    /// renderer does not count them (the CPU renderer).
    pub segments: Option<u64>,
}

impl RenderStats {
    /// Pixel samples per second.
    pub fn samples_per_sec(&self) -> f64 {
        (self.spp * self.pixels) as f64 / self.elapsed.as_secs_f64().max(1e-9)
    }

    /// Path segments per second (0 where segments are not counted).
    pub fn segments_per_sec(&self) -> f64 {
        self.segments.unwrap_or(0) as f64 / self.elapsed.as_secs_f64().max(1e-9)
    }
}
