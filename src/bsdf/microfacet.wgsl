// microfacet.wgsl — twin of src/bsdf/microfacet.rs: GGX / Trowbridge–Reitz and Beckmann normal
// distributions, Smith Λ, G1, height-correlated G2 and visible-normal sampling (isotropic α).
// Directions in the local shading frame (z = macro normal); microfacet normals have m.z > 0.
// `wo` of the visible-normal functions is on the upper side (callers mirror it, Walter et al.
// 2007 §5.3). `Microfacet::method` is `microfacet_method` here.

// Pipeline specialisation: distributions no material uses are compiled out.
override HAS_GGX: bool = true;
override HAS_BECKMANN: bool = true;

// 1/√π.
const INV_SQRT_PI: f32 = 0.5641896;

// Largest finite f32 stands in for Λ = +∞ (grazing w); G1 and G2 return 0 for it, as 1/(1 + ∞).
const LAMBDA_INF: f32 = 3.40282347e38;

// A microfacet normal distribution with isotropic roughness α.
struct Microfacet {
    dist: u32,
    alpha: f32,
}

// α is clamped to ≥ 1e-4 (below the smooth threshold callers use delta lobes anyway).
fn microfacet_new(dist: u32, alpha: f32) -> Microfacet {
    return Microfacet(dist, max(alpha, 1e-4));
}

// Normal distribution D(m) for a unit vector m (0 for m.z ≤ 0).
fn microfacet_d(mf: Microfacet, m: vec3<f32>) -> f32 {
    if m.z <= 0.0 {
        return 0.0;
    }
    let a2 = mf.alpha * mf.alpha;
    let xy2 = m.x * m.x + m.y * m.y;
    let z2 = m.z * m.z;
    if HAS_BECKMANN && mf.dist == DIST_BECKMANN {
        // D = exp(−tan²θ/α²)/(π α² cos⁴θ), Walter et al. 2007 eq. 25.
        let tan2 = xy2 / z2;
        return exp(-tan2 / a2) / (PI * a2 * z2 * z2);
    }
    // D = 1/(π α² cos⁴θ (1 + tan²θ/α²)²), Walter et al. 2007 eq. 33, with
    // cos²θ (1 + tan²θ/α²) = z² + (x² + y²)/α² (accurate for tiny α).
    let t = xy2 / a2 + z2;
    return 1.0 / (PI * a2 * t * t);
}

// Smith Λ(w) (depends on |w.z| only through tanθ). Returns LAMBDA_INF for +∞.
fn microfacet_lambda(mf: Microfacet, w: vec3<f32>) -> f32 {
    let xy2 = w.x * w.x + w.y * w.y;
    let z2 = w.z * w.z;
    if xy2 <= 0.0 {
        return 0.0;
    }
    if z2 <= 0.0 {
        return LAMBDA_INF;
    }
    let a2_tan2 = mf.alpha * mf.alpha * xy2 / z2;
    if HAS_BECKMANN && mf.dist == DIST_BECKMANN {
        // Λ = (erf(a) − 1)/2 + e^{−a²}/(2a√π), a = 1/(α tanθ);
        // Heitz 2014 (JCGT 3(2)), Smith Λ of the Beckmann distribution.
        let a = 1.0 / sqrt(a2_tan2);
        return 0.5 * (-erfc(a) + exp(-a * a) * INV_SQRT_PI / a);
    }
    // Λ = (−1 + √(1 + α² tan²θ))/2, Heitz 2014 (JCGT 3(2)), Smith Λ of the GGX distribution.
    return 0.5 * (sqrt(1.0 + a2_tan2) - 1.0);
}

// Smith masking G1(w) = 1/(1 + Λ(w)), Heitz 2014 (JCGT 3(2)), Smith masking function.
fn microfacet_g1(mf: Microfacet, w: vec3<f32>) -> f32 {
    let l = microfacet_lambda(mf, w);
    if l >= LAMBDA_INF {
        return 0.0;
    }
    return 1.0 / (1.0 + l);
}

// Height-correlated masking-shadowing G2 = 1/(1 + Λ(wo) + Λ(wi)),
// Heitz 2014 (JCGT 3(2)), height-correlated Smith masking-shadowing.
fn microfacet_g2(mf: Microfacet, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    let lo = microfacet_lambda(mf, wo);
    let li = microfacet_lambda(mf, wi);
    if lo >= LAMBDA_INF || li >= LAMBDA_INF {
        return 0.0;
    }
    // (Λo + Λi) summed first: symmetric in its arguments to the last bit.
    return 1.0 / (1.0 + (lo + li));
}

