//! Unidirectional path tracing with next-event estimation on every light and MIS (power
//! heuristic) between light and BSDF sampling. Veach 1997, ch. 9–10; PBR 4th ed. §13.4
//! (`PathIntegrator`). Depth and Russian roulette follow Mitsuba 3's `path` integrator:
//! `max_depth` 1 = emitters seen directly, 2 = direct lighting, RR from `rr_depth`.
//! Lights are reached only through `scene::light::Light`; the per-vertex work lives in
//! `Interaction` and `PathState`. The walk is compiled per set of scene features
//! (`cpu::walk_spec`): scenes without spectral lanes, a path filter, media or textures run an
//! instance with that code removed.

use super::gather::Gather;
use super::interaction::{
    Bounce, Interaction, SurfaceHit, offset_ray_origin_towards, surface, surface_with,
};
use super::medium::medium_transmittance;
use super::observer::{PathEnd, PathObserver};
use super::path_state::{Interface, PathState};
use super::spectral::{LightLine, Spectral};
use super::walk_spec::{General, Lean, WalkFeatures, WalkSpec};
use crate::bsdf::{BxDF, TransportMode};
use crate::bvh::Bvh;
use crate::math::sampling::power_heuristic;
use crate::math::{Color, rng::Sampler};
use crate::paths::{DfaTable, Symbol};
use crate::scene::Scene;
use crate::scene::light::{LiSample, LightSet};
use glam::{Vec2, Vec3};

/// The path tracer for one prepared scene.
pub struct Integrator<'a> {
    pub scene: &'a Scene,
    pub bvh: &'a Bvh,
    pub lights: &'a LightSet,
    pub max_depth: u32,
    pub rr_depth: u32,
    /// Heckbert path filter in eye→light order (`PathFilter::reversed`); None = all paths.
    pub filter: Option<&'a DfaTable>,
    /// Hero-wavelength spectral transport (only scenes with a dispersive material pay for it).
    pub spectral: bool,
    /// The scene's light line, if any: every lane carries its wavelength.
    pub line: Option<LightLine>,
    /// The scene's dielectric volumes nest or overlap (`Features::NESTED`): paths keep the
    /// medium stack and pass false hits.
    pub nested: bool,
    /// A volume absorbs (`Features::ABSORPTION`): segments inside it attenuate.
    pub absorption: bool,
    /// A material reads a texture (`Features::TEXTURES`).
    pub textures: bool,
}

/// Which Heckbert classes a next-event connection may use at a vertex (D, G), and whether
/// the walk keeps media (so the shadow ray may attenuate).
#[derive(Clone, Copy)]
struct ClassMask {
    d: bool,
    g: bool,
    media: bool,
}

/// DFA state after `sym` (0 when unfiltered).
#[inline(always)]
fn step(filter: Option<&DfaTable>, q: u32, sym: Symbol) -> u32 {
    match filter {
        Some(f) => f.step(q, sym),
        None => 0,
    }
}

/// Does a path in state `q` that now reaches a light count?
#[inline(always)]
fn accepts_light(filter: Option<&DfaTable>, q: u32) -> bool {
    match filter {
        Some(f) => f.is_accepting(f.step(q, Symbol::L)),
        None => true,
    }
}

impl<'a> Integrator<'a> {
    /// Reconstruct the surface record of a BVH hit.
    #[inline]
    pub fn surface(&self, hit: &crate::bvh::Hit) -> SurfaceHit {
        surface(self.scene, hit)
    }

    /// The colour lanes of a new path (camera or light): RGB, hero wavelengths drawn from `u`,
    /// or the light line's wavelength.
    #[inline]
    pub fn lanes(&self, u: impl FnOnce() -> f32) -> Spectral {
        Spectral::new(self.spectral, self.line, u)
    }

    /// What the camera path with lanes `sp` needs of the walk (`cpu::walk_spec`).
    #[inline]
    pub fn walk_features(&self, sp: &Spectral) -> WalkFeatures {
        WalkFeatures {
            spectral: sp.lambdas.is_some(),
            filter: self.filter.is_some(),
            media: self.nested || self.absorption,
            textures: self.textures,
        }
    }

