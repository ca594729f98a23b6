//! The media a path is inside, and Beer–Lambert absorption along a segment. Closed solid
//! glass (`MaterialKind::Glass`) is a medium; crossing its surface enters or leaves it.
//!
//! Nested dielectrics (Schmidt & Budge 2002, "Simple nested dielectrics in ray traced
//! images"): a path keeps a small stack of the volumes it is inside, in the order it entered
//! them. The medium is the stack's highest-priority entry (`Material::priority`), the one
//! entered last among equals. Crossing the surface of volume m is a *real* interface when m
//! is (or becomes) that medium: it refracts with η = n(m)/n(enclosing), where the enclosing
//! medium is the stack without m (air, n = 1, when empty). Otherwise it is a *false hit*: the
//! stack records the entry or exit and the ray continues unscattered.
//!
//! Overflow: a push onto a full stack (`MEDIUM_STACK_DEPTH` volumes) forgets the outermost
//! entry, so the innermost volumes stay exact and the path sees air behind them. Leaving a
//! volume that is not on the stack (a camera or light inside glass, or a leak) is a real
//! interface towards the current medium, the stack unchanged.
//!
//! Scenes without nested volumes (`Features::NESTED` unset) keep the one-level rule of
//! before: entering a volume makes it the medium, leaving any volume returns to air.
//! Camera and lights are in air. Twin: `MediumStack` in src/cpu/interaction.wgsl.

use super::spectral::Spectral;
use crate::math::{Color, rgb3};
use crate::scene::{MaterialKind, Scene};
use glam::Vec3;

/// The material index of the solid a segment travels in, or `None` (air).
pub type Medium = Option<u32>;

pub use crate::scene::nesting::MEDIUM_STACK_DEPTH;

/// The volumes a path is inside, oldest first (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MediumStack {
    ids: [u32; MEDIUM_STACK_DEPTH],
    len: u8,
    /// The scene has nested volumes; else the one-level rule (at most one entry).
    nested: bool,
}

/// What crossing a solid's surface does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Crossing {
    /// A real interface (refracts); `false` is a false hit the ray passes unscattered.
    pub real: bool,
    /// The medium on the other side of the volume's surface (η = n(volume)/n(enclosing)).
    pub enclosing: Medium,
    /// The stack after passing through.
    pub after: MediumStack,
}

impl MediumStack {
    /// A path in air; `nested` selects the stack rule (else the one-level rule).
    pub fn new(nested: bool) -> MediumStack {
        MediumStack {
            ids: [0; MEDIUM_STACK_DEPTH],
            len: 0,
            nested,
        }
    }

    /// The medium around a surface that bounds no volume (thin glass refracts against it);
    /// air under the one-level rule, as before nesting.
    #[inline]
    pub fn surrounding(&self, scene: &Scene) -> Medium {
        if self.nested {
            self.current(scene)
        } else {
            None
        }
    }

    /// The volumes on the stack, oldest first.
    pub fn entries(&self) -> &[u32] {
        &self.ids[..self.len as usize]
    }

    /// Index of the medium among `entries`: highest priority, the last among equals
    /// (Schmidt & Budge 2002).
    #[inline]
    fn top_index(&self, scene: &Scene) -> Option<usize> {
        let mut best: Option<(usize, i32)> = None;
        for (i, &m) in self.entries().iter().enumerate() {
            let p = scene.materials[m as usize].priority;
            if best.is_none_or(|(_, bp)| p >= bp) {
                best = Some((i, p));
            }
        }
        best.map(|(i, _)| i)
    }

    /// The medium the path travels in.
    #[inline]
    pub fn current(&self, scene: &Scene) -> Medium {
        match self.len {
            0 => None,
            1 => Some(self.ids[0]),
            _ => self.top_index(scene).map(|i| self.ids[i]),
        }
    }

    /// The stack with `m` entered (overflow forgets the outermost entry).
    #[inline]
    fn pushed(&self, m: u32) -> MediumStack {
        let mut s = *self;
        if !self.nested {
            s.ids[0] = m;
            s.len = 1;
            return s;
        }
        if s.len as usize == MEDIUM_STACK_DEPTH {
            s.ids.copy_within(1.., 0);
            s.len -= 1;
        }
        s.ids[s.len as usize] = m;
        s.len += 1;
        s
    }

