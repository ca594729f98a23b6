// integrator.wgsl — the path-tracing kernel, twin of `cpu::Integrator::li` (src/cpu/integrator.rs):
// unidirectional path tracing with next-event estimation on area and punctual lights and
// MIS (power heuristic) between light and BSDF sampling. Veach 1997, ch. 9–10;
// PBR 4th ed. §13.4 (`PathIntegrator`). Depth and Russian roulette follow Mitsuba 3's `path`
// integrator: `max_depth` 1 = emitters seen directly, 2 = direct lighting, RR from `rr_depth`.
// Random dimensions are consumed in the CPU's order: jitter (2); per vertex uc, u2 (2),
// ul, ul2 (2); Russian roulette (1).
// Lights are reached only through light.wgsl, the per-vertex step through interaction.wgsl.

// Pipeline specialisation (absent features compiled out; values never specialised).
override HAS_ENVIRONMENT: bool = true;
// Light tracing combined with this kernel by MIS (`lt+pt`, light_tracing.wgsl).
override HAS_LT: bool = false;

struct Params {
    // xyz camera position, w = tan(yfov / 2)
    cam_pos: vec4<f32>,
    // camera-to-world rotation columns; right.w = aspect
    cam_right: vec4<f32>,
    cam_up: vec4<f32>,
    cam_back: vec4<f32>,
    environment: vec4<f32>,
    // row 0 of the Mueller matrix of the filter in front of the sensor (HAS_POLARIZATION;
    // (1, 0, 0, 0) without one): chain.wgsl
    polarizer: vec4<f32>,
    width: u32,
    height: u32,
    seed: u32,
    max_depth: u32,
    rr_depth: u32,
    // index of the first sample of this batch
    sample_offset: u32,
    // samples per pixel in this batch
    batch: u32,
    light_count: u32,
    // running mean: mean' = mean · w_old + batch_sum · w_new, w_old = n/(n+k), w_new = 1/(n+k)
    w_old: f32,
    w_new: f32,
    // linear pixel index whose first sample of the batch is recorded in `stats.debug`
    debug_pixel: u32,
    // the scene's ray-offset scale (bvh::offset_scale), copied into OFFSET_SCALE
    offset_scale: f32,
    // first image row of this submission (a dispatch may cover a band of rows)
    tile_y0: u32,
    // first image row the accumulation film holds (tiles of an image larger than a binding)
    film_y0: u32,
    // sppm (photon.wgsl): r₁, 1 / (photon paths · π) and buckets − 1 per iteration; sample
    // index s is iteration s, of radius r₁ (s + 1)^photon_radius_exp
    photon_radius0: f32,
    photon_norm0: f32,
    grid_mask: u32,
    // photon paths per iteration (render::photon_aim::photon_paths)
    photon_paths: u32,
    // spheres in `targets` (0: photons leave as the light emits them)
    target_count: u32,
    photon_radius_exp: f32,
    // where finite lights aim their photons: centre xyz, radius w (photon.wgsl `photon_aim`)
    targets: array<vec4<f32>, PHOTON_TARGETS>,
    // the Heckbert path filter's table (path_filter.wgsl; zeros without a filter)
    path_filter: array<vec4<u32>, DFA_VEC4S>,
}

struct Stats {
    dropped_lo: atomic<u32>,
    dropped_hi: atomic<u32>,
    segments_lo: atomic<u32>,
    segments_hi: atomic<u32>,
    debug: array<vec4<f32>>,
}

// A read-only storage buffer, not a uniform one: lavapipe inlines the values of uniforms that
// decide branches and loop bounds (max_depth, width, batch, ...) into a new JIT-compiled
// variant for every combination it meets and keeps them all — every edit and batch size
// recompiled the kernel (≈ 10 s of LLVM each) and resident memory grew by hundreds of MB a
// variant. Storage loads are never inlined; on GPUs a read-only buffer read at a uniform
// address is a scalar load like a uniform one.
@group(0) @binding(0) var<storage, read> params: Params;
@group(0) @binding(6) var<storage, read_write> accum: array<vec4<f32>>;
@group(0) @binding(7) var<storage, read_write> stats: Stats;

// DFA state after `sym` (0 when unfiltered). Twin of `Integrator::step`.
fn integrator_step(q: u32, sym: u32) -> u32 {
    if HAS_FILTER {
        return dfa_table_step(q, sym);
    }
    return 0u;
}

// Does a path in state `q` that now reaches a light count? Twin of `Integrator::accepts_light`.
fn integrator_accepts_light(q: u32) -> bool {
    if HAS_FILTER {
        return dfa_table_is_accepting(dfa_table_step(q, SYM_L));
    }
    return true;
}

// Debug records per path vertex (gpu::renderer::DebugPath reads them; DEBUG_* from the prelude).
var<private> debug_on: bool;

fn debug_write(i: u32, v: vec4<f32>) {
    if debug_on && i < arrayLength(&stats.debug) {
        stats.debug[i] = v;
    }
}

// 64-bit counter out of two u32 atomics (carry on wrap-around).
fn add_counter_dropped(x: u32) {
    if x == 0u {
        return;
    }
    let old = atomicAdd(&stats.dropped_lo, x);
    if old + x < old {
        atomicAdd(&stats.dropped_hi, 1u);
    }
}

