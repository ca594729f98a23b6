//! Rendering a whole image on the CPU: rayon over rows, counter-based RNG per
//! (pixel, sample, dimension, seed) so images are identical across thread counts.

use super::Integrator;
use crate::bvh::Bvh;
use crate::film::Film;
use crate::math::rng::Sampler;
use crate::scene::{Scene, light::LightSet};
use rayon::prelude::*;
use std::time::{Duration, Instant};

/// Light-transport estimator.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Estimator {
    /// Unidirectional path tracing with NEE + MIS.
    #[default]
    Path,
    /// Bidirectional path tracing, MIS over all strategies (incl. light-tracing splats).
    Bdpt,
    /// Pure light tracing (light subpaths connected to the camera only).
    Lt,
    /// Path tracing and light tracing combined by MIS: the GPU estimator for caustics
    /// (src/shaders/light_tracing.wgsl). The CPU renders it with full BDPT, whose strategies
    /// are a superset.
    #[serde(rename = "lt+pt", alias = "ltpt")]
    LtPt,
}

impl std::fmt::Display for Estimator {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Estimator::Path => "path",
            Estimator::Bdpt => "bdpt",
            Estimator::Lt => "lt",
            Estimator::LtPt => "lt+pt",
        })
    }
}

impl std::str::FromStr for Estimator {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.to_ascii_lowercase().as_str() {
            "path" | "pt" => Ok(Estimator::Path),
            "bdpt" => Ok(Estimator::Bdpt),
            "lt" | "light" => Ok(Estimator::Lt),
            "lt+pt" | "ltpt" | "pt+lt" => Ok(Estimator::LtPt),
            _ => Err(format!(
                "unknown estimator '{s}' (use path, bdpt, lt or lt+pt)"
            )),
        }
    }
}

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
    /// The same filter in light→eye order (bidirectional estimators).
    pub filter_forward: Option<crate::paths::DfaTable>,
    pub estimator: Estimator,
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
            filter_forward: None,
            estimator: Estimator::Path,
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
    /// The scene has a dispersive material: paths carry hero wavelengths.
    pub spectral: bool,
}

impl Renderer {
    /// Validate the scene and build the acceleration structures.
    pub fn new(scene: Scene) -> anyhow::Result<Renderer> {
        scene.validate()?;
        let bvh = Bvh::build(&scene.mesh);
        let lights = LightSet::build(&scene);
        let spectral = scene.features().dispersion;
        Ok(Renderer {
            scene,
            bvh,
            lights,
            spectral,
        })
    }

    pub fn integrator<'a>(&'a self, opts: &'a RenderOptions) -> Integrator<'a> {
        Integrator {
            scene: &self.scene,
            bvh: &self.bvh,
            lights: &self.lights,
            max_depth: opts.max_depth.max(1),
            rr_depth: opts.rr_depth,
            filter: opts.filter.as_ref(),
            spectral: self.spectral,
        }
    }

    /// Set both directions of a Heckbert filter (None or an accept-all filter = no filter).
    pub fn set_filter(opts: &mut RenderOptions, f: Option<&crate::paths::PathFilter>) {
        match f {
            Some(f) if !f.is_accept_all() => {
                opts.filter = Some(*f.reversed());
                opts.filter_forward = Some(*f.forward());
            }
            _ => {
                opts.filter = None;
                opts.filter_forward = None;
            }
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
        if opts.estimator != Estimator::Path {
            // Bidirectional passes are not cancellable mid-pass (splats span all rows).
            self.render_pass_bdpt(opts, film, first_spp, count);
            return true;
        }
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
                        let ok = if integ.spectral {
                            Film::add_signed_to(px, v)
                        } else {
                            Film::add_to(px, v)
                        };
                        if !ok {
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

    /// Bidirectional / light-tracing pass: camera contributions per pixel, light-tracing
    /// splats into a shared buffer of atomically added f64 values, then folded into the film.
    fn render_pass_bdpt(&self, opts: &RenderOptions, film: &mut Film, first_spp: u32, count: u32) {
        use super::bdpt::{Bdpt, BdptMode};
        use std::sync::atomic::{AtomicU64, Ordering};
        let integ = self.integrator(opts);
        let mode = if opts.estimator == Estimator::Lt {
            BdptMode::LightTracing
        } else {
            BdptMode::Full
        };
        let (w, h) = (opts.width, opts.height);
        let bd = Bdpt::new(&integ, mode, opts.filter_forward.as_ref(), w, h);
        let splats: Vec<AtomicU64> = (0..(w as usize * h as usize * 3))
            .map(|_| AtomicU64::new(0f64.to_bits()))
            .collect();
        let add = |i: usize, v: f64| {
            let a = &splats[i];
            let mut cur = a.load(Ordering::Relaxed);
            loop {
                let new = (f64::from_bits(cur) + v).to_bits();
                match a.compare_exchange_weak(cur, new, Ordering::Relaxed, Ordering::Relaxed) {
                    Ok(_) => break,
                    Err(x) => cur = x,
                }
            }
        };
        let seed = opts.seed;
        let dropped: u64 = film
            .sums_mut()
            .par_chunks_mut(w as usize)
            .enumerate()
            .map(|(y, row)| {
                let mut dropped = 0u64;
                for (x, px) in row.iter_mut().enumerate() {
                    let pixel = y as u32 * w + x as u32;
                    for s in first_spp..first_spp + count {
                        let mut sampler = Sampler::new(pixel, s, seed);
                        let mut bad_splat = false;
                        let v = bd.sample(x as u32, y as u32, &mut sampler, &mut |sx, sy, v| {
                            let ok = if integ.spectral {
                                v.is_finite()
                            } else {
                                crate::film::sample_is_valid(v)
                            };
                            if ok {
                                let i = 3 * (sy as usize * w as usize + sx as usize);
                                add(i, v.x as f64);
                                add(i + 1, v.y as f64);
                                add(i + 2, v.z as f64);
                            } else {
                                bad_splat = true;
                            }
                        });
                        let ok = if integ.spectral {
                            Film::add_signed_to(px, v)
                        } else {
                            Film::add_to(px, v)
                        };
                        if !ok || bad_splat {
                            dropped += 1;
                        }
                    }
                }
                dropped
            })
            .sum();
        for (i, px) in film.sums_mut().iter_mut().enumerate() {
            for k in 0..3 {
                px[k] += f64::from_bits(splats[3 * i + k].load(Ordering::Relaxed));
            }
        }
        let _ = h;
        film.spp += count as u64;
        film.dropped += dropped;
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
