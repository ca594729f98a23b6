// glossy.wgsl — the rough conductor / glossy mirror (twin of src/bsdf/glossy.rs):
// f = R D(m) G2(wo, wi) / (4 cosθo cosθi), m = normalize(wo + wi) (Walter et al. 2007 eq. 20
// with F ≡ R; Heitz 2014 height-correlated G2).

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

// The lobe's sample (`RoughConductor::sample_reflection`): a visible normal m (Heitz 2018),
// wo reflected about it, and the scalar D G2/(4 cos cos) and pdf there; `ok` false where wi
// leaves the upper hemisphere or the numbers are not finite. Shared by every reflecting
// microfacet lobe, which multiply their own F.
struct ReflectionSample {
    ok: bool,
    wi: vec3<f32>,
    f: f32,
    pdf: f32,
}

fn rough_conductor_sample_reflection(b: Bsdf, wo: vec3<f32>, u2: vec2<f32>) -> ReflectionSample {
    let none = ReflectionSample(false, vec3<f32>(0.0), 0.0, 0.0);
    if wo.z <= 0.0 || !is_finite_v3(wo) {
        return none;
    }
    let m = microfacet_sample_visible(microfacet_new(b.dist, b.alpha), wo, u2);
    if dot3(wo, m) <= 0.0 {
        return none;
    }
    let wi = reflect(wo, m);
    if wi.z <= 0.0 {
        return none;
    }
    let ep = rough_conductor_eval_pdf(b, wo, wi);
    if !(ep.pdf > 0.0) || !is_finite_f32(ep.f) || !is_finite_f32(ep.pdf) {
        return none;
    }
    return ReflectionSample(true, wi, ep.f, ep.pdf);
}

// The weight R G2/G1(wo) analytically, computed here as f·cos/pdf from the same numbers.
fn rough_conductor_sample(b: Bsdf, wo: vec3<f32>, u2: vec2<f32>) -> BsdfSample {
    let s = rough_conductor_sample_reflection(b, wo, u2);
    if !s.ok {
        return bsdf_sample_none();
    }
    let f = b.color * s.f;
    return bsdf_sample_new(s.wi, f, f * (s.wi.z / s.pdf), s.pdf, EVENT_REFLECT, LOBE_G, 1.0);
}

// Rough conductor with a complex IOR (twin of `RoughFresnelConductor`,
// src/bsdf/complex_conductor.rs): f = T F(wo·m) D G2 / (4 cosθo cosθi), the lobe above.
// F at the half vector of (wo, wi) (`RoughFresnelConductor::fresnel_half`).
fn rough_fresnel_conductor_f_half(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> vec4<f32> {
    let h = wo + wi;
    let len2 = dot3(h, h);
    if len2 <= 0.0 {
        return vec4<f32>(0.0);
    }
    return fresnel_conductor4(dot3(wo, h) / sqrt(len2), bsdf_conductor_eta(b), bsdf_conductor_k(b));
}

fn rough_fresnel_conductor_eval(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> vec4<f32> {
    let f = rough_conductor_eval_pdf(b, wo, wi).f;
    if f == 0.0 {
        return vec4<f32>(0.0);
    }
    return b.color * rough_fresnel_conductor_f_half(b, wo, wi) * f;
}

// Visible-normal sampling as `rough_conductor_sample`, weight T F(wo·m) G2/G1(wo) = f·cos/pdf.
fn rough_fresnel_conductor_sample(b: Bsdf, wo: vec3<f32>, u2: vec2<f32>) -> BsdfSample {
    let s = rough_conductor_sample_reflection(b, wo, u2);
    if !s.ok {
        return bsdf_sample_none();
    }
    let f = b.color * rough_fresnel_conductor_f_half(b, wo, s.wi) * s.f;
    return bsdf_sample_new(s.wi, f, f * (s.wi.z / s.pdf), s.pdf, EVENT_REFLECT, LOBE_G, 1.0);
}
