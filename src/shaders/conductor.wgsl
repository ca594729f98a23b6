// conductor.wgsl — the smooth mirror (twin of src/bsdf/conductor.rs):
// f = R δ(wi − reflect(wo)) / |cos θi|; PBR 4th ed. §9.4 (specular reflection).

fn mirror_sample(reflectance: vec4<f32>, wo: vec3<f32>) -> BsdfSample {
    if wo.z <= 0.0 {
        return bsdf_sample_none();
    }
    return bsdf_sample_delta(vec3<f32>(-wo.x, -wo.y, wo.z), reflectance, 1.0, EVENT_REFLECT, 1.0);
}
