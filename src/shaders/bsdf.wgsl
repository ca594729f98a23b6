// bsdf.wgsl — the BSDF interface and its dispatch, twin of src/bsdf/mod.rs; one file per
// variant follows it (fresnel, microfacet, diffuse, conductor, dielectric, thin, glossy,
// rough_dielectric, metal_rough, thin_film, iridescent: the files of src/bsdf/), all in the local shading frame
// (z = shading normal). Conventions as in src/bsdf/mod.rs: wo and wi point away from the
// surface, eval excludes the cosine, delta lobes return 0 from eval/pdf and their weight from
// sample.
//
// The switch: `Bsdf.kind` is one of the BSDF_* constants (generated from gpu::layout), one per
// `bsdf::Bsdf` variant, and `bsdf_eval` / `bsdf_pdf` / `bsdf_sample` dispatch on it. A new CPU
// variant gets a new constant, a file with a `<name>_eval/_pdf/_sample` triple with the same
// names as its Rust methods, a case in each switch guarded by its HAS_* override, and a row in
// gpu::upload::bsdf_kind.

// Pipeline specialisation (gpu::pipeline::Specialization): absent kinds are compiled out.
override HAS_LAMBERT: bool = true;
override HAS_MIRROR: bool = true;
override HAS_SMOOTH_DIELECTRIC: bool = true;
override HAS_ROUGH_DIELECTRIC: bool = true;
override HAS_ROUGH_CONDUCTOR: bool = true;
override HAS_METAL_ROUGH: bool = true;
override HAS_THIN_DIELECTRIC: bool = true;
override HAS_CONDUCTOR: bool = true;
override HAS_IRIDESCENCE: bool = true;

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

// Whether every lobe of a BSDF of kind `kind` (a material's `bsdf`) is a delta distribution.
fn bsdf_kind_is_delta(kind: u32) -> bool {
    switch kind {
        case BSDF_MIRROR, BSDF_SMOOTH_DIELECTRIC, BSDF_THIN_DIELECTRIC, BSDF_SMOOTH_CONDUCTOR, BSDF_FILM_SMOOTH: {
            return true;
        }
        default: {
            return false;
        }
    }
}

// True if some lobe transmits (the sampled direction may cross the surface).
fn bsdf_can_transmit(b: Bsdf) -> bool {
    switch b.kind {
        case BSDF_SMOOTH_DIELECTRIC, BSDF_ROUGH_DIELECTRIC, BSDF_THIN_DIELECTRIC: {
            return true;
        }
        case BSDF_FILM_SMOOTH, BSDF_FILM_ROUGH: {
            return film_base(b) == FILM_ON_DIELECTRIC || film_base(b) == FILM_ON_SHEET;
        }
        default: {
            return false;
        }
    }
}

// Heckbert class of the non-delta part for single-class BSDFs (`Bsdf::class`).
fn bsdf_class(b: Bsdf) -> u32 {
    switch b.kind {
        case BSDF_LAMBERT: {
            return LOBE_D;
        }
        case BSDF_MIRROR, BSDF_SMOOTH_DIELECTRIC, BSDF_THIN_DIELECTRIC, BSDF_SMOOTH_CONDUCTOR, BSDF_FILM_SMOOTH: {
            return LOBE_S;
        }
        default: {
            return LOBE_G;
        }
    }
}

