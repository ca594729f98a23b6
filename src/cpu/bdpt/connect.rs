//! Connection strategies: (s, t ≥ 2) between a light and a camera subpath vertex, and
//! t = 1, light-subpath vertices splatted to the film (Veach 1997 §10.2).

use super::end::{End, lobes_of};
use super::vertex::{Kind, Vertex, to_area};
use super::{Bdpt, BdptMode, mis};
use crate::bsdf::TransportMode;
use crate::cpu::interaction::offset_ray_origin_towards;
use crate::cpu::medium::medium_transmittance;
use crate::cpu::spectral::{Spectral, finish_collapsed};
use crate::math::Color;
use crate::paths::Symbol;
use glam::Vec3;

/// Per-class values of one end of a connection (`None`: the light itself, no class).
type Classes = [(Option<Symbol>, Color); 2];

impl Bdpt<'_> {
    /// A full path's estimate: a dispersive vertex on either subpath collapses it.
    pub(super) fn finish(c: Color, collapse: bool) -> Color {
        finish_collapsed(c, collapse)
    }

    /// The light end of a connection towards `w` (unit, away from `y`): emission for s = 1,
    /// the adjoint BSDF per class otherwise.
    /// `ey` is y's evaluated end (s ≥ 2).
    fn light_end(y: &Vertex, s: usize, w: Vec3, sp: &Spectral, ey: Option<&End>) -> Classes {
        if s == 1 {
            let le = y.light().map_or(Vec3::ZERO, |(l, _)| l.le(y.p, y.ng, w));
            [(None, sp.c(le)), (None, Color::ZERO)]
        } else {
            let f = lobes_of(ey, y, w, TransportMode::Importance);
            [(Some(f[0].0), f[0].1), (Some(f[1].0), f[1].1)]
        }
    }

    /// Mutual visibility of two finite vertices, both ends offset by the same rule.
    fn visible(&self, a: &Vertex, b: &Vertex) -> bool {
        let d = b.p - a.p;
        let oa = if a.on_surface() {
            offset_ray_origin_towards(a.p, a.ng, a.ng.dot(d), self.pt.bvh.offset_scale())
        } else {
            a.p
        };
        let ob = if b.on_surface() {
            offset_ray_origin_towards(b.p, b.ng, b.ng.dot(-d), self.pt.bvh.offset_scale())
        } else {
            b.p
        };
        !self.pt.bvh.occluded(oa, ob - oa, 1.0)
    }

    /// Beer–Lambert along the connection of length √d2 leaving `v` along `w`.
    fn connection_transmittance(
        &self,
        v: &Vertex,
        w: Vec3,
        d2: f32,
        sp: &Spectral,
    ) -> Option<Color> {
        if !self.media {
            return None;
        }
        let m = v.medium_towards(w);
        m?;
        medium_transmittance(self.pt.scene, m, d2.sqrt(), sp)
    }

    /// t = 1: connect light vertex y = light[s-1] to the camera.
    pub(super) fn connect_camera(
        &self,
        light: &[Vertex],
        cam: &[Vertex],
        sp: &Spectral,
    ) -> Option<(u32, u32, Color)> {
        let s = light.len();
        let yv = &light[s - 1];
        if !yv.connectible() || yv.is_infinite_light() {
            return None;
        }
        let c0 = &cam[0];
        let to_cam = c0.p - yv.p;
        let d2 = to_cam.length_squared();
        if d2 <= 0.0 {
            return None;
        }
        let w = to_cam / d2.sqrt();
        let (px, py, cos_c) = self.cam.raster(-w)?;
        let ey = if s >= 2 { End::new(yv, w) } else { None };
        let mut contrib = Color::ZERO;
        for (cy, fv) in Self::light_end(yv, s, w, sp, ey.as_ref()) {
            if fv.max_element() <= 0.0 || !self.accepted(&light[..s - 1], cy, None, &cam[..1]) {
                continue;
            }
            contrib += fv;
        }
        if contrib.max_element() <= 0.0 {
            return None;
        }
        let cos_y = if yv.on_surface() {
            yv.ns.dot(w).abs()
        } else {
            1.0
        };
        // We·G with a pinhole: |cos_y| / (d² A_plane cos³θ) (PBR 3rd ed. §16.1.1).
        let we_g = cos_y / (d2 * self.cam.a_plane * cos_c * cos_c * cos_c);
        let mut v = yv.beta * contrib * we_g;
        if v.max_element() <= 0.0 || !self.visible(yv, c0) {
            return None;
        }
        if let Some(tr) = self.connection_transmittance(yv, w, d2, sp) {
            v *= tr;
        }
        if self.mode == BdptMode::Full {
            // Camera density of generating y (area), for the MIS ratio.
            let pdf_cam_y = to_area(self.cam.pdf_at_cos(cos_c), c0, yv);
            let p =
                self.connection_pdfs_at(light, &cam[..1], Some(pdf_cam_y), (None, ey.as_ref()), w);
            v *= mis::weight(light, &cam[..1], &p);
        }
        Some((px, py, Self::finish(v, yv.collapsed)))
    }

    /// Strategy (s = 0, t ≥ 2): the camera subpath hit an emitter.
    fn connect_emitter(&self, cam: &[Vertex], sp: &Spectral) -> Color {
        let t = cam.len();
        let z = &cam[t - 1];
        if z.kind != Kind::Surface {
            return Color::ZERO;
        }
        let Some((light, _)) = self.pt.lights.area_light(z.tri) else {
            return Color::ZERO;
        };
        let le = sp.c(light.le(z.p, z.ng, z.w_prev));
        // The emitter vertex itself is the L: feed the camera classes before it.
        if le.max_element() <= 0.0 || !self.accepted(&[], None, None, &cam[..t - 1]) {
            return Color::ZERO;
        }
        let v = z.beta * le;
        let w = if self.mode == BdptMode::Full {
            mis::weight(&[], cam, &self.connection_pdfs(&[], cam, t, None))
        } else {
            1.0
        };
        Self::finish(v * w, z.collapsed)
    }

    /// Strategy (s, t ≥ 2).
    pub(super) fn connect(&self, light: &[Vertex], cam: &[Vertex], sp: &Spectral) -> Color {
        let (s, t) = (light.len(), cam.len());
        if s == 0 {
            return self.connect_emitter(cam, sp);
        }
        let z = &cam[t - 1];
        let y = &light[s - 1];
        if z.kind != Kind::Surface || !z.connectible() || z.bsdf.is_none() || !y.connectible() {
            return Color::ZERO;
        }
        let infinite = y.is_infinite_light();
        let Some((w_zy, d2)) = Self::segment(y, z, infinite) else {
            return Color::ZERO;
        };
        let ez = End::new(z, w_zy);
        let ey = if s >= 2 { End::new(y, -w_zy) } else { None };
        let sum = self.accepted_lobes(light, cam, w_zy, (ey.as_ref(), ez.as_ref()), sp);
        if sum.max_element() <= 0.0 {
            return Color::ZERO;
        }
        let cos_z = z.ns.dot(w_zy).abs();
        let cos_y = if y.on_surface() {
            y.ns.dot(w_zy).abs()
        } else {
            1.0
        };
        let mut v = y.beta * sum * z.beta * (cos_z * cos_y / d2);
        if v.max_element() <= 0.0 || !self.connected(z, y, w_zy, infinite) {
            return Color::ZERO;
        }
        if !infinite && let Some(tr) = self.connection_transmittance(z, w_zy, d2, sp) {
            v *= tr;
        }
        let collapse = y.collapsed || z.collapsed;
        if infinite {
            // A light at infinity has two strategies only: this connection (s = 1) and the
            // camera subpath escaping towards it (s = 0, `env_escape_weight`).
            return Self::finish(v * self.infinite_weight(y, z, w_zy), collapse);
        }
        if self.mode != BdptMode::Full {
            return Self::finish(v, collapse);
        }
        let p = self.connection_pdfs_at(light, cam, None, (ez.as_ref(), ey.as_ref()), -w_zy);
        Self::finish(v * mis::weight(light, cam, &p), collapse)
    }

    /// The unit direction from the camera end `z` to the light end `y` and the squared
    /// distance (1 towards a light at infinity, which is reached along −n); `None` when the
    /// two coincide.
    #[inline(always)]
    fn segment(y: &Vertex, z: &Vertex, infinite: bool) -> Option<(Vec3, f32)> {
        if infinite {
            return Some((-y.ng, 1.0));
        }
        let d = y.p - z.p;
        let d2 = d.length_squared();
        if d2 <= 0.0 {
            return None;
        }
        Some((d / d2.sqrt(), d2))
    }

    /// f_y · f_z summed over the pairs of lobes (the classes each end scatters the
    /// connection into) whose whole path the Heckbert filter accepts.
    #[inline(always)]
    fn accepted_lobes(
        &self,
        light: &[Vertex],
        cam: &[Vertex],
        w_zy: Vec3,
        (ey, ez): (Option<&End>, Option<&End>),
        sp: &Spectral,
    ) -> Color {
        let (s, t) = (light.len(), cam.len());
        let (y, z) = (&light[s - 1], &cam[t - 1]);
        let fz = lobes_of(ez, z, w_zy, TransportMode::Radiance);
        let mut sum = Color::ZERO;
        for (cy, fyv) in Self::light_end(y, s, -w_zy, sp, ey) {
            for (cz, fzv) in fz {
                if fyv.max_element() <= 0.0 || fzv.max_element() <= 0.0 {
                    continue;
                }
                if self.accepted(&light[..s - 1], cy, Some(cz), &cam[..t - 1]) {
                    sum += fyv * fzv;
                }
            }
        }
        sum
    }

    /// Is the connection from `z` towards `y` (along `w_zy`) unoccluded?
    #[inline(always)]
    fn connected(&self, z: &Vertex, y: &Vertex, w_zy: Vec3, infinite: bool) -> bool {
        if infinite {
            let o =
                offset_ray_origin_towards(z.p, z.ng, z.ng.dot(w_zy), self.pt.bvh.offset_scale());
            !self.pt.bvh.occluded(o, w_zy, f32::INFINITY)
        } else {
            self.visible(z, y)
        }
    }
}