fn add_counter_segments(x: u32) {
    if x == 0u {
        return;
    }
    let old = atomicAdd(&stats.segments_lo, x);
    if old + x < old {
        atomicAdd(&stats.segments_hi, 1u);
    }
}

var<private> segments: u32;

// Each invocation's counts are summed per workgroup in workgroup memory, then one lane adds
// the totals to the global counters: one global atomic add per counter and workgroup instead
// of one per invocation (the usual two-level reduction; Harris, "Optimizing Parallel
// Reduction in CUDA", NVIDIA 2007). The memory is the traversal stack's (scene.wgsl), free
// once every invocation has finished its paths: slots 0 and 1 of each lane's stack, so the
// kernels need no LDS beyond the stack's 16 KiB (8 more bytes cost RADV a 512-byte block).
// Every invocation of the workgroup must call this (it has a barrier): entry points call it
// from uniform control flow, after their per-pixel work.
fn add_counters_workgroup(dropped: u32, segs: u32) {
    // The lane's own stack slots (i·64 + lane, i = 0 and 1): no other lane touches them.
    BVH_STACK[LANE] = dropped;
    BVH_STACK[WORKGROUP_LANES + LANE] = segs;
    workgroupBarrier();
    if LANE == 0u {
        var d = 0u;
        var s = 0u;
        for (var l = 0u; l < WORKGROUP_LANES; l++) {
            d += BVH_STACK[l];
            s += BVH_STACK[WORKGROUP_LANES + l];
        }
        add_counter_dropped(d);
        add_counter_segments(s);
    }
}

// Everything known about a ray/surface intersection (cpu::SurfaceHit).
struct SurfaceHit {
    p: vec3<f32>,
    ng: vec3<f32>,
    ns: vec3<f32>,
    uv: vec2<f32>,
    slot: u32,
    scene_tri: u32,
    material: u32,
    t: f32,
}

// Reconstruct the surface record of a BVH hit. Twin of `Integrator::surface`.
fn integrator_surface(h: Hit) -> SurfaceHit {
    let tri = triangles[h.slot];
    let p0 = v3(tri.p0);
    let p1 = v3(tri.p1);
    let p2 = v3(tri.p2);
    let b0 = 1.0 - h.b1 - h.b2;
    // Barycentric hit point (more accurate than o + t·d; PBR 4th ed. §6.8.4).
    let p = p0 * b0 + p1 * h.b1 + p2 * h.b2;
    let ng = normalize_or_zero3(cross3(p1 - p0, p2 - p0));
    let va = vertices[tri.i0];
    let vb = vertices[tri.i1];
    let vc = vertices[tri.i2];
    var ns = normalize_or_zero3(v3(va.normal) * b0 + v3(vb.normal) * h.b1 + v3(vc.normal) * h.b2);
    let uv = vec2<f32>(va.u, va.v) * b0 + vec2<f32>(vb.u, vb.v) * h.b1 + vec2<f32>(vc.u, vc.v) * h.b2;
    if HAS_NORMAL_MAP && any(ns != vec3<f32>(0.0)) {
        ns = normal_mapped(tri.material, va, vb, vc, vec3<f32>(b0, h.b1, h.b2), ns, uv);
    }
    if all(ns == vec3<f32>(0.0)) || !is_finite_v3(ns) {
        ns = ng;
    } else if dot3(ns, ng) < 0.0 {
        ns = -ns;
    }
    return SurfaceHit(p, ng, ns, uv, h.slot, tri.scene_tri, tri.material, h.t);
}

// Which Heckbert classes a next-event connection may use at a vertex (cpu ClassMask).
struct ClassMask {
    d: bool,
    g: bool,
}

// What the camera walk knows about the light-tracing strategy (HAS_LT; light_tracing.wgsl
// explains the densities). At vertex xj: prod = Π_{i=1..j-2} p←(xi)/p→(xi), pf_prev = p→(x_{j-1}),
// pf_cur = p→(xj), cos_prev = |ng(x_{j-1})·d| and t_prev = |xj − x_{j-1}|; ok = x1 is not delta.
struct LtMis {
    ok: bool,
    first: bool,
    prod: f32,
    pf_prev: f32,
    pf_cur: f32,
    cos_prev: f32,
    t_prev: f32,
}

// f(wo, wi) of the classes in `mask` (all of them when both are allowed).
fn bsdf_eval_masked(bsdf: Bsdf, wo: vec3<f32>, wi: vec3<f32>, mask: ClassMask, mode: u32) -> vec4<f32> {
    if mask.d && mask.g {
        return bsdf_eval(bsdf, wo, wi, mode);
    }
    let lv = bsdf_eval_lobes(bsdf, wo, wi, mode);
    return select(vec4<f32>(0.0), lv.d, mask.d) + select(vec4<f32>(0.0), lv.g, mask.g);
}