    /// Emitted radiance reaching the path at `hit` along `d`, MIS-weighted against NEE.
    #[inline]
    pub(crate) fn hit_emission(
        &self,
        hit: &SurfaceHit,
        d: Vec3,
        prev_pdf: f32,
        prev_delta: bool,
    ) -> Option<(Vec3, f32)> {
        let (light, pick) = self.lights.area_light(hit.tri)?;
        let le = light.le(hit.p, hit.ng, -d);
        if le.max_element() <= 0.0 {
            return None;
        }
        let w = if prev_delta {
            1.0
        } else {
            power_heuristic(prev_pdf, light.pdf_li(pick, d, hit.t, hit.ng.dot(d).abs()))
        };
        Some((le, w))
    }

    /// Radiance along the camera ray (origin, dir) — one path sample, RGB.
    #[inline]
    pub fn li(&self, origin: Vec3, dir: Vec3, sampler: &mut Sampler) -> Vec3 {
        self.li_observed(origin, dir, sampler, &mut ())
    }

    /// [`Integrator::li`] reporting every step of the walk to `obs` (the path inspector);
    /// with `()` the hooks compile away and this is the renderer's walk.
    pub fn li_observed<O: PathObserver>(
        &self,
        origin: Vec3,
        dir: Vec3,
        sampler: &mut Sampler,
        obs: &mut O,
    ) -> Vec3 {
        let sp = self.lanes(|| sampler.next_1d());
        self.li_walk(origin, dir, sampler, sp, obs, &())
    }

    /// The camera walk with the colour lanes `sp` given, reporting to `obs` and handing the
    /// caustic paths that end at its diffuse vertices to `gather` (`cpu::gather`): a path
    /// that reaches light from a gather vertex through specular vertices only is the
    /// gatherer's and is left out here.
    pub fn li_walk<O: PathObserver, G: Gather>(
        &self,
        origin: Vec3,
        dir: Vec3,
        sampler: &mut Sampler,
        sp: Spectral,
        obs: &mut O,
        gather: &G,
    ) -> Vec3 {
        let ray = (origin, dir);
        if self.walk_features(&sp).lean() {
            self.li_spec::<Lean, O, G>(ray, sampler, sp, obs, gather)
        } else {
            self.li_spec::<General, O, G>(ray, sampler, sp, obs, gather)
        }
    }

