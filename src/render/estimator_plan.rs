//! The one estimator decision: from what the user asked (`--estimator`, the viewer's
//! choice, a sidecar), the scene and the renderer that will run it, the estimator that runs
//! and why. The CLI, the viewer and both renderers consume this, so `auto` is resolved and
//! the GPU's limits are applied in one place, the same for all of them.
//!
//! What the GPU cannot run exactly: `bdpt` and `lt` exist on the CPU only. The GPU runs
//! light + path tracing with MIS (`lt+pt`) for them: an unbiased estimator of the same
//! image whose strategies are a subset of BDPT's, and light tracing's own strategy among
//! them. The plan says so (`EstimatorPlan::note`), and a caller free to pick the device
//! (`render --device auto`) renders such a choice on the CPU instead (`exact`).

use super::Estimator;
use crate::scene::Scene;

/// The renderer a plan is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Runner {
    Cpu,
    Gpu,
}

/// What runs for a choice of estimator on one renderer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EstimatorPlan {
    /// The choice as made (possibly `Auto`).
    pub asked: Estimator,
    /// The estimator the renderer runs: never `Auto`; on the GPU one of `Path`, `LtPt` and
    /// `Sppm`.
    pub runs: Estimator,
    /// For `auto`, the rule's reason; for a substitution, what runs instead and why; else
    /// empty.
    pub why: &'static str,
    /// `runs` is what was asked (or what `auto` means): no substitution.
    pub exact: bool,
}

impl EstimatorPlan {
    /// Decide once: `asked` for `scene` on `runner` (`Estimator::resolve_why` for `auto`,
    /// then the GPU's substitution).
    pub fn decide(asked: Estimator, scene: &Scene, runner: Runner) -> EstimatorPlan {
        let (resolved, why) = asked.resolve_why(scene);
        match (runner, resolved) {
            (Runner::Gpu, Estimator::Bdpt | Estimator::Lt) => EstimatorPlan {
                asked,
                runs: Estimator::LtPt,
                why: "bdpt and lt run on the CPU only; the GPU runs light + path tracing with \
                      MIS (lt+pt), an unbiased estimator of the same image",
                exact: false,
            },
            _ => EstimatorPlan {
                asked,
                runs: resolved,
                why,
                exact: true,
            },
        }
    }

    /// The log line for this decision: `estimator auto: sppm (why)` when `auto` chose, `note:
    /// …` when the renderer substitutes; None when the choice runs as given.
    pub fn note(&self) -> Option<String> {
        if !self.exact {
            Some(format!(
                "note: estimator {} on the GPU: {}",
                self.asked, self.why
            ))
        } else if self.asked == Estimator::Auto {
            Some(format!("estimator auto: {} ({})", self.runs, self.why))
        } else {
            None
        }
    }

    /// The kernels trace light subpaths (lt+pt).
    pub fn light_tracing(&self) -> bool {
        self.runs == Estimator::LtPt
    }

    /// The kernels photon-map caustics (sppm).
    pub fn sppm(&self) -> bool {
        self.runs == Estimator::Sppm
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_choice_has_one_plan_per_renderer() {
        let caustic = Scene::load("builtin:caustic").unwrap();
        for asked in [
            Estimator::Auto,
            Estimator::Path,
            Estimator::Bdpt,
            Estimator::Lt,
            Estimator::LtPt,
            Estimator::Sppm,
        ] {
            let cpu = EstimatorPlan::decide(asked, &caustic, Runner::Cpu);
            let gpu = EstimatorPlan::decide(asked, &caustic, Runner::Gpu);
            assert!(cpu.exact, "the CPU runs every estimator: {cpu:?}");
            assert_ne!(cpu.runs, Estimator::Auto);
            assert!(
                matches!(
                    gpu.runs,
                    Estimator::Path | Estimator::LtPt | Estimator::Sppm
                ),
                "{gpu:?}"
            );
            assert_eq!(gpu.exact, cpu.runs == gpu.runs, "{cpu:?} {gpu:?}");
            // auto resolves the same on both: the rule does not depend on the renderer.
            if asked == Estimator::Auto {
                assert_eq!(cpu.runs, gpu.runs);
                assert!(cpu.note().unwrap().starts_with("estimator auto: sppm ("));
            }
        }
        let bdpt = EstimatorPlan::decide(Estimator::Bdpt, &caustic, Runner::Gpu);
        assert_eq!((bdpt.runs, bdpt.exact), (Estimator::LtPt, false));
        assert!(bdpt.note().unwrap().contains("lt+pt"));
        assert!(bdpt.light_tracing() && !bdpt.sppm());
        let path = EstimatorPlan::decide(Estimator::Path, &caustic, Runner::Gpu);
        assert_eq!(path.note(), None);
    }
}