// MIS weight of a next-event estimate towards `ls` (power heuristic against BSDF sampling,
// plus light tracing when HAS_LT: p_t1 / p_s1 = Π_{i=1..j} p←(xi)/p→(xi), xj = this vertex,
// Veach 1997 §10.2).
fn integrator_light_mis(emit_pdf: f32, ls: LightLiSample, hit: SurfaceHit, wo: vec3<f32>, wi: vec3<f32>, bsdf: Bsdf, lt: LtMis) -> f32 {
    if HAS_LT {
        var r_t = 0.0;
        // No light subpath starts at a light at infinity (light_tracing.wgsl `lt_path`).
        if lt.ok && !ls.infinite {
            // `emit_pdf`: the light-side solid-angle density of emitting towards hit.p
            // (`integrator_nee_light`).
            if emit_pdf > 0.0 {
                let to = ls.p_light - hit.p;
                r_t = ratio(emit_pdf * abs(dot3(hit.ng, ls.wi)) / dot3(to, to), lt.pf_cur);
                if !lt.first {
                    let p_back = bsdf_pdf(bsdf, wi, wo) * lt.cos_prev / (lt.t_prev * lt.t_prev);
                    r_t *= lt.prod * ratio(p_back, lt.pf_prev);
                }
            }
        }
        var r_0 = 0.0;
        if !ls.is_delta {
            r_0 = bsdf_pdf(bsdf, wo, wi) / ls.pdf;
        }
        return mis_weight3(r_0, r_t);
    } else if !ls.is_delta {
        return power_heuristic(ls.pdf, bsdf_pdf(bsdf, wo, wi));
    }
    return 1.0;
}

// Where the camera walk samples next-event estimation's light (`integrator_nee_light`): as
// soon as it reaches a vertex, before the BSDF is built, or next to the rest of the estimate.
// The same value either way; what differs is what stays live across light sampling versus
// what is carried across the BSDF. Measured on RADV navi21 (VGPRs, late → first): every
// feature 240 → 216, ior-grid and transmission-roughness 128 → 120, rough-glass and sun-sky
// equal, but cornell-glass 96 → 104, env-spheres 136 → 144, materials 128 → 136 — first pays
// where an image environment's CDF search meets a rough dielectric's evaluation.
override NEE_LIGHT_FIRST: bool = HAS_ENV_IMAGE && HAS_ROUGH_DIELECTRIC;

// The light end of one next-event estimate: a light picked with `ul`, sampled from `p` with
// `ul2` (`ls.valid` false: no estimate), and for the light-tracing MIS (HAS_LT) its emission
// density towards `p` — everything of the estimate that needs the picked `Light`.
struct NeeLight {
    ls: LightLiSample,
    emit_pdf: f32,
}

fn integrator_nee_light(p: vec3<f32>, ul: f32, ul2: vec2<f32>, lt: LtMis) -> NeeLight {
    var nl: NeeLight; // ls.valid = false
    let pick = light_set_pick(ul);
    if pick.prob <= 0.0 {
        return nl;
    }
    nl.ls = light_sample_li(pick.light, p, ul2, pick.prob);
    // No light subpath starts at a light at infinity (light_tracing.wgsl `lt_path`).
    if HAS_LT && nl.ls.valid && lt.ok && !nl.ls.infinite {
        nl.emit_pdf = light_pdf_le(pick.light, pick.prob, nl.ls.n_light, -nl.ls.wi).pdf_dir;
    }
    return nl;
}

// What next-event estimation at a vertex leaves to its shadow ray: the estimate `c` it adds
// when the ray from `o` along `d` (to `tmax`) is unoccluded; `c` zero: nothing to trace.
struct NeeRay {
    c: vec4<f32>,
    o: vec3<f32>,
    d: vec3<f32>,
    tmax: f32,
}

// One next-event estimate at `hit` with the light end `nl`, times the path throughput `beta`,
// MIS-weighted. Twin of `Integrator::sample_light` (plus the light-tracing strategy when
// HAS_LT).
fn integrator_sample_light(nl: NeeLight, hit: SurfaceHit, ng: vec3<f32>, frame: Frame, wo: vec3<f32>, wo_w: vec3<f32>, bsdf: Bsdf, mask: ClassMask, sp: Spectral, lt: LtMis, media: MediumStack, mat: Material, beta: vec4<f32>, pol: PolRow) -> vec4<f32> {
    let r = integrator_nee_ray(nl, hit, ng, frame, wo, wo_w, bsdf, mask, sp, lt, media, mat, beta, pol);
    if all(r.c == vec4<f32>(0.0)) || bvh_occluded(r.o, r.d, r.tmax) {
        return vec4<f32>(0.0);
    }
    return r.c;
}

