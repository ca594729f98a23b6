//! The medium a path segment travels in, and Beer–Lambert absorption along it. Closed solid
//! glass (`MaterialKind::Glass`) is a medium; crossing its surface enters or leaves it. One
//! level: leaving returns to the outside (nested media come with the nested-dielectrics
//! work). Twin of `medium_transmittance` in the WGSL walks.

use super::spectral::Spectral;
use crate::math::{Color, rgb3};
use crate::scene::{MaterialKind, Scene};
use glam::Vec3;

/// The material index of the solid the path is inside, or `None` (outside everything).
pub type Medium = Option<u32>;

/// The medium after a transmission through the surface of material `material` with raw
/// (outward) geometric normal `ng_raw` into direction `wi`: entering a closed solid when `wi`
/// points against the outward normal, leaving it otherwise; other surfaces (thin glass) keep
/// the current medium.
#[inline]
pub fn medium_after_transmit(
    scene: &Scene,
    current: Medium,
    material: u32,
    wi: Vec3,
    ng_raw: Vec3,
) -> Medium {
    if scene.materials[material as usize].kind != MaterialKind::Glass {
        return current;
    }
    if wi.dot(ng_raw) < 0.0 {
        Some(material)
    } else {
        None
    }
}

/// The medium a segment leaving a surface point along `w` travels in, for a path that
/// arrived from `w_prev` in `current`: the same medium on the arrival side of `ng`, the
/// transmitted one (`medium_after_transmit`) across it. One rule for NEE shadow rays and
/// BDPT connections.
#[inline]
pub fn medium_towards(
    scene: &Scene,
    current: Medium,
    material: u32,
    (ng, w_prev): (Vec3, Vec3),
    w: Vec3,
) -> Medium {
    if w.dot(ng) * w_prev.dot(ng) > 0.0 {
        current
    } else {
        medium_after_transmit(scene, current, material, w, ng)
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

/// The refractive index of `medium` for the path's lanes `sp` (1 outside everything; at the
/// hero wavelength for a dispersive glass in a spectral path, as `Interaction::new` builds
/// its BSDF). The path inspector reports η_i and η_t through this.
#[inline]
pub fn medium_ior(scene: &Scene, medium: Medium, sp: &Spectral) -> f32 {
    let Some(m) = medium else {
        return 1.0;
    };
    let mat = &scene.materials[m as usize];
    match sp.lambdas {
        Some(l) if mat.abbe.is_some() => mat.ior_at(l[0]),
        _ => mat.ior,
    }
}
