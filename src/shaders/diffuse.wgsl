// diffuse.wgsl — the Lambertian BRDF (twin of src/bsdf/diffuse.rs). Lambert 1760; PBR 4th ed. §9.2.

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
    return bsdf_sample_new(wi, albedo * FRAC_1_PI, albedo, pdf, EVENT_REFLECT, LOBE_D, 1.0);
}
