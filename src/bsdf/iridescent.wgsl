// iridescent.wgsl — a thin film on a dielectric or a metal, smooth or rough (twin of
// src/bsdf/iridescent.rs; glTF KHR_materials_iridescence): the base BSDF with its Fresnel
// term replaced by the film's reflectance (Belcour & Barla 2017, §3). A coloured F picks
// reflection by its mean P over the lanes and weights each lane by F/P or (1 − F)/(1 − P).
// GPU films are RGB (Belcour & Barla's analytic integral, `film_rgb`): check_supported keeps
// them out of spectral kernels.
//
// `Bsdf.film` = (film index, thickness nm, factor, FILM_ON_* base); a conductor base keeps its
// η, k where the tabulated metals do (`bsdf_set_conductor_ior`), a reflectance base its F₀ in
// `color`, a dielectric or sheet its index in `eta`.

fn film_base(b: Bsdf) -> u32 {
    return u32(b.film.w);
}

// A film on glass or a sheet can transmit, on a metal not. Twin of `Iridescent::can_transmit`.
fn film_can_transmit(b: Bsdf) -> bool {
    return film_base(b) == FILM_ON_DIELECTRIC || film_base(b) == FILM_ON_SHEET;
}

// The substrate's complex index in RGB channel `i`. Twin of `Iridescent::substrate`.
fn film_substrate(b: Bsdf, i: u32) -> vec2<f32> {
    switch film_base(b) {
        case FILM_ON_CONDUCTOR: {
            return vec2<f32>(bsdf_conductor_eta(b)[i], bsdf_conductor_k(b)[i]);
        }
        case FILM_ON_REFLECTANCE: {
            let s = sqrt(clamp(b.color[i], 0.0, FILM_MAX_F0));
            return vec2<f32>((1.0 + s) / (1.0 - s), 0.0);
        }
        default: {
            return vec2<f32>(b.eta, 0.0);
        }
    }
}

// The base's own Fresnel term at the outside cosine. Twin of `Iridescent::base_fresnel`.
fn film_base_fresnel(b: Bsdf, cos1: f32) -> vec4<f32> {
    switch film_base(b) {
        case FILM_ON_CONDUCTOR: {
            return fresnel_conductor4(cos1, bsdf_conductor_eta(b), bsdf_conductor_k(b));
        }
        case FILM_ON_REFLECTANCE: {
            return b.color;
        }
        default: {
            return vec4<f32>(fresnel_dielectric(cos1, b.eta));
        }
    }
}

// The film's reflectance per RGB lane at the outside cosine `cos1` ∈ [0, 1], blended with the
// base's by the factor (w = 0 for the film). Twin of `Iridescent::reflectance` (RGB). A metal's
// substrate index differs per lane, so its film is integrated once per lane; a dielectric's
// once for all three. One loop with a data-dependent trip count (not unrolled): the
// integral's code exists once per call site, and its temporaries once.
fn film_reflectance(b: Bsdf, cos1: f32) -> vec4<f32> {
    let base = film_base(b);
    var lanes = 3u;
    if base == FILM_ON_DIELECTRIC || base == FILM_ON_SHEET {
        lanes = 1u;
    }
    var r = vec3<f32>(0.0);
    for (var i = 0u; i < lanes; i++) {
        let c = film_rgb(b.film.x, b.film.y, cos1, film_substrate(b, i));
        if lanes == 1u {
            r = c;
        } else {
            r[i] = c[i];
        }
    }
    let film = vec4<f32>(r, 0.0);
    let bf = film_base_fresnel(b, cos1);
    return bf + (film - bf) * b.film.z;
}

// The mean over the RGB lanes (the probability a coloured F selects with).
fn film_mean(c: vec4<f32>) -> f32 {
    return (c.x + c.y + c.z) / 3.0;
}

// From the side of the signed cosine `cos` of a dielectric base: the outside cosine of the
// Snell pair, 1 under total internal reflection. Twin of `Iridescent::reflectance_signed`.
fn film_reflectance_signed(b: Bsdf, cos: f32, eta: f32) -> vec4<f32> {
    // One call below, not one per side: each call inlines the film's integral.
    var cos1 = min(cos, 1.0);
    if cos < 0.0 {
        let sin2_out = max(1.0 - cos * cos, 0.0) * eta * eta;
        if sin2_out >= 1.0 {
            return vec4<f32>(1.0);
        }
        cos1 = sqrt(1.0 - sin2_out);
    }
    return film_reflectance(b, cos1);
}

// A sheet's reflectance (both faces filmed, every inter-reflection; index 1: the free-standing
// film). Twin of `Iridescent::sheet_reflectance`.
fn film_sheet_reflectance(b: Bsdf, cos: f32, eta: f32) -> vec4<f32> {
    let r = film_reflectance(b, min(abs(cos), 1.0));
    if eta == 1.0 {
        return r;
    }
    let t = vec4<f32>(1.0) - r;
    let denom = max(vec4<f32>(1.0) - r * r, vec4<f32>(1e-7));
    return min(r + t * t * r / denom, vec4<f32>(1.0));
}

// The reflection tint: a conductor's base colour, 1 otherwise.
fn film_tint(b: Bsdf) -> vec4<f32> {
    if film_base(b) == FILM_ON_CONDUCTOR {
        return b.color;
    }
    return vec4<f32>(1.0);
}

