// dielectric.wgsl — the smooth dielectric (twin of src/bsdf/dielectric.rs): reflect with
// probability F, refract with 1 − F (PBR 4th ed. §9.5.1, `DielectricBxDF`).

fn smooth_dielectric_sample(eta: f32, wo: vec3<f32>, uc: f32, mode: u32) -> BsdfSample {
    if wo.z == 0.0 {
        return bsdf_sample_none();
    }
    if eta == 1.0 {
        return bsdf_sample_index_matched(wo);
    }
    let fr = fresnel_dielectric_terms(wo.z, eta);
    // TIR (F = 1) must reflect even for uc = 1.0 (the same sin²θt ≥ 1 test decides both).
    if uc < fr.f || fr.f >= 1.0 {
        // Specular reflection (includes TIR, where F = 1).
        return bsdf_sample_delta(vec3<f32>(-wo.x, -wo.y, wo.z), vec4<f32>(1.0), fr.f, EVENT_REFLECT, 1.0);
    }
    let t = smooth_refraction(wo, fr, mode);
    return bsdf_sample_delta(t.xyz, vec4<f32>(t.w), 1.0 - fr.f, EVENT_TRANSMIT, fr.eta_rel);
}

// The refracted direction of `wo` (xyz) and the crossing's radiance scale (w), for the
// Fresnel terms `fr` of wo's cosine (no TIR): wt = −wo/η' + (cosθi/η' − cosθt) n, PBR 4th ed.
// eq. (9.19); radiance compresses by 1/η'² (Veach 1997, §5.2). Twin of `dielectric::refraction`.
fn smooth_refraction(wo: vec3<f32>, fr: FresnelTerms, mode: u32) -> vec4<f32> {
    let eta_rel = fr.eta_rel;
    var sign = 1.0;
    if wo.z < 0.0 {
        sign = -1.0;
    }
    let wi = normalize3(vec3<f32>(-wo.x / eta_rel, -wo.y / eta_rel, -sign * fr.cos_t));
    var scale = 1.0;
    if mode == MODE_RADIANCE {
        scale = 1.0 / (eta_rel * eta_rel);
    }
    return vec4<f32>(wi, scale);
}
