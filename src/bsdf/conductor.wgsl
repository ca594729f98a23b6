// conductor.wgsl — the smooth mirror (twin of src/bsdf/conductor.rs):
// f = R δ(wi − reflect(wo)) / |cos θi|; PBR 4th ed. §9.4 (specular reflection).

fn mirror_sample(reflectance: vec4<f32>, wo: vec3<f32>) -> BsdfSample {
    if wo.z <= 0.0 {
        return bsdf_sample_none();
    }
    return bsdf_sample_delta(vec3<f32>(-wo.x, -wo.y, wo.z), reflectance, 1.0, EVENT_REFLECT, 1.0);
}

// Smooth conductor with a complex IOR (twin of src/bsdf/complex_conductor.rs):
// f = T F(θo) δ(wi − reflect(wo)) / |cos θi| (PBR 4th ed. §9.4 with the conductor Fresnel
// term of §9.3.6), T = b.color (base colour).
fn smooth_conductor_sample(b: Bsdf, wo: vec3<f32>) -> BsdfSample {
    if wo.z <= 0.0 {
        return bsdf_sample_none();
    }
    let f = fresnel_conductor4(wo.z, bsdf_conductor_eta(b), bsdf_conductor_k(b));
    return bsdf_sample_delta(vec3<f32>(-wo.x, -wo.y, wo.z), b.color * f, 1.0, EVENT_REFLECT, 1.0);
}
