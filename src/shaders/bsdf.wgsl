// bsdf.wgsl — twins of src/bsdf/*.rs in the local shading frame (z = shading normal).
// Conventions as in src/bsdf/mod.rs: wo and wi point away from the surface, eval excludes the
// cosine, delta lobes return 0 from eval/pdf and their weight from sample.
//
// The BSDF switch: `Bsdf.kind` is one of the BSDF_* constants, one per `bsdf::Bsdf` variant,
// and `bsdf_eval` / `bsdf_pdf` / `bsdf_sample` dispatch on it. A new CPU variant gets a new
// constant, a `<name>_eval/_pdf/_sample` triple here with the same names as its Rust methods,
// a case in each switch guarded by its HAS_* override, and a row in gpu::upload::bsdf_kind.

const BSDF_LAMBERT: u32 = 0u;
const BSDF_MIRROR: u32 = 1u;
const BSDF_SMOOTH_DIELECTRIC: u32 = 2u;
// Reserved for the CPU BSDFs being written in src/bsdf/ (same names there).
const BSDF_ROUGH_DIELECTRIC: u32 = 3u;
const BSDF_ROUGH_CONDUCTOR: u32 = 4u;
const BSDF_METAL_ROUGH: u32 = 5u;
const BSDF_THIN_DIELECTRIC: u32 = 6u;

// Pipeline specialisation (gpu::pipeline::Specialization): absent kinds are compiled out.
override HAS_LAMBERT: bool = true;
override HAS_MIRROR: bool = true;
override HAS_SMOOTH_DIELECTRIC: bool = true;

// A BSDF instance at a surface point (material parameters resolved).
struct Bsdf {
    kind: u32,
    // Lambert albedo / mirror reflectance / specular tint.
    color: vec3<f32>,
    // IOR inside / outside.
    eta: f32,
    // Microfacet α (rough kinds).
    alpha: f32,
    metallic: f32,
}

// One sampled scattering direction (bsdf::BsdfSample; `valid` = Some).
struct BsdfSample {
    valid: bool,
    wi: vec3<f32>,
    f: vec3<f32>,
    weight: vec3<f32>,
    pdf: f32,
    is_delta: bool,
    event: u32,
    lobe: u32,
    eta_rel: f32,
}

fn bsdf_sample_none() -> BsdfSample {
    return BsdfSample(false, vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0), 0.0, false, EVENT_REFLECT, LOBE_D, 1.0);
}

// ---------------------------------------------------------------------------------------------
// Fresnel (bsdf::fresnel)

struct FresnelTerms {
    r_par: f32,
    r_perp: f32,
    f: f32,
    cos_t: f32,
    eta_rel: f32,
}

// Exact unpolarised dielectric Fresnel with r∥ and r⊥.
// Hecht, "Optics" 5th ed. §4.6.2 (Fresnel equations); PBR 4th ed. §9.3.5 (`FrDielectric`).
fn fresnel_dielectric_terms(cos_i_in: f32, eta: f32) -> FresnelTerms {
    var cos_i = clamp(cos_i_in, -1.0, 1.0);
    var eta_rel = eta;
    if cos_i < 0.0 {
        eta_rel = 1.0 / eta;
        cos_i = -cos_i;
    }
    let sin2_i = max(1.0 - cos_i * cos_i, 0.0);
    let sin2_t = sin2_i / (eta_rel * eta_rel);
    if sin2_t >= 1.0 {
        return FresnelTerms(1.0, 1.0, 1.0, 0.0, eta_rel);
    }
    let cos_t = sqrt(max(1.0 - sin2_t, 0.0));
    let r_par = (eta_rel * cos_i - cos_t) / (eta_rel * cos_i + cos_t);
    let r_perp = (cos_i - eta_rel * cos_t) / (cos_i + eta_rel * cos_t);
    return FresnelTerms(r_par, r_perp, 0.5 * (r_par * r_par + r_perp * r_perp), cos_t, eta_rel);
}

// Unpolarised dielectric reflectance F(cos_i, eta). See [`fresnel_dielectric_terms`].
fn fresnel_dielectric(cos_i: f32, eta: f32) -> f32 {
    return fresnel_dielectric_terms(cos_i, eta).f;
}

// Mirror reflection of `wo` about the normal `n`. PBR 4th ed. §9.3.1.
fn reflect(wo: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    return -wo + 2.0 * dot3(wo, n) * n;
}

// Refraction result (`None` = total internal reflection → ok = false).
struct Refracted {
    ok: bool,
    wt: vec3<f32>,
}

// Snell refraction of `wi` through a surface with normal `n` (same side as `wi`).
// PBR 4th ed. §9.3.2 (`Refract`), Snell: n_i sinθi = n_t sinθt.
fn refract(wi: vec3<f32>, n: vec3<f32>, eta_rel: f32) -> Refracted {
    let cos_i = dot3(n, wi);
    let sin2_i = max(1.0 - cos_i * cos_i, 0.0);
    let sin2_t = sin2_i / (eta_rel * eta_rel);
    if sin2_t >= 1.0 {
        return Refracted(false, vec3<f32>(0.0));
    }
    let cos_t = sqrt(1.0 - sin2_t);
    return Refracted(true, -wi / eta_rel + (cos_i / eta_rel - cos_t) * n);
}

