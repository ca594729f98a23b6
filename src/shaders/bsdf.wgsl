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
override HAS_ROUGH_DIELECTRIC: bool = true;
override HAS_ROUGH_CONDUCTOR: bool = true;
override HAS_METAL_ROUGH: bool = true;
override HAS_THIN_DIELECTRIC: bool = true;

// Smooth threshold (bsdf::SMOOTH_ALPHA).
const SMOOTH_ALPHA: f32 = 1e-3;

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

// Per-class BSDF values (bsdf::LobeValues).
struct LobeValues {
    d: vec4<f32>,
    g: vec4<f32>,
}

fn bsdf_sample_none() -> BsdfSample {
    return BsdfSample(false, vec3<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0), 0.0, false, EVENT_REFLECT, LOBE_D, 1.0);
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

// cos²θt of the refracted direction for |cos θi| = `cos_i` and relative IOR `eta_rel`:
// cos²θt = 1 − sin²θi/η'² = (cos²θi + (η' − 1)(η' + 1)) / η'² (Snell, PBR 4th ed. §9.3.2),
fn cos2_transmitted(cos_i: f32, eta_rel: f32) -> f32 {
    return (cos_i * cos_i + (eta_rel - 1.0) * (eta_rel + 1.0)) / (eta_rel * eta_rel);
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
    let cos2_t = cos2_transmitted(cos_i, eta_rel);
    if cos2_t <= 0.0 {
        return FresnelTerms(1.0, 1.0, 1.0, 0.0, eta_rel);
    }
    let cos_t = sqrt(cos2_t);
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
    let cos2_t = cos2_transmitted(min(cos_i, 1.0), eta_rel);
    if cos2_t <= 0.0 {
        return Refracted(false, vec3<f32>(0.0));
    }
    let cos_t = sqrt(cos2_t);
    return Refracted(true, -wi / eta_rel + (cos_i / eta_rel - cos_t) * n);
}

// ---------------------------------------------------------------------------------------------
// Lambert (bsdf::diffuse). Lambert 1760; PBR 4th ed. §9.2.

