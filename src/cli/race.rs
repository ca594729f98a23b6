//! `render --measure-auto` (with `auto`) on the CPU by measured efficiency (`render::race`),
//! opt-in: measured against the rule on the built-ins it loses more often than it wins
//! (docs/estimators.md, "Choosing by measurement"). Where the
//! scene has glass or mirrors (where the estimators differ), path tracing, sppm and bdpt
//! (the CPU's lt+pt) each render two short trials of a reduced image with other seeds than
//! the render's, and the least relMSE × time renders the image. Scenes without glass or
//! mirrors path-trace by the rule, without trials.

use super::job::Job;
use refract::cpu::Renderer;
use refract::render::race::{Halves, RaceReport, trials};
use refract::render::{Estimator, RenderOptions};
use refract::scene::caustic_casters::CASTERS;
use std::time::{Duration, Instant};

/// The estimators raced on the CPU.
const CANDIDATES: [Estimator; 3] = [Estimator::Path, Estimator::Sppm, Estimator::Bdpt];
/// Pixels of a trial image at most (the aspect kept): the estimators' efficiency per sample
/// does not depend on the size (sppm's radius and photon count follow the pixels), a pass of
/// this many pixels takes a fraction of a second with every estimator.
const TRIAL_PIXELS: f64 = 40.0 * 40.0;
/// Seconds of the first of a candidate's two trials without a time budget; with one, 1/60 of
/// it (the six trials take about a tenth), within [`MIN_TRIAL`, `MAX_TRIAL`].
const TRIAL: Duration = Duration::from_millis(100);
const MIN_TRIAL: Duration = Duration::from_millis(20);
const MAX_TRIAL: Duration = Duration::from_secs(2);
/// Seeds of the trials: far from any render's (`--seed` is small in practice).
const TRIAL_SEED: u32 = 0x7a1a_0000;

/// The estimator for `renderer`'s scene when `job` asks for `auto`: the race's winner and its
/// report (None: no trials, the rule's choice stands). `budget` is the render's time budget.
pub(crate) fn race_cpu(
    renderer: &Renderer,
    job: &Job,
    base: &RenderOptions,
    budget: Option<Duration>,
) -> Option<(RaceReport, (u32, u32))> {
    // Without glass or mirrors, or without a light in the distribution (a uniform
    // environment only), the estimators render the same light paths: the rule's path.
    let differ = renderer.scene.features().intersects(CASTERS) && !renderer.lights.is_empty();
    if !job.measure_auto || !differ {
        return None;
    }
    let trial = budget.map_or(TRIAL, |b| (b / 60).clamp(MIN_TRIAL, MAX_TRIAL));
    let opts = trial_options(base);
    let halves: Vec<Halves> = CANDIDATES
        .iter()
        .map(|&e| {
            run_trial(
                renderer,
                RenderOptions {
                    estimator: e,
                    ..opts
                },
                trial,
            )
        })
        .collect();
    RaceReport::decide(trials(&halves)).map(|r| (r, (opts.width, opts.height)))
}

/// `base` at most [`TRIAL_PIXELS`] pixels (its aspect kept).
fn trial_options(base: &RenderOptions) -> RenderOptions {
    let scale = (TRIAL_PIXELS / base.pixels().max(1) as f64).sqrt().min(1.0);
    let side = |n: u32| ((f64::from(n) * scale).round() as u32).max(1);
    RenderOptions {
        width: side(base.width),
        height: side(base.height),
        ..*base
    }
}

/// Two renders of `opts` with trial seeds, the first for `time`, the second for as many
/// samples, and the seconds one took.
fn run_trial(renderer: &Renderer, opts: RenderOptions, time: Duration) -> Halves {
    let half = |k: u32, spp: u32, budget: Option<Duration>| {
        let o = RenderOptions {
            seed: TRIAL_SEED.wrapping_add(opts.seed.wrapping_mul(2)) + k,
            ..opts
        };
        let t = Instant::now();
        let (film, stats) = renderer.render(&o, spp, budget, |_| {});
        (film.image(), stats.spp, t.elapsed().as_secs_f64())
    };
    let (a, spp, ta) = half(0, u32::MAX, Some(time));
    let (b, _, tb) = half(1, u32::try_from(spp).unwrap_or(u32::MAX), None);
    Halves {
        estimator: opts.estimator,
        a,
        b,
        seconds: 0.5 * (ta + tb),
        spp,
    }
}
