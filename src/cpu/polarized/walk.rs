//! The polarised camera walk: unidirectional path tracing with next-event estimation and
//! MIS exactly as `Integrator::li_spec` (the same random numbers in the same order, the same
//! scalar throughput, Russian roulette and MIS weights), with a Mueller chain
//! (`polarized::chain`) beside the scalar throughput. Emitters and the environment are
//! unpolarised; every light reached, by a BSDF sample or along a next-event connection,
//! adds its radiance times the chain's first column (for a connection, times the
//! connection vertex's Mueller BSDF value too; Wilkie & Weidlich 2012 §5, Mitsuba 3's
//! polarised `path` integrator). A separate function from the unpolarised walk, so that
//! renders which do not ask for polarisation run the old walk unchanged.
//!
//! Scope: the path tracer without a Heckbert path filter (`cli` refuses `--paths`); media
//! (nested and absorbing volumes) and spectral lanes are handled as in the `General` walk.

use super::chain::{MuellerChain, StokesLanes};
use crate::bsdf::polarized::{MuellerLanes, eval_mueller, event_mueller};
use crate::bsdf::{BxDF, TransportMode};
use crate::cpu::Integrator;
use crate::cpu::interaction::{Bounce, Interaction, surface_with};
use crate::cpu::medium::medium_transmittance;
use crate::cpu::path_state::{Interface, PathState};
use crate::cpu::spectral::Spectral;
use crate::math::Color;
use crate::math::rng::Sampler;
use crate::math::sampling::power_heuristic;
use crate::scene::light::LiSample;
use glam::{Vec2, Vec3, Vec4};

/// One polarised camera sample in linear RGB.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PolarizedSample {
    /// Stokes (I, Q, U, V) at the camera, in the camera frame (`polarized::chain`).
    pub stokes: [Vec3; 4],
    /// The intensity behind the camera's filter (I without one).
    pub filtered: Vec3,
}

impl PolarizedSample {
    const NAN: PolarizedSample = PolarizedSample {
        stokes: [Vec3::NAN; 4],
        filtered: Vec3::NAN,
    };
}

/// Adds `b` to `a` component by component.
#[inline]
fn add(a: &mut StokesLanes, b: StokesLanes) {
    for (x, y) in a.iter_mut().zip(b) {
        *x += y;
    }
}

