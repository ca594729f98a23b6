//! Caustic photons: light subpaths that pass through specular vertices only (mirror, smooth
//! and thin glass) and are stored where they first reach a diffuse surface (the paths
//! L S^k D, k ≥ 1). A photon that meets any other surface first, or none, is dropped: the
//! path tracer samples those paths itself (Jensen 1996, the caustic photon map).
//!
//! The walk is the light subpath of light tracing on the shared per-vertex step (importance
//! transport with the adjoint BSDF, Beer–Lambert, nested media, hero wavelengths).

use crate::bsdf::{Bsdf, TransportMode};
use crate::cpu::Integrator;
use crate::cpu::interaction::{Bounce, Interaction, offset_ray_origin_towards};
use crate::cpu::path_state::{Interface, PathState};
use crate::cpu::spectral::Spectral;
use crate::math::{Color, rng::Sampler};
use crate::render::photon_aim::PhotonTargets;
use glam::Vec3;

/// One stored photon.
#[derive(Clone, Copy, Debug)]
pub struct Photon {
    pub p: Vec3,
    /// Direction back towards where the photon came from (world, unit).
    pub wi: Vec3,
    /// Geometric normal of the surface it landed on, on the side it arrived from.
    pub ng: Vec3,
    /// Light-subpath throughput on arrival (Le·cosθ / (p_pos·p_dir) times the specular
    /// weights; lanes as the path's `Spectral`), not yet divided by the photon count.
    pub beta: Color,
    /// Specular vertices between the light and here (k of L S^k D).
    pub specular: u32,
    /// A dispersive vertex left only the hero wavelength alive.
    pub collapsed: bool,
}

/// Where a photon walk may end: the most segments a full path may have (`max_depth`).
#[derive(Clone, Copy)]
pub struct PhotonLimits {
    pub max_segments: u32,
}

/// Trace one photon path with `sampler`; returns the photon it stores, if any. With
/// `targets`, a finite light emits towards them only (`render::photon_aim`); lights at
/// infinity, and every light without `targets`, emit as `Light::sample_le` does.
pub fn trace_photon(
    pt: &Integrator,
    sampler: &mut Sampler,
    sp: &Spectral,
    limits: PhotonLimits,
    targets: Option<&PhotonTargets>,
) -> Option<Photon> {
    let (light, pick) = pt.lights.pick(sampler.next_1d())?;
    let (u_pos, u_dir, u_side) = (sampler.next_2d(), sampler.next_2d(), sampler.next_1d());
    let mut le = light.sample_le(u_pos, u_dir, u_side, pick)?;
    if let Some(t) = targets.filter(|_| !le.infinite) {
        // The point as sampled, the direction towards a target.
        let (w, pdf_w) = t.sample_dir(le.p, sampler.next_1d(), u_dir)?;
        le.dir = w;
        le.pdf_dir = pdf_w;
        le.l = light.le(le.p, le.n, w);
    }
    if le.pdf_dir <= 0.0 || le.pdf_pos <= 0.0 || le.l.max_element() <= 0.0 {
        return None;
    }
    let offset = pt.bvh.offset_scale();
    let (o, cos) = if le.delta_pos || le.infinite {
        (le.p, 1.0)
    } else {
        let side = le.dir.dot(le.n);
        (
            offset_ray_origin_towards(le.p, le.n, side, offset),
            side.abs(),
        )
    };
    // β₁ = Le cosθ / (p_pos p_dir) (Veach 1997 §10.2; PBR 3rd ed. eq. 16.15).
    let beta = sp.c(le.l) * (cos / (le.pdf_pos * le.pdf_dir));
    let st = PathState::new(beta, false, pt.nested);
    walk(pt, (o, le.dir), st, sampler, sp, limits)
}

/// Follow the photon through specular vertices to its first other surface.
fn walk(
    pt: &Integrator,
    (mut o, mut d): (Vec3, Vec3),
    mut st: PathState,
    sampler: &mut Sampler,
    sp: &Spectral,
    limits: PhotonLimits,
) -> Option<Photon> {
    let scene = pt.scene;
    let mut specular = 0u32;
    loop {
        let h = pt.bvh.intersect(o, d, f32::INFINITY)?;
        let hit = pt.surface(&h);
        st.attenuate(scene, hit.t, sp);
        let enclosing = match st.interface(scene, &hit, d) {
            Interface::Real(m) => m,
            Interface::Pass => {
                o = pt.pass_through(&hit, d);
                continue;
            }
            Interface::Lost => return None,
        };
        let it = Interaction::new(scene, &hit, d, sp, pt.bvh.offset_scale(), enclosing)?;
        st.arrive(&it);
        if matches!(it.bsdf, Bsdf::Lambert(_)) {
            // L S^k D: k + 1 segments from the light; the eye side adds at least one.
            let stored = specular >= 1 && specular + 2 <= limits.max_segments;
            return stored.then(|| Photon {
                p: hit.p,
                wi: -d,
                ng: it.ng,
                beta: st.beta,
                specular,
                collapsed: st.collapsed,
            });
        }
        if !it.bsdf.is_delta() || specular + 3 > limits.max_segments {
            return None;
        }
        let (s, wi) = match it.sample(
            sampler.next_1d(),
            sampler.next_2d(),
            TransportMode::Importance,
        ) {
            Bounce::Continue { s, wi } => (s, wi),
            Bounce::Absorbed | Bounce::Poisoned => return None,
        };
        st.scatter(scene, &it, &s, wi, TransportMode::Importance);
        if st.beta.max_element() <= 0.0 || !st.beta.is_finite() {
            return None;
        }
        specular += 1;
        o = it.spawn(wi);
        d = wi;
    }
}