// The estimate of `integrator_sample_light` and its shadow ray, not traced (the wavefront's
// `wf_nee` hands it to `wf_connect`).
fn integrator_nee_ray(nl: NeeLight, hit: SurfaceHit, ng: vec3<f32>, frame: Frame, wo: vec3<f32>, wo_w: vec3<f32>, bsdf: Bsdf, mask: ClassMask, sp: Spectral, lt: LtMis, media: MediumStack, mat: Material, beta: vec4<f32>, pol: PolRow) -> NeeRay {
    var zero: NeeRay;
    let ls = nl.ls;
    if !ls.valid {
        return zero;
    }
    let li = spectral_c(sp, ls.l);
    let side_o = dot3(wo_w, ng);
    let side_i = dot3(ls.wi, ng);
    let wi = frame_to_local(frame, ls.wi);
    let f = bsdf_eval_masked(bsdf, wo, wi, mask, MODE_RADIANCE);
    // Reflection must stay on the geometric side of wo; transmission must cross it.
    if side_i == 0.0 || max_element4(f) <= 0.0 {
        return zero;
    }
    if !(side_i * side_o > 0.0) && !bsdf_can_transmit(bsdf) {
        return zero;
    }
    // The whole estimate, absorption along the shadow ray included (a light inside absorbing
    // glass), is computed before the shadow ray is traced (the same operations as after it),
    // so that only it stays live across the traversal — not the BSDF, the light sample and
    // the interaction (register pressure).
    let w = integrator_light_mis(nl.emit_pdf, ls, hit, wo, wi, bsdf, lt);
    var fp = f;
    if HAS_POLARIZATION {
        fp = integrator_polarized_f(pol, hit, wo, wo_w, wi, ls.wi, bsdf, mask, f);
    }
    var c = beta * (fp * abs(wi.z) * li * (w / ls.pdf));
    if !ls.infinite {
        let m = medium_towards(media, mat, hit.material, ng, wo_w, ls.wi);
        c *= connection_transmittance(m, length(ls.p_light - hit.p), sp);
    }
    let ray = spawn_ray_to_light(hit.p, ng, side_i, ls);
    return NeeRay(c, ray.o, ray.d, ray.tmax);
}

// The polarised value of a next-event connection (HAS_POLARIZATION): the scalar `f` (of the
// classes in `mask`) turned into the light the sensor's filter passes through the chain
// `pol` (chain.wgsl `pol_through`; the glossy part takes the event's Mueller matrix, the
// diffuse part depolarises). Twin of `polarized_connection` in src/cpu/polarized/walk.rs.
fn integrator_polarized_f(pol: PolRow, hit: SurfaceHit, wo: vec3<f32>, wo_w: vec3<f32>, wi: vec3<f32>, wi_w: vec3<f32>, bsdf: Bsdf, mask: ClassMask, f: vec4<f32>) -> vec4<f32> {
    var f_g = f;
    if HAS_METAL_ROUGH && bsdf.kind == BSDF_METAL_ROUGH {
        f_g = select(vec4<f32>(0.0), bsdf_eval_lobes(bsdf, wo, wi, MODE_RADIANCE).g, mask.g);
    } else if bsdf_class(bsdf) == LOBE_D {
        f_g = vec4<f32>(0.0);
    }
    return pol_through(pol, wo_w, wi_w, hit.ns, bsdf_mueller_b(bsdf, wo, wi), f, f_g);
}

// Beer–Lambert along a connection of length `t` in `medium` (1 outside every medium): the
// twin of the CPU's `medium_transmittance` on NEE shadow rays and BDPT connections.
fn connection_transmittance(medium: u32, t: f32, sp: Spectral) -> vec4<f32> {
    if !HAS_ABSORPTION || medium == NO_MEDIUM {
        return vec4<f32>(1.0);
    }
    return medium_transmittance(materials[medium], t, sp);
}

// A quiet NaN (the film firewall drops and counts it), built at run time.
fn poison() -> vec3<f32> {
    return vec3<f32>(bitcast<f32>(0x7fc00000u + u32(params.width == 0xffffffffu)));
}

// The state of a camera path between vertices (the locals of `Integrator::li`).
struct PathState {
    sp: Spectral,
    // Only the hero wavelength is carried (a dispersive vertex was crossed).
    collapsed: bool,
    l: vec4<f32>,
    beta: vec4<f32>,
    // The ray leaving the last vertex.
    o: vec3<f32>,
    d: vec3<f32>,
    // Solid-angle pdf and delta-ness of the BSDF sample that produced `d`.
    prev_pdf: f32,
    prev_delta: bool,
    // Π η'² of the refractions so far (Russian roulette).
    eta_scale: f32,
    // The media the path is inside (the ray travels in medium_current(media)).
    media: MediumStack,
    // False hits passed (HAS_NESTED), and the distance travelled through them since the
    // last vertex.
    false_hits: u32,
    t_pass: f32,
    depth: u32,
    // Light-tracing MIS state (HAS_LT).
    lt: LtMis,
    // Path-filter state.
    q: u32,
    // The polarised chain's row (HAS_POLARIZATION; chain.wgsl).
    pol: PolRow,
    // sppm: 0 = no gather vertex (or a non-specular vertex since the last), else 1 + the
    // specular vertices since the last gather vertex (`chain` in `Integrator::li_walk`).
    chain: u32,
}

// A camera path leaving the camera along (origin, dir): hero wavelengths first (one
// dimension, spectral kernels), the path filter in state E (reversed DFA reads eye→light).
fn path_state_new(origin: vec3<f32>, dir: vec3<f32>, sampler: ptr<function, Sampler>) -> PathState {
    var ps: PathState;
    if HAS_SPPM {
        ps.sp = photon_spectral();
    } else {
        ps.sp = spectral_new(sampler);
    }
    ps.chain = 0u;
    ps.collapsed = false;
    ps.l = vec4<f32>(0.0);
    ps.beta = vec4<f32>(1.0);
    ps.o = origin;
    ps.d = dir;
    ps.prev_pdf = 0.0;
    ps.prev_delta = true;
    ps.eta_scale = 1.0;
    ps.media = medium_stack_new();
    ps.false_hits = 0u;
    ps.t_pass = 0.0;
    ps.depth = 0u;
    ps.lt = LtMis(HAS_LT, true, 1.0, 0.0, 0.0, 0.0, 0.0);
    ps.q = 0u;
    if HAS_POLARIZATION {
        ps.pol = pol_camera(dir, params.cam_right.xyz, params.polarizer);
    }
    if HAS_FILTER {
        ps.q = dfa_table_step(dfa_table_start(), SYM_E);
    }
    return ps;
}

