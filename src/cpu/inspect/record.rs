//! What the path inspector records, in the JSON shape `refract trace --json` prints:
//! `{"pixel":[x,y],"paths":[{"heckbert":"LSSDE","contribution":[r,g,b],"vertices":[{"p":…,
//! "class":"S","event":"refract","material":"glass","eta_i":1.0,"eta_t":1.5,"cos_i":0.8,
//! "cos_t":0.9,"fresnel":0.04,"throughput":[r,g,b]}, …]}]}` (plus a few extra fields).

use crate::bsdf::Bsdf;
use crate::cpu::observer::PathEnd;
use crate::paths::Symbol;
use glam::Vec3;
use serde::{Serialize, Serializer};

/// What happened at a vertex.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum VertexEvent {
    /// The eye (the path's first vertex).
    Camera,
    /// Specular reflection: a mirror, or Fresnel reflection at a dielectric (F < 1).
    Reflect,
    /// Specular transmission through a smooth (or thin) dielectric.
    Refract,
    /// Total internal reflection: η_i sinθ_i / η_t ≥ 1 at a smooth dielectric (F = 1).
    Tir,
    /// A diffuse (Lambertian) bounce.
    Diffuse,
    /// A rough (microfacet) lobe, reflected or transmitted.
    Glossy,
    /// The path ends on an emitter (an area light or the environment).
    Emission,
    /// The path ends here without scattering (depth limit, failed sample, back face).
    Absorbed,
}

/// One vertex of a camera path, in the order the walk visits them (the camera first).
#[derive(Clone, Debug, Serialize)]
pub struct VertexRecord {
    pub p: [f32; 3],
    /// Heckbert class L, D, G, S or E.
    #[serde(serialize_with = "symbol_str")]
    pub class: Symbol,
    pub event: VertexEvent,
    pub material: String,
    /// IOR of the medium the path arrives in and of the medium across the surface (the one a
    /// transmission enters); equal at opaque and thin surfaces.
    pub eta_i: f32,
    pub eta_t: f32,
    /// |cos θ_i| of the arriving direction against the shading normal (null at the camera).
    pub cos_i: Option<f32>,
    /// |cos θ_t|: at a dielectric, of the refracted direction (0 under total internal
    /// reflection, also when the sample reflected); elsewhere of the scattered direction
    /// (null where nothing scatters).
    pub cos_t: Option<f32>,
    /// The reflectance the step chose its event with: the exact dielectric Fresnel term at a
    /// smooth dielectric, R' of a thin sheet; null where no Fresnel term decides the event.
    pub fresnel: Option<f32>,
    /// Path throughput carried by the segment leaving this vertex (after its BSDF weight and
    /// Russian roulette; on arrival where the path ends), linear RGB.
    pub throughput: [f32; 3],
    /// Emitted radiance picked up here, times throughput and MIS weight (emitters only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub emitted: Option<[f32; 3]>,
    /// The relative IOR n_t/n_i the BSDF sample crossed (1 for reflection), as the step used
    /// it; not printed (tests compare it with eta_t/eta_i).
    #[serde(skip)]
    pub step_eta_rel: Option<f32>,
    /// The BSDF the step scattered with and the direction towards the previous vertex, in
    /// the shading frame: what the inspector's lobe plot evaluates. Not printed.
    #[serde(skip)]
    pub scatter: Option<ScatterRecord>,
}

/// A vertex's BSDF as the walk resolved it (textures looked up, η chosen for the path's
/// wavelengths) and the local direction `wo` towards where the path came from.
#[derive(Clone, Copy, Debug)]
pub struct ScatterRecord {
    pub bsdf: Bsdf,
    pub wo: Vec3,
    /// The colour lanes hold four hero wavelengths rather than RGB.
    pub spectral: bool,
}

/// A next-event (shadow-ray) connection from a vertex to a point on a light: drawn dashed.
#[derive(Clone, Debug, Serialize)]
pub struct ConnectionRecord {
    /// Index into the path's `vertices` of the vertex the connection starts at.
    pub from: usize,
    /// The sampled point on the light (a point far along the direction for infinite lights).
    pub p: [f32; 3],
    /// The Heckbert string of the light path this connection completes, e.g. `LDSE`.
    pub heckbert: String,
    /// Its contribution to the pixel (throughput × BSDF × Le × MIS weight / pdf), linear RGB.
    pub contribution: [f32; 3],
    /// The shadow ray was blocked.
    pub occluded: bool,
    /// The light is at infinity (environment, directional light).
    pub at_infinity: bool,
}

/// One camera sample through the pixel.
#[derive(Clone, Debug, Serialize)]
pub struct PathRecord {
    /// Heckbert string of the walk's vertices, light → eye (`LSSDE`); no leading `L` when the
    /// walk ended without reaching a light.
    pub heckbert: String,
    /// The sample's estimate (what `render` adds to the pixel): every connection plus the
    /// emission reached, linear RGB.
    pub contribution: [f32; 3],
    pub vertices: Vec<VertexRecord>,
    pub connections: Vec<ConnectionRecord>,
    pub end: PathEnd,
    /// Direction of the last segment when the path escaped the scene (world, unit).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub escape_dir: Option<[f32; 3]>,
    /// Hero wavelengths (nm) of a spectral path (scenes with dispersion).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lambda_nm: Option<[f32; 4]>,
}

/// Every path traced through one pixel.
#[derive(Clone, Debug, Serialize)]
pub struct PixelTrace {
    pub pixel: [u32; 2],
    pub width: u32,
    pub height: u32,
    pub seed: u32,
    /// Mean contribution over the paths: the pixel's estimate at this many samples.
    pub mean: [f32; 3],
    pub paths: Vec<PathRecord>,
}

impl PixelTrace {
    pub fn new(
        pixel: [u32; 2],
        (width, height): (u32, u32),
        seed: u32,
        paths: Vec<PathRecord>,
    ) -> Self {
        let mut sum = [0f64; 3];
        for p in &paths {
            for (s, c) in sum.iter_mut().zip(p.contribution) {
                *s += c as f64;
            }
        }
        let n = paths.len().max(1) as f64;
        PixelTrace {
            pixel,
            width,
            height,
            seed,
            mean: sum.map(|s| (s / n) as f32),
            paths,
        }
    }

    /// The trace as one line of JSON.
    pub fn to_json(&self) -> anyhow::Result<String> {
        serde_json::to_string(self).map_err(|e| anyhow::anyhow!("path trace as JSON: {e}"))
    }
}

/// The classes of `vertices` read light → eye (Heckbert's order), e.g. `LSSDE`.
pub fn heckbert_string(vertices: &[VertexRecord]) -> String {
    vertices.iter().rev().map(|v| v.class.as_char()).collect()
}

fn symbol_str<S: Serializer>(s: &Symbol, ser: S) -> Result<S::Ok, S::Error> {
    ser.serialize_char(s.as_char())
}
