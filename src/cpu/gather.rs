//! A density-estimation hook into the path tracer's camera walk: at a diffuse vertex a
//! photon estimator (`cpu::sppm`) may supply the radiance of the caustic paths L S+ D that
//! end there. The walk then leaves exactly those paths out of its own estimate (an emitter,
//! or an environment that emits photons, reached from that vertex through specular vertices
//! only), so both estimators together count every path once (Jensen 1996, "Global
//! Illumination using Photon Maps": the caustic photon map beside a path tracer).
//!
//! The renderer walks with `()`, which gathers nothing; its calls are inlined away.

use super::interaction::Interaction;
use super::path_state::PathState;
use super::spectral::Spectral;
use crate::math::Color;

/// Supplies caustic radiance at the camera walk's diffuse vertices.
pub trait Gather {
    /// The gatherer reads `PathState::media` or `Interaction::hit.uv` (see
    /// `PathObserver::READS_STATE`); true unless it says otherwise.
    const READS_STATE: bool = true;

    /// Radiance towards `it.wo` of the caustic paths L S^k D (k ≥ 1) ending at `it`, for
    /// a camera path in reversed-DFA state `q` (eye→light order, before `it`'s own D) with
    /// state `st`, not yet multiplied by the path throughput; `None` when this vertex is not
    /// a gather vertex (the walk then counts every path through it itself).
    #[inline(always)]
    fn gather(&self, _it: &Interaction, _st: &PathState, _q: u32, _sp: &Spectral) -> Option<Color> {
        None
    }

    /// Does the environment emit photons (so that an escaping ray after a gather vertex and
    /// specular vertices only is the gatherer's, not the walk's)?
    #[inline(always)]
    fn environment_emits(&self) -> bool {
        false
    }
}

/// The path tracer's own walk: no gather vertices.
impl Gather for () {
    const READS_STATE: bool = false;
}
