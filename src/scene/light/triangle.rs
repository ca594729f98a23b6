//! Diffuse area light on one emissive triangle (PBR 4th ed. §12.5 `DiffuseAreaLight`):
//! radiance on the front face, both faces when the material is double-sided; constant, or
//! the emission factor × an emissive texture at the point's uv (pbrt-v4 `DiffuseAreaLight`
//! with an `image`, §12.5.1).

use super::{EmissiveTexture, LeSample, LiSample};
use crate::math::{Frame, sampling};
use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_1_PI, PI};

#[derive(Clone, Debug, PartialEq)]
pub struct TriangleLight {
    /// Scene triangle index.
    pub tri: u32,
    /// Its material index.
    pub material: u32,
    /// Vertices in the mesh's order (CCW = front).
    pub v: [Vec3; 3],
    /// Unit geometric normal of the front face.
    pub n: Vec3,
    pub area: f32,
    /// Emitted radiance (linear RGB); the factor of the texture when there is one.
    pub emission: Vec3,
    pub two_sided: bool,
    /// Emissive texture: radiance = `emission` × texture(uv).rgb.
    pub texture: Option<EmissiveTexture>,
    /// Radiance averaged over the triangle (= `emission` untextured): the power estimate.
    pub mean_emission: Vec3,
}

impl TriangleLight {
    pub fn new(tri: u32, material: u32, v: [Vec3; 3], emission: Vec3, two_sided: bool) -> Self {
        let [a, b, c] = v;
        let n = (b - a).cross(c - a);
        let len = n.length();
        TriangleLight {
            tri,
            material,
            v,
            n: n / len,
            area: 0.5 * len,
            emission,
            two_sided,
            texture: None,
            mean_emission: emission,
        }
    }

    /// The light with an emissive texture (its power from the texture's mean over the
    /// triangle, `EmissiveTexture::mean`).
    pub fn with_texture(mut self, texture: EmissiveTexture) -> Self {
        self.mean_emission = self.emission * texture.mean();
        self.texture = Some(texture);
        self
    }

    /// A point sampled uniformly on the triangle (PBR 4th ed. §6.5.4).
    #[inline]
    pub fn sample_point(&self, u: Vec2) -> Vec3 {
        self.point_at(sampling::uniform_triangle(u))
    }

    /// The point at barycentrics `bc` = (b1, b2) (weights of vertices 1 and 2).
    #[inline]
    fn point_at(&self, bc: Vec2) -> Vec3 {
        let [a, b, c] = self.v;
        a * (1.0 - bc.x - bc.y) + b * bc.x + c * bc.y
    }

    /// Barycentrics (b1, b2) of a point `p` on the triangle, clamped into it (Ericson 2005,
    /// "Real-Time Collision Detection" §3.4, Cramer's rule on the edge Gram matrix).
    #[inline]
    pub fn barycentric(&self, p: Vec3) -> Vec2 {
        let [a, b, c] = self.v;
        let (e1, e2, d) = (b - a, c - a, p - a);
        let (d00, d01, d11) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
        let (d20, d21) = (d.dot(e1), d.dot(e2));
        let den = d00 * d11 - d01 * d01;
        // Degenerate (or NaN) triangle: any point is vertex 0.
        if den.is_nan() || den <= 0.0 {
            return Vec2::ZERO;
        }
        let b1 = ((d11 * d20 - d01 * d21) / den).clamp(0.0, 1.0);
        let b2 = ((d00 * d21 - d01 * d20) / den).clamp(0.0, 1.0 - b1);
        Vec2::new(b1, b2)
    }

    /// Emitted radiance at barycentrics `bc`: `emission` × texture (glTF 2.0 §3.9.2).
    #[inline]
    pub fn emission_at(&self, bc: Vec2) -> Vec3 {
        match &self.texture {
            Some(t) => self.emission * t.rgb(bc).max(Vec3::ZERO),
            None => self.emission,
        }
    }

    /// Emitted radiance at the point `p` of the triangle.
    #[inline]
    pub fn emission_at_point(&self, p: Vec3) -> Vec3 {
        match &self.texture {
            Some(_) => self.emission_at(self.barycentric(p)),
            None => self.emission,
        }
    }

