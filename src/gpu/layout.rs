//! GPU buffer layouts: `#[repr(C)]` + `bytemuck::Pod` twins of the WGSL structs in
//! the `.wgsl` twins beside the Rust files. No `vec3` in storage buffers: three-component values are `[f32; 3]`
//! (`array<f32, 3>` in WGSL). `tests/gpu.rs` checks every struct's size and field offsets
//! against the WGSL via naga reflection ([`wgsl_struct_layout`]). The enum and flag constants
//! below are the only definition of their values: `gpu::prelude` emits them into the WGSL.

use crate::bsdf::{Event, Lobe, TransportMode};
use crate::paths::{DfaTable, MAX_STATES, NUM_SYMBOLS, Symbol};
use crate::render::photon_aim::MAX_TARGETS;
use crate::scene::material::Wrap;

/// Size and field offsets of a GPU struct, for the layout check.
pub trait GpuLayout: bytemuck::Pod {
    /// Name of the WGSL struct.
    const WGSL_NAME: &'static str;
    /// (field name, byte offset) in declaration order.
    fn fields() -> Vec<(&'static str, u32)>;
    fn size() -> u32 {
        std::mem::size_of::<Self>() as u32
    }
}

/// The WGSL spelling of a field type of a struct whose WGSL declaration is generated
/// (`gpu_struct! { wgsl; … }`): scalars, and arrays as `array<T, N>` (storage structs keep
/// three-component values as `array<f32, 3>`, never `vec3`).
pub trait WgslType {
    fn wgsl() -> String;
}

impl WgslType for f32 {
    fn wgsl() -> String {
        "f32".into()
    }
}

impl WgslType for u32 {
    fn wgsl() -> String {
        "u32".into()
    }
}

impl WgslType for i32 {
    fn wgsl() -> String {
        "i32".into()
    }
}

impl<T: WgslType, const N: usize> WgslType for [T; N] {
    fn wgsl() -> String {
        format!("array<{}, {N}>", T::wgsl())
    }
}

/// A GPU struct whose WGSL twin is generated from it ([`generated_wgsl_structs`]).
pub trait GeneratedWgsl: GpuLayout {
    /// The WGSL declaration, one member per field in order.
    fn wgsl_struct() -> String;
}

macro_rules! gpu_struct {
    (wgsl; $(#[$m:meta])* pub struct $name:ident { $($(#[$fm:meta])* pub $f:ident : $t:ty),* $(,)? }) => {
        gpu_struct! { $(#[$m])* pub struct $name { $($(#[$fm])* pub $f: $t),* } }
        impl GeneratedWgsl for $name {
            fn wgsl_struct() -> String {
                let mut s = format!("struct {} {{\n", stringify!($name));
                $(s.push_str(&format!("    {}: {},\n", stringify!($f), <$t as WgslType>::wgsl()));)*
                s.push_str("}\n");
                s
            }
        }
    };
    ($(#[$m:meta])* pub struct $name:ident { $($(#[$fm:meta])* pub $f:ident : $t:ty),* $(,)? }) => {
        $(#[$m])*
        #[repr(C)]
        #[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
        pub struct $name { $($(#[$fm])* pub $f: $t),* }
        impl GpuLayout for $name {
            const WGSL_NAME: &'static str = stringify!($name);
            fn fields() -> Vec<(&'static str, u32)> {
                vec![$((stringify!($f), std::mem::offset_of!($name, $f) as u32)),*]
            }
        }
    };
}

/// The WGSL declarations of the structs generated from their Rust twins (prepended to every
/// kernel by `gpu::prelude`): a field added here reaches the WGSL without a second edit.
pub fn generated_wgsl_structs() -> String {
    [
        BvhNode::wgsl_struct(),
        Triangle::wgsl_struct(),
        Vertex::wgsl_struct(),
        Material::wgsl_struct(),
        Light::wgsl_struct(),
    ]
    .concat()
}

gpu_struct! {
    wgsl;
    /// BVH2 node (obvhs `Bvh2Node` repacked): inner if `prim_count` = 0 (children at
    /// `first_index` and `first_index + 1`), else a leaf over triangle slots
    /// `first_index .. first_index + prim_count`.
    pub struct BvhNode {
        pub lo: [f32; 3],
        pub prim_count: u32,
        pub hi: [f32; 3],
        pub first_index: u32,
    }
}

gpu_struct! {
    /// A compressed 8-wide BVH node (Ylitie, Karras & Laine 2017, "Efficient Incoherent Ray
    /// Traversal on GPUs Through Compressed Wide BVHs", HPG, §3.1; obvhs' `CwBvhNode` byte
    /// for byte, its child boxes re-quantised by `upload::cwbvh`). Child c's box on axis a is
    /// `p[a] + e[a]·q` for its two 8-bit planes q, e[a] = 2^(byte a of `e_imask` − 127).
    pub struct CwNode {
        /// The node box's minimum corner (the quantisation grid's origin).
        pub p: [f32; 3],
        /// Bytes 0–2: the biased exponents of e per axis; byte 3: `imask` (bit c set: child
        /// c is an inner node).
        pub e_imask: u32,
        /// Index of the first inner child (inner children are consecutive, in slot order).
        pub child_base: u32,
        /// First triangle slot of the leaf children.
        pub prim_base: u32,
        /// Child c's meta byte (byte c of the 8): 0 = empty slot; inner: 24 + c with the
        /// high bits 001; leaf: triangle offset (low 5 bits) and unary count (high 3 bits).
        pub child_meta: [u32; 2],
        /// Quantised planes per axis: words 0–1 the minima of children 0–3 and 4–7 (a byte
        /// each), words 2–3 the maxima.
        pub q_x: [u32; 4],
        pub q_y: [u32; 4],
        pub q_z: [u32; 4],
    }
}

gpu_struct! {
    /// A ray of the traversal probe (bvh_probe.wgsl).
    pub struct BvhProbeRay {
        pub org: [f32; 3],
        pub tmax: f32,
        pub dir: [f32; 3],
        /// 1: occlusion (first hit), 0: closest hit.
        pub any_hit: u32,
    }
}

gpu_struct! {
    /// The traversal probe's answer for one ray: the hit (`found` = 1) and, for `traverse`,
    /// its work.
    pub struct BvhProbeOut {
        pub t: f32,
        /// Leaf slot of the triangle hit.
        pub slot: u32,
        pub b1: f32,
        pub b2: f32,
        pub found: u32,
        /// Node records visited, child boxes tested, triangles tested.
        pub nodes: u32,
        pub boxes: u32,
        pub tris: u32,
    }
}

gpu_struct! {
    wgsl;
    /// A triangle in BVH leaf order (slot k holds scene triangle `primitive_indices[k]`).
    pub struct Triangle {
        pub p0: [f32; 3],
        pub material: u32,
        pub p1: [f32; 3],
        pub scene_tri: u32,
        pub p2: [f32; 3],
        /// `LightSet::tri_pick_prob` of the scene triangle.
        pub pick_prob: f32,
        pub i0: u32,
        pub i1: u32,
        pub i2: u32,
        /// `Mesh::area` of the scene triangle.
        pub area: f32,
    }
}

gpu_struct! {
    wgsl;
    /// Per-vertex shading attributes (positions live in [`Triangle`]).
    pub struct Vertex {
        pub normal: [f32; 3],
        pub u: f32,
        pub v: f32,
        /// Bitangent sign of the tangent (±1; `Mesh::tangents` w), 0 without one.
        pub tangent_w: f32,
        /// Tangent xyz (`Mesh::tangents`; zero when the scene has no normal map).
        pub tangent: [f32; 3],
    }
}

gpu_struct! {
    wgsl;
    /// A material resolved for the GPU (`bsdf` = one of the [`BSDF_LAMBERT`]… kinds).
    pub struct Material {
        pub base_color: [f32; 3],
        pub bsdf: u32,
        pub emission: [f32; 3],
        /// `MAT_*` flags ([`MAT_EMISSIVE`]…).
        pub flags: u32,
        /// Beer–Lambert σ_a (`scene::Material::sigma_a`).
        pub sigma_a: [f32; 3],
        /// `scene::Material::ior`.
        pub eta: f32,
        /// KHR_materials_specular colour (max 0) and factor (clamped to [0, 1]).
        pub specular_color: [f32; 3],
        pub specular_factor: f32,
        /// KHR_materials_volume attenuation (spectral absorption); distance 0 = none.
        pub attenuation_color: [f32; 3],
        pub attenuation_distance: f32,
        /// α of rough glass / glossy metal (`roughness_to_alpha(roughness)`).
        pub alpha: f32,
        /// Raw metallic and roughness factors (metal-rough multiplies the texture in).
        pub metallic: f32,
        pub roughness: f32,
        /// `DIST_*` ([`DIST_GGX`], [`DIST_BECKMANN`]).
        pub dist: u32,
        /// Abbe number V_d, 0 = not dispersive.
        pub abbe: f32,
        /// Texture reference slots ([`NO_TEXTURE`] = none).
        pub base_tex: u32,
        pub mr_tex: u32,
        /// Nested dielectrics: `scene::Material::priority`.
        pub priority: i32,
        /// Tabulated metal (`scene::Material::conductor`): linear-sRGB η and k per channel
        /// (`Metal::rgb`) and its code ([`METAL_NONE`] or `Metal::index() + 1`).
        pub cond_eta: [f32; 3],
        pub metal: u32,
        pub cond_k: [f32; 3],
        /// Emissive texture slot ([`NO_TEXTURE`] = none): emission × texture(uv).rgb.
        pub emit_tex: u32,
        /// Normal texture slot ([`NO_TEXTURE`] = none) and its `scale`.
        pub normal_tex: u32,
        pub normal_scale: f32,
        /// Thin film (`scene::Material::iridescence`, the film kinds only): its index, the
        /// thickness range (nm) and texture slot (green channel mixes min → max), the
        /// factor and what it lies on ([`FILM_ON_DIELECTRIC`]…).
        pub film_ior: f32,
        pub film_min: f32,
        pub film_max: f32,
        pub film_factor: f32,
        pub film_tex: u32,
        pub film_base: u32,
    }
}

gpu_struct! {
    wgsl;
    /// One entry of the light distribution (area triangle or punctual light) with its CDF.
    /// Lights at infinity (directional, environments) carry the scene's bounding sphere, the
    /// disk their light subpaths start from: centre in `position`, radius in `radius`.
    pub struct Light {
        pub position: [f32; 3],
        pub kind: u32,
        pub direction: [f32; 3],
        /// Leaf slot of the triangle for area lights.
        pub index: u32,
        pub intensity: [f32; 3],
        pub cos_inner: f32,
        pub cdf: f32,
        pub cos_outer: f32,
        /// Bounding-sphere radius of a light at infinity (`DirectionalLight::radius`).
        pub radius: f32,
        pub _pad1: u32,
    }
}

gpu_struct! {
    /// Per-dispatch uniforms of the integrator kernel.
    pub struct Params {
        pub cam_pos: [f32; 4],
        pub cam_right: [f32; 4],
        pub cam_up: [f32; 4],
        pub cam_back: [f32; 4],
        pub environment: [f32; 4],
        /// Row 0 of the Mueller matrix of the filter in front of the sensor
        /// (`render::Polarization::filter_row`; read only by polarised kernels).
        pub polarizer: [f32; 4],
        pub width: u32,
        pub height: u32,
        pub seed: u32,
        pub max_depth: u32,
        pub rr_depth: u32,
        pub sample_offset: u32,
        pub batch: u32,
        pub light_count: u32,
        pub w_old: f32,
        pub w_new: f32,
        pub debug_pixel: u32,
        /// The scene's ray-offset scale (`bvh::offset_scale`).
        pub offset_scale: f32,
        /// First image row of this submission (a dispatch may cover a band of rows).
        pub tile_y0: u32,
        /// First image row the accumulation film holds (an image larger than one binding
        /// renders in tiles of rows; 0 otherwise).
        pub film_y0: u32,
        /// `sppm`: the first iteration's photon radius r₁ (world units); iteration s (sample
        /// index s) has r₁ (s + 1)^`photon_radius_exp` (`render::photon_radius`).
        pub photon_radius0: f32,
        /// `sppm`: 1 / (photon paths per iteration · π); the density divides by r_s² too.
        pub photon_norm0: f32,
        /// `sppm`: photon-grid buckets per iteration − 1 (a power of two minus one).
        pub grid_mask: u32,
        /// `sppm`: photon paths per iteration (`render::photon_aim::photon_paths`).
        pub photon_paths: u32,
        /// `sppm`: spheres in `targets`; 0 = photons are emitted as the light does.
        pub target_count: u32,
        /// `sppm`: (α − 1) / 2, the exponent of the radius schedule.
        pub photon_radius_exp: f32,
        /// `sppm`: where finite lights aim their photons (centre xyz, radius w;
        /// `render::photon_aim::PhotonTargets`).
        pub targets: [[f32; 4]; MAX_TARGETS],
        /// The Heckbert path filter's table (`paths::DfaTable::words`, eye→light; zeros
        /// without a filter). Here rather than in a uniform of its own: lavapipe inlines a
        /// large shader's uniform values into a new compiled variant per distinct table
        /// (docs/gpu.md, "Parameters in a storage buffer"), and GL allows no 17th storage
        /// buffer.
        pub path_filter: FilterWords,
    }
}

/// The path filter's words as `vec4<u32>` rows (`Params::path_filter`).
#[repr(transparent)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct FilterWords(pub [[u32; 4]; FILTER_WORDS / 4]);

impl Default for FilterWords {
    fn default() -> Self {
        FilterWords([[0; 4]; FILTER_WORDS / 4])
    }
}

impl FilterWords {
    /// The rows of `table` (None: zeros, no filter).
    pub fn of(table: Option<&DfaTable>) -> FilterWords {
        let mut rows = FilterWords::default();
        if let Some(t) = table {
            for (row, w) in rows.0.iter_mut().zip(t.words().chunks(4)) {
                row.copy_from_slice(w);
            }
        }
        rows
    }
}

gpu_struct! {
    /// One stored caustic photon (src/gpu/photon.wgsl; cpu `sppm::photon::Photon`).
    pub struct Photon {
        pub px: f32,
        pub py: f32,
        pub pz: f32,
        /// k (specular vertices) | collapsed << 31.
        pub kflags: u32,
        pub beta: [f32; 4],
        pub wx: f32,
        pub wy: f32,
        pub wz: f32,
        /// Geometric normal, octahedral, `pack2x16snorm`.
        pub ng: u32,
    }
}

/// Words of the photon-grid buffer (photon.wgsl): photons stored this iteration, photons
/// refused by a full store (cumulative), then the bucket heads, then the `next` links.
pub const PHOTON_COUNT: u32 = 0;
pub const PHOTON_OVERFLOW: u32 = 1;
pub const PHOTON_HEADS: u32 = 2;
/// Length of `Params::targets` (`render::photon_aim::MAX_TARGETS`).
pub const PHOTON_TARGETS: u32 = MAX_TARGETS as u32;

gpu_struct! {
    /// Header of the stats buffer (64-bit counters as lo/hi u32 atomics); the debug records
    /// (`vec4<f32>`) follow it.
    pub struct Stats {
        pub dropped_lo: u32,
        pub dropped_hi: u32,
        pub segments_lo: u32,
        pub segments_hi: u32,
    }
}

gpu_struct! {
    /// Input of the probe kernel (src/gpu/probe.wgsl).
    pub struct ProbeCase {
        pub wo: [f32; 3],
        pub uc: f32,
        pub wi: [f32; 3],
        pub eta: f32,
        pub u2: [f32; 2],
        pub kind: u32,
        pub pixel: u32,
        pub sample: u32,
        pub seed: u32,
        /// Microfacet α and `DIST_*` (rough kinds; metal-rough uses GGX with this α).
        pub alpha: f32,
        pub dist: u32,
        /// Metal-rough metallic; `eta` doubles as its IOR.
        pub metallic: f32,
        /// `MODE_*` transport mode.
        pub mode: u32,
        pub _pad0: u32,
        pub _pad1: u32,
    }
}

gpu_struct! {
    /// Output of the probe kernel.
    pub struct ProbeOut {
        pub fresnel: [f32; 4],
        pub eta_rel: f32,
        pub refract_ok: f32,
        pub sample_pdf: f32,
        pub sample_eta_rel: f32,
        pub refracted: [f32; 3],
        /// valid | is_delta << 1 | event << 2 | lobe << 3
        pub sample_flags: u32,
        pub sample_wi: [f32; 3],
        pub pdf: f32,
        pub eval: [f32; 4],
        pub lobes_d: [f32; 4],
        pub lobes_g: [f32; 4],
        pub sample_f: [f32; 4],
        pub sample_weight: [f32; 4],
        /// Microfacet of (dist, alpha): D(m), Λ(wo), G2(wo, wi), pdf_visible(|wo|, m) with
        /// m = normalize(wo_up + wi_up).
        pub mf: [f32; 4],
        /// sample_visible(wo_up, u2), and G1(wo_up).
        pub mf_m: [f32; 3],
        pub mf_g1: f32,
        /// erfc(3 wo.x), erf(3 wo.y), erfinv(2 uc − 1), erfinv(0.9999 (2 u2.x − 1)).
        pub special: [f32; 4],
        /// sample_hero_wavelengths(uc).
        pub lambdas: [f32; 4],
        /// rgb_to_spectrum4(PROBE_COLOR, lambdas).
        pub uplift: [f32; 4],
        /// spectrum_sample_to_rgb(lambdas, (1, u2.x, u2.y, uc)), cauchy_from_abbe(eta, 40, lambdas.x).
        pub to_rgb: [f32; 4],
        /// pcg_hash(pixel), then the first 4 draws of sampler_new(pixel, sample, seed) as raw bits
        /// `bsdf_mueller` of the event (wo, wi) in the glossy class: (a, b, c, s), each per
        /// colour lane (bsdf/polarized.wgsl).
        pub mueller: [f32; 16],
        /// `bsdf_mueller_b` of (wo, wi) per lane.
        pub mueller_b: [f32; 4],
        pub rng: [u32; 5],
        pub _pad: [u32; 3],
    }
}

gpu_struct! {
    /// Uniforms of the light probe kernel (src/gpu/light_probe.wgsl): what light.wgsl
    /// reads of the integrator's [`Params`], plus the environment radiance.
    pub struct LightProbeParams {
        pub environment: [f32; 4],
        /// The uniform environment's bounding sphere (centre, radius).
        pub sphere: [f32; 4],
        pub light_count: u32,
        pub _pad0: u32,
        pub _pad1: u32,
        pub _pad2: u32,
    }
}

gpu_struct! {
    /// Input of the light probe kernel: one light of the packed distribution (`light` ≥ the
    /// light count probes the environment), a reference point and the random numbers.
    pub struct LightProbeCase {
        /// Reference point of `light_sample_li`.
        pub p: [f32; 3],
        pub light: u32,
        /// Normal and direction of `light_le` / `light_pdf_le`.
        pub n: [f32; 3],
        /// Selection probability folded into the densities.
        pub pick: f32,
        pub w: [f32; 3],
        /// `light_set_pick(u_pick)`.
        pub u_pick: f32,
        pub u: [f32; 2],
        pub u_pos: [f32; 2],
        pub u_dir: [f32; 2],
        /// The sampler a double-sided area light draws its side from.
        pub pixel: u32,
        pub sample: u32,
        pub seed: u32,
        pub _pad0: u32,
        pub _pad1: u32,
        pub _pad2: u32,
    }
}

gpu_struct! {
    /// Output of the light probe kernel.
    pub struct LightProbeOut {
        /// `light_sample_li`: valid | is_delta << 1 | infinite << 2.
        pub li_flags: u32,
        pub li_l: [f32; 3],
        pub li_wi: [f32; 3],
        pub li_pdf: f32,
        pub li_p: [f32; 3],
        /// `light_pdf_li(pick, |p_light − p|, n_light, wi)` of the sampled point.
        pub li_pdf_back: f32,
        pub li_n: [f32; 3],
        /// `light_sample_le`: valid | delta_pos << 1.
        pub le_flags: u32,
        pub le_p: [f32; 3],
        pub le_pdf_pos: f32,
        pub le_n: [f32; 3],
        pub le_pdf_dir: f32,
        pub le_dir: [f32; 3],
        pub le_cos_n: f32,
        pub le_l: [f32; 3],
        /// The sampler's first draw: the side a double-sided area light emits from.
        pub u_side: f32,
        /// `light_le(n, w)`, then `light_pdf_le(pick, n, w)`.
        pub emitted: [f32; 3],
        pub pdf_pos: f32,
        pub pdf_dir: f32,
        /// `light_set_pick(u_pick)`: probability and the picked entry's CDF value.
        pub pick_prob: f32,
        pub pick_cdf: f32,
        /// `light_set_area(slot).prob` of an area light's leaf slot (0 for other kinds).
        pub area_prob: f32,
    }
}

// Constants shared with the WGSL. Each one is emitted into the WGSL prelude by
// `gpu::prelude` (the shaders never define them themselves; tests/gpu.rs checks both).

/// BSDF kinds (`Bsdf.kind` in bsdf.wgsl): generated by the BSDF table (`bsdf::family`).
pub use crate::bsdf::family::kinds::*;
/// What a film lies on (`bsdf::FilmBase`), in `Material::film_base` and the WGSL `Bsdf.film.w`.
pub const FILM_ON_DIELECTRIC: u32 = 0;
pub const FILM_ON_SHEET: u32 = 1;
pub const FILM_ON_CONDUCTOR: u32 = 2;
pub const FILM_ON_REFLECTANCE: u32 = 3;

/// `Material.metal` of a material without a tabulated metal.
pub const METAL_NONE: u32 = 0;

/// Microfacet distributions (`bsdf::MicrofacetDistribution`, see `upload::dist_code`).
pub const DIST_GGX: u32 = 0;
pub const DIST_BECKMANN: u32 = 1;

/// Transport modes (`bsdf::TransportMode`).
pub const MODE_RADIANCE: u32 = TransportMode::Radiance as u32;
pub const MODE_IMPORTANCE: u32 = TransportMode::Importance as u32;

/// Sampled events (`bsdf::Event`).
pub const EVENT_REFLECT: u32 = Event::Reflect as u32;
pub const EVENT_TRANSMIT: u32 = Event::Transmit as u32;

/// Heckbert lobes (`bsdf::Lobe`); a lobe's path symbol is `LOBE_* + 1` (`SYM_*`).
pub const LOBE_D: u32 = Lobe::D as u32;
pub const LOBE_G: u32 = Lobe::G as u32;
pub const LOBE_S: u32 = Lobe::S as u32;

/// Path symbols (`paths::Symbol`, the DFA columns).
pub const SYM_L: u32 = Symbol::L as u32;
pub const SYM_D: u32 = Symbol::D as u32;
pub const SYM_G: u32 = Symbol::G as u32;
pub const SYM_S: u32 = Symbol::S as u32;
pub const SYM_E: u32 = Symbol::E as u32;

/// Word offsets of the path-filter table (`paths::DfaTable::words`, "Table layout").
pub const DFA_NUM_SYMBOLS: u32 = NUM_SYMBOLS as u32;
pub const DFA_TRANSITIONS: u32 = (MAX_STATES * NUM_SYMBOLS) as u32;
pub const DFA_ACCEPTING: u32 = DFA_TRANSITIONS;
pub const DFA_LIVE: u32 = DFA_TRANSITIONS + 1;
pub const DFA_START: u32 = DFA_TRANSITIONS + 2;
pub const DFA_DEAD: u32 = DFA_TRANSITIONS + 3;
pub const DFA_NUM_STATES: u32 = DFA_TRANSITIONS + 4;
/// `vec4<u32>` rows of the path filter's table (`Params::path_filter`).
pub const DFA_VEC4S: u32 = (FILTER_WORDS / 4) as u32;

/// No texture reference.
pub const NO_TEXTURE: u32 = u32::MAX;
/// Wrap modes of a texture reference (`scene::material::Wrap`).
pub const WRAP_REPEAT: u32 = Wrap::Repeat as u32;
pub const WRAP_MIRRORED_REPEAT: u32 = Wrap::MirroredRepeat as u32;
pub const WRAP_CLAMP_TO_EDGE: u32 = Wrap::ClampToEdge as u32;
/// Texture-reference header flags: wrap_s | wrap_t << 2 | linear | valid.
pub const TEX_LINEAR: u32 = 16;
pub const TEX_VALID: u32 = 32;

/// Words of the path filter's table (`Params::path_filter`, `DfaTable::WORDS`, a multiple of 4).
pub const FILTER_WORDS: usize = DfaTable::WORDS;

/// Material flags (`Material.flags`, see `upload::pack_material`).
pub const MAT_EMISSIVE: u32 = 1;
pub const MAT_DOUBLE_SIDED: u32 = 2;
/// The path crosses the surface (dielectrics keep the outward normal).
pub const MAT_TRANSMISSIVE: u32 = 4;
/// Solid glass: the path enters its medium (Beer–Lambert absorption applies inside).
pub const MAT_SOLID: u32 = 8;
/// Emitter that is black otherwise (the path ends there).
pub const MAT_BLACK_EMITTER: u32 = 16;
pub const MAT_ABSORBS: u32 = 32;
/// Lambert sampled uniformly over the hemisphere (`scene::Material::uniform_sampling`).
pub const MAT_UNIFORM_SAMPLING: u32 = 64;

/// Light kinds (`Light.kind` in light.wgsl): generated by the light table
/// (`scene::light::family`).
pub use crate::scene::light::family::kinds::*;

/// Nested dielectrics: entries of the medium stack and the false hits a path may pass
/// (`scene::nesting`).
pub const MEDIUM_STACK_DEPTH: u32 = crate::scene::nesting::MEDIUM_STACK_DEPTH as u32;
pub const FALSE_HIT_LIMIT: u32 = crate::scene::nesting::FALSE_HIT_LIMIT;

/// Debug records: 1 (camera dir) + 3 per vertex × 16 vertices + 1 (final sample).
pub const DEBUG_MAX_VERTICES: usize = 16;
pub const DEBUG_STRIDE: usize = 3;
pub const DEBUG_RECORDS: usize = 2 + DEBUG_STRIDE * DEBUG_MAX_VERTICES;

/// Size and (member name, offset) list of the WGSL struct `name` in `source`, by naga
/// reflection. `Err` if the source does not parse or has no such struct.
pub fn wgsl_struct_layout(source: &str, name: &str) -> anyhow::Result<(u32, Vec<(String, u32)>)> {
    let module = naga::front::wgsl::parse_str(source)
        .map_err(|e| anyhow::anyhow!("WGSL parse error: {}", e.emit_to_string(source)))?;
    for (_, ty) in module.types.iter() {
        if ty.name.as_deref() == Some(name)
            && let naga::TypeInner::Struct { members, span } = &ty.inner
        {
            let fields = members
                .iter()
                .map(|m| (m.name.clone().unwrap_or_default(), m.offset))
                .collect();
            return Ok((*span, fields));
        }
    }
    anyhow::bail!("no struct '{name}' in the WGSL source")
}

/// Compare a Rust GPU struct with its WGSL twin; `Err` describes the first mismatch.
pub fn check_layout<T: GpuLayout>(source: &str) -> anyhow::Result<()> {
    let (size, fields) = wgsl_struct_layout(source, T::WGSL_NAME)?;
    let rust: Vec<(String, u32)> = T::fields()
        .into_iter()
        .map(|(n, o)| (n.to_string(), o))
        .collect();
    anyhow::ensure!(
        size == T::size(),
        "{}: WGSL size {size} != Rust size {}",
        T::WGSL_NAME,
        T::size()
    );
    anyhow::ensure!(
        fields == rust,
        "{}: WGSL fields {fields:?} != Rust fields {rust:?}",
        T::WGSL_NAME
    );
    Ok(())
}

/// Like [`check_layout`] for a WGSL struct that ends in a runtime-sized array `tail` placed
/// right after the Rust header `T` (the stats buffer).
pub fn check_layout_with_tail<T: GpuLayout>(source: &str, tail: &str) -> anyhow::Result<()> {
    let (_, mut fields) = wgsl_struct_layout(source, T::WGSL_NAME)?;
    let last = fields.pop();
    anyhow::ensure!(
        last == Some((tail.to_string(), T::size())),
        "{}: trailing array {last:?} is not '{tail}' at offset {}",
        T::WGSL_NAME,
        T::size()
    );
    let rust: Vec<(String, u32)> = T::fields()
        .into_iter()
        .map(|(n, o)| (n.to_string(), o))
        .collect();
    anyhow::ensure!(
        fields == rust,
        "{}: WGSL fields {fields:?} != Rust fields {rust:?}",
        T::WGSL_NAME
    );
    Ok(())
}
