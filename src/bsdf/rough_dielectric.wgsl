// rough_dielectric.wgsl — the rough dielectric (twin of src/bsdf/rough_dielectric.rs).
// Walter, Marschner, Li, Torrance 2007, "Microfacet Models for Refraction through Rough
// Surfaces", EGSR.

// The reflection probability at the facet cosine `cos` (`FacetFresnel::select`): the exact
// dielectric Fresnel term, or a film's mean reflectance (iridescent.wgsl); and into `lanes` a
// film's lane factors there for an (wo, wi) pair reflecting or not (F/P or (1 − F)/(1 − P),
// `film_lane_factors`; left as they are for plain glass): the film's reflectance is
// integrated once for both.
fn rough_dielectric_facet(b: Bsdf, cos: f32, is_reflect: bool, lanes: ptr<function, vec4<f32>>) -> f32 {
    if HAS_IRIDESCENCE && b.kind == BSDF_FILM_ROUGH {
        let r = film_reflectance_signed(b, cos, b.eta);
        *lanes = film_lane_factors(r, is_reflect);
        return film_mean(r);
    }
    return fresnel_dielectric(cos, b.eta);
}

// f(wo, wi) computed with the reflection probability P (scalar) and pdf(wo, wi), computed
// together so that `eval`, `pdf` and `sample` agree exactly; `lanes` receives a film's lane
// factors at the facet (`rough_dielectric_facet`).
fn rough_dielectric_eval_pdf(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>, mode: u32, lanes: ptr<function, vec4<f32>>) -> EvalPdf {
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
    var cos_f: f32;
    if is_reflect {
        cos_f = 0.5 * (dot_o + dot_i);
    } else if cos_o > 0.0 {
        cos_f = dot_o;
    } else {
        cos_f = dot_i;
    }
    let fr = rough_dielectric_facet(b, cos_f, is_reflect, lanes);
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

// f per lane: the scalar f, times a film's lane factors.
fn rough_dielectric_lanes(b: Bsdf, f: f32, lanes: vec4<f32>) -> vec4<f32> {
    if HAS_IRIDESCENCE && b.kind == BSDF_FILM_ROUGH {
        return vec4<f32>(f) * lanes;
    }
    return vec4<f32>(f);
}

fn rough_dielectric_eval(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>, mode: u32) -> vec4<f32> {
    var lanes = vec4<f32>(1.0);
    let f = rough_dielectric_eval_pdf(b, wo, wi, mode, &lanes).f;
    return rough_dielectric_lanes(b, f, lanes);
}

fn rough_dielectric_pdf(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    var lanes = vec4<f32>(1.0);
    return rough_dielectric_eval_pdf(b, wo, wi, MODE_RADIANCE, &lanes).pdf;
}

// Sample a visible normal m from the side of `wo` (u2), then reflect with probability
// F(wo·m) (a film: P(wo·m)) or refract (uc) (Walter 2007 §5.3; Heitz & d'Eon 2014 for visible normals).
fn rough_dielectric_sample(b: Bsdf, wo: vec3<f32>, uc: f32, u2: vec2<f32>, mode: u32) -> BsdfSample {
    if wo.z == 0.0 || !is_finite_v3(wo) {
        return bsdf_sample_none();
    }
    if b.eta == 1.0 {
        return bsdf_sample_index_matched(wo);
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
    // TIR (Snell's test, fr.f = 1) reflects whatever a film says.
    var p = fr.f;
    if HAS_IRIDESCENCE && b.kind == BSDF_FILM_ROUGH && fr.f < 1.0 {
        var unused = vec4<f32>(1.0);
        p = rough_dielectric_facet(b, dot_o, true, &unused);
    }
    var wi: vec3<f32>;
    var event: u32;
    var eta_rel: f32;
    if uc < p {
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
    var lanes = vec4<f32>(1.0);
    let ep = rough_dielectric_eval_pdf(b, wo, wi, mode, &lanes);
    let f = rough_dielectric_lanes(b, ep.f, lanes);
    if !(ep.pdf > 0.0) || !is_finite_v4(f) || !is_finite_f32(ep.pdf) {
        return bsdf_sample_none();
    }
    return bsdf_sample_new(wi, f, f * (abs(wi.z) / ep.pdf), ep.pdf, event, LOBE_G, eta_rel);
}
