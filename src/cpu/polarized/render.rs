//! Rendering a polarised image: the path tracer's passes over rows with the polarised walk
//! (`polarized::walk`), the intensity behind the camera's filter into the beauty film and
//! the Stokes vector (I, Q, U, V, linear RGB each) into a four-layer `LayerFilm`.

use super::walk::PolarizedSample;
use crate::cpu::Renderer;
use crate::cpu::camera_ray::camera_ray;
use crate::cpu::layers::LayerFilm;
use crate::film::Film;
use crate::math::rng::Sampler;
pub use crate::render::Polarization;
use crate::render::{RenderOptions, RenderStats};
use crate::scene::camera::CameraRays;
use rayon::prelude::*;
use std::time::Duration;

/// The Stokes layers of a polarised render, in this order.
pub const STOKES_LAYERS: usize = 4;

impl Renderer {
    /// Add samples `first .. first + count` of the polarised walk to every pixel: the
    /// filtered intensity to `film`, the Stokes vector to `stokes` (the film's firewall
    /// drops a sample from both). Returns false if cancelled (discard both then).
    pub fn polarized_pass(
        &self,
        opts: &RenderOptions,
        pol: Polarization,
        (film, stokes): (&mut Film, &mut LayerFilm),
        (first, count): (u32, u32),
        cancelled: &(dyn Fn() -> bool + Sync),
    ) -> bool {
        assert_eq!(
            stokes.layers, STOKES_LAYERS,
            "a Stokes film has four layers"
        );
        let integ = self.integrator(opts);
        let (w, h) = (opts.width, opts.height);
        let cam = &CameraRays::new(&self.scene.camera);
        let right = self.scene.camera.rotation.x_axis;
        let row_filter = pol.filter_row();
        let row_pass = |y: usize, row: &mut [[f64; 3]], srow: &mut [[f64; 3]]| -> Option<u64> {
            if cancelled() {
                return None;
            }
            let mut dropped = 0u64;
            for (x, px) in row.iter_mut().enumerate() {
                let pixel = y as u32 * w + x as u32;
                for s in first..first + count {
                    let mut sampler = Sampler::new(pixel, s, opts.seed);
                    let dir = camera_ray(cam, (x as u32, y as u32), (w, h), &mut sampler);
                    let v =
                        integ.li_polarized((cam.position, dir), right, row_filter, &mut sampler);
                    let ok = Film::add_sample_to(px, v.filtered, integ.spectral)
                        && v.stokes.iter().all(|c| c.is_finite());
                    if ok {
                        add_stokes(&mut srow[x * STOKES_LAYERS..(x + 1) * STOKES_LAYERS], &v);
                    } else {
                        dropped += 1;
                    }
                }
            }
            Some(dropped)
        };
        let result: Option<u64> = film
            .sums_mut()
            .par_chunks_mut(w as usize)
            .zip(stokes.sums_mut().par_chunks_mut(w as usize * STOKES_LAYERS))
            .enumerate()
            .map(|(y, (row, srow))| row_pass(y, row, srow))
            .sum();
        match result {
            Some(dropped) => {
                film.spp += count as u64;
                film.dropped += dropped;
                true
            }
            None => false,
        }
    }

    /// Render `spp` polarised samples per pixel (or until `budget` runs out): the beauty
    /// film (behind the filter), the Stokes film and the statistics.
    pub fn render_polarized(
        &self,
        opts: &RenderOptions,
        pol: Polarization,
        (spp, budget): (u32, Option<Duration>),
        progress: impl FnMut(u64),
    ) -> (Film, LayerFilm, RenderStats) {
        let mut film = Film::new(opts.width, opts.height);
        let mut stokes = LayerFilm::new(opts.width, opts.height, STOKES_LAYERS);
        let mut stats = self.render_passes(opts, (spp, budget), progress, |first, n| {
            let films = (&mut film, &mut stokes);
            self.polarized_pass(opts, pol, films, (first, n), &|| false);
        });
        (stats.spp, stats.dropped) = (film.spp, film.dropped);
        (film, stokes, stats)
    }
}

/// Adds a sample's Stokes components to a pixel's four layers.
#[inline]
fn add_stokes(px: &mut [[f64; 3]], v: &PolarizedSample) {
    for (acc, c) in px.iter_mut().zip(v.stokes) {
        for (a, x) in acc.iter_mut().zip(c.to_array()) {
            *a += x as f64;
        }
    }
}