    /// [`Integrator::li_walk`] compiled for the features `S`; a path that needs more than
    /// `S` covers runs the `General` instance instead (so no choice of `S` changes an image).
    /// Each absent feature is a constant here: RGB lanes, no filter state, no medium stack and
    /// no uv unless the observer or gatherer reads them (`READS_STATE`).
    ///
    /// This is the renderer's hot loop and stays one function on purpose: split into
    /// `#[inline(always)]` steps (trace-and-arrive, emission, scatter) over a walk-state
    /// struct, the same walk (images byte-identical) ran 5.4 % more instructions
    /// (callgrind, cornell-glass 64², 16 spp, one thread: 527.7 M → 556–566 M in three
    /// variants; session 13), so the steps are marked by comments instead.
    pub fn li_spec<S: WalkSpec, O: PathObserver, G: Gather>(
        &self,
        (origin, dir): (Vec3, Vec3),
        sampler: &mut Sampler,
        sp: Spectral,
        obs: &mut O,
        gather: &G,
    ) -> Vec3 {
        if !self.walk_features(&sp).fits::<S>() {
            return self.li_spec::<General, O, G>((origin, dir), sampler, sp, obs, gather);
        }
        let sp = if S::SPECTRAL { sp } else { Spectral::RGB };
        let filter = if S::FILTER { self.filter } else { None };
        let media = S::MEDIA || O::READS_STATE || G::READS_STATE;
        let with_uv = S::TEXTURES || O::READS_STATE || G::READS_STATE;
        let scene = self.scene;
        obs.start(origin, dir, &sp);
        // Specular vertices since the last gather vertex (None: no gather vertex, or a
        // non-specular vertex since): light reached with Some(k ≥ 1) is the gatherer's.
        let mut chain: Option<u32> = None;
        let mut l = Color::ZERO;
        let mut st = PathState::new(Color::ONE, false, self.nested);
        let (mut o, mut d) = (origin, dir);
        // Distance travelled through false hits since the last vertex.
        let mut t_pass = 0.0f32;
        let (mut prev_pdf, mut prev_delta) = (0.0f32, true);
        // Path-filter state: the camera vertex is E (reversed DFA reads eye→light).
        let mut q = step(filter, filter.map_or(0, |f| f.start()), Symbol::E);
        let why = loop {
            let Some(h) = self.bvh.intersect(o, d, f32::INFINITY) else {
                // Escaped: the environment, unless the gatherer already counted it.
                let gathered = chain.is_some_and(|k| k >= 1) && gather.environment_emits();
                if accepts_light(filter, q) && !gathered {
                    l += self.escaped_light(d, &st, (prev_pdf, prev_delta), &sp, obs);
                }
                break PathEnd::Escaped;
            };
            let mut hit = surface_with(scene, &h, with_uv);
            // Without media every interface is real and refracts against air.
            let mut enclosing = None;
            if media {
                st.attenuate(scene, hit.t, &sp);
                enclosing = match st.interface(scene, &hit, d) {
                    Interface::Real(m) => m,
                    Interface::Pass => {
                        t_pass += hit.t;
                        o = self.pass_through(&hit, d);
                        continue;
                    }
                    Interface::Lost => break PathEnd::Terminated,
                };
            }
            hit.t += t_pass;
            t_pass = 0.0;
            obs.surface(scene, &hit, &st);
            // Emission found here (MIS against the previous vertex's NEE).
            if accepts_light(filter, q)
                && chain.is_none_or(|k| k == 0)
                && let Some((le, w)) = self.hit_emission(&hit, d, prev_pdf, prev_delta)
            {
                let c = st.weight() * sp.c(le) * w;
                obs.emitted(c);
                l += c;
            }
            if st.depth + 1 >= self.max_depth {
                break PathEnd::MaxDepth;
            }
            let offset = self.bvh.offset_scale();
            let Some(it) = Interaction::new(scene, &hit, d, &sp, offset, enclosing) else {
                break PathEnd::Terminated;
            };
            st.arrive(&it);
            // Scatter: the gatherer's caustic, NEE, the BSDF sample, then Russian roulette.
            let caustic = gather.gather(&it, &st, q, &sp);
            if let Some(c) = caustic {
                l += st.weight() * c;
            }
            let uc = sampler.next_1d();
            let u2 = sampler.next_2d();
            let ul = sampler.next_1d();
            let ul2 = sampler.next_2d();
            l += self.next_event(&it, &st, (ul, ul2), (filter, q, media), &sp, obs);
            let (s, wi) = match it.sample(uc, u2, TransportMode::Radiance) {
                Bounce::Continue { s, wi } => (s, wi),
                Bounce::Absorbed => break PathEnd::Absorbed,
                // A broken BSDF value: poison the sample so the film's firewall drops and
                // counts it instead of silently biasing the image.
                Bounce::Poisoned => {
                    obs.end(PathEnd::Poisoned);
                    return Vec3::NAN;
                }
            };
            obs.bounce(scene, &it, &st, &s, wi);
            if let Some(f) = filter {
                q = f.step(q, Symbol::from(s.lobe));
                if !f.can_reach_accept(q) {
                    break PathEnd::Filtered; // nothing this path can still reach counts
                }
            }
            st.scatter_with(scene, &it, (&s, wi), TransportMode::Radiance, media);
            chain = match caustic {
                Some(_) => Some(0),
                None if it.bsdf.is_delta() => chain.map(|k| k + 1),
                None => None,
            };
            (prev_pdf, prev_delta) = (s.pdf, s.is_delta);
            o = it.spawn(wi);
            d = wi;
            let alive = st.survives(self.rr_depth, || sampler.next_1d());
            obs.throughput(st.weight());
            if !alive {
                break PathEnd::Roulette;
            }
        };
        obs.end(why);
        sp.to_rgb(l)
    }

    /// The origin that continues a ray along `d` past the false hit `hit`.
    #[inline]
    pub fn pass_through(&self, hit: &SurfaceHit, d: Vec3) -> Vec3 {
        offset_ray_origin_towards(hit.p, hit.ng, d.dot(hit.ng), self.bvh.offset_scale())
    }

