// metal_rough.wgsl — the glTF metallic-roughness BRDF (twin of src/bsdf/metal_rough.rs; glTF
// 2.0 spec appendix B, coupled matte term of Kelemen & Szirmay-Kalos 2001 §3).
// `MetalRough::method` is `metal_rough_method` here.

// Σ of the colour lanes (w is 0 for RGB inputs, or a real wavelength in spectral mode).
fn lane_sum(c: vec4<f32>) -> f32 {
    return c.x + c.y + c.z + c.w;
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
    return bsdf_sample_new(wi, f, f * (wi.z / pdf), pdf, EVENT_REFLECT, lobe, 1.0);
}
