//! Lights as one interface (pbrt-v4 `Light`, PBR 4th ed. ch. 12; Mitsuba 3 `Emitter`): every
//! walk — CPU path tracing, CPU BDPT and light tracing, and their WGSL twins in
//! `src/scene/light/light.wgsl` — samples and evaluates lights only through these methods and
//! never matches on the light type itself.
//!
//! - `sample_li` / `pdf_li`: incident illumination at a reference point (next-event
//!   estimation, and the MIS density of a BSDF-sampled ray that hits an area light);
//! - `sample_le` / `pdf_le`: emission of a light subpath (light tracing, BDPT, photons);
//! - `le`: radiance leaving a point of the light (or arriving from an infinite light).
//!
//! Densities are returned with the light-selection probability `pick` already folded in, in
//! the order of operations the walks used before the interface existed (so images stayed
//! bit-identical).
//!
//! The WGSL twin differs in one documented way (tests/light_twin.rs asserts it):
//! `light_sample_le` draws a two-sided emitter's side from the sampler it is given, where
//! `sample_le` takes it as `u_side` (the CPU walks always draw it). Lights at infinity emit
//! from the scene's bounding disk on both (the GPU `Light` entry carries the sphere).
//!
//! The environment image (`ImageEnvironment`) is the one light at infinity in the selection
//! distribution: next-event estimation samples it and an escaping ray weights it by MIS
//! (`LightSet::env_weight`); the uniform environment stays outside it (weight 1 on escape).
//!
//! # Adding a light type
//!
//! A new light is one more variant, in three places (the image environment was added so):
//! 1. Rust: a file here with the type and its `sample_li`, `pdf_li`, `le`, `sample_le`,
//!    `pdf_le` and `power` (each formula with its citation), a `Light` variant dispatching
//!    to them, its entry in `LightSet::build` (`scene_lights`), and its consistency cases in
//!    `tests.rs` (`lights()`).
//! 2. WGSL: a `LIGHT_*` kind in `gpu::layout`, its fields in `upload::pack_lights` (the GPU
//!    `Light` entry), and a `case LIGHT_*` in each `light_*` function of
//!    `src/scene/light/light.wgsl`, the twins named and cited as here.
//! 3. The twin test: the light in `all_lights_scene` of tests/light_twin.rs (with reference
//!    points and directions that reach each branch), so the probe compares it with the Rust
//!    methods to f32 tolerance.

mod directional;
mod emissive_texture;
mod environment;
mod image_environment;
mod point;
mod set;
mod spot;
mod triangle;

#[cfg(test)]
mod tests;

pub use crate::math::color::luminance;
pub use directional::DirectionalLight;
pub use emissive_texture::EmissiveTexture;
pub use environment::UniformEnvironment;
pub use image_environment::ImageEnvironment;
pub use point::PointLight;
pub use set::LightSet;
pub use spot::{SPOT_MIN_RAMP_COS, SpotLight, spot_falloff};
pub use triangle::TriangleLight;

use glam::{Vec2, Vec3};

/// One light of the scene.
#[derive(Clone, Debug, PartialEq)]
pub enum Light {
    /// An emissive triangle (diffuse area light).
    Triangle(TriangleLight),
    Point(PointLight),
    Spot(SpotLight),
    Directional(DirectionalLight),
    /// Uniform radiance from every direction (escaping rays).
    Environment(UniformEnvironment),
    /// An equirectangular image at infinity, importance-sampled (in the NEE distribution).
    Image(ImageEnvironment),
}

/// Incident illumination sampled at a reference point (pbrt-v4 `LightLiSample`).
#[derive(Clone, Copy, Debug)]
pub struct LiSample {
    /// Radiance (area, environment), intensity/d² (point, spot) or irradiance (directional),
    /// RGB.
    pub l: Vec3,
    /// Unit direction from the reference point towards the light.
    pub wi: Vec3,
    /// Solid-angle density including the selection probability (= `pick` for delta lights).
    pub pdf: f32,
    /// The sampled point on the light (unused for infinite lights).
    pub p_light: Vec3,
    /// Geometric normal at `p_light` (zero for point-like lights).
    pub n_light: Vec3,
    /// A delta distribution: no BSDF-sampled ray can hit it (weight 1, no MIS).
    pub is_delta: bool,
    /// At infinity: the shadow ray runs along `wi` without end.
    pub infinite: bool,
}

impl LiSample {
    /// Illumination `l` from the delta position `p_light` along `wi`, picked with probability
    /// `pick` (point and spot lights: no density over the light).
    #[inline]
    pub fn delta_position(l: Vec3, wi: Vec3, pick: f32, p_light: Vec3) -> LiSample {
        LiSample {
            l,
            wi,
            pdf: pick,
            p_light,
            n_light: Vec3::ZERO,
            is_delta: true,
            infinite: false,
        }
    }
}

/// The origin and direction of a light subpath (pbrt-v4 `LightLeSample`).
#[derive(Clone, Copy, Debug)]
pub struct LeSample {
    pub p: Vec3,
    /// Geometric normal at `p` (zero for point lights; the emission direction's axis for
    /// infinite lights' disk points).
    pub n: Vec3,
    /// Emission direction (unit).
    pub dir: Vec3,
    /// Emitted radiance / intensity / irradiance along `dir`, RGB.
    pub l: Vec3,
    /// Area density of `p` including the selection probability (`pick` for delta positions).
    pub pdf_pos: f32,
    /// Solid-angle density of `dir` (1 for a delta direction).
    pub pdf_dir: f32,
    /// `p` is a delta position (point and spot lights).
    pub delta_pos: bool,
    /// The light sits at infinity (directional, environment): its subpath cannot be
    /// connected to by a finite segment.
    pub infinite: bool,
}

