// thin.wgsl — the thin-walled dielectric (twin of src/bsdf/thin.rs): a glass sheet with two
// parallel interfaces, no bending.

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
        return bsdf_sample_delta(vec3<f32>(-wo.x, -wo.y, wo.z), vec4<f32>(1.0), r, EVENT_REFLECT, 1.0);
    }
    // Straight pass-through: the two refractions cancel. PBR 4th ed. §9.5.
    return bsdf_sample_delta(-wo, vec4<f32>(1.0), 1.0 - r, EVENT_TRANSMIT, 1.0);
}