    /// The environment seen along the escaping direction `d` (times the path throughput),
    /// MIS-weighted against NEE when it is light-sampled, reported to `obs`.
    #[inline(always)]
    fn escaped_light<O: PathObserver>(
        &self,
        d: Vec3,
        st: &PathState,
        (prev_pdf, prev_delta): (f32, bool),
        sp: &Spectral,
        obs: &mut O,
    ) -> Color {
        let w = self.lights.env_weight(d, prev_pdf, prev_delta);
        let c = st.weight() * sp.c(self.lights.environment.le(Vec3::ZERO, Vec3::ZERO, -d)) * w;
        obs.escaped(d, c);
        c
    }

    /// Next-event estimation at a non-delta vertex whose D or G connection the path filter
    /// (in state `q`) still accepts; zero elsewhere.
    #[inline(always)]
    fn next_event<O: PathObserver>(
        &self,
        it: &Interaction,
        st: &PathState,
        u: (f32, Vec2),
        (filter, q, media): (Option<&DfaTable>, u32, bool),
        sp: &Spectral,
        obs: &mut O,
    ) -> Color {
        if it.bsdf.is_delta() || self.lights.is_empty() {
            return Color::ZERO;
        }
        let mask = ClassMask {
            d: accepts_light(filter, step(filter, q, Symbol::D)),
            g: accepts_light(filter, step(filter, q, Symbol::G)),
            media,
        };
        if mask.d || mask.g {
            self.sample_light(it, st, u, mask, sp, obs)
        } else {
            Color::ZERO
        }
    }

    /// One next-event estimate at `it` (times the path throughput), MIS-weighted, reported
    /// to `obs` once a light point is drawn.
    #[inline(always)]
    fn sample_light<O: PathObserver>(
        &self,
        it: &Interaction,
        st: &PathState,
        (ul, ul2): (f32, Vec2),
        mask: ClassMask,
        sp: &Spectral,
        obs: &mut O,
    ) -> Color {
        let Some((light, pick)) = self.lights.pick(ul) else {
            return Color::ZERO;
        };
        let Some(ls) = light.sample_li(it.hit.p, ul2, pick) else {
            return Color::ZERO;
        };
        let (c, occluded) = self.connect_light(it, st, &ls, mask, sp);
        let c = st.weight() * c;
        obs.connection(it, &ls, c, occluded);
        c
    }

    /// The unweighted next-event estimate of the light sample `ls` at `it` and whether its
    /// shadow ray was blocked.
    #[inline(always)]
    fn connect_light(
        &self,
        it: &Interaction,
        st: &PathState,
        ls: &LiSample,
        mask: ClassMask,
        sp: &Spectral,
    ) -> (Color, bool) {
        let wi = it.frame.to_local(ls.wi);
        let f = if mask.d && mask.g {
            it.bsdf.eval(it.wo, wi, TransportMode::Radiance)
        } else {
            let lv = it.bsdf.eval_lobes(it.wo, wi, TransportMode::Radiance);
            (if mask.d { lv.d } else { Color::ZERO }) + (if mask.g { lv.g } else { Color::ZERO })
        };
        if f.max_element() <= 0.0 || !it.geometric_ok(ls.wi) {
            return (Color::ZERO, false);
        }
        let (origin, sdir, stmax) = it.shadow_ray(ls);
        if self.bvh.occluded(origin, sdir, stmax) {
            return (Color::ZERO, true);
        }
        let w = if ls.is_delta {
            1.0
        } else {
            power_heuristic(ls.pdf, it.bsdf.pdf(it.wo, wi))
        };
        let c = f * wi.z.abs() * sp.c(ls.l) * (w / ls.pdf);
        // Absorption along the shadow ray (a light inside absorbing glass).
        if !mask.media {
            return (c, false);
        }
        let medium = st.medium_towards(self.scene, it, ls.wi);
        if ls.infinite || medium.is_none() {
            return (c, false);
        }
        let t = (ls.p_light - it.hit.p).length();
        let c = medium_transmittance(self.scene, medium, t, sp).map_or(c, |tr| c * tr);
        (c, false)
    }
}
