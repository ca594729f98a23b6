//! Rendering a whole image on the CPU: rayon over rows, counter-based RNG per
//! (pixel, sample, dimension, seed) so images are identical across thread counts.

use super::Integrator;
use crate::bvh::Bvh;
use crate::film::Film;
use crate::math::rng::Sampler;
use crate::render::{Estimator, RenderOptions, RenderStats};
use crate::scene::{Camera, Features, Scene, light::LightSet};
use glam::Vec3;
use rayon::prelude::*;
use std::time::{Duration, Instant};

/// The direction of a path tracer's camera ray through pixel `(x, y)` of a `(w, h)` image:
/// a uniform jitter over the pixel square (box filter), the sampler's first two dimensions.
/// The renderer and the path inspector draw their camera rays only through this.
#[inline]
pub fn camera_ray(
    cam: &Camera,
    (x, y): (u32, u32),
    (w, h): (u32, u32),
    sampler: &mut Sampler,
) -> Vec3 {
    let j = sampler.next_2d();
    let sx = (x as f32 + j.x) / w as f32;
    let sy = (y as f32 + j.y) / h as f32;
    cam.ray_dir(sx, sy, w as f32 / h as f32)
}

/// A scene prepared for CPU rendering (BVH and light distribution built once).
pub struct Renderer {
    pub scene: Scene,
    pub bvh: Bvh,
    pub lights: LightSet,
    /// The scene has a dispersive material: paths carry hero wavelengths.
    pub spectral: bool,
    /// The scene's dielectric volumes nest or overlap: paths keep a medium stack.
    pub nested: bool,
    /// A volume absorbs (Beer–Lambert along segments inside it).
    pub absorption: bool,
    /// A material reads a texture.
    pub textures: bool,
}

impl Renderer {
    /// Validate the scene and build the acceleration structures.
    pub fn new(scene: Scene) -> anyhow::Result<Renderer> {
        scene.validate()?;
        let bvh = Bvh::build(&scene.mesh);
        let lights = LightSet::build(&scene);
        let mut r = Renderer {
            scene,
            bvh,
            lights,
            spectral: false,
            nested: false,
            absorption: false,
            textures: false,
        };
        r.refresh_features();
        Ok(r)
    }

    /// Re-derive what the walks specialise on (spectral transport, media, textures) from
    /// the scene's features, after its materials changed.
    pub fn refresh_features(&mut self) {
        let features = self.scene.features();
        self.spectral = features.contains(Features::DISPERSION);
        self.nested = features.contains(Features::NESTED);
        self.absorption = features.contains(Features::ABSORPTION);
        self.textures = features.contains(Features::TEXTURES);
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
            nested: self.nested,
            absorption: self.absorption,
            textures: self.textures,
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
        let estimator = opts.estimator.resolve(&self.scene);
        if estimator == Estimator::Sppm {
            return self.render_pass_sppm(opts, film, first_spp, count, cancelled);
        }
        if estimator != Estimator::Path {
            // Bidirectional passes are not cancellable mid-pass (splats span all rows).
            self.render_pass_bdpt(opts, estimator, film, first_spp, count);
            return true;
        }
        let integ = self.integrator(opts);
        let (w, h) = (opts.width, opts.height);
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
                        let dir = camera_ray(cam, (x as u32, y as u32), (w, h), &mut sampler);
                        let v = integ.li(cam.position, dir, &mut sampler);
                        let ok = Film::add_sample_to(px, v, integ.spectral);
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

    /// Photon-mapping pass (`cpu::sppm`): sample index s is iteration s, so the image does
    /// not depend on how samples are split into passes.
    fn render_pass_sppm(
        &self,
        opts: &RenderOptions,
        film: &mut Film,
        first_spp: u32,
        count: u32,
        cancelled: &(dyn Fn() -> bool + Sync),
    ) -> bool {
        use super::sppm::{Frame, SppmParams, render_iteration};
        let integ = self.integrator(opts);
        let (w, h) = (opts.width, opts.height);
        let params = SppmParams::new(&self.scene.camera, self.scene.bounds(), w, h);
        let mut dropped = 0u64;
        for s in first_spp..first_spp + count {
            let frame = Frame {
                film: &mut *film,
                width: w,
                height: h,
                seed: opts.seed,
            };
            match render_iteration(&integ, &params, s, frame, cancelled) {
                Some(d) => dropped += d,
                None => return false,
            }
        }
        film.spp += count as u64;
        film.dropped += dropped;
        true
    }

    /// Bidirectional / light-tracing pass: camera contributions per pixel, light-tracing
    /// splats into a shared buffer of atomically added f64 values, then folded into the film.
    /// `estimator` is `opts.estimator` resolved: bdpt, lt or lt+pt (which runs full bdpt).
    fn render_pass_bdpt(
        &self,
        opts: &RenderOptions,
        estimator: Estimator,
        film: &mut Film,
        first_spp: u32,
        count: u32,
    ) {
        use super::bdpt::{Bdpt, BdptMode};
        use std::sync::atomic::{AtomicU64, Ordering};
        let integ = self.integrator(opts);
        let mode = if estimator == Estimator::Lt {
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
                let mut scratch = super::bdpt::Scratch::new();
                for (x, px) in row.iter_mut().enumerate() {
                    let pixel = y as u32 * w + x as u32;
                    for s in first_spp..first_spp + count {
                        let mut sampler = Sampler::new(pixel, s, seed);
                        let mut bad_splat = false;
                        let v = bd.sample(
                            x as u32,
                            y as u32,
                            &mut sampler,
                            &mut |sx, sy, v| {
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
                            },
                            &mut scratch,
                        );
                        let ok = Film::add_sample_to(px, v, integ.spectral);
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
        let pass = opts.pass_spp();
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
            dropped: film.dropped,
            elapsed: start.elapsed(),
            pixels: opts.pixels(),
            segments: None,
        };
        (film, stats)
    }
}
