//! The light family's one table ([`light_table!`]): every [`Light`] variant with what the
//! rest of the renderer needs to know about it, written once. From it [`family_items`]
//! generates the `Light` enum and its dispatch (`sample_li`, `pdf_li`, `le`, `sample_le`,
//! `pdf_le`, `power`, `is_delta_position`, `is_infinite`), the GPU kind constants (`LIGHT_*`,
//! emitted into the WGSL prelude by `gpu::prelude`), the kernel's light parts
//! ([`LightParts`]: a `Specialization` flag and its WGSL `HAS_*` override) and, through
//! `scene::light::family_wgsl`, the WGSL override declarations and the `switch` of every
//! `light_*` interface function. `scene::features` reads the same table for each part's
//! `Features` flag.
//!
//! Adding a light type: its Rust file with the methods the row calls, its WGSL functions in
//! `light.wgsl`, a row here, its `mod` in `scene/light/mod.rs`, its entry in `LightSet::build`
//! (`set.rs`) and its GPU packing (`gpu/upload/lights.rs`) — see `scene/light/mod.rs`.

use super::{
    DirectionalLight, ImageEnvironment, LeSample, LiSample, PointLight, SpotLight, TriangleLight,
    UniformEnvironment,
};
use crate::bsdf::family::optional;
use crate::math::sampling::UNIFORM_SPHERE_PDF;
use glam::{Vec2, Vec3};