    /// Area sampling converted to solid angle: pdf = p_pick/A · d²/|cosθ_l| (PBR 4th ed.
    /// eq. 12.3).
    #[inline]
    pub fn sample_li(&self, p: Vec3, u: Vec2, pick: f32) -> Option<LiSample> {
        let bc = sampling::uniform_triangle(u);
        let pl = self.point_at(bc);
        let nl = self.n;
        let to = pl - p;
        let dist2 = to.length_squared();
        if dist2 <= 0.0 {
            return None;
        }
        let wi = to / dist2.sqrt();
        let cos_l = -wi.dot(nl);
        if cos_l <= 0.0 && !self.two_sided {
            return None;
        }
        let cos_l = cos_l.abs();
        if cos_l <= 0.0 {
            return None;
        }
        Some(LiSample {
            l: self.emission_at(bc),
            wi,
            pdf: pick / self.area * dist2 / cos_l,
            p_light: pl,
            n_light: nl,
            is_delta: false,
            infinite: false,
        })
    }

    /// Solid-angle density of `sample_li` for a point at distance `dist` seen under
    /// `cos_light` (PBR 4th ed. eq. 12.3).
    #[inline]
    pub fn pdf_li(&self, pick: f32, dist: f32, cos_light: f32) -> f32 {
        if pick <= 0.0 || cos_light <= 0.0 || self.area <= 0.0 {
            return 0.0;
        }
        pick / self.area * dist * dist / cos_light
    }

    /// Emitted radiance towards `w` from the point `p` with raw normal `n`: one-sided unless
    /// double-sided (glTF `doubleSided`).
    #[inline]
    pub fn le(&self, p: Vec3, n: Vec3, w: Vec3) -> Vec3 {
        if n.dot(w) > 0.0 || self.two_sided {
            self.emission_at_point(p)
        } else {
            Vec3::ZERO
        }
    }

    /// Uniform point, cosine-weighted direction about the emitting face (PBR 4th ed.
    /// §12.5.1 `DiffuseAreaLight::SampleLe`); a two-sided emitter picks its face with
    /// `u_side`. A direction that degenerates to the tangent plane has `pdf_dir` 0 (the point
    /// still serves as a light vertex).
    #[inline]
    pub fn sample_le(&self, u_pos: Vec2, u_dir: Vec2, u_side: f32, pick: f32) -> Option<LeSample> {
        let bc = sampling::uniform_triangle(u_pos);
        let p = self.point_at(bc);
        let n = self.n;
        let mut local = sampling::cosine_hemisphere(u_dir);
        let side = if self.two_sided && u_side < 0.5 {
            -n
        } else {
            n
        };
        let two = if self.two_sided { 0.5 } else { 1.0 };
        let ok = local.z > 0.0;
        local.z = local.z.max(1e-7);
        Some(LeSample {
            p,
            n,
            dir: Frame::from_normal(side).to_world(local),
            l: self.emission_at(bc),
            pdf_pos: pick / self.area,
            pdf_dir: if ok { two * local.z * FRAC_1_PI } else { 0.0 },
            delta_pos: false,
            infinite: false,
        })
    }

    /// (area density including `pick`, solid-angle density) of emitting along `w` from a
    /// point with normal `n`.
    #[inline]
    pub fn pdf_le(&self, pick: f32, n: Vec3, w: Vec3) -> (f32, f32) {
        let c = n.dot(w);
        let pdf_dir = if self.two_sided {
            0.5 * c.abs() * FRAC_1_PI
        } else if c > 0.0 {
            c * FRAC_1_PI
        } else {
            0.0
        };
        let pdf_pos = if self.area > 0.0 {
            pick / self.area
        } else {
            0.0
        };
        (pdf_pos, pdf_dir)
    }

    /// Power π·L·A per emitting face (luminance; L averaged over a textured triangle).
    pub fn power(&self) -> f32 {
        let sides = if self.two_sided { 2.0 } else { 1.0 };
        sides * PI * super::luminance(self.mean_emission).max(1e-6) * self.area
    }
}
