//! The scene's lights and the discrete distribution next-event estimation and light tracing
//! pick them from: proportional to (approximate) emitted power (pbrt-v4 `PowerLightSampler`).

use super::{
    DirectionalLight, EmissiveTexture, ImageEnvironment, Light, PointLight, SpotLight,
    TriangleLight, UniformEnvironment,
};
use crate::scene::{PunctualLight, Scene, Texture};
use glam::Vec3;
use std::collections::HashMap;
use std::sync::Arc;

/// The lights of a scene with their selection CDF.
#[derive(Clone, Debug)]
pub struct LightSet {
    /// Area and punctual lights, in the order of the CDF.
    pub lights: Vec<Light>,
    /// Inclusive CDF, last entry 1.
    pub cdf: Vec<f32>,
    /// Selection probability of each scene triangle (0 for non-emitters).
    pub tri_pick_prob: Vec<f32>,
    /// Index into `lights` of each scene triangle's area light (`u32::MAX`: none).
    tri_light: Vec<u32>,
    /// The environment escaping rays read: a uniform one (not in the distribution) or the
    /// image environment (also the last entry of `lights`).
    pub environment: Light,
    /// Selection probability of the environment in the distribution (0: not in it, so an
    /// escaping ray takes it with MIS weight 1).
    pub env_pick: f32,
}

impl Default for LightSet {
    fn default() -> Self {
        LightSet {
            lights: Vec::new(),
            cdf: Vec::new(),
            tri_pick_prob: Vec::new(),
            tri_light: Vec::new(),
            environment: Light::Environment(UniformEnvironment {
                radiance: Vec3::ZERO,
                center: Vec3::ZERO,
                radius: 1.0,
            }),
            env_pick: 0.0,
        }
    }
}

/// The scene's lights: emissive triangles first, then `KHR_lights_punctual` lights.
fn scene_lights(scene: &Scene, center: Vec3, radius: f32) -> Vec<Light> {
    let mut lights = area_lights(scene);
    lights.extend(
        scene
            .punctual_lights
            .iter()
            .map(|l| punctual_light(l, center, radius)),
    );
    if let Some(img) = &scene.env_map {
        lights.push(Light::Image(ImageEnvironment::new(
            img.clone(),
            center,
            radius,
        )));
    }
    lights
}

/// One area light per emissive triangle, in `Scene::emissive_triangles` order.
fn area_lights(scene: &Scene) -> Vec<Light> {
    // Each emissive texture is shared by the triangles that read it (one copy of its texels).
    let mut shared: HashMap<u32, Arc<Texture>> = HashMap::new();
    scene
        .emissive_triangles()
        .into_iter()
        .map(|t| Light::Triangle(triangle_light(scene, t, &mut shared)))
        .collect()
}

/// The area light of emissive triangle `t`, with its emissive texture (taken from, or added
/// to, `shared`) when it has one.
fn triangle_light(scene: &Scene, t: u32, shared: &mut HashMap<u32, Arc<Texture>>) -> TriangleLight {
    let mi = scene.mesh.tri_material[t as usize];
    let m = &scene.materials[mi as usize];
    let v = scene.mesh.tri(t as usize);
    let light = TriangleLight::new(t, mi, v, m.emission, m.double_sided);
    let Some(r) = m.emissive_texture else {
        return light;
    };
    let Some(tex) = scene.textures.get(r.texture as usize) else {
        return light;
    };
    let texture = shared
        .entry(r.texture)
        .or_insert_with(|| Arc::new(tex.clone()))
        .clone();
    let uv = scene.mesh.indices[t as usize]
        .map(|i| scene.mesh.uvs.get(i as usize).copied().unwrap_or_default());
    light.with_texture(EmissiveTexture {
        texture,
        transform: r.transform,
        uv,
    })
}

