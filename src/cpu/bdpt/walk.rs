//! The random walks of both subpaths: one loop for camera (radiance) and light (importance)
//! transport, on the shared per-vertex step (`Interaction`, `PathState`).

use super::vertex::{Kind, Vertex, to_area};
use super::{Bdpt, BdptMode};
use crate::bsdf::{BxDF, TransportMode};
use crate::cpu::interaction::{
    Bounce, Interaction, SurfaceHit, offset_ray_origin_towards, surface_with,
};
use crate::cpu::path_state::{Interface, PathState};
use crate::cpu::spectral::Spectral;
use crate::math::{Color, rng::Sampler};
use crate::paths::Symbol;
use crate::scene::light::LeSample;
use glam::Vec3;

/// Where a subpath's walk starts: its first ray, the path state there, the solid-angle
/// density of the ray's direction, and the kind of transport.
pub(super) struct WalkStart {
    pub ray: (Vec3, Vec3),
    pub st: PathState,
    pub pdf_w: f32,
    pub mode: TransportMode,
}

impl<'a> Bdpt<'a> {
    /// Random walk from `start` (PBR 3rd ed. §16.3.2 structure). Appends vertices to `path`
    /// (at most `max_verts` in all); returns the throughput, collapse flag and direction of a
    /// ray that escaped the scene.
    pub(super) fn walk(
        &self,
        path: &mut Vec<Vertex<'a>>,
        start: WalkStart,
        max_verts: usize,
        sampler: &mut Sampler,
        sp: &Spectral,
    ) -> Option<(Color, bool, Vec3)> {
        let scene = self.pt.scene;
        let WalkStart {
            ray: (mut o, mut d),
            mut st,
            mut pdf_w,
            mode,
        } = start;
        while path.len() < max_verts {
            let Some(h) = self.pt.bvh.intersect(o, d, f32::INFINITY) else {
                return Some((st.beta, st.collapsed, d));
            };
            let hit = surface_with(scene, &h, self.with_uv);
            // Without media every interface is real and refracts against air.
            let mut enclosing = None;
            if self.media {
                st.attenuate(scene, hit.t, sp);
                enclosing = match st.interface(scene, &hit, d) {
                    Interface::Real(m) => m,
                    Interface::Pass => {
                        // A false hit is no vertex: the area densities use vertex positions.
                        o = self.pt.pass_through(&hit, d);
                        continue;
                    }
                    Interface::Lost => break,
                };
            }
            let offset = self.pt.bvh.offset_scale();
            let Some(it) = Interaction::new(scene, &hit, d, sp, offset, enclosing) else {
                self.push_emitter(path, &hit, d, &st, pdf_w);
                break;
            };
            st.arrive(&it);
            let mut v = Vertex::surface(scene, &it, &st, self.media);
            v.pdf_fwd = to_area(pdf_w, &path[path.len() - 1], &v);
            path.push(v);
            if path.len() >= max_verts {
                break;
            }
            let Some(wi) = self.bounce(path, &it, &mut st, (&mut pdf_w, mode), sampler) else {
                break;
            };
            o = it.spawn(wi);
            d = wi;
            if !st.survives(self.pt.rr_depth, || sampler.next_1d()) {
                break;
            }
        }
        None
    }

    /// The walk ended on a surface that does not scatter: an emitter still counts as a vertex
    /// (s = 0 strategies hit it), with its raw normals; a black back face does not.
    #[inline(always)]
    fn push_emitter(
        &self,
        path: &mut Vec<Vertex<'a>>,
        hit: &SurfaceHit,
        d: Vec3,
        st: &PathState,
        pdf_w: f32,
    ) {
        let scene = self.pt.scene;
        if !scene.materials[hit.material as usize].is_emissive() {
            return;
        }
        let mut v = Vertex {
            ng: hit.ng,
            ns: hit.ns,
            w_prev: -d,
            tri: hit.tri,
            collapsed: st.collapsed,
            medium: st.medium(scene),
            medium_across: st.medium(scene),
            ..Vertex::new(Kind::Surface, hit.p, st.beta, 0.0, Symbol::D)
        };
        v.pdf_fwd = to_area(pdf_w, &path[path.len() - 1], &v);
        path.push(v);
    }

