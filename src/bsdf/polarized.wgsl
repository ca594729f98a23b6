// polarized.wgsl — the polarising part of every BSDF (issue 38), twin of src/bsdf/polarized.rs
// with the Fresnel amplitudes of src/bsdf/fresnel_polarized.rs: for a scattering event
// (wo, wi) its Mueller matrix in the s/p basis, normalised to m₀₀ = 1 (the scalar BSDF
// carries the intensity). Hecht, "Optics" 5th ed. §4.6.2 (amplitudes); Azzam & Bashara,
// "Ellipsometry and Polarized Light" §2.11 (a diagonal Jones matrix as a Mueller matrix);
// Wilkie & Weidlich 2012, "Polarised Light in Computer Graphics" §5 (microfacet events at
// the half vector). Complex numbers are vec2 (re, im) with thin_film.wgsl's cx_* helpers.
//
// Every event matrix of this renderer has the form
//     [ 1  b  0  0 ]
//     [ b  a  0  0 ]
//     [ 0  0  c  s ]
//     [ 0  0 -s  c ]
// per colour lane: a = 1 for a Fresnel event (a diagonal Jones matrix diag(r_s, r_p):
// b = (|r_s|² − |r_p|²) / (|r_s|² + |r_p|²), c + i s = 2 r_s r_p* / (|r_s|² + |r_p|²)),
// a = b = c = s = 0 for the depolariser (diffuse). The camera walk (chain.wgsl) keeps only
// a row of the chain, so the four numbers are all it needs.

// An event's normalised Mueller matrix, one vec4 per entry across the colour lanes.
struct Mueller {
    a: vec4<f32>,
    b: vec4<f32>,
    c: vec4<f32>,
    s: vec4<f32>,
}

// The ideal depolariser diag(1, 0, 0, 0) (Lambert; `mueller::depolarizer`).
fn mueller_depolarizer() -> Mueller {
    return Mueller(vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0));
}

// No interface (η = 1): the identity.
fn mueller_identity() -> Mueller {
    return Mueller(vec4<f32>(1.0), vec4<f32>(0.0), vec4<f32>(1.0), vec4<f32>(0.0));
}

// The ideal conductor r_s = −1, r_p = 1 (`ideal_conductor_mueller`).
fn mueller_ideal_conductor() -> Mueller {
    return Mueller(vec4<f32>(1.0), vec4<f32>(0.0), vec4<f32>(-1.0), vec4<f32>(0.0));
}

// The same lane values (a, b, c, s) in every lane.
fn mueller_splat(v: vec4<f32>) -> Mueller {
    return Mueller(vec4<f32>(v.x), vec4<f32>(v.y), vec4<f32>(v.z), vec4<f32>(v.w));
}

// (a, b, c, s) of the Jones matrix diag(ja, jb), normalised by m₀₀ = (|ja|² + |jb|²)/2; the
// depolariser's zeros when m₀₀ is 0 or not finite (`mueller::normalized`).
fn jones_diagonal(ja: vec2<f32>, jb: vec2<f32>) -> vec4<f32> {
    let aa = cx_norm2(ja);
    let bb = cx_norm2(jb);
    let p = 0.5 * (aa + bb);
    let c = cx_mul(ja, vec2<f32>(jb.x, -jb.y));
    let inv = 1.0 / p;
    if !(p > 0.0) || !is_finite_f32(inv) {
        return vec4<f32>(0.0);
    }
    let v = vec4<f32>(1.0, 0.5 * (aa - bb) * inv, c.x * inv, c.y * inv);
    if !is_finite_v4(v) {
        return vec4<f32>(0.0);
    }
    return v;
}

// The Fresnel amplitudes r_s, r_p (xy, zw) at incidence cosine `cos_i` (negative: from
// inside, η' = 1/η) for η = n_inside/n_outside, complex (η − ik) for a conductor, with cos θt
// the root with Im ≤ 0 (the evanescent one beyond the critical angle); `fresnel_amplitudes`
// (whose cos θt, η' and |cos θi| only its refraction reads: dielectric_lane's here).
fn fresnel_amplitudes(cos_i_in: f32, eta: vec2<f32>) -> vec4<f32> {
    let c0 = clamp(cos_i_in, -1.0, 1.0);
    var eta_rel = eta;
    if c0 < 0.0 {
        eta_rel = cx_div(vec2<f32>(1.0, 0.0), eta);
    }
    let c = abs(c0);
    let sin2_t = cx_div(vec2<f32>(1.0 - c * c, 0.0), cx_mul(eta_rel, eta_rel));
    var cos_t = cx_sqrt(vec2<f32>(1.0, 0.0) - sin2_t);
    if cos_t.y > 0.0 {
        cos_t.y = -cos_t.y;
    }
    // The numerators multiplied out, as in the Rust (no cancellation as η' → 1).
    let d_s = vec2<f32>(c, 0.0) + cx_mul(eta_rel, cos_t);
    let d_p = eta_rel * c + cos_t;
    let eta2 = cx_mul(eta_rel, eta_rel);
    let one_minus_eta2 = cx_mul(vec2<f32>(1.0, 0.0) - eta_rel, vec2<f32>(1.0, 0.0) + eta_rel);
    let r_s = cx_div(one_minus_eta2, cx_mul(d_s, d_s));
    let brewster = c * c * (eta2 + vec2<f32>(1.0, 0.0)) - vec2<f32>(1.0, 0.0);
    let r_p = cx_div(-cx_mul(one_minus_eta2, brewster), cx_mul(eta2, cx_mul(d_p, d_p)));
    return vec4<f32>(r_s, r_p);
}

