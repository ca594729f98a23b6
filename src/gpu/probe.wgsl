// probe.wgsl — evaluates the WGSL maths on a list of cases so tests/gpu.rs can compare it with
// the Rust twins (fresnel, refract, each BSDF's eval/pdf/sample and polarising matrix, the RNG).

struct ProbeCase {
    wo: array<f32, 3>,
    uc: f32,
    wi: array<f32, 3>,
    eta: f32,
    u2: array<f32, 2>,
    // BSDF_* kind
    kind: u32,
    // RNG probe: pixel, sample, seed come from these three
    pixel: u32,
    sample: u32,
    seed: u32,
    // microfacet α and DIST_* (rough kinds; metal-rough: GGX with this α)
    alpha: f32,
    dist: u32,
    // metal-rough metallic (eta doubles as its IOR)
    metallic: f32,
    // MODE_*
    mode: u32,
    _pad0: u32,
    _pad1: u32,
}

struct ProbeOut {
    // r_par, r_perp, f, cos_t of fresnel_dielectric_terms(wo.z, eta)
    fresnel: array<f32, 4>,
    eta_rel: f32,
    // 1 if refract(wo, ±z, eta_rel) is defined
    refract_ok: f32,
    sample_pdf: f32,
    sample_eta_rel: f32,
    refracted: array<f32, 3>,
    // valid | is_delta << 1 | event << 2 | lobe << 3
    sample_flags: u32,
    sample_wi: array<f32, 3>,
    pdf: f32,
    eval: array<f32, 4>,
    lobes_d: array<f32, 4>,
    lobes_g: array<f32, 4>,
    sample_f: array<f32, 4>,
    sample_weight: array<f32, 4>,
    // D(m), Λ(wo), G2(wo, wi), pdf_visible(wo_up, m), m = normalize(wo_up + wi_up)
    mf: array<f32, 4>,
    // sample_visible(wo_up, u2)
    mf_m: array<f32, 3>,
    mf_g1: f32,
    // erfc(3 wo.x), erf(3 wo.y), erfinv(2 uc − 1), erfinv(0.9999 (2 u2.x − 1))
    special: array<f32, 4>,
    lambdas: array<f32, 4>,
    uplift: array<f32, 4>,
    to_rgb: array<f32, 4>,
    // bsdf_mueller(b, wo, wi, event of (wo, wi), LOBE_G): a, b, c, s (4 lanes each), and
    // bsdf_mueller_b (polarized.wgsl)
    mueller: array<f32, 16>,
    mueller_b: array<f32, 4>,
    // pcg_hash(pixel), then the first 4 draws of sampler_new(pixel, sample, seed) as raw bits
    rng: array<u32, 5>,
    _pad: array<u32, 3>,
}

@group(0) @binding(0) var<storage, read> cases: array<ProbeCase>;
@group(0) @binding(1) var<storage, read_write> outs: array<ProbeOut>;

// Fixed colours of the probe BSDFs (tests/gpu.rs uses the same).
const PROBE_COLOR: vec3<f32> = vec3<f32>(0.25, 0.5, 0.875);
// Complex IOR of the probe conductors: η = eta × PROBE_COND_ETA, k = PROBE_COND_K.
const PROBE_COND_ETA: vec3<f32> = vec3<f32>(0.15, 0.4, 1.2);
const PROBE_COND_K: vec3<f32> = vec3<f32>(4.0, 2.4, 1.6);
// The probe films (BSDF_FILM_*): index, thickness 250 + 400 uc nm, factor; the base is the
// case's `metallic` slot (FILM_ON_*).
const PROBE_FILM_IOR: f32 = 1.42;
const PROBE_FILM_FACTOR: f32 = 0.85;

fn a4(v: vec4<f32>) -> array<f32, 4> {
    return array<f32, 4>(v.x, v.y, v.z, v.w);
}

fn a3(v: vec3<f32>) -> array<f32, 3> {
    return array<f32, 3>(v.x, v.y, v.z);
}