fn lambert_eval(albedo: vec4<f32>, wo: vec3<f32>, wi: vec3<f32>) -> vec4<f32> {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return vec4<f32>(0.0);
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
fn lambert_sample(albedo: vec4<f32>, wo: vec3<f32>, u2: vec2<f32>) -> BsdfSample {
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

fn mirror_sample(reflectance: vec4<f32>, wo: vec3<f32>) -> BsdfSample {
    if wo.z <= 0.0 {
        return bsdf_sample_none();
    }
    return BsdfSample(true, vec3<f32>(-wo.x, -wo.y, wo.z), vec4<f32>(0.0), reflectance, 1.0, true, EVENT_REFLECT, LOBE_S, 1.0);
}

// ---------------------------------------------------------------------------------------------
// Smooth dielectric (bsdf::dielectric). Reflect with probability F, refract with 1 − F (PBR 4th ed. §9.5.1, `DielectricBxDF`

fn smooth_dielectric_sample(eta: f32, wo: vec3<f32>, uc: f32, mode: u32) -> BsdfSample {
    if wo.z == 0.0 {
        return bsdf_sample_none();
    }
    if eta == 1.0 {
        // Index-matched: no interface at all.
        return BsdfSample(true, -wo, vec4<f32>(0.0), vec4<f32>(1.0), 1.0, true, EVENT_TRANSMIT, LOBE_S, 1.0);
    }
    let fr = fresnel_dielectric_terms(wo.z, eta);
    // TIR (F = 1) must reflect even for uc = 1.0 (the same sin²θt ≥ 1 test decides both).
    if uc < fr.f || fr.f >= 1.0 {
        // Specular reflection (includes TIR, where F = 1).
        return BsdfSample(true, vec3<f32>(-wo.x, -wo.y, wo.z), vec4<f32>(0.0), vec4<f32>(1.0), fr.f, true, EVENT_REFLECT, LOBE_S, 1.0);
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
    return BsdfSample(true, wi, vec4<f32>(0.0), vec4<f32>(scale), 1.0 - fr.f, true, EVENT_TRANSMIT, LOBE_S, eta_rel);
}

// ---------------------------------------------------------------------------------------------
// Thin-walled dielectric (bsdf::thin): a glass sheet with two parallel interfaces, no bending.

// Reflectance R' of a thin sheet with two parallel smooth interfaces, summing every internal
// bounce: R' = R + T²R/(1 − R²), T = 1 − R, where R is the exact dielectric Fresnel
// reflectance of one interface (R = 1 under TIR stays 1).
// PBR 4th ed. §9.5 (pbrt-v4 `ThinDielectricBxDF`); Mitsuba 3 `thindielectric`.
fn thin_dielectric_reflectance(abs_cos_i: f32, eta: f32) -> f32 {
    // Both faces see the same outside medium, so the Fresnel term uses |cos θ| and eta as is.
    let r = fresnel_dielectric(abs(abs_cos_i), eta);
    if r >= 1.0 {
        return 1.0;
    }
    let t = 1.0 - r;
    // Geometric series of the inter-reflections: R + T²R Σ R^(2k). PBR 4th ed. §9.5.
    return min(r + t * t * r / (1.0 - r * r), 1.0);
}

// Reflect with probability R' (weight 1), pass straight through (wi = −wo) with 1 − R'
// (weight 1); no η² scaling in either mode. PBR 4th ed. §9.5 (pbrt-v4 `ThinDielectricBxDF`); Mitsuba 3 `thindielectric`.
fn thin_dielectric_sample(eta: f32, wo: vec3<f32>, uc: f32) -> BsdfSample {
    if wo.z == 0.0 || !is_finite_f32(wo.z) {
        return bsdf_sample_none();
    }
    let r = thin_dielectric_reflectance(abs(wo.z), eta);
    // R' = 1 (TIR at the first face) must reflect even for uc = 1.0.
    if uc < r || r >= 1.0 {
        // Specular reflection about the normal. PBR 4th ed. §9.3.1.
        return BsdfSample(true, vec3<f32>(-wo.x, -wo.y, wo.z), vec4<f32>(0.0), vec4<f32>(1.0), r, true, EVENT_REFLECT, LOBE_S, 1.0);
    }
    // Straight pass-through: the two refractions cancel. PBR 4th ed. §9.5.
    return BsdfSample(true, -wo, vec4<f32>(0.0), vec4<f32>(1.0), 1.0 - r, true, EVENT_TRANSMIT, LOBE_S, 1.0);
}

// ---------------------------------------------------------------------------------------------
// Rough dielectric (bsdf::rough_dielectric). Walter, Marschner, Li, Torrance 2007, "Microfacet
// Models for Refraction through Rough Surfaces", EGSR.

// f (scalar) and pdf, computed together (`RoughDielectric::eval_pdf`).
struct EvalPdf {
    f: f32,
    pdf: f32,
}

// f(wo, wi) (scalar, the same for every channel) and pdf(wo, wi), computed together so that
// `eval`, `pdf` and `sample` agree exactly.
fn rough_dielectric_eval_pdf(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>, mode: u32) -> EvalPdf {
    let none = EvalPdf(0.0, 0.0);
    let cos_o = wo.z;
    let cos_i = wi.z;
    let eta = b.eta;
    if cos_o == 0.0 || cos_i == 0.0 || eta == 1.0 {
        return none;
    }
    let is_reflect = cos_o * cos_i > 0.0;
    // eta' = n(wi side) / n(wo side).
    var etap = 1.0;
    if !is_reflect {
        if cos_o > 0.0 {
            etap = eta;
        } else {
            etap = 1.0 / eta;
        }
    }
    // Generalised half vector m ∝ n_o wo + n_i wi, Walter 2007 eq. 16 (eq. 13 for
    // reflection), face-forwarded to the outside (m.z > 0), in the canonical order
    // (outside direction + eta · inside direction).
    var h: vec3<f32>;
    if is_reflect {
        h = wo + wi;
    } else if cos_o > 0.0 {
        h = wo + wi * eta;
    } else {
        h = wi + wo * eta;
    }
    let len2 = dot3(h, h);
    if len2 <= 0.0 || !is_finite_f32(len2) {
        return none;
    }
    var m = h / sqrt(len2);
    if m.z < 0.0 {
        m = -m;
    }
    let dot_o = dot3(wo, m);
    let dot_i = dot3(wi, m);
    // Back-facing microfacets contribute nothing: each direction must be on the same side of
    // m as of the macro normal (Walter 2007 §5, the χ⁺ terms of eqs. 20–21).
    if dot_o * cos_o <= 0.0 || dot_i * cos_i <= 0.0 {
        return none;
    }
    let mf = microfacet_new(b.dist, b.alpha);
    let d = microfacet_d(mf, m);
    if d <= 0.0 {
        return none;
    }
    // Visible normals of the side wo is on (wo mirrored to the upper hemisphere).
    var wo_up = wo;
    if cos_o <= 0.0 {
        wo_up = -wo;
    }
    let pdf_m = microfacet_pdf_visible(mf, wo_up, m);
    let g = microfacet_g2(mf, wo, wi);
    // Fresnel at the microfacet, from a symmetric argument (reciprocity).
    var fr: f32;
    if is_reflect {
        fr = fresnel_dielectric(0.5 * (dot_o + dot_i), eta);
    } else if cos_o > 0.0 {
        fr = fresnel_dielectric(dot_o, eta);
    } else {
        fr = fresnel_dielectric(dot_i, eta);
    }
    if is_reflect {
        // f_r = F G D / (4 |wo·n| |wi·n|), Walter 2007 eq. 20.
        let f = fr * g * d / (4.0 * abs(cos_o) * abs(cos_i));
        // dω_m/dω_i = 1/(4 |wi·m|), Walter 2007 eq. 14 (|wi·m| = |wo·m| for reflection).
        let pdf = pdf_m * fr / (4.0 * abs(dot_o));
        return EvalPdf(f, pdf);
    }
    // (wo·m + eta' wi·m)², from the canonical (outside + eta · inside) sum.
    var denom: f32;
    if cos_o > 0.0 {
        denom = dot_o + eta * dot_i;
    } else {
        denom = (dot_i + eta * dot_o) / eta;
    }
    let denom2 = denom * denom;
    // f_t = |wi·m||wo·m| / (|wi·n||wo·n|) · n_o² (1 − F) G D / (n_i wi·m + n_o wo·m)²,
    // Walter 2007 eq. 21 (wo = Walter's o, wi = i), divided through by n_o².
    let f_rad = abs(dot_i * dot_o) * (1.0 - fr) * g * d / (abs(cos_i * cos_o) * denom2);
    // Radiance mode keeps the 1/eta'² (Walter's n_o²); importance mode removes it
    // (Veach 1997 §5.2, non-symmetric BSDF due to refraction).
    var f = f_rad;
    if mode == MODE_IMPORTANCE {
        f = f_rad * etap * etap;
    }
    // dω_m/dω_i = eta'² |wi·m| / (wo·m + eta' wi·m)², Walter 2007 eq. 17.
    let pdf = pdf_m * (1.0 - fr) * etap * etap * abs(dot_i) / denom2;
    return EvalPdf(f, pdf);
}

fn rough_dielectric_eval(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>, mode: u32) -> vec4<f32> {
    return vec4<f32>(rough_dielectric_eval_pdf(b, wo, wi, mode).f);
}

fn rough_dielectric_pdf(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    return rough_dielectric_eval_pdf(b, wo, wi, MODE_RADIANCE).pdf;
}

// Sample a visible normal m from the side of `wo` (u2), then reflect with probability
// F(wo·m) or refract (uc) (Walter 2007 §5.3; Heitz & d'Eon 2014 for visible normals).
fn rough_dielectric_sample(b: Bsdf, wo: vec3<f32>, uc: f32, u2: vec2<f32>, mode: u32) -> BsdfSample {
    if wo.z == 0.0 || !is_finite_v3(wo) {
        return bsdf_sample_none();
    }
    if b.eta == 1.0 {
        // Index-matched: no interface at all (same as SmoothDielectric).
        return BsdfSample(true, -wo, vec4<f32>(0.0), vec4<f32>(1.0), 1.0, true, EVENT_TRANSMIT, LOBE_S, 1.0);
    }
    var side = 1.0;
    if wo.z < 0.0 {
        side = -1.0;
    }
    let wo_up = wo * side;
    let m = microfacet_sample_visible(microfacet_new(b.dist, b.alpha), wo_up, u2);
    let dot_o = dot3(wo, m);
    if dot_o * side <= 0.0 || m.z <= 0.0 {
        return bsdf_sample_none();
    }
    let fr = fresnel_dielectric_terms(dot_o, b.eta);
    var wi: vec3<f32>;
    var event: u32;
    var eta_rel: f32;
    if uc < fr.f {
        // Microfacet mirror reflection (includes TIR where F = 1).
        wi = reflect(wo, m);
        event = EVENT_REFLECT;
        eta_rel = 1.0;
    } else {
        // Snell refraction through the microfacet (normal on wo's side).
        let rr = refract(wo, m * side, fr.eta_rel);
        if !rr.ok {
            return bsdf_sample_none();
        }
        wi = normalize3(rr.wt);
        event = EVENT_TRANSMIT;
        eta_rel = fr.eta_rel;
    }
    let same_side = wi.z * wo.z > 0.0;
    if same_side != (event == EVENT_REFLECT) || wi.z == 0.0 {
        return bsdf_sample_none();
    }
    let ep = rough_dielectric_eval_pdf(b, wo, wi, mode);
    if !(ep.pdf > 0.0) || !is_finite_f32(ep.f) || !is_finite_f32(ep.pdf) {
        return bsdf_sample_none();
    }
    let f = vec4<f32>(ep.f);
    return BsdfSample(true, wi, f, f * (abs(wi.z) / ep.pdf), ep.pdf, false, event, LOBE_G, eta_rel);
}

// ---------------------------------------------------------------------------------------------
// Rough conductor / glossy mirror (bsdf::glossy): f = R D(m) G2(wo, wi) / (4 cosθo cosθi),
// m = normalize(wo + wi) (Walter et al. 2007 eq. 20 with F ≡ R; Heitz 2014 height-correlated G2).

// Scalar D G2/(4 cos cos) and pdf, shared by eval/pdf/sample so they agree exactly.
fn rough_conductor_eval_pdf(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> EvalPdf {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return EvalPdf(0.0, 0.0);
    }
    let h = wo + wi;
    let len2 = dot3(h, h);
    if len2 <= 0.0 {
        return EvalPdf(0.0, 0.0);
    }
    let m = h / sqrt(len2);
    let dot_o = dot3(wo, m);
    if dot_o <= 0.0 {
        return EvalPdf(0.0, 0.0);
    }
    let mf = microfacet_new(b.dist, b.alpha);
    let d = microfacet_d(mf, m);
    // Walter 2007 eq. 20 (F = 1 here; the reflectance multiplies outside).
    let f = d * microfacet_g2(mf, wo, wi) / (4.0 * wo.z * wi.z);
    // Visible-normal pdf × reflection Jacobian 1/(4 wo·m), Walter 2007 eq. 14.
    let pdf = microfacet_pdf_visible(mf, wo, m) / (4.0 * dot_o);
    return EvalPdf(f, pdf);
}

fn rough_conductor_eval(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> vec4<f32> {
    return b.color * rough_conductor_eval_pdf(b, wo, wi).f;
}

fn rough_conductor_pdf(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    return rough_conductor_eval_pdf(b, wo, wi).pdf;
}

// Visible-normal sampling + mirror reflection about m (Heitz 2018); the weight is
// R G2/G1(wo) analytically, computed here as f·cos/pdf from the same numbers.
fn rough_conductor_sample(b: Bsdf, wo: vec3<f32>, u2: vec2<f32>) -> BsdfSample {
    if wo.z <= 0.0 || !is_finite_v3(wo) {
        return bsdf_sample_none();
    }
    let m = microfacet_sample_visible(microfacet_new(b.dist, b.alpha), wo, u2);
    if dot3(wo, m) <= 0.0 {
        return bsdf_sample_none();
    }
    let wi = reflect(wo, m);
    if wi.z <= 0.0 {
        return bsdf_sample_none();
    }
    let ep = rough_conductor_eval_pdf(b, wo, wi);
    if !(ep.pdf > 0.0) || !is_finite_f32(ep.f) || !is_finite_f32(ep.pdf) {
        return bsdf_sample_none();
    }
    let f = b.color * ep.f;
    return BsdfSample(true, wi, f, f * (wi.z / ep.pdf), ep.pdf, false, EVENT_REFLECT, LOBE_G, 1.0);
}

// ---------------------------------------------------------------------------------------------
// glTF metallic-roughness BRDF (bsdf::metal_rough; glTF 2.0 spec appendix B, coupled matte
// term of Kelemen & Szirmay-Kalos 2001 §3). `MetalRough::method` is `metal_rough_method` here.

// Σ of the colour lanes (w is 0 for RGB inputs, or a real wavelength in spectral mode).
fn lane_sum(c: vec4<f32>) -> f32 {
    return c.x + c.y + c.z + c.w;
}

// glam's Vec4::max_element order: ((x max y) max z) max w.
fn max_element4(c: vec4<f32>) -> f32 {
    return max(max(max(c.x, c.y), c.z), c.w);
}

// Schlick weight (1 − c)⁵, Schlick 1994, "An Inexpensive BRDF Model", eq. 15.
fn schlick_weight(cos: f32) -> f32 {
    let m = clamp(1.0 - abs(cos), 0.0, 1.0);
    let m2 = m * m;
    return m2 * m2 * m;
}

// Dielectric F0 = min(((ior − 1)/(ior + 1))² · specular_color, 1), KHR_materials_specular
// (glTF spec appendix B.3.4 for the ior → F0 rule).
fn metal_rough_dielectric_f0(b: Bsdf) -> vec4<f32> {
    let r = (b.ior - 1.0) / (b.ior + 1.0);
    return min(b.specular_color * (r * r), vec4<f32>(1.0));
}

// Schlick-Fresnel of the dielectric layer Fd = f0 + (1 − f0) w (per lane).
fn metal_rough_fresnel_dielectric_layer(b: Bsdf, w: f32) -> vec4<f32> {
    let f0 = metal_rough_dielectric_f0(b);
    return f0 + (vec4<f32>(1.0) - f0) * w;
}

// 1 − s·F(μ) with the max-channel dielectric Schlick F (module docs).
fn metal_rough_matte_weight(b: Bsdf, mu: f32) -> f32 {
    let f0 = max_element4(metal_rough_dielectric_f0(b));
    let f = f0 + (1.0 - f0) * schlick_weight(mu);
    return max(1.0 - b.specular_factor * f, 0.0);
}

// 1 − s·F̄, F̄ = 2∫₀¹ F(μ) μ dμ = f0 + (1 − f0)/21 (2∫(1−μ)⁵μ dμ = 2·B(2, 6) = 1/21).
fn metal_rough_matte_norm(b: Bsdf) -> f32 {
    let f0 = max_element4(metal_rough_dielectric_f0(b));
    return max(1.0 - b.specular_factor * (f0 + (1.0 - f0) / 21.0), 1e-6);
}

// Schlick-Fresnel of the metal, F0 = base colour (glTF appendix B.3.5 `conductor_fresnel`).
fn metal_rough_fresnel_metal(b: Bsdf, w: f32) -> vec4<f32> {
    return b.color + (vec4<f32>(1.0) - b.color) * w;
}

// f split into the diffuse (D) and specular (G) Heckbert classes.
fn metal_rough_eval_lobes(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> LobeValues {
    let none = LobeValues(vec4<f32>(0.0), vec4<f32>(0.0));
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return none;
    }
    let hh = wo + wi;
    let len2 = dot3(hh, hh);
    if len2 <= 0.0 {
        return none;
    }
    let h = hh / sqrt(len2);
    let mf = microfacet_new(DIST_GGX, b.alpha);
    // Specular microfacet BRDF D G2/(4 cos cos), glTF appendix B.3.2 (height-correlated V).
    let spec = microfacet_d(mf, h) * microfacet_g2(mf, wo, wi) / (4.0 * wo.z * wi.z);
    let w = schlick_weight(dot3(wo, h));
    let fd = metal_rough_fresnel_dielectric_layer(b, w);
    let s = b.specular_factor;
    let m = b.metallic;
    // Coupled matte weight (module docs; Kelemen & Szirmay-Kalos 2001 §3).
    let diffuse_weight = metal_rough_matte_weight(b, wo.z) * metal_rough_matte_weight(b, wi.z) / metal_rough_matte_norm(b);
    let d = b.color * ((1.0 - m) * diffuse_weight * FRAC_1_PI);
    let g = (metal_rough_fresnel_metal(b, w) * m + fd * ((1.0 - m) * s)) * spec;
    return LobeValues(d, g);
}

// Probability of sampling the specular lobe: the specular and diffuse shares estimated
// with Schlick at cosθo (glTF appendix B.3.5 weights), clamped to [0.1, 0.9] when both
// are present.
fn metal_rough_spec_probability(b: Bsdf, wo: vec3<f32>) -> f32 {
    let w = schlick_weight(wo.z);
    let fd = max_element4(metal_rough_fresnel_dielectric_layer(b, w)) * b.specular_factor;
    let m = b.metallic;
    let spec = m * max_element4(metal_rough_fresnel_metal(b, w)) + (1.0 - m) * fd;
    let diff = (1.0 - m) * max(1.0 - fd, 0.0) * max_element4(b.color);
    if diff <= 0.0 {
        return 1.0;
    } else if spec <= 0.0 {
        return 0.0;
    }
    return clamp(spec / (spec + diff), 0.1, 0.9);
}

// Mixture pdf p_s · D_wo(h)/(4 wo·h) + (1 − p_s) · cosθi/π (Walter 2007 eq. 14;
// PBR 4th ed. §A.5.3).
fn metal_rough_pdf_inner(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>, p_spec: f32) -> f32 {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    let hh = wo + wi;
    let len2 = dot3(hh, hh);
    var pdf_spec = 0.0;
    if len2 > 0.0 {
        let h = hh / sqrt(len2);
        let dt = dot3(wo, h);
        if dt > 0.0 {
            pdf_spec = microfacet_pdf_visible(microfacet_new(DIST_GGX, b.alpha), wo, h) / (4.0 * dt);
        }
    }
    return p_spec * pdf_spec + (1.0 - p_spec) * cosine_hemisphere_pdf(wi.z);
}

fn metal_rough_eval(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> vec4<f32> {
    let l = metal_rough_eval_lobes(b, wo, wi);
    return l.d + l.g;
}

fn metal_rough_pdf(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    return metal_rough_pdf_inner(b, wo, wi, metal_rough_spec_probability(b, wo));
}

// See the module docs for the lobe choice and the stochastic class label.
fn metal_rough_sample(b: Bsdf, wo: vec3<f32>, uc: f32, u2: vec2<f32>) -> BsdfSample {
    if wo.z <= 0.0 || !is_finite_v3(wo) {
        return bsdf_sample_none();
    }
    let p_spec = metal_rough_spec_probability(b, wo);
    var wi: vec3<f32>;
    var u_label: f32;
    if uc < p_spec {
        let h = microfacet_sample_visible(microfacet_new(DIST_GGX, b.alpha), wo, u2);
        if dot3(wo, h) <= 0.0 {
            return bsdf_sample_none();
        }
        wi = reflect(wo, h);
        u_label = uc / p_spec;
    } else {
        wi = cosine_hemisphere(u2);
        u_label = (uc - p_spec) / (1.0 - p_spec);
    }
    if wi.z <= 0.0 {
        return bsdf_sample_none();
    }
    let pdf = metal_rough_pdf_inner(b, wo, wi, p_spec);
    if !(pdf > 0.0) || !is_finite_f32(pdf) {
        return bsdf_sample_none();
    }
    let lobes = metal_rough_eval_lobes(b, wo, wi);
    let sd = lane_sum(lobes.d);
    let sg = lane_sum(lobes.g);
    // Class label with probability q_k ∝ Σ f_k; the reported f = f_k/q_k (module docs).
    var pick_g: bool;
    if sd <= 0.0 {
        pick_g = true;
    } else if sg <= 0.0 {
        pick_g = false;
    } else {
        pick_g = u_label * (sd + sg) < sg;
    }
    var f: vec4<f32>;
    var lobe: u32;
    if pick_g {
        var q = 1.0;
        if sg > 0.0 {
            q = sg / (sd + sg);
        }
        f = lobes.g / q;
        lobe = LOBE_G;
    } else {
        f = lobes.d * ((sd + sg) / sd);
        lobe = LOBE_D;
    }
    if !is_finite_v4(f) {
        return bsdf_sample_none();
    }
    return BsdfSample(true, wi, f, f * (wi.z / pdf), pdf, false, EVENT_REFLECT, lobe, 1.0);
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

// Heckbert class of the non-delta part for single-class BSDFs (`Bsdf::class`).
fn bsdf_class(b: Bsdf) -> u32 {
    switch b.kind {
        case BSDF_LAMBERT: {
            return LOBE_D;
        }
        case BSDF_MIRROR, BSDF_SMOOTH_DIELECTRIC, BSDF_THIN_DIELECTRIC: {
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
        default: {}
    }
    // Delta lobes (mirror, smooth and thin dielectric) and compiled-out kinds.
    return vec4<f32>(0.0);
}

fn bsdf_pdf(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    switch b.kind {
        case BSDF_LAMBERT: {
            if HAS_LAMBERT {
                return lambert_pdf(wo, wi);
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
        default: {}
    }
    return bsdf_sample_none();
}
