//! Power-heuristic MIS weights of the bidirectional strategies by the ratio recurrence of
//! Veach 1997 §10.2 (each vertex stores the area densities of being generated from either
//! side; the weight of strategy (s,t) is 1 / Σ_i (p_i/p_s)², delta vertices excluded).

use super::Bdpt;
use super::vertex::{Vertex, remap0, to_area};
use crate::bsdf::BxDF;
use crate::math::Frame;

impl Bdpt<'_> {
    /// Solid-angle density of sampling the BSDF at surface vertex `z` towards `w` (from
    /// its predecessor's direction); 0 for delta lobes.
    fn bsdf_pdf_dir(&self, z: &Vertex, w: glam::Vec3) -> f32 {
        match z.bsdf {
            Some(b) if !b.is_delta() => {
                let frame = Frame::from_normal(z.ns);
                b.pdf(frame.to_local(z.w_prev), frame.to_local(w))
            }
            _ => 0.0,
        }
    }

    /// Power-heuristic weight of connecting camera vertex `z` to the light at infinity `y`
    /// along `w` (s = 1) against the camera subpath's BSDF sample escaping along `w` (s = 0);
    /// 1 for a delta direction (directional light). Veach 1997 §9.2.4.
    pub(super) fn infinite_weight(&self, y: &Vertex, z: &Vertex, w: glam::Vec3) -> f32 {
        let Some((light, pick)) = y.light() else {
            return 1.0;
        };
        let p_light = light.pdf_li(pick, w, 1.0, 1.0);
        if p_light <= 0.0 {
            return 1.0;
        }
        crate::math::sampling::power_heuristic(p_light, self.bsdf_pdf_dir(z, w))
    }

    /// The weight of the camera subpath `cam` escaping along `d` to the environment (s = 0)
    /// against the s = 1 connection at its last vertex.
    pub(super) fn env_escape_weight(&self, cam: &[Vertex], d: glam::Vec3) -> f32 {
        match cam.last() {
            Some(z) if cam.len() >= 2 && !z.delta => {
                self.pt.lights.env_weight(d, self.bsdf_pdf_dir(z, d), false)
            }
            _ => 1.0,
        }
    }

    /// Area density at `to` of sampling the BSDF at `v` given the other direction `w_other`.
    pub(super) fn bsdf_pdf_area(&self, v: &Vertex, w_other: glam::Vec3, to: &Vertex) -> f32 {
        let Some(b) = v.bsdf else {
            return 0.0;
        };
        if b.is_delta() {
            return 0.0;
        }
        let frame = Frame::from_normal(v.ns);
        let w = (to.p - v.p).normalize_or_zero();
        let pdf = b.pdf(frame.to_local(w_other), frame.to_local(w));
        to_area(pdf, v, to)
    }

    /// Solid-angle density with which light vertex `y` emits towards `w`.
    pub(super) fn light_pdf_dir(&self, y: &Vertex, w: glam::Vec3) -> f32 {
        y.light().map_or(0.0, |(l, pick)| l.pdf_le(pick, y.ng, w).1)
    }

    /// Area density of choosing surface vertex `z` as a light-subpath origin.
    pub(super) fn light_point_pdf(&self, z: &Vertex) -> f32 {
        self.pt
            .lights
            .area_light(z.tri)
            .map_or(0.0, |(l, pick)| l.pdf_le(pick, z.ng, z.ng).0)
    }

    /// Emission density (area, at `to`) of the emitter vertex `z` sending light to `to`.
    fn emission_pdf_area(&self, z: &Vertex, to: &Vertex) -> f32 {
        let w = (to.p - z.p).normalize_or_zero();
        let pdf_w = self
            .pt
            .lights
            .area_light(z.tri)
            .map_or(0.0, |(l, pick)| l.pdf_le(pick, z.ng, w).1);
        to_area(pdf_w, z, to)
    }

    /// The reverse densities of the connection vertices of strategy (s, t): returns the
    /// modified copies of (y_{s-1}, y_{s-2}) and (z_{t-1}, z_{t-2}).
    fn connection_densities<'v>(
        &self,
        light: &[Vertex<'v>],
        cam: &[Vertex<'v>],
        t: usize,
        pdf_cam_y: Option<f32>,
    ) -> ([Vertex<'v>; 2], [Vertex<'v>; 2]) {
        let s = light.len();
        let mut lv: [Vertex; 2] = [light.last().copied().unwrap_or(cam[0]); 2];
        let mut cv: [Vertex; 2] = [cam[t - 1]; 2];
        if s >= 2 {
            lv[1] = light[s - 2];
        }
        if t >= 2 {
            cv[1] = cam[t - 2];
        }
        let y = if s >= 1 { Some(light[s - 1]) } else { None };
        let z = cam[t - 1];
        // z.pdf_rev: density of z generated from the light side (for s = 0 z is on an
        // emitter: the density of choosing it as a light point).
        cv[0].pdf_rev = match y {
            Some(yv) if s == 1 => to_area(
                self.light_pdf_dir(&yv, (z.p - yv.p).normalize_or_zero()),
                &yv,
                &z,
            ),
            Some(yv) => self.bsdf_pdf_area(&yv, yv.w_prev, &z),
            None => self.light_point_pdf(&z),
        };
        // z_{t-2}.pdf_rev: density of z_{t-2} generated from z.
        if t >= 2 {
            cv[1].pdf_rev = match y {
                Some(yv) => self.bsdf_pdf_area(&z, (yv.p - z.p).normalize_or_zero(), &cam[t - 2]),
                None => self.emission_pdf_area(&z, &cam[t - 2]),
            };
        }
        // y.pdf_rev: density of y generated from the camera side.
        if let Some(yv) = y {
            lv[0].pdf_rev = if t == 1 {
                pdf_cam_y.unwrap_or(0.0)
            } else {
                self.bsdf_pdf_area(&z, z.w_prev, &yv)
            };
            if s >= 2 {
                lv[1].pdf_rev =
                    self.bsdf_pdf_area(&yv, (z.p - yv.p).normalize_or_zero(), &light[s - 2]);
            }
        }
        (lv, cv)
    }

    /// Power-heuristic MIS weight of strategy (s = light.len(), t) for the path light + cam.
    /// `pdf_cam_y` is the camera density of the light end vertex for t = 1.
    pub(super) fn mis_weight(
        &self,
        light: &[Vertex],
        cam: &[Vertex],
        t: usize,
        pdf_cam_y: Option<f32>,
    ) -> f32 {
        let s = light.len();
        if s + t == 2 {
            return 1.0; // only (0,2) exists for paths of one segment (see `sample`)
        }
        let (lv, cv) = self.connection_densities(light, cam, t, pdf_cam_y);
        let cam_at = |i: usize| -> &Vertex {
            if i == t - 1 {
                &cv[0]
            } else if t >= 2 && i == t - 2 {
                &cv[1]
            } else {
                &cam[i]
            }
        };
        let light_at = |i: usize| -> &Vertex {
            if i == s - 1 {
                &lv[0]
            } else if s >= 2 && i == s - 2 {
                &lv[1]
            } else {
                &light[i]
            }
        };
        let mut sum = 0.0f32;
        let mut ri = 1.0f32;
        // Strategies with fewer camera vertices.
        for i in (1..t).rev() {
            let v = cam_at(i);
            ri *= remap0(v.pdf_rev) / remap0(v.pdf_fwd);
            if !v.delta && !cam_at(i - 1).delta {
                sum += ri * ri;
            }
        }
        // Strategies with fewer light vertices.
        ri = 1.0;
        for i in (0..s).rev() {
            let v = light_at(i);
            ri *= remap0(v.pdf_rev) / remap0(v.pdf_fwd);
            let prev_delta = if i > 0 {
                light_at(i - 1).delta
            } else {
                light_at(0).is_delta_light()
            };
            if !v.delta && !prev_delta {
                sum += ri * ri;
            }
        }
        1.0 / (1.0 + sum)
    }
}