/// The table. A row per [`Light`] variant: its documentation, the variant and the type it
/// holds; the kernel part that compiles it in — `part: FIELD = HAS_*, feature: FLAG` where
/// the row owns it (a [`LightParts`] field, its WGSL override and the `scene::Features` flag
/// that sets it), `guard: HAS_*` where it shares an earlier row's, neither where it is always
/// compiled in; `kind`, its WGSL constant and value; `infinite` (at infinity) and
/// `delta_position` (a point-like position: it starts subpaths but cannot be hit); `rust`,
/// its dispatch (closures over the light and the method's arguments); `wgsl`, the WGSL
/// expressions of its switch arms (a delta light has no `pdf_li`: its density is 0), with
/// the interface functions' arguments in scope (`light.wgsl`). `$then!` is called with the
/// rows.
macro_rules! light_table {
    ($then:ident) => {
        $then! {
            /// An emissive triangle (diffuse area light).
            Triangle(TriangleLight) {
                part: area_lights = HAS_LIGHTS, feature: AREA_LIGHTS,
                kind: LIGHT_TRIANGLE = 0, infinite: false, delta_position: false,
                rust: {
                    sample_li: |l, p, u, pick| l.sample_li(p, u, pick),
                    pdf_li: |l, pick, _wi, dist, cos| l.pdf_li(pick, dist, cos),
                    le: |l, p, n, w| l.le(p, n, w),
                    sample_le: |l, u_pos, u_dir, u_side, pick| {
                        l.sample_le(u_pos, u_dir, u_side, pick)
                    },
                    pdf_le: |l, pick, n, w| l.pdf_le(pick, n, w),
                },
                wgsl: {
                    sample_li: "light_triangle_sample_li(light, p_ref, u, pick)",
                    pdf_li: "light_triangle_pdf_li(light, pick, dist, n_light, wi)",
                    le: "light_triangle_le(light, p, n_light, w)",
                    sample_le: "light_triangle_sample_le(light, u_pos, u_dir, sampler, pick)",
                    pdf_le: "light_triangle_pdf_le(light, pick, n_light, w)",
                },
            }
            /// A point light (KHR_lights_punctual "Point").
            Point(PointLight) {
                part: punctual_lights = HAS_PUNCTUAL, feature: PUNCTUAL_LIGHTS,
                kind: LIGHT_POINT = 1, infinite: false, delta_position: true,
                rust: {
                    sample_li: |l, p, _u, pick| l.sample_li(p, pick),
                    pdf_li: |_l, _pick, _wi, _dist, _cos| 0.0,
                    le: |l, _p, _n, _w| l.intensity,
                    sample_le: |l, _u_pos, u_dir, _u_side, pick| Some(l.sample_le(u_dir, pick)),
                    pdf_le: |_l, pick, _n, _w| (pick, UNIFORM_SPHERE_PDF),
                },
                wgsl: {
                    sample_li: "light_punctual_sample_li(light, p_ref, pick)",
                    le: "v3(light.intensity)",
                    sample_le: "light_punctual_sample_le(light, u_dir, pick)",
                    pdf_le: "LightLePdf(pick, light_punctual_pdf_dir(light))",
                },
            }
            /// A spot light with glTF's smooth falloff (KHR_lights_punctual "Spot").
            Spot(SpotLight) {
                guard: HAS_PUNCTUAL,
                kind: LIGHT_SPOT = 2, infinite: false, delta_position: true,
                rust: {
                    sample_li: |l, p, _u, pick| l.sample_li(p, pick),
                    pdf_li: |_l, _pick, _wi, _dist, _cos| 0.0,
                    le: |l, _p, _n, w| l.le(w),
                    sample_le: |l, _u_pos, u_dir, _u_side, pick| Some(l.sample_le(u_dir, pick)),
                    pdf_le: |l, pick, _n, w| (pick, l.pdf_dir(w)),
                },
                wgsl: {
                    sample_li: "light_punctual_sample_li(light, p_ref, pick)",
                    le: "v3(light.intensity) * spot_falloff(dot3(w, v3(light.direction)), light.cos_inner, light.cos_outer)",
                    sample_le: "light_punctual_sample_le(light, u_dir, pick)",
                    pdf_le: "light_spot_pdf_le(light, pick, w)",
                },
            }
            /// A directional light (KHR_lights_punctual "Directional"), at infinity.
            Directional(DirectionalLight) {
                guard: HAS_PUNCTUAL,
                kind: LIGHT_DIRECTIONAL = 3, infinite: true, delta_position: false,
                rust: {
                    sample_li: |l, _p, _u, pick| l.sample_li(pick),
                    pdf_li: |_l, _pick, _wi, _dist, _cos| 0.0,
                    le: |l, _p, _n, _w| l.irradiance,
                    sample_le: |l, u_pos, _u_dir, _u_side, pick| Some(l.sample_le(u_pos, pick)),
                    pdf_le: |l, pick, _n, _w| (pick * l.pdf_pos(), 0.0),
                },
                wgsl: {
                    sample_li: "light_directional_sample_li(light, pick)",
                    le: "v3(light.intensity)",
                    sample_le: "light_directional_sample_le(light, u_pos, pick)",
                    pdf_le: "LightLePdf(pick * light_directional_pdf_pos(light), 0.0)",
                },
            }
            /// Uniform radiance from every direction (escaping rays).
            Environment(UniformEnvironment) {
                kind: LIGHT_ENVIRONMENT = 4, infinite: true, delta_position: false,
                rust: {
                    sample_li: |l, _p, u, pick| l.sample_li(u, pick),
                    pdf_li: |l, pick, _wi, _dist, _cos| l.pdf_li(pick),
                    le: |l, _p, _n, _w| l.radiance,
                    sample_le: |l, u_pos, u_dir, _u_side, pick| {
                        Some(l.sample_le(u_pos, u_dir, pick))
                    },
                    pdf_le: |l, pick, _n, _w| l.pdf_le(pick),
                },
                wgsl: {
                    sample_li: "light_environment_sample_li(light, u, pick)",
                    pdf_li: "pick * UNIFORM_SPHERE_PDF",
                    le: "v3(light.intensity)",
                    sample_le: "light_environment_sample_le(light, u_pos, u_dir, pick)",
                    pdf_le: "LightLePdf(light_infinite_pdf_pos(light, pick), UNIFORM_SPHERE_PDF)",
                },
            }
            /// An equirectangular image at infinity, importance-sampled (in the NEE
            /// distribution).
            Image(ImageEnvironment) {
                part: env_image = HAS_ENV_IMAGE, feature: ENV_IMAGE,
                kind: LIGHT_IMAGE = 5, infinite: true, delta_position: false,
                rust: {
                    sample_li: |l, _p, u, pick| l.sample_li(u, pick),
                    pdf_li: |l, pick, wi, _dist, _cos| l.pdf_li(pick, wi),
                    le: |l, _p, _n, w| l.radiance(-w),
                    sample_le: |l, u_pos, u_dir, _u_side, pick| l.sample_le(u_pos, u_dir, pick),
                    pdf_le: |l, pick, _n, w| l.pdf_le(pick, w),
                },
                wgsl: {
                    sample_li: "light_image_sample_li(light, u, pick)",
                    pdf_li: "pick * light_image_pdf_dir(light, wi)",
                    le: "light_image_radiance(light, -w)",
                    sample_le: "light_image_sample_le(light, u_pos, u_dir, pick)",
                    pdf_le: "LightLePdf(light_infinite_pdf_pos(light, pick), light_image_pdf_dir(light, -w))",
                },
            }
        }
    };
}
pub(crate) use light_table;

