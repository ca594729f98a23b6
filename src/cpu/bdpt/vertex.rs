//! Subpath vertices of the bidirectional estimators and the density conversions between
//! them (Veach 1997, ch. 10; PBR 3rd ed. §16.3 `Vertex`).

use crate::bsdf::Bsdf;
use crate::cpu::interaction::Interaction;
use crate::cpu::medium::Medium;
use crate::cpu::path_state::PathState;
use crate::math::{Color, Frame};
use crate::paths::Symbol;
use crate::scene::Scene;
use crate::scene::light::Light;
use glam::Vec3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Kind<'a> {
    Camera,
    /// Light subpath origin: the light (in the scene's `LightSet`) and its selection
    /// probability. A reference keeps the vertex small: MIS copies vertices often.
    Light {
        light: &'a Light,
        pick: f32,
    },
    Surface,
}

/// One vertex of a camera or light subpath.
#[derive(Clone, Copy, Debug)]
pub(super) struct Vertex<'a> {
    pub kind: Kind<'a>,
    pub p: Vec3,
    /// Geometric and shading normal, oriented to the side the subpath arrived from for opaque
    /// double-sided materials (outward for dielectrics); zero for camera/point lights; the
    /// emission direction for infinite lights.
    pub ng: Vec3,
    pub ns: Vec3,
    pub bsdf: Option<Bsdf>,
    /// Throughput up to and including this vertex (RGB in lanes xyz).
    pub beta: Color,
    /// Area density of generating this vertex from its predecessor on its own subpath.
    pub pdf_fwd: f32,
    /// Area density of generating it from the other direction (filled in by the walk).
    pub pdf_rev: f32,
    /// The BSDF sample taken at this vertex was a delta lobe (cannot be connected).
    pub delta: bool,
    /// Heckbert class of the scattering event sampled at this vertex.
    pub class: Symbol,
    /// Direction towards the predecessor on its subpath (world).
    pub w_prev: Vec3,
    /// Surface vertices: the shading frame (`Frame::from_normal(ns)`) and `w_prev` in it, as
    /// the walk's interaction computed them, so that connections do not rebuild them per
    /// strategy (`End::new`); `Frame::WORLD` and zero elsewhere.
    pub frame: Frame,
    pub wo: Vec3,
    /// Scene triangle of a surface vertex.
    pub tri: u32,
    /// Spectral mode: a dispersive event on this subpath (up to here) left only the hero
    /// wavelength alive (lanes 1–3 are zero; the ×4 is applied once per full path).
    pub collapsed: bool,
    /// The medium the segment arriving here travelled in.
    pub medium: Medium,
    /// The medium a segment leaving across the surface travels in (`medium_towards`;
    /// kept instead of the medium stack so that vertices stay small).
    pub medium_across: Medium,
    /// Partial sum of the MIS ratio recurrence along the subpath up to this vertex, with the
    /// densities the walk stored (`mis::prefix_sums`; Veach 1997 §10.2).
    pub mis_sum: f32,
    /// Heckbert filter (`filter::prefix_states`): on a light subpath the DFA state after L and
    /// the classes up to this vertex; on a camera subpath the bit set of states from which the
    /// classes from this vertex back to the camera, then E, are accepted.
    pub filter: u32,
}

impl<'a> Vertex<'a> {
    /// A vertex with everything but its kind, position and throughput zeroed.
    pub fn new(kind: Kind<'a>, p: Vec3, beta: Color, pdf_fwd: f32, class: Symbol) -> Vertex<'a> {
        Vertex {
            kind,
            p,
            ng: Vec3::ZERO,
            ns: Vec3::ZERO,
            bsdf: None,
            beta,
            pdf_fwd,
            pdf_rev: 0.0,
            delta: false,
            class,
            w_prev: Vec3::ZERO,
            frame: Frame::WORLD,
            wo: Vec3::ZERO,
            tri: 0,
            collapsed: false,
            medium: None,
            medium_across: None,
            mis_sum: 0.0,
            filter: 0,
        }
    }

    /// The vertex of a walk arriving at `it` with state `st`; `media`: the walk keeps a
    /// medium stack (else both media are air).
    #[inline]
    pub fn surface(scene: &Scene, it: &Interaction, st: &PathState, media: bool) -> Vertex<'a> {
        let (medium, medium_across) = if media {
            (st.medium(scene), st.medium_towards(scene, it, -it.wo_w))
        } else {
            (None, None)
        };
        Vertex {
            ng: it.ng,
            ns: it.ns,
            bsdf: Some(it.bsdf),
            w_prev: it.wo_w,
            frame: it.frame,
            wo: it.wo,
            tri: it.hit.tri,
            collapsed: st.collapsed,
            medium,
            medium_across,
            ..Vertex::new(Kind::Surface, it.hit.p, st.beta, 0.0, Symbol::D)
        }
    }

    /// The light of a light-subpath origin.
    pub fn light(&self) -> Option<(&'a Light, f32)> {
        match self.kind {
            Kind::Light { light, pick } => Some((light, pick)),
            _ => None,
        }
    }

    /// A light-subpath origin at a delta position (point, spot).
    pub fn is_delta_light(&self) -> bool {
        self.light().is_some_and(|(l, _)| l.is_delta_position())
    }

    /// A light-subpath origin at infinity (reached along −`ng`).
    pub fn is_infinite_light(&self) -> bool {
        self.light().is_some_and(|(l, _)| l.is_infinite())
    }

    /// Has a surface (area measure, cosine factors).
    pub fn on_surface(&self) -> bool {
        match self.kind {
            Kind::Surface => true,
            Kind::Light { light, .. } => !light.is_delta_position() && !light.is_infinite(),
            Kind::Camera => false,
        }
    }

    pub fn connectible(&self) -> bool {
        match self.kind {
            Kind::Surface => !self.delta && self.bsdf.is_some_and(|b| !b.is_delta()),
            _ => true,
        }
    }

    /// The medium a segment leaving this vertex along `w` travels in.
    pub fn medium_towards(&self, w: Vec3) -> Medium {
        if self.kind != Kind::Surface || w.dot(self.ng) * self.w_prev.dot(self.ng) > 0.0 {
            self.medium
        } else {
            self.medium_across
        }
    }
}

/// Area density from a solid-angle density at `from` towards `to` (Veach 1997, eq. 8.10).
#[inline]
pub(super) fn to_area(pdf_w: f32, from: &Vertex, to: &Vertex) -> f32 {
    let d = to.p - from.p;
    let d2 = d.length_squared();
    if d2 <= 0.0 {
        return 0.0;
    }
    let mut pdf = pdf_w / d2;
    if to.on_surface() {
        pdf *= (to.ng.dot(d) / d2.sqrt()).abs();
    }
    pdf
}

/// Ratio helper: delta densities are stored as 0 and count as 1 (Veach 1997, §10.3.5).
#[inline]
pub(super) fn remap0(x: f32) -> f32 {
    if x != 0.0 { x } else { 1.0 }
}
