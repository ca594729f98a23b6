//! The WGSL prelude: the enum and flag constants the shaders share with Rust (`BSDF_*`,
//! `MAT_*`, `LIGHT_*`, `SYM_*`, `DFA_*`, …) and the numbers a WGSL function shares with its
//! Rust twin (`SMOOTH_ALPHA`, the sampling pdfs, the spectral range and uplift, the Abbe
//! model's coefficients, …), generated from their single Rust definition and prepended to
//! every kernel by `pipeline::integrator_source` / `probe_source`. No `.wgsl` file defines
//! one of these names itself, nor writes one of the numbers as a literal; tests/gpu.rs
//! checks both, and the assembled source against [`WGSL_CONSTANTS`], [`WGSL_F32_CONSTANTS`]
//! and [`WGSL_VEC3_CONSTANTS`] with naga (bit for bit).

use super::layout::*;
use crate::bsdf::SMOOTH_ALPHA;
use crate::bsdf::iridescent::MAX_F0;
use crate::bsdf::thin_film::{MAX_R123_SQ, SENSITIVITY_FIT};
use crate::math::sampling::{UNIFORM_HEMISPHERE_PDF, UNIFORM_SPHERE_PDF};
use crate::math::spectrum::{
    ABBE_B_NM2, ABBE_C, CIE_CMF_INTEGRAL, HERO_COUNT, LAMBDA_MAX, LAMBDA_MIN, UPLIFT_BLUE_EDGE_NM,
    UPLIFT_BLUE_HALF_WIDTH_NM, UPLIFT_RED_EDGE_NM, UPLIFT_RED_HALF_WIDTH_NM,
};
use crate::render::photon_params::{PHOTON_DIMS, SAME_SURFACE_COS as PHOTON_SAME_SURFACE_COS};
use crate::scene::light::SPOT_MIN_RAMP_COS;
use std::fmt::Write;

macro_rules! wgsl_constants {
    ($($name:ident),* $(,)?) => {
        /// (WGSL name, value) of the generated `u32` constants other than the tables' kinds.
        const LAYOUT_CONSTANTS: &[(&str, u32)] = &[$((stringify!($name), $name as u32)),*];
    };
}

/// `a` then `b` (a const concatenation: `N` = the sum of their lengths; `fill` is overwritten).
pub(crate) const fn concat<T: Copy, const N: usize>(a: &[T], b: &[T], fill: T) -> [T; N] {
    let mut out = [fill; N];
    let mut i = 0;
    while i < N {
        out[i] = if i < a.len() { a[i] } else { b[i - a.len()] };
        i += 1;
    }
    out
}

const BSDF_KINDS: &[(&str, u32)] = crate::bsdf::family::GPU_KIND_CONSTANTS;
const LIGHT_KINDS: &[(&str, u32)] = crate::scene::light::family::GPU_KIND_CONSTANTS;
const KINDS: &[(&str, u32)] =
    &concat::<_, { BSDF_KINDS.len() + LIGHT_KINDS.len() }>(BSDF_KINDS, LIGHT_KINDS, ("", 0));

/// (WGSL name, value) of every generated constant (`const NAME: u32 = value;`): the BSDF and
/// light tables' kinds (`bsdf::family`, `scene::light::family`), then the layout's.
pub const WGSL_CONSTANTS: &[(&str, u32)] =
    &concat::<_, { KINDS.len() + LAYOUT_CONSTANTS.len() }>(KINDS, LAYOUT_CONSTANTS, ("", 0));

wgsl_constants![
    FILM_ON_DIELECTRIC,
    FILM_ON_SHEET,
    FILM_ON_CONDUCTOR,
    FILM_ON_REFLECTANCE,
    METAL_NONE,
    DIST_GGX,
    DIST_BECKMANN,
    MODE_RADIANCE,
    MODE_IMPORTANCE,
    EVENT_REFLECT,
    EVENT_TRANSMIT,
    LOBE_D,
    LOBE_G,
    LOBE_S,
    SYM_L,
    SYM_D,
    SYM_G,
    SYM_S,
    SYM_E,
    DFA_NUM_SYMBOLS,
    DFA_TRANSITIONS,
    DFA_ACCEPTING,
    DFA_LIVE,
    DFA_START,
    DFA_DEAD,
    DFA_NUM_STATES,
    DFA_VEC4S,
    NO_TEXTURE,
    WRAP_REPEAT,
    WRAP_MIRRORED_REPEAT,
    WRAP_CLAMP_TO_EDGE,
    TEX_LINEAR,
    TEX_VALID,
    MAT_EMISSIVE,
    MAT_DOUBLE_SIDED,
    MAT_TRANSMISSIVE,
    MAT_SOLID,
    MAT_BLACK_EMITTER,
    MAT_ABSORBS,
    MAT_UNIFORM_SAMPLING,
    MEDIUM_STACK_DEPTH,
    FALSE_HIT_LIMIT,
    DEBUG_MAX_VERTICES,
    DEBUG_STRIDE,
    PHOTON_COUNT,
    PHOTON_OVERFLOW,
    PHOTON_HEADS,
    PHOTON_TARGETS,
    PHOTON_DIMS,
    HERO_COUNT,
];

