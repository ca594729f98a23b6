//! `auto` by measured efficiency (issue 35; opt-in, `render --measure-auto`): each candidate
//! estimator renders two independent short trials of the scene (other seeds than the
//! render's), and the one whose error per unit of time is least renders the image. Without a reference, a trial's error is the
//! larger of two estimates:
//!
//! - the difference of its two halves: for independent unbiased estimates a and b of one
//!   pixel, E[(a − b)²] = Var a + Var b, so (a − b)² / 2 estimates each half's squared error;
//! - its distance from the consensus, the per-pixel median of the candidates' images: a
//!   heavy-tailed estimator (path tracing of a caustic under a small light) has not sampled
//!   its rare large contributions in a short trial, so its halves agree — both without the
//!   caustic — while the estimators that do sample it put the median there.
//!
//! With the error falling as 1/time (Monte Carlo variance), error × seconds is an efficiency
//! that does not depend on how long the trial ran (Veach 1997, §2.4.1: efficiency =
//! 1 / (variance × time)). sppm is consistent, not unbiased: its halves see its variance
//! only, the consensus some of the blur of its radius, which shrinks as the render goes on.
//!
//! The choice is a fixed estimator afterwards: `--estimator X` with the same seed renders the
//! same image; the line [`RaceReport::line`] says which one and the figures behind it.

use super::Estimator;
use glam::Vec3;

/// The measured cost of one candidate: the estimated relMSE of one half and its seconds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Trial {
    pub estimator: Estimator,
    /// relMSE of one half against the (unknown) truth, estimated from the two halves.
    pub rel_mse: f64,
    /// Seconds one half took (the mean of the two).
    pub seconds: f64,
    /// Samples per pixel of one half.
    pub spp: u64,
}

impl Trial {
    /// relMSE × seconds: the relMSE the estimator would reach in one second (lower is better).
    pub fn cost(&self) -> f64 {
        self.rel_mse * self.seconds
    }
}

/// relMSE (as `bench::rel_mse`: per channel (x − ref)² / (ref² + 10⁻²)) of one of two
/// independent renders `a` and `b` against the truth, estimated from their difference with
/// their mean standing in for the reference.
pub fn half_rel_mse(a: &[Vec3], b: &[Vec3]) -> f64 {
    let mut s = 0.0f64;
    for (x, y) in a.iter().zip(b) {
        for k in 0..3 {
            let (x, y) = (f64::from(x[k]), f64::from(y[k]));
            let m = 0.5 * (x + y);
            s += 0.5 * (x - y) * (x - y) / (m * m + 1e-2);
        }
    }
    s / (3 * a.len().max(1)) as f64
}

/// Per pixel and channel, the median of `images` (all of one size; 1 to 3 of them, the mean
/// of the middle two for an even count).
pub fn median_image(images: &[&[Vec3]]) -> Vec<Vec3> {
    let n = images.first().map_or(0, |i| i.len());
    (0..n)
        .map(|p| {
            Vec3::from_array(std::array::from_fn(|k| {
                let mut v: Vec<f32> = images.iter().map(|i| i[p][k]).collect();
                v.sort_by(f32::total_cmp);
                let m = v.len() / 2;
                if v.len() % 2 == 1 {
                    v[m]
                } else {
                    0.5 * (v[m - 1] + v[m])
                }
            }))
        })
        .collect()
}

/// relMSE of `x` against `reference` (per channel (x − ref)² / (ref² + 10⁻²), as
/// `bench::rel_mse`).
pub fn rel_mse(x: &[Vec3], reference: &[Vec3]) -> f64 {
    let mut s = 0.0f64;
    for (a, r) in x.iter().zip(reference) {
        for k in 0..3 {
            let (a, r) = (f64::from(a[k]), f64::from(r[k]));
            s += (a - r) * (a - r) / (r * r + 1e-2);
        }
    }
    s / (3 * x.len().max(1)) as f64
}

/// A candidate's two trial halves and the seconds and samples per pixel of one.
pub struct Halves {
    pub estimator: Estimator,
    pub a: Vec<Vec3>,
    pub b: Vec<Vec3>,
    pub seconds: f64,
    pub spp: u64,
}