// Distribution of visible normals D_wo(m) = G1(wo) max(0, wo·m) D(m) / |wo.z|
// (Heitz 2018, JCGT 7(4), eq. 1). `wo` must be on the upper side (wo.z > 0).
fn microfacet_pdf_visible(mf: Microfacet, wo: vec3<f32>, m: vec3<f32>) -> f32 {
    let dot = dot3(wo, m);
    if wo.z <= 0.0 || dot <= 0.0 {
        return 0.0;
    }
    return microfacet_g1(mf, wo) * dot * microfacet_d(mf, m) / wo.z;
}

// Sample a microfacet normal from D_wo (see the module docs for the methods).
// `wo` must be on the upper side (wo.z > 0). The result has m.z ≥ 0.
fn microfacet_sample_visible(mf: Microfacet, wo: vec3<f32>, u: vec2<f32>) -> vec3<f32> {
    if HAS_BECKMANN && mf.dist == DIST_BECKMANN {
        return microfacet_sample_visible_beckmann(mf, wo, u);
    }
    return microfacet_sample_visible_ggx(mf, wo, u);
}

// Heitz 2018 (JCGT 7(4)), listing 1: stretch → sample the visible hemisphere disk with
// the foreshortened half warped (§4.2) → unstretch.
fn microfacet_sample_visible_ggx(mf: Microfacet, wo: vec3<f32>, u: vec2<f32>) -> vec3<f32> {
    let a = mf.alpha;
    // Stretch the view direction to the α = 1 configuration (Heitz 2018 §4.1).
    let vh = normalize3(vec3<f32>(a * wo.x, a * wo.y, wo.z));
    // Orthonormal basis around vh (Heitz 2018 §4.2, T1 ⟂ z).
    let lensq = vh.x * vh.x + vh.y * vh.y;
    var t1 = vec3<f32>(1.0, 0.0, 0.0);
    if lensq > 0.0 {
        t1 = vec3<f32>(-vh.y, vh.x, 0.0) / sqrt(lensq);
    }
    let t2 = cross3(vh, t1);
    // Uniform point on the unit disk (polar map), then squash the half hidden behind the
    // hemisphere's projection: t2 ← (1 − s)√(1 − t1²) + s t2, s = (1 + vh.z)/2 (§4.2).
    let r = sqrt(u.x);
    let phi = 2.0 * PI * u.y;
    let p1 = r * cos(phi);
    var p2 = r * sin(phi);
    let s = 0.5 * (1.0 + vh.z);
    p2 = (1.0 - s) * sqrt(max(1.0 - p1 * p1, 0.0)) + s * p2;
    // Reproject onto the hemisphere and unstretch (§4.3).
    let nh = p1 * t1 + p2 * t2 + sqrt(max(1.0 - p1 * p1 - p2 * p2, 0.0)) * vh;
    return normalize3(vec3<f32>(a * nh.x, a * nh.y, max(nh.z, 0.0)));
}

// Stretched Beckmann visible-normal sampling (Heitz & d'Eon 2014 §4, Alg. 1 structure)
// with the α = 1 slope sampler [`beckmann_visible_slopes`].
fn microfacet_sample_visible_beckmann(mf: Microfacet, wo: vec3<f32>, u: vec2<f32>) -> vec3<f32> {
    let a = mf.alpha;
    // 1. Stretch wo (Heitz 2014, JCGT 3(2): shape-invariant distributions stretch with α).
    let ws = normalize3(vec3<f32>(a * wo.x, a * wo.y, wo.z));
    let sin_t = sqrt(ws.x * ws.x + ws.y * ws.y);
    var cos_p = 1.0;
    var sin_p = 0.0;
    if sin_t > 1e-7 {
        cos_p = ws.x / sin_t;
        sin_p = ws.y / sin_t;
    }
    // 2. Visible slopes of the unit-roughness surface for incidence angle θ (φ = 0).
    let sl = beckmann_visible_slopes(ws.z, sin_t, u);
    // 3. Rotate to φ and 4. unstretch the slopes.
    let rx = (cos_p * sl.x - sin_p * sl.y) * a;
    let ry = (sin_p * sl.x + cos_p * sl.y) * a;
    // 5. Slope → normal: m ∝ (−x̃, −ỹ, 1) (Heitz 2014, JCGT 3(2), slope space).
    return normalize3(vec3<f32>(-rx, -ry, 1.0));
}

// Unnormalised visible-slope CDF C̃(x) = erfc(−x) + k e^{−x²} (the closure `cdf` of the Rust).
fn beckmann_slope_cdf(x: f32, k: f32) -> f32 {
    return erfc(-x) + k * exp(-x * x);
}