// Specular reflection's (a, b, c, s) at `cos_i` for a complex η (`reflection_mueller`,
// normalised): conductors.
fn reflection_lane(cos_i: f32, eta: vec2<f32>) -> vec4<f32> {
    let r = fresnel_amplitudes(cos_i, eta);
    return jones_diagonal(r.xy, r.zw);
}

// (a, b, c, s) of the real Jones diagonal diag(ja, jb), normalised (`jones_diagonal`).
fn jones_real(ja: f32, jb: f32) -> vec4<f32> {
    let p = 0.5 * (ja * ja + jb * jb);
    let inv = 1.0 / p;
    if !(p > 0.0) || !is_finite_f32(inv) {
        return vec4<f32>(0.0);
    }
    return vec4<f32>(1.0, 0.5 * (ja * ja - jb * jb) * inv, ja * jb * inv, 0.0);
}

// A dielectric event (reflection or refraction; η real) at the light's incidence cosine
// `cos_i` (negative: from inside), in real arithmetic: the matrices of `fresnel_amplitudes`
// with a real η, whose amplitudes are real except under total internal reflection. There
// cos θt = −iκ, κ = √(sin²θi/η'² − 1), and r_s = z_s / z_s*, r_p = z_p / z_p* with
// z_s = cos θi + iη'κ, z_p = η' cos θi + iκ, so r_s r_p* = w² / |w|² for
// w = z_s z_p* = η'(cos²θi + κ²) + i cos θi κ (η'² − 1): |r_s| = |r_p| = 1 and a retarder of
// phase arg w² (Born & Wolf §1.5.4). Refraction is zero there (the depolariser's zeros, as
// `transmission_mueller`'s zero matrix normalised), and at grazing incidence.
fn dielectric_lane(cos_i_in: f32, eta: f32, event: u32) -> vec4<f32> {
    var c = clamp(cos_i_in, -1.0, 1.0);
    var e = eta;
    if c < 0.0 {
        e = 1.0 / eta;
        c = -c;
    }
    let cos2_t = 1.0 - (1.0 - c * c) / (e * e);
    if cos2_t < 0.0 {
        if event != EVENT_REFLECT {
            return vec4<f32>(0.0);
        }
        let k = sqrt(-cos2_t);
        let w = vec2<f32>(e * (c * c + k * k), c * k * (e * e - 1.0));
        let n = w.x * w.x + w.y * w.y;
        if !(n > 0.0) {
            return vec4<f32>(0.0);
        }
        return vec4<f32>(1.0, 0.0, (w.x * w.x - w.y * w.y) / n, 2.0 * w.x * w.y / n);
    }
    // `fresnel_amplitudes`' cancellation-free forms.
    let ct = sqrt(cos2_t);
    let one_minus_e2 = (1.0 - e) * (1.0 + e);
    let ds = c + e * ct;
    let dp = e * c + ct;
    let rs = one_minus_e2 / (ds * ds);
    let rp = -one_minus_e2 * (c * c * (e * e + 1.0) - 1.0) / (e * e * dp * dp);
    if event == EVENT_REFLECT {
        return jones_real(rs, rp);
    }
    if c == 0.0 {
        return vec4<f32>(0.0);
    }
    return jones_real(1.0 + rs, (1.0 + rp) / e);
}

// Through both faces of a thin sheet: Jones diag(t_s², t_p²) (`normalized(t · t)`). With
// the single pass normalised to (1, β, γ, 0), t_s² : t_p² = (1 + β) : (1 − β).
fn sheet_transmission_lane(cos_i: f32, eta: f32) -> vec4<f32> {
    let t = dielectric_lane(cos_i, eta, EVENT_TRANSMIT);
    if t.x == 0.0 {
        return t;
    }
    return jones_real(0.5 * (1.0 + t.y), 0.5 * (1.0 - t.y));
}

// A conductor's reflection per lane (η − ik per lane; RGB: lane w unused).
fn conductor_mueller(cos_i: f32, eta: vec4<f32>, k: vec4<f32>) -> Mueller {
    let r = reflection_lane(cos_i, vec2<f32>(eta.x, -k.x));
    let g = reflection_lane(cos_i, vec2<f32>(eta.y, -k.y));
    let b = reflection_lane(cos_i, vec2<f32>(eta.z, -k.z));
    let w = reflection_lane(cos_i, vec2<f32>(eta.w, -k.w));
    return Mueller(vec4<f32>(r.x, g.x, b.x, w.x), vec4<f32>(r.y, g.y, b.y, w.y), vec4<f32>(r.z, g.z, b.z, w.z), vec4<f32>(r.w, g.w, b.w, w.w));
}