/// The trials of `halves`: each one's error is the larger of its halves' difference and its
/// mean's distance from the median of the candidates' means (module docs).
pub fn trials(halves: &[Halves]) -> Vec<Trial> {
    let means: Vec<Vec<Vec3>> = halves
        .iter()
        .map(|h| h.a.iter().zip(&h.b).map(|(a, b)| 0.5 * (*a + *b)).collect())
        .collect();
    let refs: Vec<&[Vec3]> = means.iter().map(Vec::as_slice).collect();
    let consensus = median_image(&refs);
    halves
        .iter()
        .zip(&means)
        .map(|(h, m)| Trial {
            estimator: h.estimator,
            rel_mse: half_rel_mse(&h.a, &h.b).max(rel_mse(m, &consensus)),
            seconds: h.seconds,
            spp: h.spp,
        })
        .collect()
}

/// The outcome of a race: the trials and the winner.
#[derive(Clone, Debug, PartialEq)]
pub struct RaceReport {
    pub trials: Vec<Trial>,
    pub winner: Estimator,
}

impl RaceReport {
    /// The race over `trials` (at least one): the least [`Trial::cost`] wins; a trial whose
    /// cost is not a finite number (no samples, NaN) never does.
    pub fn decide(trials: Vec<Trial>) -> Option<RaceReport> {
        let winner = trials
            .iter()
            .filter(|t| t.cost().is_finite() && t.spp > 0)
            .min_by(|a, b| a.cost().total_cmp(&b.cost()))?
            .estimator;
        Some(RaceReport { trials, winner })
    }

    /// One line for the log: each candidate's relMSE·s, the winner, and how to repeat it.
    pub fn line(&self, trial_size: (u32, u32)) -> String {
        let figures: Vec<String> = self
            .trials
            .iter()
            .map(|t| {
                format!(
                    "{} {:.2e} ({} spp in {:.2} s)",
                    t.estimator, t.rel_mse, t.spp, t.seconds
                )
            })
            .collect();
        format!(
            "estimator auto: {} by measurement (estimated relMSE of a trial at {}x{}: {}; \
             least relMSE × time wins; --estimator {} repeats it)",
            self.winner,
            trial_size.0,
            trial_size.1,
            figures.join(", "),
            self.winner
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two halves 2d apart around a mean of 1: each has variance (2d)² / 2 = 2d², relMSE
    /// 2d² / (1 + 10⁻²); equal halves none.
    #[test]
    fn halves_estimate_their_error() {
        let d = 0.1f32;
        let a = vec![Vec3::splat(1.0 + d); 10];
        let b = vec![Vec3::splat(1.0 - d); 10];
        let e = half_rel_mse(&a, &b);
        let want = 0.5 * (2.0 * f64::from(d)).powi(2) / 1.01;
        assert!((e - want).abs() < 1e-6 * want, "{e} vs {want}");
        assert_eq!(half_rel_mse(&a, &a), 0.0);
    }

    /// The consensus outvotes a candidate whose halves agree on a wrong image: two halves
    /// without the caustic (0) against two estimators with it (1 ± noise).
    #[test]
    fn the_consensus_catches_agreeing_halves() {
        let h = |estimator, a: f32, b: f32| Halves {
            estimator,
            a: vec![Vec3::splat(a); 4],
            b: vec![Vec3::splat(b); 4],
            seconds: 1.0,
            spp: 4,
        };
        let t = trials(&[
            h(Estimator::Path, 0.0, 0.0),
            h(Estimator::Sppm, 1.05, 0.95),
            h(Estimator::Bdpt, 1.1, 0.9),
        ]);
        assert!(half_rel_mse(&[Vec3::ZERO], &[Vec3::ZERO]) == 0.0);
        assert!(t[0].rel_mse > 0.9, "{t:?}");
        assert!(t[1].rel_mse < 0.01 && t[2].rel_mse < 0.03, "{t:?}");
        let r = RaceReport::decide(t).expect("a winner");
        assert_eq!(r.winner, Estimator::Sppm);
    }

    /// Half the error in twice the time ties; the cheaper one wins; NaN never wins.
    #[test]
    fn least_error_per_time_wins() {
        let t = |estimator, rel_mse, seconds| Trial {
            estimator,
            rel_mse,
            seconds,
            spp: 4,
        };
        let r = RaceReport::decide(vec![
            t(Estimator::Path, 4e-3, 0.5),
            t(Estimator::Sppm, 1e-3, 1.0),
            t(Estimator::Bdpt, f64::NAN, 0.1),
        ])
        .expect("a winner");
        assert_eq!(r.winner, Estimator::Sppm);
        assert!(r.line((64, 48)).contains("--estimator sppm repeats it"));
        assert!(RaceReport::decide(vec![t(Estimator::Path, f64::NAN, 1.0)]).is_none());
    }
}