/// The light of a `KHR_lights_punctual` light (a directional one covers the scene's bounding
/// sphere at `center`, `radius`).
fn punctual_light(l: &PunctualLight, center: Vec3, radius: f32) -> Light {
    match *l {
        PunctualLight::Point {
            position,
            intensity,
        } => Light::Point(PointLight {
            position,
            intensity,
        }),
        PunctualLight::Spot {
            position,
            direction,
            intensity,
            cos_inner,
            cos_outer,
        } => Light::Spot(SpotLight {
            position,
            direction,
            intensity,
            cos_inner,
            cos_outer,
        }),
        PunctualLight::Directional {
            direction,
            irradiance,
        } => Light::Directional(DirectionalLight {
            direction,
            irradiance,
            center,
            radius,
        }),
    }
}

impl LightSet {
    /// Build the lights and their distribution: area lights by power π·L·A (two-sided:
    /// 2π·L·A; L averaged over the triangle when textured), point lights by 4π·I, spots by their cone solid angle, directional by
    /// irradiance × the scene's bounding-disk area.
    pub fn build(scene: &Scene) -> LightSet {
        let (lo, hi) = scene.bounds();
        let center = 0.5 * (lo + hi);
        let radius = 0.5 * (hi - lo).length().max(1e-3);
        let lights = scene_lights(scene, center, radius);
        let weights: Vec<f32> = lights
            .iter()
            .map(|l| match l {
                Light::Triangle(t) => t.power(),
                other => other.power().max(1e-9),
            })
            .collect();
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
        let n_tris = scene.mesh.triangle_count();
        let mut tri_pick_prob = vec![0.0f32; n_tris];
        let mut tri_light = vec![u32::MAX; n_tris];
        for (i, (l, w)) in lights.iter().zip(&weights).enumerate() {
            if let Light::Triangle(t) = l {
                tri_pick_prob[t.tri as usize] = (*w as f64 / total) as f32;
                tri_light[t.tri as usize] = i as u32;
            }
        }
        let (environment, env_pick) = match lights.last() {
            Some(l @ Light::Image(_)) => (
                l.clone(),
                (*weights.last().unwrap_or(&0.0) as f64 / total) as f32,
            ),
            _ => (
                Light::Environment(UniformEnvironment {
                    radiance: scene.environment,
                    center,
                    radius,
                }),
                0.0,
            ),
        };
        LightSet {
            lights,
            cdf,
            tri_pick_prob,
            tri_light,
            environment,
            env_pick,
        }
    }

    /// MIS weight of the environment reached by an escaping ray along `d` after a BSDF
    /// sample of density `prev_pdf` (power heuristic against `sample_li`; 1 after a delta
    /// lobe or when the environment is not in the distribution).
    #[inline]
    pub fn env_weight(&self, d: Vec3, prev_pdf: f32, prev_delta: bool) -> f32 {
        if prev_delta || self.env_pick <= 0.0 {
            return 1.0;
        }
        let p_light = self.environment.pdf_li(self.env_pick, d, 1.0, 1.0);
        crate::math::sampling::power_heuristic(prev_pdf, p_light)
    }

    pub fn is_empty(&self) -> bool {
        self.lights.is_empty()
    }

    /// Pick a light with `u` ∈ [0,1): (light, probability).
    #[inline]
    pub fn pick(&self, u: f32) -> Option<(&Light, f32)> {
        if self.lights.is_empty() {
            return None;
        }
        let i = self
            .cdf
            .partition_point(|&c| c <= u)
            .min(self.lights.len() - 1);
        // A select, not a branch (which light is picked is random per sample).
        let prev = std::hint::select_unpredictable(i > 0, self.cdf[i.saturating_sub(1)], 0.0);
        let p = self.cdf[i] - prev;
        if p <= 0.0 {
            return None;
        }
        Some((&self.lights[i], p))
    }

    /// The area light on scene triangle `tri` and its selection probability, if it emits.
    #[inline]
    pub fn area_light(&self, tri: u32) -> Option<(&Light, f32)> {
        let i = *self.tri_light.get(tri as usize)?;
        let l = self.lights.get(i as usize)?;
        Some((l, self.tri_pick_prob[tri as usize]))
    }
}