// Visible slopes (x, y) of the α = 1 Beckmann surface seen from the direction
// (sinθ, 0, cosθ): y ~ N(0, ½) by inversion; x by inverting
// C(x) ∝ erfc(−x) + tanθ/√π e^{−x²} on (−∞, cotθ) (derivation in the module docs;
// Heitz & d'Eon 2014 §4, Jakob 2014 §2) with Newton steps safeguarded by bisection.
fn beckmann_visible_slopes(cos_t: f32, sin_t: f32, u: vec2<f32>) -> vec2<f32> {
    // y: Gaussian with variance ½ (the Beckmann slope marginal), y = erfinv(2u − 1).
    let y = erfinv(clamp(2.0 * u.y - 1.0, -0.9999999, 0.9999999));
    if sin_t <= 1e-6 * cos_t {
        // Normal incidence: x is the same Gaussian.
        let x0 = erfinv(clamp(2.0 * u.x - 1.0, -0.9999999, 0.9999999));
        return vec2<f32>(x0, y);
    }
    let tan_t = sin_t / cos_t;
    let cot_t = cos_t / sin_t;
    let k = tan_t * INV_SQRT_PI;
    // Unnormalised CDF and its normalisation Z = C̃(cotθ).
    let z = beckmann_slope_cdf(cot_t, k);
    let target_c = u.x * z;
    // Bracket: below −6 the CDF mass is < 1e-15 of Z for every θ.
    var lo = -6.0;
    var hi = min(cot_t, 6.0);
    var x = erfinv(clamp(2.0 * u.x - 1.0, -0.999999, 0.999999));
    if !(x > lo && x < hi) {
        x = 0.5 * (lo + hi);
    }
    for (var it = 0u; it < 40u; it++) {
        let g = beckmann_slope_cdf(x, k) - target_c;
        if abs(g) <= 1e-6 * z {
            break;
        }
        if g > 0.0 {
            hi = x;
        } else {
            lo = x;
        }
        // dC̃/dx = (2/√π) e^{−x²} (1 − x tanθ).
        let dg = 2.0 * INV_SQRT_PI * exp(-x * x) * (1.0 - x * tan_t);
        let xn = x - g / dg;
        if xn > lo && xn < hi {
            x = xn;
        } else {
            x = 0.5 * (lo + hi);
        }
        if hi - lo < 1e-7 {
            break;
        }
    }
    return vec2<f32>(x, y);
}

// Complementary error function, fractional error < 1.2e-7 everywhere.
// Press et al., "Numerical Recipes in C" 2nd ed. §6.2 (`erfcc`, Chebyshev fit).
fn erfc(x: f32) -> f32 {
    let z = abs(x);
    let t = 1.0 / (1.0 + 0.5 * z);
    let poly = -1.2655122
        + t * (1.0000237
            + t * (0.37409196
                + t * (0.09678418
                    + t * (-0.18628806
                        + t * (0.27886807
                            + t * (-1.13520398
                                + t * (1.48851587 + t * (-0.82215223 + t * 0.17087277))))))));
    let r = t * exp(-z * z + poly);
    if x >= 0.0 {
        return r;
    }
    return 2.0 - r;
}

// Error function erf(x) = 1 − erfc(x) (see [`erfc`]).
fn erf(x: f32) -> f32 {
    return 1.0 - erfc(x);
}

// Inverse error function for |x| < 1, single precision.
// Giles 2010, "Approximating the erfinv function" (GPU Computing Gems Jade, ch. 10), Fig. 2.
fn erfinv(x: f32) -> f32 {
    var w = -log((1.0 - x) * (1.0 + x));
    var p: f32;
    if w < 5.0 {
        w = w - 2.5;
        p = 2.81022636e-08;
        p = 3.43273939e-07 + p * w;
        p = -3.5233877e-06 + p * w;
        p = -4.39150654e-06 + p * w;
        p = 0.00021858087 + p * w;
        p = -0.00125372503 + p * w;
        p = -0.00417768164 + p * w;
        p = 0.246640727 + p * w;
        p = 1.50140941 + p * w;
    } else {
        w = sqrt(w) - 3.0;
        p = -0.000200214257;
        p = 0.000100950558 + p * w;
        p = 0.00134934322 + p * w;
        p = -0.00367342844 + p * w;
        p = 0.00573950773 + p * w;
        p = -0.0076224613 + p * w;
        p = 0.00943887047 + p * w;
        p = 1.00167406 + p * w;
        p = 2.83297682 + p * w;
    }
    return p * x;
}