// ---------------------------------------------------------------------------------------------
// Lambert (bsdf::diffuse). Lambert 1760; PBR 4th ed. §9.2.

fn lambert_eval(albedo: vec3<f32>, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return vec3<f32>(0.0);
    }
    return albedo * FRAC_1_PI;
}

fn lambert_pdf(wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    return cosine_hemisphere_pdf(wi.z);
}

// Cosine-weighted sampling: weight = ρ. PBR 4th ed. §9.2.
fn lambert_sample(albedo: vec3<f32>, wo: vec3<f32>, u2: vec2<f32>) -> BsdfSample {
    if wo.z <= 0.0 {
        return bsdf_sample_none();
    }
    let wi = cosine_hemisphere(u2);
    let pdf = cosine_hemisphere_pdf(wi.z);
    if pdf <= 0.0 {
        return bsdf_sample_none();
    }
    return BsdfSample(true, wi, albedo * FRAC_1_PI, albedo, pdf, false, EVENT_REFLECT, LOBE_D, 1.0);
}

// ---------------------------------------------------------------------------------------------
// Mirror (bsdf::conductor). f = R δ(wi − reflect(wo)) / |cos θi|; PBR 4th ed. §9.4 (specular reflection).

fn mirror_sample(reflectance: vec3<f32>, wo: vec3<f32>) -> BsdfSample {
    if wo.z <= 0.0 {
        return bsdf_sample_none();
    }
    return BsdfSample(true, vec3<f32>(-wo.x, -wo.y, wo.z), vec3<f32>(0.0), reflectance, 1.0, true, EVENT_REFLECT, LOBE_S, 1.0);
}

// ---------------------------------------------------------------------------------------------
// Smooth dielectric (bsdf::dielectric). Reflect with probability F, refract with 1 − F (PBR 4th ed. §9.5.1, `DielectricBxDF`

fn smooth_dielectric_sample(eta: f32, wo: vec3<f32>, uc: f32, mode: u32) -> BsdfSample {
    if wo.z == 0.0 {
        return bsdf_sample_none();
    }
    if eta == 1.0 {
        // Index-matched: no interface at all.
        return BsdfSample(true, -wo, vec3<f32>(0.0), vec3<f32>(1.0), 1.0, true, EVENT_TRANSMIT, LOBE_S, 1.0);
    }
    let fr = fresnel_dielectric_terms(wo.z, eta);
    if uc < fr.f {
        // Specular reflection (includes TIR, where F = 1).
        return BsdfSample(true, vec3<f32>(-wo.x, -wo.y, wo.z), vec3<f32>(0.0), vec3<f32>(1.0), fr.f, true, EVENT_REFLECT, LOBE_S, 1.0);
    }
    // wt = −wo/η' + (cosθi/η' − cosθt) n, PBR 4th ed. eq. (9.19).
    let eta_rel = fr.eta_rel;
    var sign = 1.0;
    if wo.z < 0.0 {
        sign = -1.0;
    }
    let wi = normalize3(vec3<f32>(-wo.x / eta_rel, -wo.y / eta_rel, -sign * fr.cos_t));
    // Radiance compresses by 1/η'² when entering a denser medium. Veach 1997, §5.2.
    var scale = 1.0;
    if mode == MODE_RADIANCE {
        scale = 1.0 / (eta_rel * eta_rel);
    }
    return BsdfSample(true, wi, vec3<f32>(0.0), vec3<f32>(scale), 1.0 - fr.f, true, EVENT_TRANSMIT, LOBE_S, eta_rel);
}

// ---------------------------------------------------------------------------------------------
// The switch (bsdf::Bsdf)

// True if every lobe is a delta distribution (next-event estimation is skipped).
fn bsdf_is_delta(b: Bsdf) -> bool {
    switch b.kind {
        case BSDF_MIRROR, BSDF_SMOOTH_DIELECTRIC, BSDF_THIN_DIELECTRIC: {
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
        default: {
            return false;
        }
    }
}

fn bsdf_eval(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>, mode: u32) -> vec3<f32> {
    switch b.kind {
        case BSDF_LAMBERT: {
            if HAS_LAMBERT {
                return lambert_eval(b.color, wo, wi);
            }
        }
        default: {}
    }
    // Delta lobes (mirror, smooth dielectric) and compiled-out kinds.
    return vec3<f32>(0.0);
}

fn bsdf_pdf(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    switch b.kind {
        case BSDF_LAMBERT: {
            if HAS_LAMBERT {
                return lambert_pdf(wo, wi);
            }
        }
        default: {}
    }
    return 0.0;
}

fn bsdf_sample(b: Bsdf, wo: vec3<f32>, uc: f32, u2: vec2<f32>, mode: u32) -> BsdfSample {
    switch b.kind {
        case BSDF_LAMBERT: {
            if HAS_LAMBERT {
                return lambert_sample(b.color, wo, u2);
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
        default: {}
    }
    return bsdf_sample_none();
}
