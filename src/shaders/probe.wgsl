// probe.wgsl — evaluates the WGSL maths on a list of cases so tests/gpu.rs can compare it with
// the Rust twins (fresnel, refract, each BSDF's eval/pdf/sample, the RNG).

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
    _pad0: u32,
    _pad1: u32,
}

struct ProbeOut {
    // r_par, r_perp, f, cos_t of fresnel_dielectric_terms(wo.z, eta)
    fresnel: array<f32, 4>,
    eta_rel: f32,
    // 1 if refract(wo, ±z, eta_rel) is defined
    refract_ok: f32,
    eval_pdf: array<f32, 4>,
    refracted: array<f32, 3>,
    sample_pdf: f32,
    sample_wi: array<f32, 3>,
    sample_eta_rel: f32,
    sample_weight: array<f32, 3>,
    // valid | is_delta << 1 | event << 2 | lobe << 3
    sample_flags: u32,
    // pcg_hash(pixel), then the first 4 draws of sampler_new(pixel, sample, seed) as raw bits
    rng: array<u32, 5>,
    _pad: u32,
}

@group(0) @binding(0) var<storage, read> cases: array<ProbeCase>;
@group(0) @binding(1) var<storage, read_write> outs: array<ProbeOut>;

// Fixed colours of the probe BSDFs (tests/gpu.rs uses the same).
const PROBE_COLOR: vec3<f32> = vec3<f32>(0.25, 0.5, 0.875);

@compute @workgroup_size(64, 1, 1)
fn probe(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= arrayLength(&cases) {
        return;
    }
    let c = cases[i];
    let wo = v3(c.wo);
    let wi = v3(c.wi);
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
    o.refracted = array<f32, 3>(rr.wt.x, rr.wt.y, rr.wt.z);
    let b = Bsdf(c.kind, PROBE_COLOR, c.eta, 0.0, 0.0);
    let f = bsdf_eval(b, wo, wi, MODE_RADIANCE);
    o.eval_pdf = array<f32, 4>(f.x, f.y, f.z, bsdf_pdf(b, wo, wi));
    let s = bsdf_sample(b, wo, c.uc, vec2<f32>(c.u2[0], c.u2[1]), MODE_RADIANCE);
    o.sample_pdf = s.pdf;
    o.sample_wi = array<f32, 3>(s.wi.x, s.wi.y, s.wi.z);
    o.sample_eta_rel = s.eta_rel;
    o.sample_weight = array<f32, 3>(s.weight.x, s.weight.y, s.weight.z);
    o.sample_flags = select(0u, 1u, s.valid) | (select(0u, 1u, s.is_delta) << 1u) | (s.event << 2u) | (s.lobe << 3u);
    var smp = sampler_new(c.pixel, c.sample, c.seed);
    o.rng[0] = pcg_hash(c.pixel);
    for (var k = 1u; k < 5u; k++) {
        o.rng[k] = bitcast<u32>(sampler_next_1d(&smp));
    }
    o._pad = 0u;
    outs[i] = o;
}
