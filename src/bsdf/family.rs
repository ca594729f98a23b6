//! The BSDF family's one table ([`bsdf_table!`]): every [`Bsdf`] variant with what the rest of
//! the renderer needs to know about it, written once. From it [`family_items`] generates the
//! `Bsdf` enum and its [`BxDF`] dispatch, the GPU kind constants (`BSDF_*`, emitted into the
//! WGSL prelude by `gpu::prelude`), the kernel's parts ([`BsdfParts`]: one `Specialization`
//! flag and one WGSL `HAS_*` override per variant), the WGSL override declarations and the
//! `switch` arms of `bsdf_eval`, `bsdf_pdf`, `bsdf_sample`, `bsdf_class` and
//! `bsdf_kind_is_delta` (`bsdf::family_wgsl`), and the variants' WGSL files for the kernels.
//! `scene::features` reads the same table for each variant's `Features` flag.
//!
//! Adding a BSDF: its Rust file (`BxDF`, including what the enum asks of a variant:
//! `can_transmit`, `mueller`, and where it has them `map_colors`, `at_wavelengths`,
//! `distribution`) and its WGSL twin (`<name>_eval/_pdf/_sample`), a row here, a
//! `pub mod` in `bsdf/mod.rs`, its
//! `Features` flag in `scene/features.rs`, and the material that becomes it
//! (`scene/material.rs`) — docs/architecture.md "Adding a BSDF".

use super::{
    BsdfSample, BxDF, Event, Iridescent, Lambert, Lobe, MetalRough, MicrofacetDistribution, Mirror,
    MuellerLanes, RoughConductor, RoughDielectric, RoughFresnelConductor, RoughThinDielectric,
    SmoothConductor, SmoothDielectric, ThinDielectric, TransportMode,
};
use crate::math::Color;
use glam::{Vec2, Vec3};

