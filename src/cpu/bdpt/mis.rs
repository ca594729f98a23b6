//! Power-heuristic MIS weights of the bidirectional strategies by the ratio recurrence of
//! Veach 1997 §10.2 (each vertex stores the area densities of being generated from either
//! side; the weight of strategy (s,t) is 1 / Σ_i (p_i/p_s)², delta vertices excluded).
//!
//! The sums are evaluated in O(1) per connection: a connection changes only the reverse
//! densities of its two end vertices and their predecessors, so everything further along
//! each subpath is a partial sum stored once per vertex after the walks (`prefix_sums`), in
//! Horner form Σ_{i≤k} Π_{j=i..k} r_j² = r_k² (1 + Σ_{i≤k−1} …) — the recursive form of
//! Veach 1997 §10.2.1 and the sub-path quantities of Georgiev et al. 2012 ("Light Transport
//! Simulation with Vertex Connection and Merging", §4; tech. report "Implementing VCM").
//! `mis_oracle` (tests) keeps the direct recurrence as the reference.

use super::Bdpt;
use super::end::End;
use super::vertex::Kind;
use super::vertex::{Vertex, remap0, to_area};
use crate::bsdf::BxDF;

impl Bdpt<'_> {
    /// Solid-angle density of sampling the BSDF at surface vertex `z` towards `w` (from
    /// its predecessor's direction); 0 for delta lobes.
    fn bsdf_pdf_dir(&self, z: &Vertex, w: glam::Vec3) -> f32 {
        match z.bsdf {
            Some(b) if !b.is_delta() => b.pdf(z.wo, z.frame.to_local(w)),
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
    pub(super) fn emission_pdf_area(&self, z: &Vertex, to: &Vertex) -> f32 {
        let w = (to.p - z.p).normalize_or_zero();
        let pdf_w = self
            .pt
            .lights
            .area_light(z.tri)
            .map_or(0.0, |(l, pick)| l.pdf_le(pick, z.ng, w).1);
        to_area(pdf_w, z, to)
    }

    /// The reverse area densities strategy (s = light.len(), t) gives the connection vertices
    /// z = cam[t−1], cam[t−2], y = light[s−1], light[s−2] (`pdf_cam_y`: the camera density
    /// of y for t = 1).
    pub(super) fn connection_pdfs(
        &self,
        light: &[Vertex],
        cam: &[Vertex],
        t: usize,
        pdf_cam_y: Option<f32>,
    ) -> ConnectionPdfs {
        let cam = &cam[..t];
        let (z, y) = (&cam[t - 1], light.last());
        let w_zy = y.map_or(glam::Vec3::ZERO, |y| (y.p - z.p).normalize_or_zero());
        let ez = (t >= 2 && y.is_some()).then(|| End::new(z, w_zy)).flatten();
        let ey = y
            .filter(|_| light.len() >= 2)
            .and_then(|y| End::new(y, -w_zy));
        self.connection_pdfs_at(light, cam, pdf_cam_y, (ez.as_ref(), ey.as_ref()), -w_zy)
    }

    /// `connection_pdfs` (t = cam.len()) with the end vertices already evaluated along the
    /// connection: `ez` for t ≥ 2 and `ey` for s ≥ 2 (`None`: no non-delta BSDF there);
    /// `w_yz`: the unit direction from y to z.
    pub(super) fn connection_pdfs_at(
        &self,
        light: &[Vertex],
        cam: &[Vertex],
        pdf_cam_y: Option<f32>,
        (ez, ey): (Option<&End>, Option<&End>),
        w_yz: glam::Vec3,
    ) -> ConnectionPdfs {
        let (s, t) = (light.len(), cam.len());
        let z = &cam[t - 1];
        let mut p = ConnectionPdfs::default();
        let Some(y) = light.last() else {
            // s = 0: z is on an emitter, generated from the light side as a light point.
            p.z = self.light_point_pdf(z);
            if t >= 2 {
                p.z_prev = self.emission_pdf_area(z, &cam[t - 2]);
            }
            return p;
        };
        let pdf = |e: Option<&End>, f: &dyn Fn(&End) -> f32| e.map_or(0.0, f);
        let towards = |v: &Vertex, to: &Vertex| (to.p - v.p).normalize_or_zero();
        p.z = if s == 1 {
            to_area(self.light_pdf_dir(y, w_yz), y, z)
        } else {
            to_area(pdf(ey, &|e| e.pdf_out()), y, z)
        };
        if t >= 2 {
            let zp = &cam[t - 2];
            p.z_prev = to_area(pdf(ez, &|e| e.pdf_back(towards(z, zp))), z, zp);
            p.y = to_area(pdf(ez, &|e| e.pdf_out()), z, y);
        } else {
            p.y = pdf_cam_y.unwrap_or(0.0);
        }
        if s >= 2 {
            let yp = &light[s - 2];
            p.y_prev = to_area(pdf(ey, &|e| e.pdf_back(towards(y, yp))), y, yp);
        }
        p
    }
}

/// The reverse area densities a connection gives its end vertices and their predecessors.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct ConnectionPdfs {
    /// z = cam[t−1] generated from y (for s = 0: as a point on the light).
    pub z: f32,
    /// cam[t−2] generated from z (for s = 0: emitted by the light at z).
    pub z_prev: f32,
    /// y = light[s−1] generated from z (for t = 1: by the camera).
    pub y: f32,
    /// light[s−2] generated from y.
    pub y_prev: f32,
}