/// What the table generates in the scene layer (see the module documentation).
macro_rules! family_items {
    ($(
        $(#[$attr:meta])*
        $variant:ident($ty:ident) {
            $(part: $part:ident = $has:ident, feature: $feature:ident,)?
            $(guard: $guard:ident,)?
            kind: $kind:ident = $value:literal, infinite: $infinite:literal,
            delta_position: $delta:literal,
            rust: {
                sample_li: |$sl:tt, $sp:tt, $su:tt, $spick:tt| $sample_li:expr,
                pdf_li: |$pl:tt, $ppick:tt, $pwi:tt, $pdist:tt, $pcos:tt| $pdf_li:expr,
                le: |$ll:tt, $lp:tt, $ln:tt, $lw:tt| $le:expr,
                sample_le: |$el:tt, $eupos:tt, $eudir:tt, $euside:tt, $epick:tt| $sample_le:expr,
                pdf_le: |$dl:tt, $dpick:tt, $dn:tt, $dw:tt| $pdf_le:expr,
            },
            wgsl: {
                sample_li: $w_sample_li:literal,
                $(pdf_li: $w_pdf_li:literal,)?
                le: $w_le:literal,
                sample_le: $w_sample_le:literal,
                pdf_le: $w_pdf_le:literal,
            },
        }
    )*) => {
        /// One light of the scene: one variant per row of the table ([`light_table!`]).
        #[derive(Clone, Debug, PartialEq)]
        pub enum Light {
            $($(#[$attr])* $variant($ty),)*
        }

        impl Light {
            /// Sample incident illumination at `p` with the 2D sample `u` (PBR 4th ed.
            /// §12.2).
            #[inline]
            pub fn sample_li(&self, p: Vec3, u: Vec2, pick: f32) -> Option<LiSample> {
                match self {
                    $(Light::$variant($sl) => {
                        let ($sp, $su, $spick) = (p, u, pick);
                        $sample_li
                    })*
                }
            }

            /// Solid-angle density of `sample_li` for direction `wi` (towards the light)
            /// reaching a point on the light at distance `dist` seen under `cos_light` =
            /// |n_light·ω| (0 for delta lights; PBR 4th ed. eq. 12.3).
            #[inline]
            pub fn pdf_li(&self, pick: f32, wi: Vec3, dist: f32, cos_light: f32) -> f32 {
                match self {
                    $(Light::$variant($pl) => {
                        let ($ppick, $pwi, $pdist, $pcos) = (pick, wi, dist, cos_light);
                        $pdf_li
                    })*
                }
            }

            /// Radiance leaving the light along `w` (unit, pointing away from the light) from
            /// the point `p` with raw geometric normal `n` (an area light's emissive texture
            /// is read at `p`). For infinite lights `w` is the direction light travels (minus
            /// the escaping ray's direction) and `p`, `n` are ignored. Delta lights return
            /// their intensity (point, spot with falloff) or irradiance (directional).
            #[inline]
            pub fn le(&self, p: Vec3, n: Vec3, w: Vec3) -> Vec3 {
                match self {
                    $(Light::$variant($ll) => {
                        let ($lp, $ln, $lw) = (p, n, w);
                        $le
                    })*
                }
            }

            /// Sample an emitted ray (PBR 4th ed. §12.x `SampleLe`): `u_pos` picks the point,
            /// `u_dir` the direction and `u_side` the face of a two-sided emitter.
            #[inline]
            pub fn sample_le(
                &self,
                u_pos: Vec2,
                u_dir: Vec2,
                u_side: f32,
                pick: f32,
            ) -> Option<LeSample> {
                match self {
                    $(Light::$variant($el) => {
                        let ($eupos, $eudir, $euside, $epick) = (u_pos, u_dir, u_side, pick);
                        $sample_le
                    })*
                }
            }

            /// Emission densities (area density of the point including the selection
            /// probability `pick`, solid-angle density of `w`) of `sample_le` for a point with
            /// normal `n` emitting along `w` (PBR 4th ed. `PDF_Le`). A delta position reports
            /// `pick` as its density and a delta direction 0 (Veach 1997 §10.3.5: delta
            /// densities are excluded from the ratios).
            #[inline]
            pub fn pdf_le(&self, pick: f32, n: Vec3, w: Vec3) -> (f32, f32) {
                match self {
                    $(Light::$variant($dl) => {
                        let ($dpick, $dn, $dw) = (pick, n, w);
                        $pdf_le
                    })*
                }
            }

            /// Approximate emitted power, luminance-weighted (pbrt-v4 `Phi`), for the
            /// selection distribution.
            pub fn power(&self) -> f32 {
                match self {
                    $(Light::$variant(l) => l.power(),)*
                }
            }

            /// The light is a delta position (point, spot): it starts subpaths but cannot be
            /// hit.
            pub fn is_delta_position(&self) -> bool {
                match self {
                    $(Light::$variant(_) => $delta,)*
                }
            }

            /// The light is at infinity (directional, environments).
            pub fn is_infinite(&self) -> bool {
                match self {
                    $(Light::$variant(_) => $infinite,)*
                }
            }

            /// The GPU kind (`LIGHT_*`) of this light.
            pub fn gpu_kind(&self) -> u32 {
                match self {
                    $(Light::$variant(_) => $kind,)*
                }
            }
        }

        /// The GPU light kinds (`Light.kind` in light.wgsl), one module so that `gpu::layout`
        /// can re-export every one of them by a glob.
        pub mod kinds {
            $(
                #[doc = concat!("GPU kind of [`Light::", stringify!($variant), "`](super::Light::",
                    stringify!($variant), ") (WGSL `", stringify!($kind), "`).")]
                pub const $kind: u32 = $value;
            )*
        }
        pub use kinds::*;

        /// (WGSL name, value) of every GPU light kind, for the WGSL prelude.
        pub const GPU_KIND_CONSTANTS: &[(&str, u32)] = &[$((stringify!($kind), $kind),)*];

        /// Which lights a kernel compiles in (the `gpu::pipeline::Specialization` key's light
        /// part), each a WGSL `HAS_*` override.
        #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
        pub struct LightParts {
            $($(
                #[doc = concat!("Compiles in [`Light::", stringify!($variant), "`] (WGSL `",
                    stringify!($has), "`).")]
                pub $part: bool,
            )?)*
        }

        impl LightParts {
            /// No part compiled in.
            pub const NONE: LightParts = LightParts { $($($part: false,)?)* };
            /// Every part compiled in.
            pub const ALL: LightParts = LightParts { $($($part: true,)?)* };
            /// Every part's field name, in table order.
            pub const NAMES: &[&str] = &[$($(stringify!($part),)?)*];

            /// (WGSL override name, value) of every part, in table order.
            pub fn overrides(&self) -> Vec<(&'static str, bool)> {
                vec![$($((stringify!($has), self.$part),)?)*]
            }

            /// The part named `name` (a field name, [`LightParts::NAMES`]).
            pub fn part_mut(&mut self, name: &str) -> Option<&mut bool> {
                match name {
                    $($(stringify!($part) => Some(&mut self.$part),)?)*
                    _ => None,
                }
            }
        }

        /// The table's GPU kinds, in table order (for the generated WGSL switches).
        pub const GPU_KINDS: &[GpuLightKind] = &[$(GpuLightKind {
            name: stringify!($kind),
            guard: optional!($(stringify!($has))? $(stringify!($guard))?),
            infinite: $infinite,
            sample_li: $w_sample_li,
            pdf_li: optional!($($w_pdf_li)?),
            le: $w_le,
            sample_le: $w_sample_le,
            pdf_le: $w_pdf_le,
        },)*];
    };
}

