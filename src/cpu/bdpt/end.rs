//! One end vertex of a connection, evaluated once per connection: the shading frame and the
//! local directions towards its subpath predecessor and along the connection, shared by the
//! BSDF value and both directional densities the MIS weight needs (Veach 1997 §10.2: f at
//! each end, the density of sampling the connection and the reverse one towards the
//! predecessor given the connection direction).

use super::vertex::Vertex;
use crate::bsdf::{Bsdf, BxDF, TransportMode};
use crate::cpu::path_state::shading_correction;
use crate::math::{Color, Frame};
use crate::paths::Symbol;
use glam::Vec3;

/// Per-class BSDF values of a connection end (Heckbert classes D and G).
pub(super) type Lobes = [(Symbol, Color); 2];

const NO_LOBES: Lobes = [(Symbol::D, Color::ZERO), (Symbol::G, Color::ZERO)];

pub(super) struct End {
    frame: Frame,
    bsdf: Bsdf,
    /// Local direction towards the subpath predecessor (`Vertex::w_prev`).
    wo: Vec3,
    /// Local direction along the connection.
    wi: Vec3,
}

impl End {
    /// Surface vertex `v` connected along `w` (world, unit, away from `v`); `None` without a
    /// non-delta BSDF (every value and density is then 0).
    #[inline]
    pub fn new(v: &Vertex, w: Vec3) -> Option<End> {
        let bsdf = v.bsdf.filter(|b| !b.is_delta())?;
        // A vertex with a BSDF is a surface vertex: its walk stored frame and wo.
        Some(End {
            frame: v.frame,
            bsdf,
            wo: v.wo,
            wi: v.frame.to_local(w),
        })
    }

    /// BSDF value per class for light flowing between the predecessor and the connection
    /// direction `w` (world), with the adjoint shading-normal correction in importance mode
    /// (Veach 1997 eq. 5.19).
    #[inline]
    pub fn lobes(&self, v: &Vertex, w: Vec3, mode: TransportMode) -> Lobes {
        let (so, si) = (v.w_prev.dot(v.ng), w.dot(v.ng));
        if so * si <= 0.0 && !self.bsdf.can_transmit() {
            return NO_LOBES;
        }
        let corr = if mode == TransportMode::Importance {
            shading_correction(v.w_prev, w, v.ns, v.ng)
        } else {
            1.0
        };
        let lv = self.bsdf.eval_lobes(self.wo, self.wi, mode);
        [(Symbol::D, lv.d * corr), (Symbol::G, lv.g * corr)]
    }

    /// Solid-angle density of sampling the connection direction, having arrived from the
    /// predecessor.
    #[inline]
    pub fn pdf_out(&self) -> f32 {
        self.bsdf.pdf(self.wo, self.wi)
    }

    /// Solid-angle density of sampling `w` (world), having arrived along the connection.
    #[inline]
    pub fn pdf_back(&self, w: Vec3) -> f32 {
        self.bsdf.pdf(self.wi, self.frame.to_local(w))
    }
}

/// The BSDF values of an optional end (`None`: all zero).
#[inline]
pub(super) fn lobes_of(end: Option<&End>, v: &Vertex, w: Vec3, mode: TransportMode) -> Lobes {
    end.map_or(NO_LOBES, |e| e.lobes(v, w, mode))
}
