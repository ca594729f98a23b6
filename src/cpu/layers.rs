//! Extra per-pixel images accumulated alongside the beauty film by a camera-walk observer:
//! the path-class decomposition (`cpu::decompose`) and the event heatmaps (`cpu::aov`). The
//! observer sees the walk through the `PathObserver` hooks and, after each sample, adds its
//! values to the pixel's layers ([`LayerObserver::commit`]). The plain render walks with
//! `()`, which has no layers, so it pays nothing.

use super::observer::{PathEnd, PathObserver};
use super::{interaction::Interaction, interaction::SurfaceHit, path_state::PathState};
use crate::bsdf::BsdfSample;
use crate::cpu::spectral::Spectral;
use crate::math::Color;
use crate::scene::Scene;
use crate::scene::light::LiSample;
use glam::Vec3;

/// A camera-walk observer that accumulates [`LayerObserver::layers`] RGB values per pixel.
/// One copy per worker is cloned from a prototype; `start` resets it for each sample.
pub trait LayerObserver: PathObserver + Clone + Send + Sync {
    /// RGB layers per pixel.
    fn layers(&self) -> usize;
    /// Add the sample just walked to the pixel's layers `px` (`layers()` long). `accepted`:
    /// the film's firewall kept the sample's total (a dropped sample's parts are dropped too,
    /// so the layers stay consistent with the beauty image).
    fn commit(&mut self, accepted: bool, px: &mut [[f64; 3]]);
}

impl LayerObserver for () {
    #[inline(always)]
    fn layers(&self) -> usize {
        0
    }
    #[inline(always)]
    fn commit(&mut self, _accepted: bool, _px: &mut [[f64; 3]]) {}
}

/// An observer that is there or not: `None` sees nothing and has no layers.
impl<T: PathObserver> PathObserver for Option<T> {
    #[inline(always)]
    fn start(&mut self, origin: Vec3, dir: Vec3, sp: &Spectral) {
        if let Some(o) = self {
            o.start(origin, dir, sp);
        }
    }
    #[inline(always)]
    fn surface(&mut self, scene: &Scene, hit: &SurfaceHit, st: &PathState) {
        if let Some(o) = self {
            o.surface(scene, hit, st);
        }
    }
    #[inline(always)]
    fn emitted(&mut self, contribution: Color) {
        if let Some(o) = self {
            o.emitted(contribution);
        }
    }
    #[inline(always)]
    fn connection(&mut self, it: &Interaction, ls: &LiSample, c: Color, occluded: bool) {
        if let Some(o) = self {
            o.connection(it, ls, c, occluded);
        }
    }
    #[inline(always)]
    fn bounce(
        &mut self,
        scene: &Scene,
        it: &Interaction,
        st: &PathState,
        s: &BsdfSample,
        wi: Vec3,
    ) {
        if let Some(o) = self {
            o.bounce(scene, it, st, s, wi);
        }
    }
    #[inline(always)]
    fn throughput(&mut self, weight: Color) {
        if let Some(o) = self {
            o.throughput(weight);
        }
    }
    #[inline(always)]
    fn escaped(&mut self, dir: Vec3, contribution: Color) {
        if let Some(o) = self {
            o.escaped(dir, contribution);
        }
    }
    #[inline(always)]
    fn end(&mut self, why: PathEnd) {
        if let Some(o) = self {
            o.end(why);
        }
    }
}

impl<T: LayerObserver> LayerObserver for Option<T> {
    fn layers(&self) -> usize {
        self.as_ref().map_or(0, T::layers)
    }
    fn commit(&mut self, accepted: bool, px: &mut [[f64; 3]]) {
        if let Some(o) = self {
            o.commit(accepted, px);
        }
    }
}