// The microfacet normal of (wo, wi) face-forwarded to z > 0 (Walter et al. 2007, eqs. 13
// and 16; `half_vector`); w = 0 when degenerate.
fn polarized_half(wo: vec3<f32>, wi: vec3<f32>, event: u32, eta: f32) -> vec4<f32> {
    var h = wo + wi;
    if event == EVENT_TRANSMIT {
        if wo.z > 0.0 {
            h = wo + wi * eta;
        } else {
            h = wi + wo * eta;
        }
    }
    let len2 = dot3(h, h);
    let rcp = 1.0 / sqrt(len2);
    if !(len2 > 0.0) || !is_finite_f32(rcp) {
        return vec4<f32>(0.0);
    }
    var m = h * rcp;
    if m.z < 0.0 {
        m = -m;
    }
    return vec4<f32>(m, 1.0);
}

// A rough dielectric's event at the half vector (the depolariser when it is degenerate).
fn rough_dielectric_lane(wo: vec3<f32>, wi: vec3<f32>, event: u32, eta: f32) -> vec4<f32> {
    let m = polarized_half(wo, wi, event, eta);
    if m.w == 0.0 {
        return vec4<f32>(0.0);
    }
    return dielectric_lane(dot3(wi, m.xyz), eta, event);
}

// The kinds' matrices, each the arm of its kind in `bsdf_mueller` (generated from the BSDF
// table, `bsdf::family_wgsl`; a kind without one gets the depolariser there, and polarised
// films are refused on the GPU, `check_polarization`). Twins of each variant's
// `BxDF::mueller`.

// A smooth dielectric: Fresnel reflection or refraction at the normal; none at η = 1.
fn smooth_dielectric_mueller(b: Bsdf, wi: vec3<f32>, event: u32) -> Mueller {
    if b.eta == 1.0 {
        return mueller_identity();
    }
    return mueller_splat(dielectric_lane(wi.z, b.eta, event));
}

// A rough dielectric: at the half vector; none at η = 1.
fn rough_dielectric_mueller(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>, event: u32) -> Mueller {
    if b.eta == 1.0 {
        return mueller_identity();
    }
    return mueller_splat(rough_dielectric_lane(wo, wi, event, b.eta));
}

// A sheet at the incidence cosine `c`: one interface's reflection, transmission through both
// (`thin::sheet_mueller`; also the rough sheet's at its facet).
fn sheet_lane(c: f32, eta: f32, event: u32) -> vec4<f32> {
    if event == EVENT_REFLECT {
        return dielectric_lane(c, eta, event);
    }
    return sheet_transmission_lane(c, eta);
}

// A thin sheet at the normal.
fn thin_dielectric_mueller(b: Bsdf, wi: vec3<f32>, event: u32) -> Mueller {
    return mueller_splat(sheet_lane(abs(wi.z), b.eta, event));
}

// A tabulated rough metal: conductor reflection at the half vector (the depolariser where
// it is degenerate).
fn rough_fresnel_conductor_mueller(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> Mueller {
    let m = polarized_half(wo, wi, EVENT_REFLECT, 1.0);
    if m.w == 0.0 {
        return mueller_depolarizer();
    }
    return conductor_mueller(dot3(wi, m.xyz), bsdf_conductor_eta(b), bsdf_conductor_k(b));
}

// glTF metallic-roughness: its specular lobe's matrix, the depolariser for its diffuse one.
fn metal_rough_mueller(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>, lobe: u32) -> Mueller {
    if lobe == LOBE_G {
        return mueller_splat(metal_rough_specular_lane(b, wo, wi));
    }
    return mueller_depolarizer();
}

// m₀₁ of a rough dielectric's glossy event (wo, wi) (`bsdf_mueller_b`).
fn rough_dielectric_mueller_b(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> vec4<f32> {
    if b.eta == 1.0 {
        return vec4<f32>(0.0);
    }
    let event = select(EVENT_TRANSMIT, EVENT_REFLECT, wo.z * wi.z >= 0.0);
    return vec4<f32>(rough_dielectric_lane(wo, wi, event, b.eta).y);
}

// glTF metallic-roughness's specular lobe: dielectric reflection at the material's IOR at the
// half vector, blended towards the ideal conductor by `metallic` (docs/polarization.md:
// Schlick's F has no phases); the depolariser's zeros where the half vector is degenerate.
fn metal_rough_specular_lane(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> vec4<f32> {
    let m = polarized_half(wo, wi, EVENT_REFLECT, 1.0);
    var d = vec4<f32>(0.0);
    if m.w != 0.0 {
        d = dielectric_lane(dot3(wi, m.xyz), b.ior, EVENT_REFLECT);
    }
    let t = b.metallic;
    return d * (1.0 - t) + vec4<f32>(1.0, 0.0, -1.0, 0.0) * t;
}