/// One step of the Horner form: the partial sum including a vertex with density ratio `r`
/// (Veach 1997 §10.2: r = p_rev / p_fwd, delta densities counted as 1) whose strategy exists
/// (`counts`) on top of the partial sum `acc` of the vertices behind it.
#[inline]
fn extend(acc: f32, r: f32, counts: bool) -> f32 {
    let inner = acc + if counts { 1.0 } else { 0.0 };
    // An infinite ratio must not turn an empty sum into NaN.
    if inner > 0.0 { r * r * inner } else { 0.0 }
}

/// Whether the strategy that samples vertex `i` of a subpath from the other side exists: it
/// and its predecessor are not delta (a light subpath's origin: not a delta-position light).
#[inline]
fn strategy_exists(path: &[Vertex], i: usize) -> bool {
    let prev_delta = if i > 0 {
        path[i - 1].delta
    } else {
        path[0].is_delta_light()
    };
    !path[i].delta && !prev_delta
}

#[inline]
fn ratio(rev: f32, v: &Vertex) -> f32 {
    remap0(rev) / remap0(v.pdf_fwd)
}

/// Fill `mis_sum` along a finished subpath from the densities its walk stored. The camera
/// vertex itself is never sampled from the light side (no term).
pub(super) fn prefix_sums(path: &mut [Vertex]) {
    let mut acc = 0.0;
    for i in 0..path.len() {
        if path[i].kind != Kind::Camera {
            acc = extend(
                acc,
                ratio(path[i].pdf_rev, &path[i]),
                strategy_exists(path, i),
            );
        }
        path[i].mis_sum = acc;
    }
}

/// Σ over one subpath's other strategies for a connection at `path[n − 1]` whose new reverse
/// densities are `rev_end` and `rev_prev` (of `path[n − 2]`). `first`: index of the first
/// vertex with a term (1 on the camera subpath, 0 on the light subpath).
#[inline]
fn side_sum(path: &[Vertex], first: usize, rev_end: f32, rev_prev: f32) -> f32 {
    let n = path.len();
    if n <= first {
        return 0.0;
    }
    let mut acc = 0.0;
    if n >= first + 2 {
        acc = if n >= 3 { path[n - 3].mis_sum } else { 0.0 };
        acc = extend(
            acc,
            ratio(rev_prev, &path[n - 2]),
            strategy_exists(path, n - 2),
        );
    }
    extend(
        acc,
        ratio(rev_end, &path[n - 1]),
        strategy_exists(path, n - 1),
    )
}

/// Power-heuristic weight of strategy (s = light.len(), t = cam.len()) from the subpaths'
/// partial sums and the connection's densities (`Bdpt::connection_pdfs`).
pub(super) fn weight(light: &[Vertex], cam: &[Vertex], p: &ConnectionPdfs) -> f32 {
    if light.len() + cam.len() == 2 {
        return 1.0; // only (0,2) exists for paths of one segment (see `sample`)
    }
    let sum = side_sum(cam, 1, p.z, p.z_prev) + side_sum(light, 0, p.y, p.y_prev);
    1.0 / (1.0 + sum)
}
