//! Light selection for next-event estimation: area-light triangles and punctual lights in one
//! discrete distribution proportional to (approximate) emitted power.

use super::{PunctualLight, Scene};
use crate::math::sampling;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// One entry of the light distribution.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightRef {
    /// Emissive triangle (scene triangle index).
    Triangle(u32),
    /// Index into `Scene::punctual_lights`.
    Punctual(u32),
}

/// Discrete light distribution (CDF over lights) plus per-triangle selection probabilities
/// (needed for MIS when a BSDF-sampled ray hits an emitter).
#[derive(Clone, Debug, Default)]
pub struct LightSet {
    pub lights: Vec<LightRef>,
    /// Inclusive CDF, last entry 1.
    pub cdf: Vec<f32>,
    /// Selection probability of each scene triangle (0 for non-emitters).
    pub tri_pick_prob: Vec<f32>,
}

/// Luminance of linear Rec.709 RGB (ITU-R BT.709 weights).
#[inline]
pub fn luminance(c: Vec3) -> f32 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}

impl LightSet {
    /// Build the distribution: area lights by power π·L·A (two-sided: 2π·L·A), point lights by
    /// 4π·I, spots by their cone solid angle, directional by irradiance × the scene's
    /// bounding-disk area.
    pub fn build(scene: &Scene) -> LightSet {
        let mut lights = Vec::new();
        let mut weights = Vec::new();
        for t in scene.emissive_triangles() {
            let m = &scene.materials[scene.mesh.tri_material[t as usize] as usize];
            let sides = if m.double_sided { 2.0 } else { 1.0 };
            let w = sides * PI * luminance(m.emission).max(1e-6) * scene.mesh.area(t as usize);
            lights.push(LightRef::Triangle(t));
            weights.push(w);
        }
        let (lo, hi) = scene.bounds();
        let radius = 0.5 * (hi - lo).length().max(1e-3);
        for (i, l) in scene.punctual_lights.iter().enumerate() {
            let w = match *l {
                PunctualLight::Point { intensity, .. } => 4.0 * PI * luminance(intensity),
                PunctualLight::Spot {
                    intensity,
                    cos_inner,
                    cos_outer,
                    ..
                } => 2.0 * PI * (1.0 - 0.5 * (cos_inner + cos_outer)) * luminance(intensity),
                PunctualLight::Directional { irradiance, .. } => {
                    PI * radius * radius * luminance(irradiance)
                }
            };
            lights.push(LightRef::Punctual(i as u32));
            weights.push(w.max(1e-9));
        }
        let total: f64 = weights.iter().map(|&w| w as f64).sum();
        let mut cdf = Vec::with_capacity(weights.len());
        let mut acc = 0.0f64;
        for w in &weights {
            acc += *w as f64;
            cdf.push((acc / total) as f32);
        }
        if let Some(last) = cdf.last_mut() {
            *last = 1.0;
        }
        let mut tri_pick_prob = vec![0.0f32; scene.mesh.triangle_count()];
        for (l, w) in lights.iter().zip(&weights) {
            if let LightRef::Triangle(t) = l {
                tri_pick_prob[*t as usize] = (*w as f64 / total) as f32;
            }
        }
        LightSet {
            lights,
            cdf,
            tri_pick_prob,
        }
    }

    pub fn is_empty(&self) -> bool {
        self.lights.is_empty()
    }

    /// Pick a light with `u` ∈ [0,1): (light, probability).
    #[inline]
    pub fn pick(&self, u: f32) -> Option<(LightRef, f32)> {
        if self.lights.is_empty() {
            return None;
        }
        let i = self
            .cdf
            .partition_point(|&c| c <= u)
            .min(self.lights.len() - 1);
        let prev = if i == 0 { 0.0 } else { self.cdf[i - 1] };
        let p = self.cdf[i] - prev;
        if p <= 0.0 {
            return None;
        }
        Some((self.lights[i], p))
    }
}

/// A point sampled uniformly on triangle `t`: (position, unit geometric normal, area).
#[inline]
pub fn sample_triangle(scene: &Scene, t: u32, u: Vec2) -> (Vec3, Vec3, f32) {
    let [a, b, c] = scene.mesh.tri(t as usize);
    let bc = sampling::uniform_triangle(u);
    let p = a * (1.0 - bc.x - bc.y) + b * bc.x + c * bc.y;
    let n = (b - a).cross(c - a);
    let len = n.length();
    (p, n / len, 0.5 * len)
}

/// glTF spot-light angular falloff (KHR_lights_punctual spec, "Spot"): smooth, squared
/// linear ramp of cosθ between the outer and inner cone.
#[inline]
pub fn spot_falloff(cos_theta: f32, cos_inner: f32, cos_outer: f32) -> f32 {
    let scale = 1.0 / (cos_inner - cos_outer).max(1e-3);
    let offset = -cos_outer * scale;
    let a = (cos_theta * scale + offset).clamp(0.0, 1.0);
    a * a
}