// Light-tracing MIS bookkeeping on arrival at `hit`: p→ of this vertex (area; 1 after a delta
// vertex), the camera density for x1.
fn lt_mis_arrive(ps: ptr<function, PathState>, hit: SurfaceHit) {
    let d = ps.d;
    let cos_here = abs(dot3(hit.ng, d));
    ps.lt.pf_prev = ps.lt.pf_cur;
    ps.lt.first = ps.depth == 0u;
    ps.lt.t_prev = hit.t;
    if ps.depth == 0u {
        ps.lt.pf_cur = camera_pdf_dir(-dot3(d, params.cam_back.xyz)) * cos_here / (hit.t * hit.t);
    } else if ps.prev_delta {
        ps.lt.pf_cur = 1.0;
    } else {
        ps.lt.pf_cur = ps.prev_pdf * cos_here / (hit.t * hit.t);
    }
}

// The throughput `beta` of unpolarised light arriving along the path's current segment
// behind the sensor's filter: times the chain row's r₀ (HAS_POLARIZATION; chain.wgsl).
fn integrator_polarized(ps: ptr<function, PathState>, beta: vec4<f32>) -> vec4<f32> {
    if HAS_POLARIZATION {
        return beta * pol_lanes(ps.pol).i;
    }
    return beta;
}

// The ray escaped: the environment image, MIS-weighted against next-event estimation (the
// only other strategy that reaches it: lt+pt starts no light subpath at infinity); else
// the uniform environment (not light-sampled, so MIS weight 1). Twin of the escape in
// `Integrator::li` (`LightSet::env_weight`). With sppm the image emits photons, so light
// reached from a gather vertex through specular vertices only is theirs (`environment_emits`).
fn integrator_add_escaped(ps: ptr<function, PathState>) {
    let env = light_set_environment();
    if env.prob > 0.0 && sppm_leaves_out(ps.chain) {
        return;
    }
    if env.prob > 0.0 && integrator_accepts_light(ps.q) {
        let le = light_le(env.light, vec3<f32>(0.0), vec3<f32>(0.0), -ps.d);
        var w = 1.0;
        if !ps.prev_delta {
            let p_light = light_pdf_li(env.light, env.prob, 1.0, vec3<f32>(0.0), ps.d);
            w = power_heuristic(ps.prev_pdf, p_light);
        }
        ps.l += integrator_polarized(ps, ps.beta) * spectral_c(ps.sp, le) * w;
        return;
    }
    if HAS_ENVIRONMENT && integrator_accepts_light(ps.q) {
        let le = light_le(light_environment(params.environment.xyz), vec3<f32>(0.0), vec3<f32>(0.0), ps.d);
        ps.l += integrator_polarized(ps, ps.beta) * spectral_c(ps.sp, le);
    }
}

// A BSDF-sampled ray hit an emitter (s = 0): its radiance, MIS-weighted against next-event
// estimation (s = 1) and light tracing (t = 1; needs k ≥ 2 and x1 non-delta).
fn integrator_add_emitted(ps: ptr<function, PathState>, hit: SurfaceHit, mat: Material) {
    if !HAS_LIGHTS || (mat.flags & MAT_EMISSIVE) == 0u || !integrator_accepts_light(ps.q) {
        return;
    }
    if sppm_leaves_out(ps.chain) {
        return; // the photons' path L S+ D … (photon.wgsl)
    }
    let d = ps.d;
    let area = light_set_area(hit.slot);
    let le = light_le(area.light, hit.p, hit.ng, -d);
    if all(le == vec3<f32>(0.0)) {
        return; // one-sided emitter seen from behind
    }
    var w = 1.0;
    if HAS_LT {
        // Ratios of next-event estimation and light tracing to this BSDF-sampled hit.
        var r_1 = 0.0;
        if !ps.prev_delta {
            r_1 = light_pdf_li(area.light, area.prob, hit.t, hit.ng, d) / ps.prev_pdf;
        }
        var r_t = 0.0;
        let lt = ps.lt;
        if lt.ok && ps.depth >= 1u {
            let pe = light_pdf_le(area.light, area.prob, hit.ng, -d);
            let p_back = pe.pdf_dir * lt.cos_prev / (hit.t * hit.t);
            r_t = lt.prod * ratio(p_back, lt.pf_prev) * ratio(pe.pdf_pos, lt.pf_cur);
        }
        w = mis_weight3(r_1, r_t);
    } else if !ps.prev_delta {
        w = power_heuristic(ps.prev_pdf, light_pdf_li(area.light, area.prob, hit.t, hit.ng, d));
    }
    ps.l += integrator_polarized(ps, ps.beta) * spectral_c(ps.sp, le) * w;
}