fn bsdf_eval(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>, mode: u32) -> vec4<f32> {
    switch b.kind {
        case BSDF_LAMBERT: {
            if HAS_LAMBERT {
                return lambert_eval(b.color, wo, wi);
            }
        }
        case BSDF_ROUGH_DIELECTRIC: {
            if HAS_ROUGH_DIELECTRIC {
                return rough_dielectric_eval(b, wo, wi, mode);
            }
        }
        case BSDF_ROUGH_CONDUCTOR: {
            if HAS_ROUGH_CONDUCTOR {
                return rough_conductor_eval(b, wo, wi);
            }
        }
        case BSDF_METAL_ROUGH: {
            if HAS_METAL_ROUGH {
                return metal_rough_eval(b, wo, wi);
            }
        }
        case BSDF_ROUGH_FRESNEL_CONDUCTOR: {
            if HAS_CONDUCTOR {
                return rough_fresnel_conductor_eval(b, wo, wi);
            }
        }
        case BSDF_FILM_ROUGH: {
            if HAS_IRIDESCENCE {
                return film_eval(b, wo, wi, mode);
            }
        }
        default: {}
    }
    // Delta lobes (mirror, smooth and thin dielectric) and compiled-out kinds.
    return vec4<f32>(0.0);
}

fn bsdf_pdf(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    switch b.kind {
        case BSDF_LAMBERT: {
            if HAS_LAMBERT {
                return lambert_pdf(wo, wi, b.metallic != 0.0);
            }
        }
        case BSDF_ROUGH_DIELECTRIC: {
            if HAS_ROUGH_DIELECTRIC {
                return rough_dielectric_pdf(b, wo, wi);
            }
        }
        case BSDF_ROUGH_CONDUCTOR: {
            if HAS_ROUGH_CONDUCTOR {
                return rough_conductor_pdf(b, wo, wi);
            }
        }
        case BSDF_METAL_ROUGH: {
            if HAS_METAL_ROUGH {
                return metal_rough_pdf(b, wo, wi);
            }
        }
        case BSDF_ROUGH_FRESNEL_CONDUCTOR: {
            if HAS_CONDUCTOR {
                return rough_conductor_pdf(b, wo, wi);
            }
        }
        case BSDF_FILM_ROUGH: {
            if HAS_IRIDESCENCE {
                return film_pdf(b, wo, wi);
            }
        }
        default: {}
    }
    return 0.0;
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

fn bsdf_sample(b: Bsdf, wo: vec3<f32>, uc: f32, u2: vec2<f32>, mode: u32) -> BsdfSample {
    switch b.kind {
        case BSDF_LAMBERT: {
            if HAS_LAMBERT {
                return lambert_sample(b.color, wo, u2, b.metallic != 0.0);
            }
        }
        case BSDF_MIRROR: {
            if HAS_MIRROR {
                return mirror_sample(b.color, wo);
            }
        }
        case BSDF_SMOOTH_DIELECTRIC: {
            if HAS_SMOOTH_DIELECTRIC {
                return smooth_dielectric_sample(b.eta, wo, uc, mode);
            }
        }
        case BSDF_THIN_DIELECTRIC: {
            if HAS_THIN_DIELECTRIC {
                return thin_dielectric_sample(b.eta, wo, uc);
            }
        }
        case BSDF_ROUGH_DIELECTRIC: {
            if HAS_ROUGH_DIELECTRIC {
                return rough_dielectric_sample(b, wo, uc, u2, mode);
            }
        }
        case BSDF_ROUGH_CONDUCTOR: {
            if HAS_ROUGH_CONDUCTOR {
                return rough_conductor_sample(b, wo, u2);
            }
        }
        case BSDF_METAL_ROUGH: {
            if HAS_METAL_ROUGH {
                return metal_rough_sample(b, wo, uc, u2);
            }
        }
        case BSDF_SMOOTH_CONDUCTOR: {
            if HAS_CONDUCTOR {
                return smooth_conductor_sample(b, wo);
            }
        }
        case BSDF_ROUGH_FRESNEL_CONDUCTOR: {
            if HAS_CONDUCTOR {
                return rough_fresnel_conductor_sample(b, wo, u2);
            }
        }
        case BSDF_FILM_SMOOTH, BSDF_FILM_ROUGH: {
            if HAS_IRIDESCENCE {
                return film_sample(b, wo, uc, u2, mode);
            }
        }
        default: {}
    }
    return bsdf_sample_none();
}
