//! A hook into the path tracer's camera walk: every call the walk makes to it reports what
//! the shared per-vertex step (`Interaction`, `PathState`) just did. The renderer walks with
//! `()`, whose methods are empty and inlined away (the walk is generic over the observer, so
//! the normal render compiles to the same code as without the hook); the path inspector
//! (`cpu::inspect`) records every vertex through it.

use super::interaction::{Interaction, SurfaceHit};
use super::path_state::PathState;
use super::spectral::Spectral;
use crate::bsdf::BsdfSample;
use crate::math::Color;
use crate::scene::Scene;
use crate::scene::light::LiSample;
use glam::Vec3;

/// Why a camera walk ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PathEnd {
    /// The ray left the scene (the environment, if any, was added).
    Escaped,
    /// The path reached `max_depth` vertices.
    MaxDepth,
    /// An emitter that does not scatter, or a one-sided back face.
    Terminated,
    /// The BSDF sample failed or was inconsistent with the geometric normal.
    Absorbed,
    /// The BSDF returned a non-finite weight (the sample is poisoned and dropped by the film).
    Poisoned,
    /// The Heckbert path filter can no longer accept anything this path reaches.
    Filtered,
    /// Russian roulette ended it.
    Roulette,
}

impl PathEnd {
    /// The name the JSON uses (`escaped`, `max_depth`, …).
    pub fn as_str(self) -> &'static str {
        match self {
            PathEnd::Escaped => "escaped",
            PathEnd::MaxDepth => "max_depth",
            PathEnd::Terminated => "terminated",
            PathEnd::Absorbed => "absorbed",
            PathEnd::Poisoned => "poisoned",
            PathEnd::Filtered => "filtered",
            PathEnd::Roulette => "roulette",
        }
    }
}

/// Receives the camera walk's events in order: `start`, then per surface `surface`,
/// `emitted`?, `connection`?, `bounce`, `throughput`, and finally `escaped`? and `end`.
/// Contributions are in the path's colour lanes and already include the path throughput
/// (and MIS weights): summed, they are the sample's estimate.
pub trait PathObserver {
    /// The observer reads walk state the renderer itself does not need in every scene (the
    /// medium stack `PathState::media`, `SurfaceHit::uv`): a walk specialised on a scene
    /// without media or textures keeps them exact only when this is true (the default).
    const READS_STATE: bool = true;
    /// A camera ray from `origin` along `dir`, carrying the lanes `sp`.
    #[inline(always)]
    fn start(&mut self, _origin: Vec3, _dir: Vec3, _sp: &Spectral) {}
    /// The walk reached `hit` (Beer–Lambert along the segment already applied to `st`).
    #[inline(always)]
    fn surface(&mut self, _scene: &Scene, _hit: &SurfaceHit, _st: &PathState) {}
    /// Emission picked up at the current hit (MIS-weighted, times the throughput).
    #[inline(always)]
    fn emitted(&mut self, _contribution: Color) {}
    /// A next-event connection from `it` to the light sample `ls`: its contribution (times
    /// the throughput; zero when `occluded` or when the BSDF does not pass light that way).
    #[inline(always)]
    fn connection(
        &mut self,
        _it: &Interaction,
        _ls: &LiSample,
        _contribution: Color,
        _occluded: bool,
    ) {
    }
    /// The BSDF sample `s` at `it` leaving along world `wi`, seen before `st` scatters (so
    /// `st.medium` is the medium the path arrived in).
    #[inline(always)]
    fn bounce(
        &mut self,
        _scene: &Scene,
        _it: &Interaction,
        _st: &PathState,
        _s: &BsdfSample,
        _wi: Vec3,
    ) {
    }
    /// The throughput carried by the segment leaving the current vertex (after its BSDF
    /// weight and Russian roulette).
    #[inline(always)]
    fn throughput(&mut self, _weight: Color) {}
    /// The ray along `dir` escaped; `contribution` is the environment's (times throughput).
    #[inline(always)]
    fn escaped(&mut self, _dir: Vec3, _contribution: Color) {}
    /// The walk is over.
    #[inline(always)]
    fn end(&mut self, _why: PathEnd) {}
}

/// The renderer's observer: sees nothing, costs nothing.
impl PathObserver for () {
    const READS_STATE: bool = false;
}