/// (WGSL name, value) of every generated `f32` constant: the numbers a WGSL function shares
/// with its Rust twin.
pub const WGSL_F32_CONSTANTS: &[(&str, f32)] = &[
    ("SMOOTH_ALPHA", SMOOTH_ALPHA),
    ("UNIFORM_HEMISPHERE_PDF", UNIFORM_HEMISPHERE_PDF),
    ("UNIFORM_SPHERE_PDF", UNIFORM_SPHERE_PDF),
    ("LAMBDA_MIN", LAMBDA_MIN),
    ("LAMBDA_MAX", LAMBDA_MAX),
    ("UPLIFT_BLUE_EDGE_NM", UPLIFT_BLUE_EDGE_NM),
    ("UPLIFT_BLUE_HALF_WIDTH_NM", UPLIFT_BLUE_HALF_WIDTH_NM),
    ("UPLIFT_RED_EDGE_NM", UPLIFT_RED_EDGE_NM),
    ("UPLIFT_RED_HALF_WIDTH_NM", UPLIFT_RED_HALF_WIDTH_NM),
    ("ABBE_B_NM2", ABBE_B_NM2),
    ("ABBE_C", ABBE_C),
    ("PHOTON_SAME_SURFACE_COS", PHOTON_SAME_SURFACE_COS),
    ("SPOT_MIN_RAMP_COS", SPOT_MIN_RAMP_COS),
    ("FILM_MAX_F0", MAX_F0),
    ("FILM_MAX_R123_SQ", MAX_R123_SQ),
];

/// (WGSL name, value) of every generated `vec3<f32>` constant.
/// The film's sensitivity fit rows are (amplitude, centre frequency, variance) of x̄, ȳ, z̄ and
/// x̄'s second lobe (`bsdf::thin_film::SENSITIVITY_FIT`).
pub const WGSL_VEC3_CONSTANTS: &[(&str, [f32; 3])] = &[
    ("CIE_CMF_INTEGRAL", CIE_CMF_INTEGRAL.to_array()),
    ("FILM_FIT_X", SENSITIVITY_FIT[0]),
    ("FILM_FIT_Y", SENSITIVITY_FIT[1]),
    ("FILM_FIT_Z", SENSITIVITY_FIT[2]),
    ("FILM_FIT_X2", SENSITIVITY_FIT[3]),
];

/// A WGSL literal that parses back to exactly `v` (Rust's shortest round-trip form, with a
/// decimal point so that WGSL reads a float).
fn f32_literal(v: f32) -> String {
    let s = format!("{v:?}");
    if s.contains(['.', 'e', 'E']) {
        s
    } else {
        format!("{s}.0")
    }
}

/// The prelude's WGSL text: one `const NAME: TYPE = value;` line per generated constant.
pub fn wgsl_prelude() -> String {
    let mut s = String::from(
        "// prelude — generated by gpu::prelude from the Rust constants (gpu::layout).\n",
    );
    for (name, value) in WGSL_CONSTANTS {
        let _ = writeln!(s, "const {name}: u32 = {value}u;");
    }
    for &(name, value) in WGSL_F32_CONSTANTS {
        let _ = writeln!(s, "const {name}: f32 = {};", f32_literal(value));
    }
    for &(name, [x, y, z]) in WGSL_VEC3_CONSTANTS {
        let [x, y, z] = [x, y, z].map(f32_literal);
        let _ = writeln!(s, "const {name}: vec3<f32> = vec3<f32>({x}, {y}, {z});");
    }
    s.push_str("// The scene's structs, generated from gpu::layout.\n");
    s.push_str(&generated_wgsl_structs());
    s
}
