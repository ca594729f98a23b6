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
//! A new light is one more row of the light table (`family.rs`, `light_table!`), which
//! generates the `Light` variant and its dispatch, the `LIGHT_*` kind, its part of the kernel
//! and the WGSL switch arms; besides the row:
//! 1. Rust: a file here with the type and the methods its row calls (`sample_li`, `pdf_li`,
//!    `le`, `sample_le`, `pdf_le`, `power`; each formula with its citation), its `mod` here,
//!    its entry in `LightSet::build` (`scene_lights`), and its consistency cases in `tests.rs`
//!    (`lights()`).
//! 2. WGSL: the functions its row's arms call, in `light.wgsl`, and its fields in
//!    `upload::pack_lights` (the GPU `Light` entry).
//! 3. The twin test: the light in `all_lights_scene` of tests/light_twin.rs (with reference
//!    points and directions that reach each branch), so the probe compares it with the Rust
//!    methods to f32 tolerance.

mod directional;
mod emissive_texture;
mod environment;
pub mod family;
pub mod family_wgsl;
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
pub use family::{Light, LightParts};
pub use image_environment::ImageEnvironment;
pub use point::PointLight;
pub use set::LightSet;
pub use spot::{SPOT_MIN_RAMP_COS, SpotLight, spot_falloff};
pub use triangle::TriangleLight;

use glam::Vec3;

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