/// One GPU light kind of the table: its WGSL constant, the override that compiles it in
/// (none: always), whether it is at infinity, and the WGSL expressions of its switch arms.
#[derive(Clone, Copy, Debug)]
pub struct GpuLightKind {
    pub name: &'static str,
    pub guard: Option<&'static str>,
    pub infinite: bool,
    pub sample_li: &'static str,
    pub pdf_li: Option<&'static str>,
    pub le: &'static str,
    pub sample_le: &'static str,
    pub pdf_le: &'static str,
}

light_table!(family_items);

#[cfg(test)]
mod tests {
    use super::*;

    /// Kind values and part overrides are distinct; every part can be reached by its name.
    #[test]
    fn the_table_is_consistent() {
        let mut values: Vec<u32> = GPU_KIND_CONSTANTS.iter().map(|&(_, v)| v).collect();
        values.sort_unstable();
        values.dedup();
        assert_eq!(values.len(), GPU_KIND_CONSTANTS.len(), "kind values repeat");
        let mut p = LightParts::NONE;
        for name in LightParts::NAMES {
            *p.part_mut(name).expect("named part") = true;
        }
        assert_eq!(p, LightParts::ALL);
        assert_eq!(LightParts::ALL.overrides().len(), LightParts::NAMES.len());
    }
}
