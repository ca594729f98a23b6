// fresnel.wgsl — Fresnel equations, reflection and refraction (twin of src/bsdf/fresnel.rs).

struct FresnelTerms {
    r_par: f32,
    r_perp: f32,
    f: f32,
    cos_t: f32,
    eta_rel: f32,
}

// cos²θt of the refracted direction for |cos θi| = `cos_i` and relative IOR `eta_rel`:
// cos²θt = 1 − sin²θi/η'² = (cos²θi + (η' − 1)(η' + 1)) / η'² (Snell, PBR 4th ed. §9.3.2),
fn cos2_transmitted(cos_i: f32, eta_rel: f32) -> f32 {
    return (cos_i * cos_i + (eta_rel - 1.0) * (eta_rel + 1.0)) / (eta_rel * eta_rel);
}

// Exact unpolarised dielectric Fresnel with r∥ and r⊥.
// Hecht, "Optics" 5th ed. §4.6.2 (Fresnel equations); PBR 4th ed. §9.3.5 (`FrDielectric`).
fn fresnel_dielectric_terms(cos_i_in: f32, eta: f32) -> FresnelTerms {
    var cos_i = clamp(cos_i_in, -1.0, 1.0);
    var eta_rel = eta;
    if cos_i < 0.0 {
        eta_rel = 1.0 / eta;
        cos_i = -cos_i;
    }
    let cos2_t = cos2_transmitted(cos_i, eta_rel);
    if cos2_t <= 0.0 {
        return FresnelTerms(1.0, 1.0, 1.0, 0.0, eta_rel);
    }
    let cos_t = sqrt(cos2_t);
    let r_par = (eta_rel * cos_i - cos_t) / (eta_rel * cos_i + cos_t);
    let r_perp = (cos_i - eta_rel * cos_t) / (cos_i + eta_rel * cos_t);
    return FresnelTerms(r_par, r_perp, 0.5 * (r_par * r_par + r_perp * r_perp), cos_t, eta_rel);
}

// Unpolarised dielectric reflectance F(cos_i, eta). See [`fresnel_dielectric_terms`].
fn fresnel_dielectric(cos_i: f32, eta: f32) -> f32 {
    return fresnel_dielectric_terms(cos_i, eta).f;
}

// Exact unpolarised conductor Fresnel reflectance per lane for complex relative IOR η − ik.
// Real-arithmetic form of PBR 4th ed. §9.3.6 (`FrComplex`), as PBR 3rd ed. §8.2.1
// (`FrConductor`); Born & Wolf §14.2. Twin of `fresnel_conductor` in src/bsdf/fresnel.rs
// (same degenerate-denominator guards).
fn fresnel_conductor4(cos_i: f32, eta: vec4<f32>, k: vec4<f32>) -> vec4<f32> {
    let cos = min(abs(cos_i), 1.0);
    let cos2 = cos * cos;
    let sin2 = 1.0 - cos2;
    let t1 = eta * eta - k * k - sin2;
    let a2b2 = sqrt(t1 * t1 + 4.0 * eta * eta * k * k);
    let a = sqrt(max(0.5 * (a2b2 + t1), vec4<f32>(0.0)));
    let t2 = 2.0 * a * cos;
    let d1 = a2b2 + cos2 + t2;
    let rs = select(vec4<f32>(1.0), (a2b2 + cos2 - t2) / d1, d1 > vec4<f32>(0.0));
    let t3 = a2b2 * cos2 + sin2 * sin2;
    let t4 = t2 * sin2;
    let d2 = t3 + t4;
    let rp = select(rs, rs * (t3 - t4) / d2, d2 > vec4<f32>(0.0));
    return clamp(0.5 * (rs + rp), vec4<f32>(0.0), vec4<f32>(1.0));
}

// Mirror reflection of `wo` about the normal `n`. PBR 4th ed. §9.3.1.
fn reflect(wo: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    return -wo + 2.0 * dot3(wo, n) * n;
}

// Refraction result (`None` = total internal reflection → ok = false).
struct Refracted {
    ok: bool,
    wt: vec3<f32>,
}

// Snell refraction of `wi` through a surface with normal `n` (same side as `wi`).
// PBR 4th ed. §9.3.2 (`Refract`), Snell: n_i sinθi = n_t sinθt.
fn refract(wi: vec3<f32>, n: vec3<f32>, eta_rel: f32) -> Refracted {
    let cos_i = dot3(n, wi);
    let cos2_t = cos2_transmitted(min(cos_i, 1.0), eta_rel);
    if cos2_t <= 0.0 {
        return Refracted(false, vec3<f32>(0.0));
    }
    let cos_t = sqrt(cos2_t);
    return Refracted(true, -wi / eta_rel + (cos_i / eta_rel - cos_t) * n);
}
