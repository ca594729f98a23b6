//! The random walks of both subpaths: one loop for camera (radiance) and light (importance)
//! transport, on the shared per-vertex step (`Interaction`, `PathState`).

use super::vertex::{Kind, Vertex, to_area};
use super::{Bdpt, BdptMode};
use crate::bsdf::{BxDF, TransportMode};
use crate::cpu::interaction::{Bounce, Interaction, offset_ray_origin_towards, surface_with};
use crate::cpu::path_state::{Interface, PathState};
use crate::cpu::spectral::Spectral;
use crate::math::{Color, rng::Sampler};
use crate::paths::Symbol;
use glam::Vec3;

impl<'a> Bdpt<'a> {
    /// Random walk from `o` in direction `d` with state `st` and solid-angle pdf `pdf_w` of
    /// that direction (PBR 3rd ed. §16.3.2 structure). Appends vertices to `path`; returns the
    /// throughput, collapse flag and direction of a ray that escaped the scene.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn walk(
        &self,
        path: &mut Vec<Vertex<'a>>,
        (mut o, mut d): (Vec3, Vec3),
        mut st: PathState,
        mut pdf_w: f32,
        max_verts: usize,
        mode: TransportMode,
        sampler: &mut Sampler,
        sp: &Spectral,
    ) -> Option<(Color, bool, Vec3)> {
        let scene = self.pt.scene;
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
            let prev = path.len() - 1;
            let offset = self.pt.bvh.offset_scale();
            let Some(it) = Interaction::new(scene, &hit, d, sp, offset, enclosing) else {
                // Emitters and black back faces end the walk but an emitter still counts as
                // a vertex (s = 0 strategies hit it), with its raw normals.
                if scene.materials[hit.material as usize].is_emissive() {
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
                    v.pdf_fwd = to_area(pdf_w, &path[prev], &v);
                    path.push(v);
                }
                break;
            };
            st.arrive(&it);
            let mut v = Vertex::surface(scene, &it, &st, self.media);
            v.pdf_fwd = to_area(pdf_w, &path[prev], &v);
            path.push(v);
            if path.len() >= max_verts {
                break;
            }
            let cur = path.len() - 1;
            let (s, wi) = match it.sample(sampler.next_1d(), sampler.next_2d(), mode) {
                Bounce::Continue { s, wi } => (s, wi),
                Bounce::Absorbed | Bounce::Poisoned => break,
            };
            st.scatter_with(scene, &it, (&s, wi), mode, self.media);
            path[cur].class = Symbol::from(s.lobe);
            if s.is_delta {
                path[cur].delta = true;
                pdf_w = 0.0;
                path[cur - 1].pdf_rev = 0.0;
            } else {
                pdf_w = s.pdf;
                let rev = it.bsdf.pdf(s.wi, it.wo);
                path[cur - 1].pdf_rev = to_area(rev, &path[cur], &path[cur - 1]);
            }
            o = it.spawn(wi);
            d = wi;
            if !st.survives(self.pt.rr_depth, || sampler.next_1d()) {
                break;
            }
        }
        None
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
        let (o, cos) = if le.delta_pos || le.infinite {
            (le.p, 1.0)
        } else {
            (
                offset_ray_origin_towards(le.p, le.n, le.dir.dot(le.n), self.pt.bvh.offset_scale()),
                le.n.dot(le.dir).abs(),
            )
        };
        // β₁ = Le cosθ / (p_pos p_dir) (Veach 1997 §10.2; PBR 3rd ed. eq. 16.15).
        let beta = v0.beta * sp.c(le.l) * (cos / le.pdf_dir);
        self.walk(
            path,
            (o, le.dir),
            PathState::new(beta, false, self.pt.nested),
            le.pdf_dir,
            max_verts,
            TransportMode::Importance,
            sampler,
            sp,
        );
    }
}
