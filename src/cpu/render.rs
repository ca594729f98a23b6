//! Rendering a whole image on the CPU: rayon over rows, counter-based RNG per
//! (pixel, sample, dimension, seed) so images are identical across thread counts.

use super::Integrator;
use super::bdpt::{Bdpt, BdptMode, Scratch};
use super::layers::{LayerFilm, LayerObserver};
use super::spectral::LightLine;
use super::splat_buffer::SplatBuffer;
use crate::bvh::Bvh;
use crate::film::Film;
use crate::math::rng::Sampler;
use crate::render::photon_aim::PhotonTargets;
use crate::render::{Estimator, EstimatorPlan, RenderOptions, RenderStats, Runner};
use crate::scene::{Features, Scene, light::LightSet};
use glam::Vec3;
use rayon::prelude::*;
use std::time::{Duration, Instant};

use super::camera_ray::camera_ray;
use crate::scene::camera::CameraRays;

/// A scene prepared for CPU rendering (BVH and light distribution built once).
pub struct Renderer {
    pub scene: Scene,
    pub bvh: Bvh,
    pub lights: LightSet,
    /// The scene has a dispersive material: paths carry hero wavelengths.
    pub spectral: bool,
    /// The scene's light is one spectral line (`RenderSettings::light_line_nm`): every lane
    /// carries its wavelength (spectral transport, whatever `spectral` says).
    pub line: Option<LightLine>,
    /// The scene's dielectric volumes nest or overlap: paths keep a medium stack.
    pub nested: bool,
    /// A volume absorbs (Beer–Lambert along segments inside it).
    pub absorption: bool,
    /// A material reads a texture.
    pub textures: bool,
    /// Where `sppm` aims the photons of finite lights (the surfaces that can be specular)
    /// and the share of the lights' power sent there, found at the first `sppm` pass after
    /// the materials or lights changed (`Renderer::photon_aim`).
    photon_aim: std::sync::OnceLock<(PhotonTargets, f32)>,
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
            line: None,
            nested: false,
            absorption: false,
            textures: false,
            photon_aim: Default::default(),
        };
        r.refresh_features();
        Ok(r)
    }

    /// Re-derive what the walks specialise on (spectral transport, media, textures) from
    /// the scene's features, and where photons are aimed, after its materials changed.
    pub fn refresh_features(&mut self) {
        let features = self.scene.features();
        self.spectral = features.contains(Features::DISPERSION);
        self.line = self.scene.settings.light_line_nm.map(LightLine::new);
        self.nested = features.contains(Features::NESTED);
        self.absorption = features.contains(Features::ABSORPTION);
        self.textures = features.contains(Features::TEXTURES);
        self.photon_aim = Default::default();
    }

    /// Where `sppm` aims photons and the share of the power that goes there
    /// (`render::photon_aim`), computed once per scene state. Whoever replaces `lights` or
    /// the materials calls [`Renderer::refresh_features`] (the viewer's render loop does).
    pub fn photon_aim(&self) -> &(PhotonTargets, f32) {
        self.photon_aim
            .get_or_init(|| PhotonTargets::with_fraction(&self.scene, &self.lights))
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
            line: self.line,
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
        let estimator = EstimatorPlan::decide(opts.estimator, &self.scene, Runner::Cpu).runs;
        if estimator == Estimator::Sppm {
            return self.render_pass_sppm(opts, film, first_spp, count, cancelled);
        }
        if estimator != Estimator::Path {
            // Bidirectional passes are not cancellable mid-pass (splats span all rows).
            self.render_pass_bdpt(opts, estimator, film, first_spp, count);
            return true;
        }
        self.path_pass(opts, film, None, &(), (first_spp, count), cancelled)
    }

    /// A path-tracing pass that also walks with the observer `proto` (cloned per row) and
    /// adds its per-sample values to `layers` (`proto.layers()` per pixel): the path-class
    /// decomposition and the event heatmaps. The walk and the beauty film are those of
    /// [`Renderer::render_pass_cancellable`] with `--estimator path` (the callers refuse the
    /// other estimators). Returns false if cancelled (discard `film` and `layers` then).
    pub fn render_pass_layered<O: LayerObserver>(
        &self,
        opts: &RenderOptions,
        film: &mut Film,
        layers: &mut LayerFilm,
        proto: &O,
        (first_spp, count): (u32, u32),
        cancelled: &(dyn Fn() -> bool + Sync),
    ) -> bool {
        assert_eq!(
            layers.layers,
            proto.layers(),
            "layer film and observer disagree"
        );
        self.path_pass(
            opts,
            film,
            Some(layers),
            proto,
            (first_spp, count),
            cancelled,
        )
    }

    /// The path-tracing pass over rows, with an observer `proto` whose layers go to `layers`
    /// (`None` with `()`: the plain render, whose hooks compile away).
    fn path_pass<O: LayerObserver>(
        &self,
        opts: &RenderOptions,
        film: &mut Film,
        layers: Option<&mut LayerFilm>,
        proto: &O,
        (first_spp, count): (u32, u32),
        cancelled: &(dyn Fn() -> bool + Sync),
    ) -> bool {
        let integ = self.integrator(opts);
        let (w, h) = (opts.width, opts.height);
        let cam = &CameraRays::new(&self.scene.camera);
        let seed = opts.seed;
        let per_pixel = proto.layers();
        let row_pass = |y: usize, row: &mut [[f64; 3]], lrow: &mut [[f64; 3]]| -> Option<u64> {
            if cancelled() {
                return None;
            }
            let mut obs = proto.clone();
            let mut dropped = 0u64;
            for (x, px) in row.iter_mut().enumerate() {
                let pixel = y as u32 * w + x as u32;
                for s in first_spp..first_spp + count {
                    let mut sampler = Sampler::new(pixel, s, seed);
                    let dir = camera_ray(cam, (x as u32, y as u32), (w, h), &mut sampler);
                    let v = integ.li_observed(cam.position, dir, &mut sampler, &mut obs);
                    let ok = Film::add_sample_to(px, v, integ.spectral);
                    if per_pixel > 0 {
                        obs.commit(ok, &mut lrow[x * per_pixel..(x + 1) * per_pixel]);
                    }
                    if !ok {
                        dropped += 1;
                    }
                }
            }
            Some(dropped)
        };
        let rows = film.sums_mut().par_chunks_mut(w as usize).enumerate();
        let result: Option<u64> = match layers {
            Some(l) if per_pixel > 0 => rows
                .zip(l.sums_mut().par_chunks_mut(w as usize * per_pixel))
                .map(|((y, row), lrow)| row_pass(y, row, lrow))
                .sum(),
            _ => rows.map(|(y, row)| row_pass(y, row, &mut [])).sum(),
        };
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
        let (targets, fraction) = self.photon_aim();
        let params = SppmParams::new(&self.scene.camera, self.scene.bounds(), (w, h), *fraction);
        let mut dropped = 0u64;
        for s in first_spp..first_spp + count {
            let frame = Frame {
                film: &mut *film,
                width: w,
                height: h,
                seed: opts.seed,
            };
            match render_iteration(&integ, (&params, Some(targets)), s, frame, cancelled) {
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
        let integ = self.integrator(opts);
        let mode = if estimator == Estimator::Lt {
            BdptMode::LightTracing
        } else {
            BdptMode::Full
        };
        let (w, h) = (opts.width, opts.height);
        let bd = Bdpt::new(&integ, mode, opts.filter_forward.as_ref(), w, h);
        let splats = SplatBuffer::new(w, h);
        let pass = BdptPass {
            bd: &bd,
            splats: &splats,
            samples: (first_spp, count),
            seed: opts.seed,
            width: w,
            spectral: integ.spectral,
        };
        let dropped: u64 = film
            .sums_mut()
            .par_chunks_mut(w as usize)
            .enumerate()
            .map(|(y, row)| pass.row(y as u32, row))
            .sum();
        splats.fold_into(film);
        film.spp += count as u64;
        film.dropped += dropped;
    }

    /// Render `spp` samples per pixel (or until `budget` runs out, whichever first; at least
    /// one pass), sample indices `opts.first_sample ..`. `progress` is called after each pass
    /// with the samples done so far.
    pub fn render(
        &self,
        opts: &RenderOptions,
        spp: u32,
        budget: Option<Duration>,
        progress: impl FnMut(u64),
    ) -> (Film, RenderStats) {
        let mut film = Film::new(opts.width, opts.height);
        let mut stats = self.render_passes(opts, (spp, budget), progress, |first, n| {
            self.render_pass(opts, &mut film, first, n);
        });
        (stats.spp, stats.dropped) = (film.spp, film.dropped);
        (film, stats)
    }

    /// [`Renderer::render`] that also returns the mean image after the first `k` samples
    /// and `k` (the denoiser's two-halves variance, `denoise::half_variance`): no pass
    /// crosses `spp / 2`. The film is that of [`Renderer::render`] sample for sample; only
    /// the path tracer and SPPM are split (their films do not depend on how samples are split
    /// into passes; bidirectional splats are folded per pass), else no half is returned.
    pub fn render_with_half(
        &self,
        opts: &RenderOptions,
        (spp, budget): (u32, Option<Duration>),
        progress: impl FnMut(u64),
    ) -> (Film, Option<(Vec<Vec3>, u64)>, RenderStats) {
        let resolved = opts.estimator.resolve(&self.scene);
        let split = matches!(resolved, Estimator::Path | Estimator::Sppm) && spp >= 2;
        let half_at = if split { spp / 2 } else { u32::MAX };
        let mut film = Film::new(opts.width, opts.height);
        let mut half = None;
        let mut stats = self.render_passes_split(opts, (spp, budget), half_at, progress, |f, n| {
            self.render_pass(opts, &mut film, f, n);
            if half.is_none() && film.spp >= half_at as u64 {
                half = Some((film.image(), film.spp));
            }
        });
        (stats.spp, stats.dropped) = (film.spp, film.dropped);
        let half = half.filter(|h| h.1 < film.spp);
        (film, half, stats)
    }

    /// [`Renderer::render`] walking with the layer observer `proto` (path tracing only): the
    /// beauty film and the observer's layers.
    pub fn render_layered<O: LayerObserver>(
        &self,
        opts: &RenderOptions,
        (spp, budget): (u32, Option<Duration>),
        proto: &O,
        progress: impl FnMut(u64),
    ) -> (Film, LayerFilm, RenderStats) {
        let mut film = Film::new(opts.width, opts.height);
        let mut layers = LayerFilm::new(opts.width, opts.height, proto.layers());
        let mut stats = self.render_passes(opts, (spp, budget), progress, |first, n| {
            let pass = (first, n);
            self.render_pass_layered(opts, &mut film, &mut layers, proto, pass, &|| false);
        });
        (stats.spp, stats.dropped) = (film.spp, film.dropped);
        (film, layers, stats)
    }

    /// Run `pass(first_spp, count)` in passes of `opts.pass_spp()` until `spp` samples or
    /// the time budget (at least one pass), from sample index `opts.first_sample` on.
    pub(crate) fn render_passes(
        &self,
        opts: &RenderOptions,
        (spp, budget): (u32, Option<Duration>),
        progress: impl FnMut(u64),
        pass: impl FnMut(u32, u32),
    ) -> RenderStats {
        self.render_passes_split(opts, (spp, budget), u32::MAX, progress, pass)
    }

    /// [`Renderer::render_passes`] in which no pass crosses `split` samples.
    fn render_passes_split(
        &self,
        opts: &RenderOptions,
        (spp, budget): (u32, Option<Duration>),
        split: u32,
        mut progress: impl FnMut(u64),
        mut pass: impl FnMut(u32, u32),
    ) -> RenderStats {
        let start = Instant::now();
        // Passes of a few spp keep the progress bar and time budget responsive.
        let pass_spp = opts.pass_spp();
        let mut done = 0u32;
        while done < spp {
            let n = pass_spp
                .min(spp - done)
                .min(budget.map_or(u32::MAX, |b| spp_that_fit(b, start.elapsed(), done)))
                .min(if done < split { split - done } else { u32::MAX });
            pass(opts.first_sample.saturating_add(done), n);
            done += n;
            progress(done as u64);
            if let Some(b) = budget
                && start.elapsed() >= b
            {
                break;
            }
        }
        // The caller fills in the film's spp and drop count.
        RenderStats {
            spp: done as u64,
            dropped: 0,
            elapsed: start.elapsed(),
            pixels: opts.pixels(),
            segments: None,
        }
    }
}

/// With a time `budget` of which `elapsed` is spent on `done` spp, how many more spp fit at
/// the rate so far (rounded up, at least 1: the pass that reaches the budget overruns it by
/// less than one spp's time, not by a whole pass). Before the first pass, no limit.
fn spp_that_fit(budget: Duration, elapsed: Duration, done: u32) -> u32 {
    if done == 0 {
        return u32::MAX;
    }
    let per_spp = elapsed.as_secs_f64() / done as f64;
    let left = budget.saturating_sub(elapsed).as_secs_f64();
    if per_spp > 0.0 {
        (left / per_spp).ceil().clamp(1.0, u32::MAX as f64) as u32
    } else {
        u32::MAX
    }
}

/// One BDPT pass over the image: what every row's task shares.
struct BdptPass<'p, 'a> {
    bd: &'p Bdpt<'a>,
    splats: &'p SplatBuffer,
    /// (first sample index, number of samples per pixel).
    samples: (u32, u32),
    seed: u32,
    width: u32,
    spectral: bool,
}

impl<'a> BdptPass<'_, 'a> {
    /// Every sample of row `y` (its film sums `row`); returns the samples dropped.
    fn row(&self, y: u32, row: &mut [[f64; 3]]) -> u64 {
        let mut dropped = 0u64;
        let mut scratch = Scratch::new();
        let (first, count) = self.samples;
        for (x, px) in row.iter_mut().enumerate() {
            let pixel = y * self.width + x as u32;
            for s in first..first + count {
                if !self.sample(
                    px,
                    (x as u32, y),
                    Sampler::new(pixel, s, self.seed),
                    &mut scratch,
                ) {
                    dropped += 1;
                }
            }
        }
        dropped
    }

    /// One sample of pixel (x, y): its camera-side value into `px`, its light-tracing splats
    /// into the shared buffer; false when the value or a splat was invalid (dropped).
    fn sample(
        &self,
        px: &mut [f64; 3],
        (x, y): (u32, u32),
        mut sampler: Sampler,
        scratch: &mut Scratch<'a>,
    ) -> bool {
        let mut bad_splat = false;
        let mut splat = |sx: u32, sy: u32, v: Vec3| {
            let ok = if self.spectral {
                v.is_finite()
            } else {
                crate::film::sample_is_valid(v)
            };
            if ok {
                self.splats.add_rgb(sx, sy, v);
            } else {
                bad_splat = true;
            }
        };
        let v = self.bd.sample(x, y, &mut sampler, &mut splat, scratch);
        Film::add_sample_to(px, v, self.spectral) && !bad_splat
    }
}

#[cfg(test)]
mod tests {
    use super::spp_that_fit;
    use std::time::Duration;

    /// The pass that would cross a time budget shrinks to the spp that fit at the rate so
    /// far, rounded up (never 0); the first pass is not limited.
    #[test]
    fn the_last_pass_shrinks_to_the_time_left() {
        let s = Duration::from_secs_f64;
        assert_eq!(spp_that_fit(s(10.0), s(0.0), 0), u32::MAX);
        assert_eq!(spp_that_fit(s(10.0), s(4.0), 8), 12); // 0.5 s per spp, 6 s left
        assert_eq!(spp_that_fit(s(10.0), s(9.8), 8), 1); // 0.2 s left: one more spp
        assert_eq!(spp_that_fit(s(10.0), s(9.75), 39), 1);
        assert_eq!(spp_that_fit(s(10.0), s(12.0), 8), 1); // already over: never 0
        assert_eq!(spp_that_fit(s(10.0), s(0.0), 8), u32::MAX); // no time measured yet
    }
}
