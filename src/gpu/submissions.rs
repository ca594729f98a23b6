//! Bounded GPU submissions: the batch size (samples per pixel) and the band of image rows
//! of each submission follow from the measured time per path sample, so that no submission
//! runs longer than a budget — 50 ms by default, far below the watchdogs that reset a GPU
//! whose work runs too long (Windows TDR: 2 s; Linux and macOS drivers similar). A fixed
//! 2²⁰ samples per dispatch took seconds at 1080p with 64 bounces on an integrated GPU.

use std::time::Duration;

/// Default wall-time bound of one submission.
pub const SUBMISSION_BUDGET: Duration = Duration::from_millis(50);

/// Most samples per pixel one submission adds (each thread loops over them).
pub const MAX_SPP_PER_SUBMISSION: u32 = 16;

/// Pixel samples of the first, untimed submission (about 1 ms on a desktop GPU, ~0.1 s on
/// lavapipe): small enough for any device, large enough to time.
const PROBE_SAMPLES: u64 = 1 << 16;

/// The planner's state: the measured seconds per pixel sample (exponential average).
#[derive(Clone, Debug)]
pub struct Submissions {
    pub budget: Duration,
    seconds_per_sample: Option<f64>,
    /// The samples per pixel of the last plan (for reports).
    pub last_k: Option<u32>,
    /// Submissions queued so far (for reports and tests: how many the samples took).
    pub submitted: u64,
}

impl Default for Submissions {
    fn default() -> Self {
        Submissions {
            budget: SUBMISSION_BUDGET,
            seconds_per_sample: None,
            last_k: None,
            submitted: 0,
        }
    }
}

impl Submissions {
    /// (samples per pixel, rows per submission) for a `w`×`h` image with `spp_left` samples
    /// to go. Rows are whole workgroups (multiples of 8) unless the image is shorter; with
    /// `whole_image` (light tracing splats anywhere) every submission covers all rows.
    pub fn plan(&mut self, w: u32, h: u32, spp_left: u32, whole_image: bool) -> (u32, u32) {
        let pixels = u64::from(w) * u64::from(h);
        let allowed = match self.seconds_per_sample {
            Some(s) if s > 0.0 => (self.budget.as_secs_f64() / s).max(1.0) as u64,
            Some(_) => u64::MAX,
            None => PROBE_SAMPLES,
        };
        let k_max = spp_left.clamp(1, MAX_SPP_PER_SUBMISSION);
        if whole_image || allowed >= pixels {
            let k = (allowed / pixels.max(1)).clamp(1, u64::from(k_max)) as u32;
            self.last_k = Some(k);
            return (k, h);
        }
        let rows = (allowed / u64::from(w.max(1))) as u32 / 8 * 8;
        self.last_k = Some(1);
        (1, rows.clamp(8, h.max(8)).min(h.max(1)))
    }

    /// Record that a submission of `samples` pixel samples took `took`.
    pub fn observe(&mut self, took: Duration, samples: u64) {
        if samples == 0 {
            return;
        }
        let s = took.as_secs_f64() / samples as f64;
        self.seconds_per_sample = Some(match self.seconds_per_sample {
            // Weighted towards the latest: the cost per sample changes with the view.
            Some(old) => 0.5 * old + 0.5 * s,
            None => s,
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plans_fit_the_budget() {
        let mut s = Submissions::default();
        // Untimed: a probe of about 2^16 samples, in whole workgroup rows.
        assert_eq!(s.plan(1920, 1080, 100, false), (1, 32));
        // 1 µs per sample: 50 ms = 50,000 samples = 26 rows of 1920 → 24.
        s.observe(Duration::from_micros(1), 1);
        assert_eq!(s.plan(1920, 1080, 100, false), (1, 24));
        // 1 ns per sample: 5e7 samples = 24 spp of 1080p, capped at 16 and at what is left.
        let mut f = Submissions::default();
        f.observe(Duration::from_nanos(1), 1);
        assert_eq!(f.plan(1920, 1080, 100, false), (16, 1080));
        assert_eq!(f.plan(1920, 1080, 3, false), (3, 1080));
        // Light tracing: always the whole image, at least one sample.
        assert_eq!(s.plan(1920, 1080, 100, true), (1, 1080));
        // A tiny image never gets zero rows.
        assert_eq!(s.plan(4, 3, 10, false).1, 3);
    }
}