/// Unit direction from `p` to the light position `pl` and the squared distance (`None` when
/// they coincide): the geometry of every delta-position light's `sample_li`.
#[inline]
pub(crate) fn towards_position(p: Vec3, pl: Vec3) -> Option<(Vec3, f32)> {
    let to = pl - p;
    let d2 = to.length_squared();
    if d2 <= 0.0 {
        return None;
    }
    Some((to / d2.sqrt(), d2))
}

impl Light {
    /// Sample incident illumination at `p` with the 2D sample `u` (PBR 4th ed. §12.2).
    #[inline]
    pub fn sample_li(&self, p: Vec3, u: Vec2, pick: f32) -> Option<LiSample> {
        match self {
            Light::Triangle(l) => l.sample_li(p, u, pick),
            Light::Point(l) => l.sample_li(p, pick),
            Light::Spot(l) => l.sample_li(p, pick),
            Light::Directional(l) => l.sample_li(pick),
            Light::Environment(l) => l.sample_li(u, pick),
            Light::Image(l) => l.sample_li(u, pick),
        }
    }

    /// Solid-angle density of `sample_li` for direction `wi` (towards the light) reaching a
    /// point on the light at distance `dist` seen under `cos_light` = |n_light·ω| (0 for delta
    /// lights; PBR 4th ed. eq. 12.3).
    #[inline]
    pub fn pdf_li(&self, pick: f32, wi: Vec3, dist: f32, cos_light: f32) -> f32 {
        match self {
            Light::Triangle(l) => l.pdf_li(pick, dist, cos_light),
            Light::Environment(l) => l.pdf_li(pick),
            Light::Image(l) => l.pdf_li(pick, wi),
            Light::Point(_) | Light::Spot(_) | Light::Directional(_) => 0.0,
        }
    }

    /// Radiance leaving the light along `w` (unit, pointing away from the light) from the
    /// point `p` with raw geometric normal `n` (an area light's emissive texture is read at
    /// `p`). For infinite lights `w` is the direction light travels (minus the escaping ray's
    /// direction) and `p`, `n` are ignored. Delta lights return their intensity (point, spot
    /// with falloff) or irradiance (directional).
    #[inline]
    pub fn le(&self, p: Vec3, n: Vec3, w: Vec3) -> Vec3 {
        match self {
            Light::Triangle(l) => l.le(p, n, w),
            Light::Point(l) => l.intensity,
            Light::Spot(l) => l.le(w),
            Light::Directional(l) => l.irradiance,
            Light::Environment(l) => l.radiance,
            Light::Image(l) => l.radiance(-w),
        }
    }

    /// Sample an emitted ray (PBR 4th ed. §12.x `SampleLe`): `u_pos` picks the point, `u_dir`
    /// the direction and `u_side` the face of a two-sided emitter.
    #[inline]
    pub fn sample_le(&self, u_pos: Vec2, u_dir: Vec2, u_side: f32, pick: f32) -> Option<LeSample> {
        match self {
            Light::Triangle(l) => l.sample_le(u_pos, u_dir, u_side, pick),
            Light::Point(l) => Some(l.sample_le(u_dir, pick)),
            Light::Spot(l) => Some(l.sample_le(u_dir, pick)),
            Light::Directional(l) => Some(l.sample_le(u_pos, pick)),
            Light::Environment(l) => Some(l.sample_le(u_pos, u_dir, pick)),
            Light::Image(l) => l.sample_le(u_pos, u_dir, pick),
        }
    }

    /// Emission densities (area density of the point including the selection probability
    /// `pick`, solid-angle density of `w`) of `sample_le` for a point with normal `n` emitting
    /// along `w` (PBR 4th ed. `PDF_Le`). A delta position reports `pick` as its density and a
    /// delta direction 0 (Veach 1997 §10.3.5: delta densities are excluded from the ratios).
    #[inline]
    pub fn pdf_le(&self, pick: f32, n: Vec3, w: Vec3) -> (f32, f32) {
        match self {
            Light::Triangle(l) => l.pdf_le(pick, n, w),
            Light::Point(_) => (pick, crate::math::sampling::UNIFORM_SPHERE_PDF),
            Light::Spot(l) => (pick, l.pdf_dir(w)),
            Light::Directional(l) => (pick * l.pdf_pos(), 0.0),
            Light::Environment(l) => l.pdf_le(pick),
            Light::Image(l) => l.pdf_le(pick, w),
        }
    }

    /// Approximate emitted power, luminance-weighted (pbrt-v4 `Phi`), for the selection
    /// distribution.
    pub fn power(&self) -> f32 {
        match self {
            Light::Triangle(l) => l.power(),
            Light::Point(l) => l.power(),
            Light::Spot(l) => l.power(),
            Light::Directional(l) => l.power(),
            Light::Environment(l) => l.power(),
            Light::Image(l) => l.power(),
        }
    }

    /// The light is a delta position (point, spot): it starts subpaths but cannot be hit.
    pub fn is_delta_position(&self) -> bool {
        matches!(self, Light::Point(_) | Light::Spot(_))
    }

    /// The light is at infinity (directional, environment).
    pub fn is_infinite(&self) -> bool {
        matches!(
            self,
            Light::Directional(_) | Light::Environment(_) | Light::Image(_)
        )
    }
}