// The IOR the path sees at `mat` with `enclosing` on its far side (`interface_eta`): a
// dispersive interface refracts the hero wavelength, and from then on only the hero lane is
// carried (`spectral_collapse`).
fn integrator_eta(ps: ptr<function, PathState>, mat: Material, enclosing: u32) -> f32 {
    let ie = interface_eta(mat, enclosing, ps.sp);
    if ie.dispersive && !ps.collapsed {
        ps.beta = spectral_collapse(ps.beta);
        ps.collapsed = true;
    }
    return ie.eta;
}

// The light-tracing MIS density p←(x_{j-1}) of the BSDF sample `b` at `hit`: the vertex
// sampling its predecessor (1 for a delta sample; only read from the second vertex on).
fn integrator_p_back(ps: ptr<function, PathState>, hit: SurfaceHit, bsdf: Bsdf, wo: vec3<f32>, b: Bounce) -> f32 {
    var p_back = 1.0;
    if HAS_LT && ps.depth >= 1u && b.step == STEP_CONTINUE && !b.s.is_delta {
        p_back = bsdf_pdf(bsdf, b.s.wi, wo) * ps.lt.cos_prev / (hit.t * hit.t);
    }
    return p_back;
}

// Continue the path with the BSDF sample `b` taken at `hit` (PBR 4th ed. §13.4
// `PathIntegrator::Li`, "Sample BSDF to get new path direction"): throughput, filter state,
// light-tracing MIS bookkeeping (`p_back` from `integrator_p_back`), medium and the next ray.
// `integrator_li` applies it before next-event estimation at the same vertex, which then
// reads the state from before (register pressure: see there).
fn integrator_scatter(ps: ptr<function, PathState>, hit: SurfaceHit, mat: Material, ng: vec3<f32>, b: Bounce, p_back: f32) -> u32 {
    if b.step != STEP_CONTINUE {
        return b.step; // STEP_POISON: the firewall drops and counts the sample
    }
    let s = b.s;
    let wi_w = b.wi_w;
    let side_i = b.side_i;
    if HAS_FILTER {
        ps.q = dfa_table_step(ps.q, s.lobe + 1u);
        if !dfa_table_can_reach_accept(ps.q) {
            return STEP_BREAK; // nothing this path can still reach counts
        }
    }
    ps.beta *= s.weight;
    if HAS_LT {
        if ps.depth >= 1u {
            // p←(x_{j-1}): this vertex samples the previous one (1 if delta).
            ps.lt.prod *= ratio(p_back, ps.lt.pf_prev);
        } else if s.is_delta {
            ps.lt.ok = false; // x1 is delta: light tracing cannot connect it to the camera
        }
        ps.lt.cos_prev = abs(dot3(hit.ng, wi_w));
    }
    if s.event == EVENT_TRANSMIT {
        ps.eta_scale *= s.eta_rel * s.eta_rel;
        ps.media = medium_after_transmit(ps.media, mat, hit.material, wi_w, hit.ng);
    }
    ps.prev_pdf = s.pdf;
    ps.prev_delta = s.is_delta;
    ps.o = offset_ray_origin_towards(hit.p, ng, side_i);
    ps.d = wi_w;
    ps.depth++;
    let rec = DEBUG_STRIDE * min(ps.depth - 1u, DEBUG_MAX_VERTICES - 1u);
    debug_write(2u + rec, vec4<f32>(ps.beta.xyz, f32(ps.depth)));
    debug_write(3u + rec, vec4<f32>(ps.d, f32(hit.scene_tri)));
    return STEP_CONTINUE;
}

// The BSDF sample at `hit` (random numbers uc, u2 in `u`) and the path continued with it
// (`integrator_scatter`), its polarised chain too (HAS_POLARIZATION: the event's Mueller
// matrix, chain.wgsl `pol_scatter`); the step `integrator_scatter` returns.
fn integrator_bounce(ps: ptr<function, PathState>, hit: SurfaceHit, mat: Material, ng: vec3<f32>, bsdf: Bsdf, frame: Frame, wo_w: vec3<f32>, wo: vec3<f32>, u: vec3<f32>) -> u32 {
    let bounce = interaction_sample(bsdf, frame, ng, wo_w, wo, u.x, u.yz, MODE_RADIANCE);
    let p_back = integrator_p_back(ps, hit, bsdf, wo, bounce);
    let step = integrator_scatter(ps, hit, mat, ng, bounce, p_back);
    if HAS_POLARIZATION && step == STEP_CONTINUE {
        let m = bsdf_mueller(bsdf, wo, bounce.s.wi, bounce.s.event, bounce.s.lobe);
        ps.pol = pol_scatter(ps.pol, wo_w, bounce.wi_w, hit.ns, m);
    }
    return step;
}

// Radiance along the camera ray (origin, dir) — one path sample, RGB. Twin of `Integrator::li`.
fn integrator_li(origin: vec3<f32>, dir: vec3<f32>, sampler: ptr<function, Sampler>) -> vec3<f32> {
    var ps = path_state_new(origin, dir, sampler);
    loop {
        let h = bvh_intersect(ps.o, ps.d, F32_MAX);
        segments++;
        let v = integrator_vertex(&ps, sampler, h, WALK_WHOLE);
        if v == VERTEX_POISON {
            return poison();
        }
        if v == VERTEX_END {
            break;
        }
    }
    if HAS_POLARIZATION {
        // The intensity a filter passes is ≥ 0 (`li_polarized` clamps per lane too).
        return spectral_to_rgb(ps.sp, max(ps.l, vec4<f32>(0.0)));
    }
    return spectral_to_rgb(ps.sp, ps.l);
}

