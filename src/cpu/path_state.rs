//! The state a random walk carries from vertex to vertex — throughput, spectral collapse,
//! the medium it is in, the η² factor and the depth — and the per-bounce updates every CPU
//! walk shares: Beer–Lambert on each segment, collapse at dispersive vertices, the BSDF
//! weight (with the adjoint shading-normal correction for importance) and Russian roulette.

use super::interaction::{Interaction, SurfaceHit};
use super::medium::{
    Medium, MediumStack, medium_after_transmit, medium_towards, medium_transmittance,
};
use super::spectral::{Spectral, collapse_lanes};
use crate::bsdf::{BsdfSample, Event, TransportMode};
use crate::math::Color;
use crate::scene::Scene;
use glam::Vec3;

pub use crate::scene::nesting::FALSE_HIT_LIMIT;

/// What a surface a path reaches is to it (`PathState::interface`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interface {
    /// A real interface; the medium on its far side (η = n(inside)/n(this)).
    Real(Medium),
    /// A false hit: continue the ray from the far side, no vertex, no bounce.
    Pass,
    /// Too many false hits: the path ends.
    Lost,
}

#[derive(Clone, Copy, Debug)]
pub struct PathState {
    /// Throughput; after a collapse only lane 0 is alive and stands for ¼ of the estimate.
    pub beta: Color,
    /// A dispersive vertex left only the hero wavelength alive.
    pub collapsed: bool,
    /// The media the path is inside (`MediumStack`); the segment travels in its current one.
    pub media: MediumStack,
    /// False hits passed so far (capped at `FALSE_HIT_LIMIT`).
    pub false_hits: u32,
    /// Product of η'² over transmissions (Russian roulette on radiance, not importance).
    pub eta_scale: f32,
    /// Scattering events so far.
    pub depth: u32,
}

impl PathState {
    /// A path leaving the camera or a light (in air); `nested`: the scene's volumes nest.
    pub fn new(beta: Color, collapsed: bool, nested: bool) -> PathState {
        PathState {
            beta,
            collapsed,
            media: MediumStack::new(nested),
            false_hits: 0,
            eta_scale: 1.0,
            depth: 0,
        }
    }

    /// The throughput as an estimate (×4 on the hero lane after a collapse; exact).
    #[inline]
    pub fn weight(&self) -> Color {
        if self.collapsed {
            self.beta * 4.0
        } else {
            self.beta
        }
    }

    /// Beer–Lambert over the segment of length `t` just travelled.
    #[inline]
    pub fn attenuate(&mut self, scene: &Scene, t: f32, sp: &Spectral) {
        if let Some(tr) = medium_transmittance(scene, self.medium(scene), t, sp) {
            self.beta *= tr;
        }
    }

    /// The medium the current segment travels in.
    #[inline]
    pub fn medium(&self, scene: &Scene) -> Medium {
        self.media.current(scene)
    }

    /// What the surface `hit` reached along `d` is to this path: a false hit of a nested
    /// volume (the stack records it; the walk continues the ray without a vertex) or a real
    /// interface with the medium enclosing it on the far side.
    #[inline]
    pub fn interface(&mut self, scene: &Scene, hit: &SurfaceHit, d: Vec3) -> Interface {
        match self.media.crossing_at(scene, hit.material, d, hit.ng) {
            Some(c) if !c.real => {
                self.media = c.after;
                self.false_hits += 1;
                if self.false_hits > FALSE_HIT_LIMIT {
                    Interface::Lost
                } else {
                    Interface::Pass
                }
            }
            Some(c) => Interface::Real(c.enclosing),
            None => Interface::Real(self.media.surrounding(scene)),
        }
    }

    /// Arrival at `it`: a wavelength-dependent BSDF keeps only the hero lane from here on.
    #[inline]
    pub fn arrive(&mut self, it: &Interaction) {
        if it.dispersive && !self.collapsed {
            self.beta = collapse_lanes(self.beta);
            self.collapsed = true;
        }
    }

    /// The medium a segment leaving `it` along `w` travels in.
    #[inline]
    pub fn medium_towards(&self, scene: &Scene, it: &Interaction, w: Vec3) -> Medium {
        medium_towards(scene, &self.media, it.hit.material, (it.ng, it.wo_w), w)
    }

    /// Scatter at `it` with the sample `s` into world direction `wi`.
    #[inline]
    pub fn scatter(
        &mut self,
        scene: &Scene,
        it: &Interaction,
        s: &BsdfSample,
        wi: Vec3,
        mode: TransportMode,
    ) {
        self.scatter_with(scene, it, (s, wi), mode, true);
    }

    /// [`PathState::scatter`], updating the medium stack only when `media` (a walk over a
    /// scene without nested or absorbing volumes keeps none: `cpu::walk_spec`).
    #[inline(always)]
    pub fn scatter_with(
        &mut self,
        scene: &Scene,
        it: &Interaction,
        (s, wi): (&BsdfSample, Vec3),
        mode: TransportMode,
        media: bool,
    ) {
        let mut w = s.weight;
        if mode == TransportMode::Importance {
            w *= shading_correction(it.wo_w, wi, it.ns, it.ng);
        }
        self.beta *= w;
        if s.event == Event::Transmit {
            self.eta_scale *= s.eta_rel * s.eta_rel;
            if media {
                self.media =
                    medium_after_transmit(scene, &self.media, it.hit.material, wi, it.hit.ng);
            }
        }
        self.depth += 1;
    }

    /// Russian roulette from `rr_depth` on (Mitsuba 3 `path`: q = min(max(β)·η², 0.95));
    /// `false` ends the path. `u` is drawn only when the roulette is played.
    #[inline]
    pub fn survives(&mut self, rr_depth: u32, u: impl FnOnce() -> f32) -> bool {
        if self.depth >= rr_depth {
            let q = (self.weight().max_element() * self.eta_scale).min(0.95);
            if q <= 0.0 || u() >= q {
                return false;
            }
            self.beta /= q;
            true
        } else {
            self.beta.max_element() > 0.0
        }
    }
}

/// Adjoint shading-normal correction for importance transport (Veach 1997, eq. 5.19):
/// |ωo·ns||ωi·ng| / (|ωo·ng||ωi·ns|), ωo towards the previous vertex, ωi the new direction.
#[inline]
pub fn shading_correction(wo: Vec3, wi: Vec3, ns: Vec3, ng: Vec3) -> f32 {
    let num = wo.dot(ns).abs() * wi.dot(ng).abs();
    let den = wo.dot(ng).abs() * wi.dot(ns).abs();
    if den <= 0.0 { 0.0 } else { num / den }
}