/// Two observers side by side: `A`'s layers first, then `B`'s.
impl<A: PathObserver, B: PathObserver> PathObserver for (A, B) {
    #[inline(always)]
    fn start(&mut self, origin: Vec3, dir: Vec3, sp: &Spectral) {
        self.0.start(origin, dir, sp);
        self.1.start(origin, dir, sp);
    }
    #[inline(always)]
    fn surface(&mut self, scene: &Scene, hit: &SurfaceHit, st: &PathState) {
        self.0.surface(scene, hit, st);
        self.1.surface(scene, hit, st);
    }
    #[inline(always)]
    fn emitted(&mut self, contribution: Color) {
        self.0.emitted(contribution);
        self.1.emitted(contribution);
    }
    #[inline(always)]
    fn connection(&mut self, it: &Interaction, ls: &LiSample, c: Color, occluded: bool) {
        self.0.connection(it, ls, c, occluded);
        self.1.connection(it, ls, c, occluded);
    }
    #[inline(always)]
    fn bounce(
        &mut self,
        scene: &Scene,
        it: &Interaction,
        st: &PathState,
        s: &BsdfSample,
        wi: Vec3,
    ) {
        self.0.bounce(scene, it, st, s, wi);
        self.1.bounce(scene, it, st, s, wi);
    }
    #[inline(always)]
    fn throughput(&mut self, weight: Color) {
        self.0.throughput(weight);
        self.1.throughput(weight);
    }
    #[inline(always)]
    fn escaped(&mut self, dir: Vec3, contribution: Color) {
        self.0.escaped(dir, contribution);
        self.1.escaped(dir, contribution);
    }
    #[inline(always)]
    fn end(&mut self, why: PathEnd) {
        self.0.end(why);
        self.1.end(why);
    }
}

impl<A: LayerObserver, B: LayerObserver> LayerObserver for (A, B) {
    fn layers(&self) -> usize {
        self.0.layers() + self.1.layers()
    }
    fn commit(&mut self, accepted: bool, px: &mut [[f64; 3]]) {
        let (a, b) = px.split_at_mut(self.0.layers());
        self.0.commit(accepted, a);
        self.1.commit(accepted, b);
    }
}

/// The layers' per-pixel sums (f64, like the film), pixel-major: pixel `i`'s layers are
/// `sums[i * layers .. (i + 1) * layers]`. Means divide by the beauty film's `spp`.
#[derive(Clone, Debug)]
pub struct LayerFilm {
    pub width: u32,
    pub height: u32,
    pub layers: usize,
    sums: Vec<[f64; 3]>,
}

impl LayerFilm {
    pub fn new(width: u32, height: u32, layers: usize) -> LayerFilm {
        LayerFilm {
            width,
            height,
            layers,
            sums: vec![[0.0; 3]; width as usize * height as usize * layers],
        }
    }

    /// Bytes of a `width` × `height` layer film of `layers` layers.
    pub fn bytes_for(width: u32, height: u32, layers: usize) -> u64 {
        crate::film::Film::bytes_for(width, height) * layers as u64
    }

    /// Mutable sums for the render loop (row `y` is `[y * width * layers ..][.. width * layers]`).
    pub fn sums_mut(&mut self) -> &mut [[f64; 3]] {
        &mut self.sums
    }

    /// Mean of layer `layer` over `spp` samples, row-major, top row first.
    pub fn image(&self, layer: usize, spp: u64) -> Vec<Vec3> {
        let n = spp.max(1) as f64;
        self.sums
            .chunks_exact(self.layers.max(1))
            .map(|px| {
                let s = px[layer];
                Vec3::new((s[0] / n) as f32, (s[1] / n) as f32, (s[2] / n) as f32)
            })
            .collect()
    }

    /// Mean of channel `channel` of layer `layer`, as a grey image (the event heatmaps keep
    /// three scalars in one layer).
    pub fn channel_image(&self, layer: usize, channel: usize, spp: u64) -> Vec<Vec3> {
        self.image(layer, spp)
            .into_iter()
            .map(|v| Vec3::splat(v[channel]))
            .collect()
    }
}