    /// The stack without entry `i`.
    #[inline]
    fn removed(&self, i: usize) -> MediumStack {
        let mut s = *self;
        s.ids.copy_within(i + 1.., i);
        s.len -= 1;
        s
    }

    /// Crossing the surface of solid `m`, entering it when `entering`.
    #[inline]
    pub fn crossing(&self, scene: &Scene, m: u32, entering: bool) -> Crossing {
        if !self.nested {
            let after = if entering {
                self.pushed(m)
            } else {
                MediumStack::new(false)
            };
            return Crossing {
                real: true,
                enclosing: None,
                after,
            };
        }
        if entering {
            let enclosing = self.current(scene);
            let p = scene.materials[m as usize].priority;
            let real = enclosing.is_none_or(|e| p >= scene.materials[e as usize].priority);
            return Crossing {
                real,
                enclosing,
                after: self.pushed(m),
            };
        }
        let Some(i) = self.entries().iter().rposition(|&e| e == m) else {
            return Crossing {
                real: true,
                enclosing: self.current(scene),
                after: *self,
            };
        };
        let after = self.removed(i);
        Crossing {
            real: self.top_index(scene) == Some(i),
            enclosing: after.current(scene),
            after,
        }
    }

    /// The crossing of the surface of `material` (raw outward normal `ng_raw`) along `d`;
    /// `None` for surfaces that bound no medium (opaque, thin glass).
    #[inline]
    pub fn crossing_at(
        &self,
        scene: &Scene,
        material: u32,
        d: Vec3,
        ng_raw: Vec3,
    ) -> Option<Crossing> {
        if scene.materials[material as usize].kind != MaterialKind::Glass {
            return None;
        }
        Some(self.crossing(scene, material, d.dot(ng_raw) < 0.0))
    }
}

/// The stack after a transmission through the surface of `material` with raw (outward)
/// geometric normal `ng_raw` into direction `wi`; other surfaces (thin glass) keep it.
#[inline]
pub fn medium_after_transmit(
    scene: &Scene,
    current: &MediumStack,
    material: u32,
    wi: Vec3,
    ng_raw: Vec3,
) -> MediumStack {
    current
        .crossing_at(scene, material, wi, ng_raw)
        .map_or(*current, |c| c.after)
}

/// The medium a segment leaving a surface point along `w` travels in, for a path that
/// arrived from `w_prev` with stack `current`: the same medium on the arrival side of `ng`,
/// the transmitted one (`medium_after_transmit`) across it. One rule for NEE shadow rays and
/// BDPT connections.
#[inline]
pub fn medium_towards(
    scene: &Scene,
    current: &MediumStack,
    material: u32,
    (ng, w_prev): (Vec3, Vec3),
    w: Vec3,
) -> Medium {
    if w.dot(ng) * w_prev.dot(ng) > 0.0 {
        current.current(scene)
    } else {
        medium_after_transmit(scene, current, material, w, ng).current(scene)
    }
}

/// The IOR of `medium` at the path's hero wavelength (air: 1), as `Interaction::new` builds
/// its BSDF; the path inspector reports η_i and η_t through this.
#[inline]
pub fn medium_ior(scene: &Scene, medium: Medium, sp: &Spectral) -> f32 {
    let Some(m) = medium else {
        return 1.0;
    };
    let mm = &scene.materials[m as usize];
    match sp.lambdas {
        Some(l) => mm.ior_at(l[0]),
        None => mm.ior,
    }
}

/// Beer–Lambert transmittance T = exp(−σ_a t) over distance `t` in `medium`, σ_a =
/// −ln(attenuationColor)/attenuationDistance (glTF KHR_materials_volume); `None` when the
/// medium does not absorb (so callers skip the multiply and stay bit-exact).
#[inline]
pub fn medium_transmittance(scene: &Scene, medium: Medium, t: f32, sp: &Spectral) -> Option<Color> {
    let mm = &scene.materials[medium? as usize];
    if !mm.has_absorption() {
        return None;
    }
    let sa = match sp.lambdas {
        Some(_) => {
            let c = sp.c(mm.attenuation_color).max(Color::splat(1e-6));
            -Color::new(c.x.ln(), c.y.ln(), c.z.ln(), c.w.ln()) / mm.attenuation_distance
        }
        None => rgb3(mm.sigma_a()),
    };
    let tr = -sa * t;
    Some(Color::new(tr.x.exp(), tr.y.exp(), tr.z.exp(), tr.w.exp()))
}