@compute @workgroup_size(64, 1, 1)
fn probe(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= arrayLength(&cases) {
        return;
    }
    let c = cases[i];
    let wo = v3(c.wo);
    let wi = v3(c.wi);
    let u2 = vec2<f32>(c.u2[0], c.u2[1]);
    var o: ProbeOut;
    let fr = fresnel_dielectric_terms(wo.z, c.eta);
    o.fresnel = array<f32, 4>(fr.r_par, fr.r_perp, fr.f, fr.cos_t);
    o.eta_rel = fr.eta_rel;
    var n = vec3<f32>(0.0, 0.0, 1.0);
    if wo.z < 0.0 {
        n = vec3<f32>(0.0, 0.0, -1.0);
    }
    let rr = refract(wo, n, fr.eta_rel);
    o.refract_ok = select(0.0, 1.0, rr.ok);
    o.refracted = a3(rr.wt);
    let color = vec4<f32>(PROBE_COLOR, 0.0);
    // Specular colour Color::ONE (w = 1) as in `MetalRough::new`.
    var b = bsdf_new(c.kind, color, c.eta, c.alpha, c.dist);
    b.metallic = c.metallic;
    b.ior = c.eta;
    b.specular_color = vec4<f32>(1.0);
    if c.kind == BSDF_SMOOTH_CONDUCTOR || c.kind == BSDF_ROUGH_FRESNEL_CONDUCTOR {
        bsdf_set_conductor_ior(&b, c.eta * PROBE_COND_ETA, PROBE_COND_K);
    }
    if c.kind == BSDF_FILM_SMOOTH || c.kind == BSDF_FILM_ROUGH {
        b.film = vec4<f32>(PROBE_FILM_IOR, 250.0 + 400.0 * c.uc, PROBE_FILM_FACTOR, c.metallic);
        if u32(c.metallic) == FILM_ON_CONDUCTOR {
            bsdf_set_conductor_ior(&b, c.eta * PROBE_COND_ETA, PROBE_COND_K);
        }
    }
    o.eval = a4(bsdf_eval(b, wo, wi, c.mode));
    o.pdf = bsdf_pdf(b, wo, wi);
    let lv = bsdf_eval_lobes(b, wo, wi, c.mode);
    o.lobes_d = a4(lv.d);
    o.lobes_g = a4(lv.g);
    let s = bsdf_sample(b, wo, c.uc, u2, c.mode);
    o.sample_pdf = s.pdf;
    o.sample_wi = a3(s.wi);
    o.sample_eta_rel = s.eta_rel;
    o.sample_f = a4(s.f);
    o.sample_weight = a4(s.weight);
    o.sample_flags = select(0u, 1u, s.valid) | (select(0u, 1u, s.is_delta) << 1u) | (s.event << 2u) | (s.lobe << 3u);
    // Microfacet pieces on the upper side.
    let mf = microfacet_new(c.dist, c.alpha);
    let wo_up = vec3<f32>(wo.x, wo.y, abs(wo.z));
    let wi_up = vec3<f32>(wi.x, wi.y, abs(wi.z));
    let m = normalize_or_zero3(wo_up + wi_up);
    o.mf = array<f32, 4>(microfacet_d(mf, m), microfacet_lambda(mf, wo), microfacet_g2(mf, wo, wi), microfacet_pdf_visible(mf, wo_up, m));
    if wo_up.z > 0.0 {
        o.mf_m = a3(microfacet_sample_visible(mf, wo_up, u2));
    }
    o.mf_g1 = microfacet_g1(mf, wo_up);
    o.special = array<f32, 4>(erfc(3.0 * wo.x), erf(3.0 * wo.y), erfinv(2.0 * c.uc - 1.0), erfinv(0.9999 * (2.0 * u2.x - 1.0)));
    let lambdas = sample_hero_wavelengths(c.uc);
    o.lambdas = a4(lambdas);
    o.uplift = a4(rgb_to_spectrum4(PROBE_COLOR, lambdas));
    let rgb = spectrum_sample_to_rgb(lambdas, vec4<f32>(1.0, u2.x, u2.y, c.uc));
    o.to_rgb = array<f32, 4>(rgb.x, rgb.y, rgb.z, cauchy_from_abbe(c.eta, 40.0, lambdas.x));
    let event = select(EVENT_TRANSMIT, EVENT_REFLECT, wo.z * wi.z >= 0.0);
    let mu = bsdf_mueller(b, wo, wi, event, LOBE_G);
    for (var k = 0u; k < 4u; k++) {
        o.mueller[k] = mu.a[k];
        o.mueller[4u + k] = mu.b[k];
        o.mueller[8u + k] = mu.c[k];
        o.mueller[12u + k] = mu.s[k];
    }
    o.mueller_b = a4(bsdf_mueller_b(b, wo, wi));
    var smp = sampler_new(c.pixel, c.sample, c.seed);
    o.rng[0] = pcg_hash(c.pixel);
    for (var k = 1u; k < 5u; k++) {
        o.rng[k] = bitcast<u32>(sampler_next_1d(&smp));
    }
    o._pad = array<u32, 3>(0u, 0u, 0u);
    outs[i] = o;
}
