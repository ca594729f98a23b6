// bsdf.wgsl — the BSDF interface and its dispatch, twin of src/bsdf/mod.rs; one file per
// variant follows it (fresnel, microfacet, diffuse, conductor, dielectric, thin, glossy,
// rough_dielectric, metal_rough, thin_film, iridescent: the files of src/bsdf/), all in the local shading frame
// (z = shading normal). Conventions as in src/bsdf/mod.rs: wo and wi point away from the
// surface, eval excludes the cosine, delta lobes return 0 from eval/pdf and their weight from
// sample.
//
// The switch: `Bsdf.kind` is one of the BSDF_* constants, and `bsdf_eval` / `bsdf_pdf` /
// `bsdf_sample` / `bsdf_class` / `bsdf_kind_is_delta` dispatch on it. All five, the constants and
// the HAS_* overrides are generated from the BSDF table (src/bsdf/family.rs, one row per
// `bsdf::Bsdf` variant; bsdf::family_wgsl writes the WGSL); a new variant is a row there and a
// file with its `<name>_eval/_pdf/_sample` (the same names as its Rust methods).

// Pipeline specialisation (gpu::pipeline::Specialization): absent kinds are compiled out. Each
// variant's `HAS_*` override is declared by the generated dispatch (bsdf::family_wgsl); the
// tabulated metals' shared Fresnel code is compiled in where either of them is.
override HAS_CONDUCTOR: bool = HAS_SMOOTH_CONDUCTOR || HAS_ROUGH_FRESNEL_CONDUCTOR;

// Smooth threshold (bsdf::SMOOTH_ALPHA).

// glTF convention: α = roughness².
fn roughness_to_alpha(roughness: f32) -> f32 {
    let r = clamp(roughness, 0.0, 1.0);
    return r * r;
}

// A BSDF instance at a surface point (material parameters resolved). Colours are `Color`
// (vec4: RGB with w = 0, or four hero wavelengths in spectral mode), like the Rust.
struct Bsdf {
    kind: u32,
    // Lambert albedo / mirror or rough-conductor reflectance / metal-rough base colour.
    color: vec4<f32>,
    // IOR inside / outside.
    eta: f32,
    // Microfacet α (rough kinds).
    alpha: f32,
    // MicrofacetDistribution (DIST_*).
    dist: u32,
    // Metal-rough parameters (MetalRough::{metallic, ior, specular_factor, specular_color}).
    metallic: f32,
    ior: f32,
    specular_factor: f32,
    specular_color: vec4<f32>,
    // Thin film (BSDF_FILM_*; iridescent.wgsl): index, thickness nm, factor, FILM_ON_* base.
    film: vec4<f32>,
}

// Tabulated metals (BSDF_SMOOTH_CONDUCTOR, BSDF_ROUGH_FRESNEL_CONDUCTOR; bsdf::ComplexIor) keep
// their complex IOR η − ik in the metal-rough slots, which they do not otherwise use (two more
// vec4 fields cost the all-features kernel 8 VGPRs over its budget, tests/gpu_registers.rs):
// η per RGB channel in `specular_color` (w = 0), k in (`metallic`, `ior`, `specular_factor`).
// RGB only: gpu::upload::check_supported keeps conductors out of spectral kernels.
fn bsdf_set_conductor_ior(b: ptr<function, Bsdf>, eta: vec3<f32>, k: vec3<f32>) {
    (*b).specular_color = vec4<f32>(eta, 0.0);
    (*b).metallic = k.x;
    (*b).ior = k.y;
    (*b).specular_factor = k.z;
}

fn bsdf_conductor_eta(b: Bsdf) -> vec4<f32> {
    return b.specular_color;
}

fn bsdf_conductor_k(b: Bsdf) -> vec4<f32> {
    return vec4<f32>(b.metallic, b.ior, b.specular_factor, 0.0);
}

// A BSDF of `kind`; the metal-rough parameters (read only by BSDF_METAL_ROUGH, which sets
// them in `material_bsdf`) start as metallic 0, IOR 1.5, specular factor 1, white.
fn bsdf_new(kind: u32, color: vec4<f32>, eta: f32, alpha: f32, dist: u32) -> Bsdf {
    return Bsdf(kind, color, eta, alpha, dist, 0.0, 1.5, 1.0, vec4<f32>(1.0, 1.0, 1.0, 0.0), vec4<f32>(0.0));
}

// One sampled scattering direction (bsdf::BsdfSample; `valid` = Some).
struct BsdfSample {
    valid: bool,
    wi: vec3<f32>,
    f: vec4<f32>,
    weight: vec4<f32>,
    pdf: f32,
    is_delta: bool,
    event: u32,
    lobe: u32,
    eta_rel: f32,
}

// f (scalar) and pdf, computed together (`RoughDielectric::eval_pdf`).
struct EvalPdf {
    f: f32,
    pdf: f32,
}

// Per-class BSDF values (bsdf::LobeValues).
struct LobeValues {
    d: vec4<f32>,
    g: vec4<f32>,
}

// No sample (`None`).
fn bsdf_sample_none() -> BsdfSample {
    return BsdfSample(false, vec3<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0), 0.0, false, EVENT_REFLECT, LOBE_D, 1.0);
}

// A sample of a non-delta lobe: value f, direction wi, solid-angle pdf, weight f|cos θi|/pdf,
// event, Heckbert lobe and relative IOR (pbrt-v4 `BSDFSample(f, wi, pdf, flags, eta)`).
fn bsdf_sample_new(wi: vec3<f32>, f: vec4<f32>, weight: vec4<f32>, pdf: f32, event: u32, lobe: u32, eta_rel: f32) -> BsdfSample {
    return BsdfSample(true, wi, f, weight, pdf, false, event, lobe, eta_rel);
}

// A sample of a delta lobe (specular, LOBE_S): f is not a function value (0), `pdf` is the
// lobe's selection probability and `weight` the throughput factor (pbrt-v4 `BSDFSample` with
// `BxDFFlags::Specular`).
fn bsdf_sample_delta(wi: vec3<f32>, weight: vec4<f32>, pdf: f32, event: u32, eta_rel: f32) -> BsdfSample {
    return BsdfSample(true, wi, vec4<f32>(0.0), weight, pdf, true, event, LOBE_S, eta_rel);
}

// An index-matched interface (η = 1): no interface at all, the sample passes straight through
// with weight 1.
fn bsdf_sample_index_matched(wo: vec3<f32>) -> BsdfSample {
    return bsdf_sample_delta(-wo, vec4<f32>(1.0), 1.0, EVENT_TRANSMIT, 1.0);
}

// ---------------------------------------------------------------------------------------------
// The switch (bsdf::Bsdf)

// True if every lobe is a delta distribution (next-event estimation is skipped).
fn bsdf_is_delta(b: Bsdf) -> bool {
    return bsdf_kind_is_delta(b.kind);
}

// f(wo, wi) split by Heckbert class (delta lobes contribute nothing).
fn bsdf_eval_lobes(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>, mode: u32) -> LobeValues {
    if HAS_METAL_ROUGH && b.kind == BSDF_METAL_ROUGH {
        return metal_rough_eval_lobes(b, wo, wi);
    }
    let f = bsdf_eval(b, wo, wi, mode);
    if bsdf_class(b) == LOBE_D {
        return LobeValues(f, vec4<f32>(0.0));
    }
    return LobeValues(vec4<f32>(0.0), f);
}