/// The table. A row per [`Bsdf`] variant: its documentation, the variant and the type it holds;
/// `part`, its [`BsdfParts`] field (the kernel part that compiles it in) and `has`, that part's
/// WGSL override; `feature`, the `scene::Features` flag a material of this variant sets;
/// `wgsl`, the file of its WGSL twin (once, where two variants share one); `kinds`, its GPU
/// kinds — the WGSL constant and its value, its Heckbert class (`S`: every lobe a delta, no
/// eval or pdf arm) and the WGSL calls of its switch arms, with `b: Bsdf`, `wo`, `wi`, `uc`,
/// `u2`, `mode`, `event` and `lobe` in scope: sample, eval and pdf, whether it transmits
/// (absent: never), its polarisation (`mueller`, absent: the depolariser; `mueller_b` for the
/// glossy kinds next-event estimation connects to, `bsdf::polarized`); a row of two kinds
/// names the one a value takes (`select`).
/// `$then!` is called with the rows.
macro_rules! bsdf_table {
    ($then:ident) => {
        $then! {
            /// Lambertian diffuse (Lambert 1760; pbrt-v4 §9.2).
            Lambert(Lambert) {
                part: lambert, has: HAS_LAMBERT, feature: DIFFUSE, wgsl: "diffuse.wgsl",
                kinds: [BSDF_LAMBERT = 0 (D) {
                    sample: "lambert_sample(b.color, wo, u2, b.metallic != 0.0)",
                    eval: "lambert_eval(b.color, wo, wi)",
                    pdf: "lambert_pdf(wo, wi, b.metallic != 0.0)",
                    mueller: "mueller_depolarizer()",
                }],
            }
            /// Perfect mirror (also smooth glossy metal).
            Mirror(Mirror) {
                part: mirror, has: HAS_MIRROR, feature: MIRROR, wgsl: "conductor.wgsl",
                kinds: [BSDF_MIRROR = 1 (S) {
                    sample: "mirror_sample(b.color, wo)",
                    mueller: "mueller_ideal_conductor()",
                }],
            }
            /// Smooth dielectric interface: Snell, exact Fresnel, total internal reflection.
            SmoothDielectric(SmoothDielectric) {
                part: smooth_dielectric, has: HAS_SMOOTH_DIELECTRIC, feature: SMOOTH_GLASS,
                wgsl: "dielectric.wgsl",
                kinds: [BSDF_SMOOTH_DIELECTRIC = 2 (S) {
                    sample: "smooth_dielectric_sample(b.eta, wo, uc, mode)",
                    transmits: "true",
                    mueller: "smooth_dielectric_mueller(b, wi, event)",
                }],
            }
            /// Thin-walled dielectric (a sheet: reflection and straight transmission).
            ThinDielectric(ThinDielectric) {
                part: thin_dielectric, has: HAS_THIN_DIELECTRIC, feature: THIN_GLASS,
                wgsl: "thin.wgsl",
                kinds: [BSDF_THIN_DIELECTRIC = 6 (S) {
                    sample: "thin_dielectric_sample(b.eta, wo, uc)",
                    transmits: "true",
                    mueller: "thin_dielectric_mueller(b, wi, event)",
                }],
            }
            /// Rough dielectric (Walter et al. 2007), GGX or Beckmann.
            RoughDielectric(RoughDielectric) {
                part: rough_dielectric, has: HAS_ROUGH_DIELECTRIC, feature: ROUGH_GLASS,
                wgsl: "rough_dielectric.wgsl",
                kinds: [BSDF_ROUGH_DIELECTRIC = 3 (G) {
                    sample: "rough_dielectric_sample(b, wo, uc, u2, mode)",
                    eval: "rough_dielectric_eval(b, wo, wi, mode)",
                    pdf: "rough_dielectric_pdf(b, wo, wi)",
                    transmits: "true",
                    mueller: "rough_dielectric_mueller(b, wo, wi, event)",
                    mueller_b: "rough_dielectric_mueller_b(b, wo, wi)",
                }],
            }
            /// Rough thin-walled dielectric (a frosted sheet; glTF's transmission BTDF).
            RoughThinDielectric(RoughThinDielectric) {
                part: rough_thin_dielectric, has: HAS_ROUGH_THIN_DIELECTRIC,
                feature: ROUGH_THIN_GLASS, wgsl: "rough_thin.wgsl",
                kinds: [BSDF_ROUGH_THIN_DIELECTRIC = 11 (G) {
                    sample: "rough_thin_sample(b, wo, uc, u2)",
                    eval: "rough_thin_eval(b, wo, wi)",
                    pdf: "rough_thin_pdf(b, wo, wi)",
                    transmits: "true",
                    mueller: "rough_thin_mueller(b, wo, wi, event)",
                    mueller_b: "rough_thin_mueller_b(b, wo, wi)",
                }],
            }
            /// Rough conductor with a coloured Schlick Fresnel term (glossy metal).
            RoughConductor(RoughConductor) {
                part: rough_conductor, has: HAS_ROUGH_CONDUCTOR, feature: GLOSSY_METAL,
                wgsl: "glossy.wgsl",
                kinds: [BSDF_ROUGH_CONDUCTOR = 4 (G) {
                    sample: "rough_conductor_sample(b, wo, u2)",
                    eval: "rough_conductor_eval(b, wo, wi)",
                    pdf: "rough_conductor_pdf(b, wo, wi)",
                    mueller: "mueller_ideal_conductor()",
                }],
            }
            /// The glTF metallic-roughness BRDF.
            MetalRough(MetalRough) {
                part: metal_rough, has: HAS_METAL_ROUGH, feature: METAL_ROUGH,
                wgsl: "metal_rough.wgsl",
                kinds: [BSDF_METAL_ROUGH = 5 (G) {
                    sample: "metal_rough_sample(b, wo, uc, u2)",
                    eval: "metal_rough_eval(b, wo, wi)",
                    pdf: "metal_rough_pdf(b, wo, wi)",
                    mueller: "metal_rough_mueller(b, wo, wi, lobe)",
                    mueller_b: "vec4<f32>(metal_rough_specular_lane(b, wo, wi).y)",
                }],
            }
            /// Smooth conductor with a complex IOR (tabulated metal).
            SmoothConductor(SmoothConductor) {
                part: smooth_conductor, has: HAS_SMOOTH_CONDUCTOR, feature: SMOOTH_CONDUCTOR,
                kinds: [BSDF_SMOOTH_CONDUCTOR = 7 (S) {
                    sample: "smooth_conductor_sample(b, wo)",
                    mueller: "conductor_mueller(wi.z, bsdf_conductor_eta(b), bsdf_conductor_k(b))",
                }],
            }
            /// Rough conductor with a complex IOR (tabulated metal).
            RoughFresnelConductor(RoughFresnelConductor) {
                part: rough_fresnel_conductor, has: HAS_ROUGH_FRESNEL_CONDUCTOR,
                feature: ROUGH_FRESNEL_CONDUCTOR,
                kinds: [BSDF_ROUGH_FRESNEL_CONDUCTOR = 8 (G) {
                    sample: "rough_fresnel_conductor_sample(b, wo, u2)",
                    eval: "rough_fresnel_conductor_eval(b, wo, wi)",
                    pdf: "rough_conductor_pdf(b, wo, wi)",
                    mueller: "rough_fresnel_conductor_mueller(b, wo, wi)",
                    mueller_b: "rough_fresnel_conductor_mueller(b, wo, wi).b",
                }],
            }
            /// A dielectric or metal under a thin film (iridescence), smooth or rough.
            Iridescent(Iridescent) {
                part: iridescence, has: HAS_IRIDESCENCE, feature: IRIDESCENCE,
                wgsl: "iridescent.wgsl",
                kinds: [BSDF_FILM_SMOOTH = 9 (S) {
                    sample: "film_sample(b, wo, uc, u2, mode)",
                    transmits: "film_can_transmit(b)",
                }, BSDF_FILM_ROUGH = 10 (G) {
                    sample: "film_sample(b, wo, uc, u2, mode)",
                    eval: "film_eval(b, wo, wi, mode)",
                    pdf: "film_pdf(b, wo, wi)",
                    transmits: "film_can_transmit(b)",
                }],
                select: |b| if b.is_smooth() { BSDF_FILM_SMOOTH } else { BSDF_FILM_ROUGH },
            }
        }
    };
}
pub(crate) use bsdf_table;

