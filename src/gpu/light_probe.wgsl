// light_probe.wgsl — evaluates light.wgsl on a list of cases so tests/light_twin.rs can
// compare it with the Rust `Light` methods (src/scene/light/). Assembled after scene.wgsl and
// light.wgsl (`gpu::pipeline::light_probe_source`); binds the scene's triangles, materials and
// light distribution as the integrator does (`gpu::light_probe::run_light_probe`).

// The integrator's `params` as far as light.wgsl reads it, plus the environment radiance.
struct LightProbeParams {
    environment: vec4<f32>,
    // The uniform environment's bounding sphere (centre, radius).
    sphere: vec4<f32>,
    light_count: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

struct LightProbeCase {
    // Reference point of light_sample_li.
    p: array<f32, 3>,
    // Index into `lights`; light_count or more probes the environment.
    light: u32,
    // Normal and direction of light_le / light_pdf_le.
    n: array<f32, 3>,
    // Selection probability folded into the densities.
    pick: f32,
    w: array<f32, 3>,
    // light_set_pick(u_pick).
    u_pick: f32,
    u: array<f32, 2>,
    u_pos: array<f32, 2>,
    u_dir: array<f32, 2>,
    // The sampler a double-sided area light draws its side from.
    pixel: u32,
    sample: u32,
    seed: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

struct LightProbeOut {
    // light_sample_li(light, p, u, pick): valid | is_delta << 1 | infinite << 2
    li_flags: u32,
    li_l: array<f32, 3>,
    li_wi: array<f32, 3>,
    li_pdf: f32,
    li_p: array<f32, 3>,
    // light_pdf_li(light, pick, |p_light − p|, n_light, wi) of the sampled point
    li_pdf_back: f32,
    li_n: array<f32, 3>,
    // light_sample_le(light, u_pos, u_dir, sampler, pick): valid | delta_pos << 1
    le_flags: u32,
    le_p: array<f32, 3>,
    le_pdf_pos: f32,
    le_n: array<f32, 3>,
    le_pdf_dir: f32,
    le_dir: array<f32, 3>,
    le_cos_n: f32,
    le_l: array<f32, 3>,
    // The sampler's first draw (the side a double-sided area light emits from)
    u_side: f32,
    // light_le(light, n, w), then light_pdf_le(light, pick, n, w)
    emitted: array<f32, 3>,
    pdf_pos: f32,
    pdf_dir: f32,
    // light_set_pick(u_pick): probability and the picked entry's CDF value
    pick_prob: f32,
    pick_cdf: f32,
    // light_set_area(slot).prob of an area light's leaf slot (0 for other kinds)
    area_prob: f32,
}

@group(0) @binding(0) var<uniform> params: LightProbeParams;
@group(0) @binding(6) var<storage, read> light_cases: array<LightProbeCase>;
@group(0) @binding(7) var<storage, read_write> light_outs: array<LightProbeOut>;

fn la3(v: vec3<f32>) -> array<f32, 3> {
    return array<f32, 3>(v.x, v.y, v.z);
}

fn la2(a: array<f32, 2>) -> vec2<f32> {
    return vec2<f32>(a[0], a[1]);
}

@compute @workgroup_size(64, 1, 1)
fn light_probe(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(local_invocation_index) lane: u32,
) {
    LANE = lane;
    let i = gid.x;
    if i >= arrayLength(&light_cases) {
        return;
    }
    let c = light_cases[i];
    var light = light_environment(params.environment.xyz);
    light.position = la3(params.sphere.xyz);
    light.radius = params.sphere.w;
    if c.light < params.light_count {
        light = lights[c.light];
    }
    let p = v3(c.p);
    var o: LightProbeOut;
    let li = light_sample_li(light, p, la2(c.u), c.pick);
    o.li_flags = select(0u, 1u, li.valid) | (select(0u, 1u, li.is_delta) << 1u) | (select(0u, 1u, li.infinite) << 2u);
    o.li_l = la3(li.l);
    o.li_wi = la3(li.wi);
    o.li_pdf = li.pdf;
    o.li_p = la3(li.p_light);
    o.li_n = la3(li.n_light);
    if li.valid {
        let to = li.p_light - p;
        o.li_pdf_back = light_pdf_li(light, c.pick, sqrt(dot3(to, to)), li.n_light, li.wi);
    }
    var smp = sampler_new(c.pixel, c.sample, c.seed);
    var side = smp;
    o.u_side = sampler_next_1d(&side);
    let le = light_sample_le(light, la2(c.u_pos), la2(c.u_dir), &smp, c.pick);
    o.le_flags = select(0u, 1u, le.valid) | (select(0u, 1u, le.delta_pos) << 1u);
    o.le_p = la3(le.p);
    o.le_pdf_pos = le.pdf_pos;
    o.le_n = la3(le.n);
    o.le_pdf_dir = le.pdf_dir;
    o.le_dir = la3(le.dir);
    o.le_cos_n = le.cos_n;
    o.le_l = la3(le.l);
    let n = v3(c.n);
    let w = v3(c.w);
    o.emitted = la3(light_le(light, p, n, w));
    let pe = light_pdf_le(light, c.pick, n, w);
    o.pdf_pos = pe.pdf_pos;
    o.pdf_dir = pe.pdf_dir;
    let pk = light_set_pick(c.u_pick);
    o.pick_prob = pk.prob;
    o.pick_cdf = pk.light.cdf;
    if light.kind == LIGHT_TRIANGLE && c.light < params.light_count {
        o.area_prob = light_set_area(light.index).prob;
    }
    light_outs[i] = o;
}
