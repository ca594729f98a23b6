//! `sppm`: path tracing with the caustics from progressive photon mapping — the estimator
//! for what no connection strategy samples, caustics seen through glass or in a mirror
//! (L S+ D S+ E) and caustics of point lights.
//!
//! Each sample index s of the image is one iteration (Hachisuka & Jensen 2009, "Stochastic
//! Progressive Photon Mapping": a new photon pass and a new camera sample per pixel):
//!
//! 1. `photons_per_iteration` light subpaths are traced; those that pass through specular
//!    vertices only and reach a diffuse surface are stored there (`photon`): the paths
//!    L S^k D, k ≥ 1. Finite lights emit them towards the surfaces that can be specular
//!    only (`render::photon_aim`), where every stored photon must start. All photons of an
//!    iteration share one set of hero wavelengths with the iteration's camera paths (scenes
//!    with dispersion), so their lanes multiply.
//! 2. Every pixel traces one camera path with the path tracer (NEE + MIS); at each diffuse
//!    vertex it adds the photons within radius r_s (`lookup`), and it leaves out the paths
//!    the photons stand for (light reached from that vertex through specular vertices
//!    only: `cpu::gather`). Every other path is the path tracer's, unbiased.
//!
//! The radius shrinks with the iteration as in Knaus & Zwicker 2011 ("Progressive Photon
//! Mapping: A Probabilistic Approach", eq. 15 in closed form): r_s² = r₁² · (s + 1)^(α − 1),
//! α = 2/3, so the average over iterations is consistent — bias and variance both vanish.
//! r₁ is a few pixel footprints at the distance of the scene's centre. Unaimed, an iteration
//! traces one photon path per camera path (as VCM, Georgiev et al. 2012, times
//! `PHOTONS_PER_PIXEL`); aimed, a share of that set by how much of the light reaches the
//! casters (`render::photon_aim::photon_paths`).
//!
//! Images are identical for any thread count: photon paths are traced in fixed chunks whose
//! results are concatenated in order, and each pixel's estimate depends only on its own
//! sampler stream and the iteration's photons.

mod grid;
mod lookup;
mod photon;

use super::Integrator;
use super::camera_ray::camera_ray;
use super::spectral::Spectral;
use crate::film::Film;
use crate::math::rng::Sampler;
pub use crate::render::photon_aim::PhotonTargets;
use crate::render::{photon_aim, photon_radius};
use crate::scene::Camera;
use grid::HashGrid;
use lookup::PhotonLookup;
use photon::{Photon, PhotonLimits, trace_photon};
use rayon::prelude::*;

pub use crate::render::photon_radius::{ALPHA, RADIUS_PIXELS};
/// Photon paths per iteration per pixel.
pub const PHOTONS_PER_PIXEL: u32 = 1;
/// Photon paths per parallel chunk (fixed, for images independent of the thread count).
const CHUNK: u32 = 1024;
pub use crate::render::photon_params::PHOTON_DIMS;

/// The photon-mapping parameters of one render.
#[derive(Clone, Copy, Debug)]
pub struct SppmParams {
    /// r₁, world units.
    pub radius0: f32,
    pub photons_per_iteration: u32,
}

impl SppmParams {
    /// The defaults for an image of `width × height` of a scene with `bounds` seen by
    /// `cam`, whose photons are aimed where `aimed_fraction` of the lights' power goes
    /// (`render::photon_aim`; 1 = unaimed: one photon path per pixel).
    pub fn new(
        cam: &Camera,
        bounds: (glam::Vec3, glam::Vec3),
        (width, height): (u32, u32),
        aimed_fraction: f32,
    ) -> Self {
        SppmParams {
            radius0: photon_radius::radius0(cam, bounds, height),
            photons_per_iteration: photon_aim::photon_paths(
                (width * height).saturating_mul(PHOTONS_PER_PIXEL),
                aimed_fraction,
            ),
        }
    }

    /// The radius of iteration `s` (0-based): r₁ · (s + 1)^((α − 1)/2).
    pub fn radius(&self, s: u32) -> f32 {
        photon_radius::radius(self.radius0, s)
    }
}

/// One iteration's photons and their grid.
struct PhotonPass {
    photons: Vec<Photon>,
    grid: HashGrid,
    norm: f32,
}

/// Trace iteration `s`'s photon paths (in parallel, deterministic order).
fn photon_pass(
    pt: &Integrator,
    params: &SppmParams,
    s: u32,
    seed: u32,
    sp: &Spectral,
    targets: Option<&PhotonTargets>,
) -> PhotonPass {
    let n = params.photons_per_iteration;
    let limits = PhotonLimits {
        max_segments: pt.max_depth,
    };
    let chunks: Vec<Vec<Photon>> = (0..n.div_ceil(CHUNK))
        .into_par_iter()
        .map(|c| {
            let mut out = Vec::new();
            for i in c * CHUNK..((c + 1) * CHUNK).min(n) {
                let mut sampler = Sampler::new(i, s, seed).with_dim(PHOTON_DIMS);
                out.extend(trace_photon(pt, &mut sampler, sp, limits, targets));
            }
            out
        })
        .collect();
    let photons: Vec<Photon> = chunks.concat();
    let r = params.radius(s);
    let grid = HashGrid::build(photons.iter().map(|p| p.p), r);
    let norm = 1.0 / (n as f32 * std::f32::consts::PI * r * r);
    PhotonPass {
        photons,
        grid,
        norm,
    }
}

/// What one iteration renders into.
pub struct Frame<'f> {
    pub film: &'f mut Film,
    pub width: u32,
    pub height: u32,
    pub seed: u32,
}

/// Render iteration (sample index) `s` into `frame.film`'s sums: one photon pass (photons
/// of finite lights aimed at `targets` when given, `render::photon_aim`), then one camera
/// path per pixel. Returns the dropped (non-finite or negative) samples, or None if
/// `cancelled` returned true (the film then holds a partial iteration).
pub fn render_iteration(
    pt: &Integrator,
    (params, targets): (&SppmParams, Option<&PhotonTargets>),
    s: u32,
    frame: Frame,
    cancelled: &(dyn Fn() -> bool + Sync),
) -> Option<u64> {
    let Frame {
        film,
        width: w,
        height: h,
        seed,
    } = frame;
    // One set of hero wavelengths per iteration, shared by its photons and camera paths.
    let sp = pt.lanes(|| Sampler::new(u32::MAX, s, seed).next_1d());
    let pass = photon_pass(pt, params, s, seed, &sp, targets);
    let lookup = PhotonLookup {
        photons: &pass.photons,
        grid: &pass.grid,
        norm: pass.norm,
        max_depth: pt.max_depth,
        filter: pt.filter,
        env_emits: pt.lights.env_pick > 0.0,
    };
    let cam = &crate::scene::camera::CameraRays::new(&pt.scene.camera);
    film.sums_mut()
        .par_chunks_mut(w as usize)
        .enumerate()
        .map(|(y, row)| {
            if cancelled() {
                return None;
            }
            let mut dropped = 0u64;
            for (x, px) in row.iter_mut().enumerate() {
                let pixel = y as u32 * w + x as u32;
                let mut sampler = Sampler::new(pixel, s, seed);
                let dir = camera_ray(cam, (x as u32, y as u32), (w, h), &mut sampler);
                let v = pt.li_walk(cam.position, dir, &mut sampler, sp, &mut (), &lookup);
                let ok = Film::add_sample_to(px, v, pt.spectral);
                dropped += u64::from(!ok);
            }
            Some(dropped)
        })
        .sum()
}

#[cfg(test)]
mod tests;
