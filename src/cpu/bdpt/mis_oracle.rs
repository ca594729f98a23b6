//! The direct form of the MIS ratio recurrence (Veach 1997 §10.2), kept as the test oracle of
//! the O(1) partial-sum form in `mis`: copies of the connection vertices get their new reverse
//! densities and the ratios are multiplied out along both subpaths for every connection.

use super::Bdpt;
use super::vertex::{Vertex, remap0, to_area};
use crate::bsdf::BxDF;
use crate::math::Frame;

impl Bdpt<'_> {
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
