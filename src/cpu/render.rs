//! Rendering a whole image on the CPU: rayon over rows, counter-based RNG per
//! (pixel, sample, dimension, seed) so images are identical across thread counts.

use super::Integrator;
use crate::bvh::Bvh;
use crate::film::Film;
use crate::math::rng::Sampler;
use crate::scene::{Scene, light::LightSet};
use rayon::prelude::*;
use std::time::{Duration, Instant};

/// Per-render options (overrides of the scene's settings are applied by the caller).
#[derive(Clone, Copy, Debug)]
pub struct RenderOptions {
    pub width: u32,
    pub height: u32,
    pub max_depth: u32,
    pub rr_depth: u32,
    pub seed: u32,
    /// Heckbert path filter (eye→light table); None = all paths.
    pub filter: Option<crate::paths::DfaTable>,
}

impl RenderOptions {
    pub fn from_scene(scene: &Scene) -> RenderOptions {
        let s = scene.settings;
        RenderOptions {
            width: s.width,
            height: s.height,
            max_depth: s.max_depth,
            rr_depth: s.rr_depth,
            seed: 0,
            filter: None,
        }
    }
}

/// Counters of one render.
#[derive(Clone, Copy, Debug, Default)]
pub struct RenderStats {
    pub spp: u64,
    pub elapsed: Duration,
    pub dropped: u64,
}

impl RenderStats {
    /// Pixel samples per second.
    pub fn samples_per_sec(&self, pixels: u64) -> f64 {
        (self.spp * pixels) as f64 / self.elapsed.as_secs_f64().max(1e-9)
    }
}

/// A scene prepared for CPU rendering (BVH and light distribution built once).
pub struct Renderer {
    pub scene: Scene,
    pub bvh: Bvh,
    pub lights: LightSet,
}

impl Renderer {
    /// Validate the scene and build the acceleration structures.
    pub fn new(scene: Scene) -> anyhow::Result<Renderer> {
        scene.validate()?;
        let bvh = Bvh::build(&scene.mesh);
        let lights = LightSet::build(&scene);
        Ok(Renderer { scene, bvh, lights })
    }

    pub fn integrator<'a>(&'a self, opts: &'a RenderOptions) -> Integrator<'a> {
        Integrator {
            scene: &self.scene,
            bvh: &self.bvh,
            lights: &self.lights,
            max_depth: opts.max_depth.max(1),
            rr_depth: opts.rr_depth,
            filter: opts.filter.as_ref(),
        }
    }

    /// Add samples `first_spp .. first_spp + count` to every pixel of `film`.
    pub fn render_pass(&self, opts: &RenderOptions, film: &mut Film, first_spp: u32, count: u32) {
        self.render_pass_cancellable(opts, film, first_spp, count, &|| false);
    }

    /// [`Renderer::render_pass`] that polls `cancelled` once per row and stops early when it
    /// returns true (the interactive viewer calls it so an edit never waits for a whole pass).
    /// Returns false if the pass was cancelled: `film` then holds a partial pass and must be
    /// discarded (its `spp` and `dropped` counters are left unchanged).
    pub fn render_pass_cancellable(
        &self,
        opts: &RenderOptions,
        film: &mut Film,
        first_spp: u32,
        count: u32,
        cancelled: &(dyn Fn() -> bool + Sync),
    ) -> bool {
        let integ = self.integrator(opts);
        let (w, h) = (opts.width, opts.height);
        let aspect = w as f32 / h as f32;
        let cam = &self.scene.camera;
        let seed = opts.seed;
        let result: Option<u64> = film
            .sums_mut()
            .par_chunks_mut(w as usize)
            .enumerate()
            .map(|(y, row)| {
                if cancelled() {
                    return None;
                }
                let mut dropped = 0u64;
                for (x, px) in row.iter_mut().enumerate() {
                    let pixel = y as u32 * w + x as u32;
                    for s in first_spp..first_spp + count {
                        let mut sampler = Sampler::new(pixel, s, seed);
                        let j = sampler.next_2d();
                        let sx = (x as f32 + j.x) / w as f32;
                        let sy = (y as f32 + j.y) / h as f32;
                        let dir = cam.ray_dir(sx, sy, aspect);
                        let v = integ.li(cam.position, dir, &mut sampler);
                        if !Film::add_to(px, v) {
                            dropped += 1;
                        }
                    }
                }
                Some(dropped)
            })
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

    /// Render `spp` samples per pixel (or until `budget` runs out, whichever first; at least
    /// one pass). `progress` is called after each pass with the samples done so far.
    pub fn render(
        &self,
        opts: &RenderOptions,
        spp: u32,
        budget: Option<Duration>,
        mut progress: impl FnMut(u64),
    ) -> (Film, RenderStats) {
        let mut film = Film::new(opts.width, opts.height);
        let start = Instant::now();
        // Passes of a few spp keep the progress bar and time budget responsive.
        let pixels = (opts.width as u64 * opts.height as u64).max(1);
        let pass = ((1u64 << 20) / pixels).clamp(1, 16) as u32;
        let mut done = 0u32;
        while done < spp {
            let n = pass.min(spp - done);
            self.render_pass(opts, &mut film, done, n);
            done += n;
            progress(done as u64);
            if let Some(b) = budget
                && start.elapsed() >= b
            {
                break;
            }
        }
        let stats = RenderStats {
            spp: film.spp,
            elapsed: start.elapsed(),
            dropped: film.dropped,
        };
        (film, stats)
    }
}