impl Integrator<'_> {
    /// One polarised sample along the camera ray (origin, dir) of a camera whose right axis
    /// is `right`; `filter_row` is row 0 of the Mueller matrix in front of the sensor
    /// ((1, 0, 0, 0) without a filter), the intensity it passes per lane clamped at 0.
    pub fn li_polarized(
        &self,
        (origin, dir): (Vec3, Vec3),
        right: Vec3,
        filter_row: Vec4,
        sampler: &mut Sampler,
    ) -> PolarizedSample {
        let sp = self.lanes(|| sampler.next_1d());
        let Some(l) = self.polarized_walk((origin, dir), right, sampler, &sp) else {
            return PolarizedSample::NAN;
        };
        let filtered = (l[0] * filter_row.x + l[1] * filter_row.y)
            + (l[2] * filter_row.z + l[3] * filter_row.w);
        PolarizedSample {
            stokes: l.map(|c| sp.to_rgb(c)),
            filtered: sp.to_rgb(filtered.max(Color::ZERO)),
        }
    }

    /// The walk's Stokes estimate per lane; None for a sample the BSDF poisoned.
    fn polarized_walk(
        &self,
        (origin, dir): (Vec3, Vec3),
        right: Vec3,
        sampler: &mut Sampler,
        sp: &Spectral,
    ) -> Option<StokesLanes> {
        let scene = self.scene;
        let media = self.nested || self.absorption;
        let mut chain = MuellerChain::camera(dir, right);
        let mut l: StokesLanes = [Color::ZERO; 4];
        let mut st = PathState::new(Color::ONE, false, self.nested);
        let (mut o, mut d) = (origin, dir);
        let mut t_pass = 0.0f32;
        let (mut prev_pdf, mut prev_delta) = (0.0f32, true);
        loop {
            let Some(h) = self.bvh.intersect(o, d, f32::INFINITY) else {
                let w = self.lights.env_weight(d, prev_pdf, prev_delta);
                let le = self.lights.environment.le(Vec3::ZERO, Vec3::ZERO, -d);
                add(&mut l, chain.unpolarized(st.weight() * sp.c(le) * w));
                return Some(l);
            };
            let mut hit = surface_with(scene, &h, self.textures || media);
            let mut enclosing = None;
            if media {
                st.attenuate(scene, hit.t, sp);
                enclosing = match st.interface(scene, &hit, d) {
                    Interface::Real(m) => m,
                    Interface::Pass => {
                        t_pass += hit.t;
                        o = self.pass_through(&hit, d);
                        continue;
                    }
                    Interface::Lost => return Some(l),
                };
            }
            hit.t += t_pass;
            t_pass = 0.0;
            if let Some((le, w)) = self.hit_emission(&hit, d, prev_pdf, prev_delta) {
                add(&mut l, chain.unpolarized(st.weight() * sp.c(le) * w));
            }
            if st.depth + 1 >= self.max_depth {
                return Some(l);
            }
            let offset = self.bvh.offset_scale();
            let Some(it) = Interaction::new(scene, &hit, d, sp, offset, enclosing) else {
                return Some(l);
            };
            st.arrive(&it);
            let uc = sampler.next_1d();
            let u2 = sampler.next_2d();
            let ul = sampler.next_1d();
            let ul2 = sampler.next_2d();
            add(
                &mut l,
                self.polarized_light(&it, &st, (ul, ul2), media, sp, &chain),
            );
            let (s, wi) = match it.sample(uc, u2, TransportMode::Radiance) {
                Bounce::Continue { s, wi } => (s, wi),
                Bounce::Absorbed => return Some(l),
                Bounce::Poisoned => return None,
            };
            let ev = event_mueller(&it.bsdf, it.wo, s.wi, s.event, s.lobe);
            chain.scatter((it.wo_w, wi, it.ns), &ev);
            st.scatter_with(scene, &it, (&s, wi), TransportMode::Radiance, media);
            (prev_pdf, prev_delta) = (s.pdf, s.is_delta);
            o = it.spawn(wi);
            d = wi;
            if !st.survives(self.rr_depth, || sampler.next_1d()) {
                return Some(l);
            }
        }
    }

    /// Next-event estimation at `it` through the chain (zero at delta vertices).
    #[inline]
    fn polarized_light(
        &self,
        it: &Interaction,
        st: &PathState,
        (ul, ul2): (f32, Vec2),
        media: bool,
        sp: &Spectral,
        chain: &MuellerChain,
    ) -> StokesLanes {
        let zero = [Color::ZERO; 4];
        if it.bsdf.is_delta() || self.lights.is_empty() {
            return zero;
        }
        let Some((light, pick)) = self.lights.pick(ul) else {
            return zero;
        };
        let Some(ls) = light.sample_li(it.hit.p, ul2, pick) else {
            return zero;
        };
        match self.polarized_connection(it, st, &ls, media, sp) {
            Some((m, c)) => chain.through((it.wo_w, ls.wi, it.ns), &m, st.weight() * c),
            None => zero,
        }
    }

    /// The Mueller BSDF value at `it` towards the light sample `ls` and the scalar factor
    /// |cos θi| L w / pdf (times the shadow ray's transmittance), or None when no light
    /// arrives.
    fn polarized_connection(
        &self,
        it: &Interaction,
        st: &PathState,
        ls: &LiSample,
        media: bool,
        sp: &Spectral,
    ) -> Option<(MuellerLanes, Color)> {
        let wi = it.frame.to_local(ls.wi);
        let lobes = it.bsdf.eval_lobes(it.wo, wi, TransportMode::Radiance);
        if (lobes.d + lobes.g).max_element() <= 0.0 || !it.geometric_ok(ls.wi) {
            return None;
        }
        let (origin, sdir, stmax) = it.shadow_ray(ls);
        if self.bvh.occluded(origin, sdir, stmax) {
            return None;
        }
        let w = if ls.is_delta {
            1.0
        } else {
            power_heuristic(ls.pdf, it.bsdf.pdf(it.wo, wi))
        };
        let mut c = wi.z.abs() * sp.c(ls.l) * (w / ls.pdf);
        if media && !ls.infinite {
            let medium = st.medium_towards(self.scene, it, ls.wi);
            let t = (ls.p_light - it.hit.p).length();
            if let Some(tr) = medium_transmittance(self.scene, medium, t, sp) {
                c *= tr;
            }
        }
        Some((eval_mueller(&it.bsdf, it.wo, wi, lobes), c))
    }
}