// What `integrator_vertex` does at the vertex: all of it, next-event estimation with its
// shadow ray included (the megakernel `render`); all but next-event estimation (the
// wavefront's `wf_shade`); only next-event estimation, untraced, into `NEE_RAY`, on a copy of
// the state (`wf_nee`).
const WALK_WHOLE: u32 = 0u;
const WALK_SHADE: u32 = 1u;
const WALK_NEE: u32 = 2u;

// How the path goes on after `integrator_vertex`: along (ps.o, ps.d); it ended; or its sample
// is poisoned (the firewall drops and counts it).
const VERTEX_NEXT: u32 = 0u;
const VERTEX_END: u32 = 1u;
const VERTEX_POISON: u32 = 2u;

// `WALK_NEE`'s result (c = 0: no estimate at this vertex).
var<private> NEE_RAY: NeeRay;

// The path in `ps` arriving at the closest hit `h` of its ray (not found: escaped) — one turn
// of the loop of `Integrator::li`.
fn integrator_vertex(ps: ptr<function, PathState>, sampler: ptr<function, Sampler>, h: Hit, mode: u32) -> u32 {
    if !h.found {
        if mode != WALK_NEE {
            integrator_add_escaped(ps);
        }
        return VERTEX_END;
    }
    var hit = integrator_surface(h);
    let medium = medium_current(ps.media);
    if HAS_ABSORPTION && medium != NO_MEDIUM {
        ps.beta *= medium_transmittance(materials[medium], hit.t, ps.sp);
    }
    let mat = materials[hit.material];
    var enclosing = NO_MEDIUM;
    if HAS_NESTED {
        let c = medium_interface(ps.media, mat, hit.material, ps.d, hit.ng);
        if !c.real {
            // A false hit: no vertex, no bounce; the ray continues past it.
            ps.media = c.after;
            ps.false_hits++;
            if ps.false_hits > FALSE_HIT_LIMIT {
                return VERTEX_END;
            }
            ps.t_pass += hit.t;
            ps.o = offset_ray_origin_towards(hit.p, hit.ng, dot3(ps.d, hit.ng));
            return VERTEX_NEXT;
        }
        enclosing = c.enclosing;
        hit.t += ps.t_pass;
        ps.t_pass = 0.0;
    }
    let front = dot3(ps.d, hit.ng) < 0.0;
    if HAS_LT {
        lt_mis_arrive(ps, hit);
    }
    if mode != WALK_NEE {
        integrator_add_emitted(ps, hit, mat);
    }
    debug_write(1u + DEBUG_STRIDE * min(ps.depth, DEBUG_MAX_VERTICES - 1u), vec4<f32>(hit.p, hit.t));
    if ps.depth + 1u >= params.max_depth {
        return VERTEX_END;
    }
    let on = orient_normals(mat, hit, front);
    if !on.ok {
        return VERTEX_END;
    }
    if (mat.flags & MAT_BLACK_EMITTER) != 0u {
        return VERTEX_END; // emitters are black surfaces otherwise
    }
    let uc = sampler_next_1d(sampler);
    let u2 = sampler_next_2d(sampler);
    let ul = sampler_next_1d(sampler);
    let ul2 = sampler_next_2d(sampler);
    // Next-event estimation's light sample, taken before the BSDF is built: across light
    // sampling (every light type, the environment image's CDF search) only the path and
    // the hit are live, and only the sample is carried on (register pressure).
    let mask = ClassMask(integrator_accepts_light(integrator_step(ps.q, SYM_D)), integrator_accepts_light(integrator_step(ps.q, SYM_G)));
    let delta = bsdf_kind_is_delta(mat.bsdf);
    let nee = (HAS_LIGHTS || HAS_PUNCTUAL || HAS_ENV_IMAGE) && !delta && params.light_count > 0u && (mask.d || mask.g) && mode != WALK_SHADE;
    var nl: NeeLight;
    if nee && NEE_LIGHT_FIRST {
        nl = integrator_nee_light(hit.p, ul, ul2, ps.lt);
    }
    let eta = integrator_eta(ps, mat, enclosing);
    let bsdf = material_bsdf(mat, hit.uv, eta, ps.sp);
    let frame = frame_from_normal(on.ns);
    let wo_w = -ps.d;
    let wo = frame_to_local(frame, wo_w);

    // Photon-mapped caustics at a diffuse vertex (HAS_SPPM, photon.wgsl).
    let gathered = sppm_is_gather_vertex(bsdf, ps.depth);
    if gathered && mode != WALK_NEE {
        let g = GatherPoint(hit.p, on.ng, on.ns, frame, wo, ps.depth, ps.q, ps.collapsed, photon_radius());
        ps.l += ps.beta * photon_gather(g, bsdf);
    }

    // BSDF sampling, applied to the path before next-event estimation runs at this
    // vertex with the state from before it (throughput, filter state, light-tracing MIS
    // and media): the CPU's operations on the same random numbers (the CPU estimates
    // first; the values are the same), but across the shadow ray only the continued path
    // and the estimate stay live, not the BSDF, the sample and the interaction (register
    // pressure; see README "Register pressure").
    let before = *ps;
    var step = STEP_CONTINUE;
    if mode != WALK_NEE {
        step = integrator_bounce(ps, hit, mat, on.ng, bsdf, frame, wo_w, wo, vec3<f32>(uc, u2));
    }

    // Next-event estimation.
    if nee {
        if !NEE_LIGHT_FIRST {
            nl = integrator_nee_light(hit.p, ul, ul2, before.lt);
        }
        if mode == WALK_NEE {
            NEE_RAY = integrator_nee_ray(nl, hit, on.ng, frame, wo, wo_w, bsdf, mask, before.sp, before.lt, before.media, mat, before.beta, before.pol);
        } else {
            ps.l += integrator_sample_light(nl, hit, on.ng, frame, wo, wo_w, bsdf, mask, before.sp, before.lt, before.media, mat, before.beta, before.pol);
        }
    }
    if mode == WALK_NEE {
        return VERTEX_END; // the caller keeps only NEE_RAY
    }
    if step == STEP_POISON {
        return VERTEX_POISON;
    }
    if step == STEP_BREAK {
        return VERTEX_END;
    }
    if HAS_SPPM {
        ps.chain = sppm_chain_next(ps.chain, gathered, delta);
    }
    let q_rr = russian_roulette(ps.beta, ps.eta_scale, ps.depth, sampler);
    if q_rr <= 0.0 {
        return VERTEX_END;
    }
    ps.beta /= q_rr;
    return VERTEX_NEXT;
}

