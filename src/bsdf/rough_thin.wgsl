// rough_thin.wgsl — the rough thin-walled dielectric (twin of src/bsdf/rough_thin.rs): a sheet
// with two rough faces, glTF's transmission BTDF (KHR_materials_transmission, "Transmission
// BTDF": the reflection lobe mirrored through the surface plane), each lobe weighted by its
// share of the sheet's Fresnel sum R' = R + T²R/(1 − R²), T' = 1 − R' (PBR 4th ed. §9.5) at
// the facet: f = share · D(m) G2(wo, wi') / (4 |cos θo| |cos θi|) (Walter et al. 2007 eq. 20;
// Heitz 2014 height-correlated G2), wi' = wi or its mirror image, m = normalize(wo + wi').

// `w` mirrored through the surface plane (z → −z).
fn rough_thin_through_plane(w: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(w.x, w.y, -w.z);
}

// Scalar f and pdf of (wo, wi) (`RoughThinDielectric::eval_pdf`): both directions turned to
// put wo above the sheet.
fn rough_thin_eval_pdf(b: Bsdf, wo_in: vec3<f32>, wi_in: vec3<f32>) -> EvalPdf {
    if wo_in.z == 0.0 || wi_in.z == 0.0 || !is_finite_v3(wo_in) || !is_finite_v3(wi_in) {
        return EvalPdf(0.0, 0.0);
    }
    var wo = wo_in;
    var wi = wi_in;
    if wo.z < 0.0 {
        wo = -wo;
        wi = -wi;
    }
    let transmit = wi.z < 0.0;
    // The reflection lobe's direction: wi itself, or for transmission its mirror image.
    let wr = select(wi, rough_thin_through_plane(wi), transmit);
    let m = normalize_or_zero3(wo + wr);
    let dot_o = dot3(wo, m);
    if dot_o <= 0.0 {
        return EvalPdf(0.0, 0.0);
    }
    // The mean of wo·m and wr·m (equal): bit for bit the same when wo and wi trade places.
    let r = thin_dielectric_reflectance(0.5 * (dot_o + dot3(wr, m)), b.eta);
    let share = select(r, 1.0 - r, transmit);
    let mf = microfacet_new(b.dist, b.alpha);
    // Walter 2007 eq. 20 with F = the lobe's share of the sheet's Fresnel sum.
    let f = share * microfacet_d(mf, m) * microfacet_g2(mf, wo, wr) / (4.0 * wo.z * wr.z);
    // The lobe's probability × visible-normal pdf × reflection Jacobian 1/(4 wo·m).
    let pdf = share * microfacet_pdf_visible(mf, wo, m) / (4.0 * dot_o);
    return EvalPdf(f, pdf);
}

fn rough_thin_eval(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> vec4<f32> {
    return vec4<f32>(rough_thin_eval_pdf(b, wo, wi).f);
}

fn rough_thin_pdf(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    return rough_thin_eval_pdf(b, wo, wi).pdf;
}

// A visible normal m (Heitz 2018), reflect about it with probability R'(wo·m), else the
// reflection mirrored through the plane; weight f·|cos θi|/pdf from `eval`'s numbers.
fn rough_thin_sample(b: Bsdf, wo: vec3<f32>, uc: f32, u2: vec2<f32>) -> BsdfSample {
    if wo.z == 0.0 || !is_finite_v3(wo) {
        return bsdf_sample_none();
    }
    let side = sign(wo.z);
    let wo_up = wo * side;
    let m = microfacet_sample_visible(microfacet_new(b.dist, b.alpha), wo_up, u2);
    let dot_o = dot3(wo_up, m);
    if dot_o <= 0.0 {
        return bsdf_sample_none();
    }
    let wr = reflect(wo_up, m);
    if wr.z <= 0.0 {
        return bsdf_sample_none();
    }
    let r = thin_dielectric_reflectance(dot_o, b.eta);
    var wi_up = wr;
    var event = EVENT_REFLECT;
    if !(uc < r || r >= 1.0) {
        wi_up = rough_thin_through_plane(wr);
        event = EVENT_TRANSMIT;
    }
    let ep = rough_thin_eval_pdf(b, wo_up, wi_up);
    if !(ep.pdf > 0.0) || !is_finite_f32(ep.f) || !is_finite_f32(ep.pdf) {
        return bsdf_sample_none();
    }
    let wi = wi_up * side;
    let f = vec4<f32>(ep.f);
    return bsdf_sample_new(wi, f, f * (abs(wi.z) / ep.pdf), ep.pdf, event, LOBE_G, 1.0);
}

// Polarisation (`RoughThinDielectric::mueller`): the smooth sheet's matrices at the facet's
// incidence cosine |wo·m|; (a, b, c, s) per lane, the depolariser's zeros where m is
// degenerate.
fn rough_thin_mueller_lane(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>, event: u32) -> vec4<f32> {
    let wr = select(wi, rough_thin_through_plane(wi), wo.z * wi.z < 0.0);
    let m = polarized_half(wo, wr, EVENT_REFLECT, 1.0);
    if m.w == 0.0 {
        return vec4<f32>(0.0);
    }
    return sheet_lane(abs(dot3(wo, m.xyz)), b.eta, event);
}

fn rough_thin_mueller(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>, event: u32) -> Mueller {
    return mueller_splat(rough_thin_mueller_lane(b, wo, wi, event));
}

// m₀₁ of the event (wo, wi) for next-event estimation (`bsdf_mueller_b`).
fn rough_thin_mueller_b(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> vec4<f32> {
    let event = select(EVENT_TRANSMIT, EVENT_REFLECT, wo.z * wi.z >= 0.0);
    return vec4<f32>(rough_thin_mueller_lane(b, wo, wi, event).y);
}