/// `Some(x)` for one argument, `None` for none (an optional column of the table).
macro_rules! optional {
    () => {
        None
    };
    ($x:expr) => {
        Some($x)
    };
}
pub(crate) use optional;

/// The GPU kind of one row's value `$x`: its only kind, or the one `select` names.
macro_rules! kind_of {
    ($x:ident; $kind:ident;) => {
        $kind
    };
    ($x:ident; $($kind:ident),+; |$b:ident| $select:expr) => {{
        let $b = $x;
        $select
    }};
}

/// What the table generates in the BSDF layer (see the module documentation).
macro_rules! family_items {
    ($(
        $(#[$attr:meta])*
        $variant:ident($ty:ident) {
            part: $part:ident, has: $has:ident, feature: $feature:ident,
            $(wgsl: $file:literal,)?
            kinds: [$($kind:ident = $value:literal ($lobe:ident) {
                sample: $sample:literal,
                $(eval: $eval:literal, pdf: $pdf:literal,)?
                $(transmits: $transmits:literal,)?
                $(mueller: $mueller:literal,)?
                $(mueller_b: $mueller_b:literal,)?
            }),+ $(,)?],
            $(select: |$b:ident| $select:expr,)?
        }
    )*) => {
        /// A BSDF instance at a surface point (material parameters already resolved: textures
        /// looked up, eta chosen for the path's wavelength). One variant per row of the
        /// table ([`bsdf_table!`]).
        #[derive(Clone, Copy, Debug)]
        pub enum Bsdf {
            $($(#[$attr])* $variant($ty),)*
        }

        impl BxDF for Bsdf {
            #[inline]
            fn eval(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> Color {
                match self {
                    $(Bsdf::$variant(b) => b.eval(wo, wi, mode),)*
                }
            }
            #[inline]
            fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
                match self {
                    $(Bsdf::$variant(b) => b.pdf(wo, wi),)*
                }
            }
            #[inline]
            fn sample(
                &self,
                wo: Vec3,
                uc: f32,
                u2: Vec2,
                mode: TransportMode,
            ) -> Option<BsdfSample> {
                match self {
                    $(Bsdf::$variant(b) => b.sample(wo, uc, u2, mode),)*
                }
            }
            #[inline]
            fn can_transmit(&self) -> bool {
                match self {
                    $(Bsdf::$variant(b) => b.can_transmit(),)*
                }
            }
            #[inline]
            fn mueller(&self, wo: Vec3, wi: Vec3, event: Event, lobe: Lobe) -> MuellerLanes {
                match self {
                    $(Bsdf::$variant(b) => b.mueller(wo, wi, event, lobe),)*
                }
            }
            #[inline]
            fn map_colors(self, f: impl Fn(Color) -> Color) -> Self {
                match self {
                    $(Bsdf::$variant(b) => Bsdf::$variant(b.map_colors(&f)),)*
                }
            }
            #[inline]
            fn at_wavelengths(self, lambdas: [f32; 4]) -> Self {
                match self {
                    $(Bsdf::$variant(b) => Bsdf::$variant(b.at_wavelengths(lambdas)),)*
                }
            }
            #[inline]
            fn distribution(&self) -> Option<MicrofacetDistribution> {
                match self {
                    $(Bsdf::$variant(b) => b.distribution(),)*
                }
            }
        }

        impl Bsdf {
            /// The GPU kind (`BSDF_*`) this BSDF is shaded as.
            #[inline]
            pub fn gpu_kind(&self) -> u32 {
                match self {
                    $(Bsdf::$variant(_x) => kind_of!(_x; $($kind),+; $(|$b| $select)?),)*
                }
            }

            /// Heckbert class of the non-delta part for single-class BSDFs (used when a BSDF
            /// has one class only; multi-lobe BSDFs report through [`Bsdf::eval_lobes`]): its
            /// kind's class in the table, so CPU and GPU cannot disagree.
            #[inline]
            pub fn class(&self) -> super::Lobe {
                match self.gpu_kind() {
                    $($($kind => super::Lobe::$lobe,)+)*
                    _ => unreachable!("gpu_kind returns one of the table's kinds"),
                }
            }

            /// True if every lobe is a delta distribution (next-event estimation is skipped):
            /// the kind's class is S.
            #[inline]
            pub fn is_delta(&self) -> bool {
                self.class() == super::Lobe::S
            }
        }

        /// The GPU kinds (`Bsdf.kind` in bsdf.wgsl), one module so that `gpu::layout` can
        /// re-export every one of them by a glob.
        pub mod kinds {
            $($(
                #[doc = concat!("GPU kind of [`Bsdf::", stringify!($variant), "`](super::Bsdf::",
                    stringify!($variant), ") (WGSL `", stringify!($kind), "`).")]
                pub const $kind: u32 = $value;
            )+)*
        }
        pub use kinds::*;

        /// (WGSL name, value) of every GPU kind constant, for the WGSL prelude.
        pub const GPU_KIND_CONSTANTS: &[(&str, u32)] = &[$($((stringify!($kind), $kind),)+)*];

        /// Which BSDFs a kernel compiles in: one part per variant (the
        /// `gpu::pipeline::Specialization` key), each a WGSL `HAS_*` override.
        #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
        pub struct BsdfParts {
            $($(#[$attr])* pub $part: bool,)*
        }

        impl BsdfParts {
            /// No BSDF compiled in.
            pub const NONE: BsdfParts = BsdfParts { $($part: false,)* };
            /// Every BSDF compiled in.
            pub const ALL: BsdfParts = BsdfParts { $($part: true,)* };
            /// Every part's field name, in table order.
            pub const NAMES: &[&str] = &[$(stringify!($part),)*];

            /// (WGSL override name, value) of every part, in table order.
            pub fn overrides(&self) -> Vec<(&'static str, bool)> {
                vec![$((stringify!($has), self.$part),)*]
            }

            /// The part named `name` (a field name, [`BsdfParts::NAMES`]).
            pub fn part_mut(&mut self, name: &str) -> Option<&mut bool> {
                match name {
                    $(stringify!($part) => Some(&mut self.$part),)*
                    _ => None,
                }
            }
        }

        /// The table's GPU kinds, in table order (for the generated WGSL switch).
        pub const GPU_KINDS: &[GpuKind] = &[$($(GpuKind {
            name: stringify!($kind),
            has: stringify!($has),
            lobe: super::Lobe::$lobe,
            sample: $sample,
            eval_pdf: optional!($(($eval, $pdf))?),
            transmits: optional!($($transmits)?),
            mueller: optional!($($mueller)?),
            mueller_b: optional!($($mueller_b)?),
        },)+)*];

        /// The variants' WGSL files (name, text), in table order.
        pub const WGSL_FILES: &[(&str, &str)] = &[$($((
            $file,
            include_str!(concat!(env!("CARGO_MANIFEST_DIR"), "/src/bsdf/", $file)),
        ),)?)*];
    };
}

/// One GPU kind of the table: its WGSL constant, its part's override, its Heckbert class, and
/// the WGSL calls of its `bsdf_sample` arm and (unless every lobe is a delta) of its
/// `bsdf_eval` and `bsdf_pdf` arms.
#[derive(Clone, Copy, Debug)]
pub struct GpuKind {
    pub name: &'static str,
    pub has: &'static str,
    pub lobe: super::Lobe,
    pub sample: &'static str,
    pub eval_pdf: Option<(&'static str, &'static str)>,
    /// Whether it can transmit (`bsdf_can_transmit`), where it can (else false).
    pub transmits: Option<&'static str>,
    /// Its normalised Mueller matrix (`bsdf_mueller`; else the depolariser), with `b`,
    /// `wo`, `wi`, `event` and `lobe` in scope, and where next-event estimation reaches it
    /// with a polarising glossy lobe, that matrix's m₀₁ (`bsdf_mueller_b`; else 0).
    pub mueller: Option<&'static str>,
    pub mueller_b: Option<&'static str>,
}

bsdf_table!(family_items);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::Lobe;

    /// Delta kinds (class S) have no eval/pdf arm, the others have both; kind values and part
    /// overrides are distinct.
    #[test]
    fn the_table_is_consistent() {
        for k in GPU_KINDS {
            assert_eq!(k.lobe == Lobe::S, k.eval_pdf.is_none(), "{}", k.name);
        }
        let mut values: Vec<u32> = GPU_KIND_CONSTANTS.iter().map(|&(_, v)| v).collect();
        values.sort_unstable();
        values.dedup();
        assert_eq!(values.len(), GPU_KIND_CONSTANTS.len(), "kind values repeat");
        let mut has: Vec<_> = BsdfParts::ALL
            .overrides()
            .into_iter()
            .map(|(n, _)| n)
            .collect();
        has.sort_unstable();
        has.dedup();
        assert_eq!(has.len(), BsdfParts::NAMES.len(), "overrides repeat");
    }

    /// Every part can be reached by its name.
    #[test]
    fn parts_are_named() {
        let mut p = BsdfParts::NONE;
        for name in BsdfParts::NAMES {
            *p.part_mut(name).expect("named part") = true;
        }
        assert_eq!(p, BsdfParts::ALL);
        assert!(p.part_mut("no such part").is_none());
    }
}