// A sample is accepted only if every component is finite and non-negative (film::sample_is_valid).
// Spectral scenes keep out-of-gamut (negative) single-wavelength estimates (Film::add_signed_to).
fn sample_is_valid(v: vec3<f32>) -> bool {
    if HAS_SPECTRAL {
        return is_finite_v3(v);
    }
    return is_finite_v3(v) && min(min(v.x, v.y), v.z) >= 0.0;
}

// Camera ray through the film point (sx, sy) ∈ [0,1]², (0,0) = top-left. Twin of `Camera::ray_dir`.
fn camera_ray_dir(sx: f32, sy: f32) -> vec3<f32> {
    let tan_half = params.cam_pos.w;
    let aspect = params.cam_right.w;
    let x = (2.0 * sx - 1.0) * tan_half * aspect;
    let y = (1.0 - 2.0 * sy) * tan_half;
    // rotation · (x, y, −1), glam's column order.
    let v = params.cam_right.xyz * x + params.cam_up.xyz * y + params.cam_back.xyz * -1.0;
    return normalize3(v);
}

@compute @workgroup_size(8, 8, 1)
fn render(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(local_invocation_index) lane: u32,
) {
    LANE = lane;
    OFFSET_SCALE = params.offset_scale;
    segments = 0u;
    var dropped = 0u;
    // Invocations past the image edge do no work but still take part in the reduction.
    let y = gid.y + params.tile_y0;
    if gid.x < params.width && y < params.height {
        dropped = render_pixel(gid.x, y);
    }
    add_counters_workgroup(dropped, segments);
}

// The batch of camera paths of pixel (x, y), folded into the running mean; returns the
// samples dropped (non-finite or negative).
fn render_pixel(x: u32, y: u32) -> u32 {
    let w = params.width;
    let h = params.height;
    let pixel = y * w + x;
    var sum = vec3<f32>(0.0);
    var dropped = 0u;
    for (var k = 0u; k < params.batch; k++) {
        let s = params.sample_offset + k;
        debug_on = pixel == params.debug_pixel && k == 0u;
        if HAS_SPPM {
            SPPM_ITER = k;
        }
        var sampler = sampler_new(pixel, s, params.seed);
        let j = sampler_next_2d(&sampler);
        let sx = (f32(x) + j.x) / f32(w);
        let sy = (f32(y) + j.y) / f32(h);
        let dir = camera_ray_dir(sx, sy);
        debug_write(0u, vec4<f32>(dir, 0.0));
        let v = integrator_li(params.cam_pos.xyz, dir, &sampler);
        debug_write(1u + DEBUG_STRIDE * DEBUG_MAX_VERTICES, vec4<f32>(v, f32(sampler.dim)));
        if sample_is_valid(v) {
            sum += v;
        } else {
            dropped++;
        }
    }
    film_fold(pixel, sum);
    return dropped;
}

// Fold the sum of a pixel's batch of camera samples (plus, with light tracing, the batch's
// splats on it) into the running mean without drift: mean·n/(n+k) + Σ/(n+k).
fn film_fold(pixel: u32, camera_sum: vec3<f32>) {
    var sum = camera_sum;
    if HAS_LT {
        // This batch's light-tracing splats (k light paths per pixel, like the camera paths).
        let lt_sum = splat_take(pixel);
        if is_finite_v3(lt_sum) {
            sum += lt_sum;
        }
    }
    let slot = pixel - params.film_y0 * params.width;
    let old = accum[slot];
    accum[slot] = vec4<f32>(old.xyz * params.w_old + sum * params.w_new, 1.0);
}