// The lane factors of the rough dielectric's f (computed with P): F/P for reflection,
// (1 − F)/(1 − P) for transmission, from the film's reflectance F. Twin of `FilmFresnel::lanes`.
fn film_lane_factors(r: vec4<f32>, is_reflect: bool) -> vec4<f32> {
    let p = film_mean(r);
    if is_reflect {
        if p > 0.0 {
            return r / p;
        }
        return vec4<f32>(0.0);
    }
    if p < 1.0 {
        return (vec4<f32>(1.0) - r) / (1.0 - p);
    }
    return vec4<f32>(0.0);
}

// Smooth filmed dielectric. Twin of `Iridescent::sample_smooth`.
fn film_smooth_dielectric_sample(b: Bsdf, wo: vec3<f32>, uc: f32, mode: u32) -> BsdfSample {
    if wo.z == 0.0 {
        return bsdf_sample_none();
    }
    let fr = fresnel_dielectric_terms(wo.z, b.eta);
    var r = vec4<f32>(1.0);
    if fr.f < 1.0 {
        r = film_reflectance_signed(b, wo.z, b.eta);
    }
    let p = film_mean(r);
    if uc < p || fr.f >= 1.0 {
        return bsdf_sample_delta(vec3<f32>(-wo.x, -wo.y, wo.z), r / p, p, EVENT_REFLECT, 1.0);
    }
    let t = smooth_refraction(wo, fr, mode);
    let weight = (vec4<f32>(1.0) - r) / (1.0 - p) * t.w;
    return bsdf_sample_delta(t.xyz, weight, 1.0 - p, EVENT_TRANSMIT, fr.eta_rel);
}

// Filmed sheet. Twin of `Iridescent::sample_sheet`.
fn film_sheet_sample(b: Bsdf, wo: vec3<f32>, uc: f32) -> BsdfSample {
    if wo.z == 0.0 || !is_finite_f32(wo.z) {
        return bsdf_sample_none();
    }
    let r = film_sheet_reflectance(b, wo.z, b.eta);
    let p = film_mean(r);
    if uc < p || p >= 1.0 {
        return bsdf_sample_delta(vec3<f32>(-wo.x, -wo.y, wo.z), r / p, p, EVENT_REFLECT, 1.0);
    }
    let weight = (vec4<f32>(1.0) - r) / (1.0 - p);
    return bsdf_sample_delta(-wo, weight, 1.0 - p, EVENT_TRANSMIT, 1.0);
}

// Rough filmed metal: tint F_film(wo·m) D G2/(4 cos cos). Twin of
// `Iridescent::rough_conductor` (f; the pdf is the glossy lobe's).
fn film_rough_conductor_eval(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> vec4<f32> {
    let f = rough_conductor_eval_pdf(b, wo, wi).f;
    if f == 0.0 {
        return vec4<f32>(0.0);
    }
    let h = normalize_or_zero3(wo + wi);
    let c = clamp(dot3(wo, h), 0.0, 1.0);
    return film_tint(b) * film_reflectance(b, c) * f;
}

// The lobe's sample with the film's F at the half vector. Twin of
// `Iridescent::sample_rough_conductor`.
fn film_rough_conductor_sample(b: Bsdf, wo: vec3<f32>, u2: vec2<f32>) -> BsdfSample {
    let s = rough_conductor_sample_reflection(b, wo, u2);
    if !s.ok {
        return bsdf_sample_none();
    }
    let f = film_rough_conductor_eval(b, wo, s.wi);
    if !is_finite_v4(f) {
        return bsdf_sample_none();
    }
    return bsdf_sample_new(s.wi, f, f * (s.wi.z / s.pdf), s.pdf, EVENT_REFLECT, LOBE_G, 1.0);
}

// The switch's entries (bsdf.wgsl): BSDF_FILM_SMOOTH samples only; BSDF_FILM_ROUGH on a
// dielectric is the rough dielectric with the film's Fresnel term (rough_dielectric.wgsl reads
// it), on a metal the rough conductor above.
fn film_eval(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>, mode: u32) -> vec4<f32> {
    if film_base(b) == FILM_ON_DIELECTRIC {
        return rough_dielectric_eval(b, wo, wi, mode);
    }
    return film_rough_conductor_eval(b, wo, wi);
}

fn film_pdf(b: Bsdf, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    if film_base(b) == FILM_ON_DIELECTRIC {
        return rough_dielectric_pdf(b, wo, wi);
    }
    return rough_conductor_eval_pdf(b, wo, wi).pdf;
}

fn film_sample(b: Bsdf, wo: vec3<f32>, uc: f32, u2: vec2<f32>, mode: u32) -> BsdfSample {
    let base = film_base(b);
    if b.kind == BSDF_FILM_ROUGH {
        if base == FILM_ON_DIELECTRIC {
            return rough_dielectric_sample(b, wo, uc, u2, mode);
        }
        return film_rough_conductor_sample(b, wo, u2);
    }
    if base == FILM_ON_DIELECTRIC {
        return film_smooth_dielectric_sample(b, wo, uc, mode);
    }
    if base == FILM_ON_SHEET {
        return film_sheet_sample(b, wo, uc);
    }
    if wo.z <= 0.0 {
        return bsdf_sample_none();
    }
    let weight = film_tint(b) * film_reflectance(b, min(wo.z, 1.0));
    return bsdf_sample_delta(vec3<f32>(-wo.x, -wo.y, wo.z), weight, 1.0, EVENT_REFLECT, 1.0);
}
