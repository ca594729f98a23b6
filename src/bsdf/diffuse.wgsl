// diffuse.wgsl — the Lambertian BRDF (twin of src/bsdf/diffuse.rs). Lambert 1760; PBR 4th ed. §9.2.

fn lambert_eval(albedo: vec4<f32>, wo: vec3<f32>, wi: vec3<f32>) -> vec4<f32> {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return vec4<f32>(0.0);
    }
    return albedo * FRAC_1_PI;
}

// `uniform`: the importance-sampling teaching switch (Lambert::uniform, MAT_UNIFORM_SAMPLING).
fn lambert_sample_pdf(cos_theta: f32, uniform: bool) -> f32 {
    if uniform {
        return UNIFORM_HEMISPHERE_PDF;
    }
    return cosine_hemisphere_pdf(cos_theta);
}

fn lambert_pdf(wo: vec3<f32>, wi: vec3<f32>, uniform: bool) -> f32 {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    return lambert_sample_pdf(wi.z, uniform);
}

// Cosine-weighted sampling: weight = ρ. PBR 4th ed. §9.2. Uniform (teaching): weight =
// f cosθ / (1/2π) = 2ρ cosθ.
fn lambert_sample(albedo: vec4<f32>, wo: vec3<f32>, u2: vec2<f32>, uniform: bool) -> BsdfSample {
    if wo.z <= 0.0 {
        return bsdf_sample_none();
    }
    var wi = cosine_hemisphere(u2);
    if uniform {
        wi = uniform_hemisphere(u2);
    }
    let pdf = lambert_sample_pdf(wi.z, uniform);
    if pdf <= 0.0 {
        return bsdf_sample_none();
    }
    let f = albedo * FRAC_1_PI;
    var weight = albedo;
    if uniform {
        weight = f * (wi.z / pdf);
    }
    return bsdf_sample_new(wi, f, weight, pdf, EVENT_REFLECT, LOBE_D, 1.0);
}