    /// Sample the BSDF at the path's last vertex `it` and scatter: records the vertex's class
    /// and delta flag and the previous vertex's reverse density, sets `pdf_w` to the new
    /// direction's density (0 for a delta lobe) and returns that direction; `None` ends the
    /// walk (absorbed, or a broken BSDF value).
    #[inline(always)]
    fn bounce(
        &self,
        path: &mut [Vertex<'a>],
        it: &Interaction,
        st: &mut PathState,
        (pdf_w, mode): (&mut f32, TransportMode),
        sampler: &mut Sampler,
    ) -> Option<Vec3> {
        let cur = path.len() - 1;
        let (s, wi) = match it.sample(sampler.next_1d(), sampler.next_2d(), mode) {
            Bounce::Continue { s, wi } => (s, wi),
            Bounce::Absorbed | Bounce::Poisoned => return None,
        };
        st.scatter_with(self.pt.scene, it, (&s, wi), mode, self.media);
        path[cur].class = Symbol::from(s.lobe);
        if s.is_delta {
            path[cur].delta = true;
            *pdf_w = 0.0;
            path[cur - 1].pdf_rev = 0.0;
        } else {
            *pdf_w = s.pdf;
            let rev = it.bsdf.pdf(s.wi, it.wo);
            path[cur - 1].pdf_rev = to_area(rev, &path[cur], &path[cur - 1]);
        }
        Some(wi)
    }

    /// Start a light subpath: pick a light, sample an emitted ray from it and walk.
    pub(super) fn light_path(
        &self,
        path: &mut Vec<Vertex<'a>>,
        max_verts: usize,
        sampler: &mut Sampler,
        sp: &Spectral,
    ) {
        let ul = sampler.next_1d();
        let u_pos = sampler.next_2d();
        let u_dir = sampler.next_2d();
        let u_side = sampler.next_1d();
        let lights: &'a crate::scene::light::LightSet = self.pt.lights;
        let Some((light, pick)) = lights.pick(ul) else {
            return;
        };
        let Some(le) = light.sample_le(u_pos, u_dir, u_side, pick) else {
            return;
        };
        let kind = Kind::Light { light, pick };
        if le.infinite && self.mode == BdptMode::Full {
            // Only the s = 1 strategy connects to a light at infinity, along −n; the vertex
            // carries 1/(pick · p_dir) (p_dir = 1 for a delta direction).
            path.push(Vertex {
                ng: le.n,
                ns: le.n,
                ..Vertex::new(
                    kind,
                    Vec3::ZERO,
                    Color::splat(1.0 / (pick * le.pdf_dir)),
                    pick,
                    Symbol::L,
                )
            });
            return;
        }
        // (Light tracing walks from a light at infinity too: from its bounding disk.)
        let v0 = Vertex {
            ng: le.n,
            ns: le.n,
            ..Vertex::new(
                kind,
                le.p,
                Color::splat(1.0 / le.pdf_pos),
                le.pdf_pos,
                Symbol::L,
            )
        };
        path.push(v0);
        if le.pdf_dir <= 0.0 || le.l.max_element() <= 0.0 {
            return;
        }
        let start = self.emitted_ray(&le, v0.beta, sp);
        self.walk(path, start, max_verts, sampler, sp);
    }

    /// The walk that leaves the light sample `le` (its vertex carries `beta0`).
    fn emitted_ray(&self, le: &LeSample, beta0: Color, sp: &Spectral) -> WalkStart {
        let (o, cos) = if le.delta_pos || le.infinite {
            (le.p, 1.0)
        } else {
            (
                offset_ray_origin_towards(le.p, le.n, le.dir.dot(le.n), self.pt.bvh.offset_scale()),
                le.n.dot(le.dir).abs(),
            )
        };
        // β₁ = Le cosθ / (p_pos p_dir) (Veach 1997 §10.2; PBR 3rd ed. eq. 16.15).
        let beta = beta0 * sp.c(le.l) * (cos / le.pdf_dir);
        WalkStart {
            ray: (o, le.dir),
            st: PathState::new(beta, false, self.pt.nested),
            pdf_w: le.pdf_dir,
            mode: TransportMode::Importance,
        }
    }
}
