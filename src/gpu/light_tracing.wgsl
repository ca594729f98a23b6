// light_tracing.wgsl — light tracing (the t = 1 strategy of Veach 1997, §10.2) combined with
// the path tracer's two strategies (s = 0: a BSDF-sampled ray hits the light; s = 1: next-event
// estimation) by multiple importance sampling, the GPU estimator `lt+pt`.
//
// Each thread traces one light subpath y0 (on a light) … ym per sample and connects every
// non-delta surface vertex to the pinhole camera. The contribution is splatted into a
// fixed-point film (`splats`, two u32 atomics per channel forming a 64-bit counter in units of
// 2⁻²⁰; WGSL has no float atomics) that the `render` kernel folds into the running mean after
// the same batch's camera paths (integrator.wgsl, HAS_LT).
//
// MIS (power heuristic, Veach 1997 §9.2.4) over three strategies for a path x0 (camera) … xk
// (light), with area densities p→(xi) of the camera-side walk and p←(xi) of the light-side walk:
//   p_s0 = Π_{i=1..k} p→(xi)
//   p_s1 = Π_{i=1..k-1} p→(xi) · p_light(xk)              (needs x_{k-1} non-delta)
//   p_t1 = p_light(xk) · Π_{i=1..k-1} p←(xi)              (needs x1 non-delta)
// Both kernels evaluate the same ratios from their own side with running products, like the
// recursive MIS of Georgiev et al. 2012 ("Light Transport Simulation with Vertex Connection and
// Merging", tech. report "Implementing VCM") restricted to these three strategies. Vertices
// sampled from a delta vertex get density 1 on both sides (the delta factors cancel; PBR 3rd ed.
// §16.3.5 `remap0`), so the weights sum to one for every path that more than one strategy can
// make. Russian roulette is not part of the densities (it stays unbiased).
//
// Importance transport uses the adjoint BSDF (`MODE_IMPORTANCE`: no 1/η² on refraction) and the
// shading-normal correction |ωo·ns||ωi·ng| / (|ωo·ng||ωi·ns|) (Veach 1997, eq. 5.19).
// Dispersion: the light subpath samples its own hero wavelengths (Wilkie et al. 2014) and, like
// the camera walk, keeps only the hero lane (×4) from the first dispersive vertex on; the
// wavelength density is the same for both walks, so it cancels in the MIS ratios.

@group(0) @binding(10) var<storage, read_write> splats: array<atomic<u32>>;

// Fixed point: 2²⁰ steps per unit of radiance; one splat may carry up to SPLAT_MAX.
const SPLAT_SCALE: f32 = 1048576.0;
const SPLAT_MAX: f32 = 1.0e6;
const TWO_POW_32: f32 = 4294967296.0;
// Largest f32 below 2³² (u32 conversion of anything larger is undefined).
const U32_MAX_F: f32 = 4294967040.0;
// Stream separation between camera and light subpaths of the same (pixel, sample).
const LT_SEED_MIX: u32 = 0x9e3779b9u;

// The splat film's slot of image pixel `pixel`: the film starts at image row film_y0 (0 unless
// the image renders in tiles); pixels above it wrap to slots past the film's end.
fn splat_slot(pixel: u32) -> u32 {
    return pixel - params.film_y0 * params.width;
}

// Add v (|v| ≤ SPLAT_MAX per channel) to pixel `pixel` of the splat film. Each channel is a
// signed 64-bit two's-complement sum (lo, hi): adding −x is adding 2⁶⁴ − x, i.e. lo' = −x_lo
// with the carry out of lo into hi and hi' = ¬x_hi (+1 when x_lo = 0), all mod 2³². Spectral
// (hero-wavelength) samples can be negative in RGB, hence the sign.
fn splat_add(pixel: u32, v: vec3<f32>) {
    // A tiled image's film holds rows film_y0 .. of the image only: a splat on a pixel outside
    // them belongs to another tile's pass (which traces the same light subpaths) and is left.
    let slot = splat_slot(pixel);
    if slot >= arrayLength(&splats) / 6u {
        return;
    }
    for (var c = 0u; c < 3u; c++) {
        let x = abs(v[c]) * SPLAT_SCALE;
        if !(x > 0.0) {
            continue;
        }
        let hi_f = floor(x / TWO_POW_32);
        var lo = u32(min(x - hi_f * TWO_POW_32 + 0.5, U32_MAX_F));
        var hi = u32(hi_f);
        if v[c] < 0.0 {
            // two's complement of (hi, lo)
            hi = ~hi;
            lo = ~lo + 1u;
            if lo == 0u {
                hi += 1u;
            }
        }
        let i = (slot * 3u + c) * 2u;
        let old = atomicAdd(&splats[i], lo);
        if old + lo < old {
            atomicAdd(&splats[i + 1u], 1u);
        }
        if hi != 0u {
            atomicAdd(&splats[i + 1u], hi);
        }
    }
}

// Take (read and clear) the splats of `pixel`: Σ of this batch's light-tracing contributions.
fn splat_take(pixel: u32) -> vec3<f32> {
    let slot = splat_slot(pixel);
    var out = vec3<f32>(0.0);
    for (var c = 0u; c < 3u; c++) {
        let i = (slot * 3u + c) * 2u;
        let lo = atomicExchange(&splats[i], 0u);
        let hi = atomicExchange(&splats[i + 1u], 0u);
        out[c] = (f32(bitcast<i32>(hi)) * TWO_POW_32 + f32(lo)) / SPLAT_SCALE;
    }
    return out;
}

// Area of the image plane at distance 1.
fn camera_a_plane() -> f32 {
    let tan_half = params.cam_pos.w;
    return 4.0 * tan_half * tan_half * params.cam_right.w;
}

// Solid-angle density of a primary ray at angle θ to the view axis (uniform on the image
// plane): 1 / (A_plane cos³θ). PBR 3rd ed. §16.1.1 (`PerspectiveCamera::Pdf_We`).
fn camera_pdf_dir(cos_theta: f32) -> f32 {
    return 1.0 / (camera_a_plane() * cos_theta * cos_theta * cos_theta);
}

struct Raster {
    ok: bool,
    pixel: u32,
    cos_theta: f32,
}

// The pixel a direction `w` from the camera lands in (inverse of `camera_ray_dir`).
fn camera_raster(w: vec3<f32>) -> Raster {
    let lx = dot3(w, params.cam_right.xyz);
    let ly = dot3(w, params.cam_up.xyz);
    let lz = dot3(w, params.cam_back.xyz);
    if lz >= 0.0 {
        return Raster(false, 0u, 0.0);
    }
    let tan_half = params.cam_pos.w;
    let x = lx / -lz / (tan_half * params.cam_right.w);
    let y = ly / -lz / tan_half;
    let sx = 0.5 * (x + 1.0);
    let sy = 0.5 * (1.0 - y);
    if !(sx >= 0.0 && sx < 1.0 && sy >= 0.0 && sy < 1.0) {
        return Raster(false, 0u, 0.0);
    }
    let px = min(u32(sx * f32(params.width)), params.width - 1u);
    let py = min(u32(sy * f32(params.height)), params.height - 1u);
    return Raster(true, py * params.width + px, -lz / sqrt(lx * lx + ly * ly + lz * lz));
}

// Veach 1997, eq. 5.19: |ωo·ns||ωi·ng| / (|ωo·ng||ωi·ns|) (twin of `bdpt::shading_correction`).
fn shading_correction(wo: vec3<f32>, wi: vec3<f32>, ns: vec3<f32>, ng: vec3<f32>) -> f32 {
    let num = abs(dot3(wo, ns)) * abs(dot3(wi, ng));
    let den = abs(dot3(wo, ng)) * abs(dot3(wi, ns));
    if den <= 0.0 {
        return 0.0;
    }
    return num / den;
}

// Heckbert classes of the light subpath's surface vertices y1 … y64, two bits each (D=1, G=2,
// S=3), so the eye→light DFA can read the full string at a camera connection.
struct SymString {
    w: array<u32, 4>,
}

const LT_MAX_SYMBOLS: u32 = 64u;

fn sym_get(s: SymString, j: u32) -> u32 {
    return (s.w[(j - 1u) / 16u] >> (2u * ((j - 1u) % 16u))) & 3u;
}

// Does E · class(ym) · class(y_{m-1}) … class(y1) · L pass the filter (read eye→light)?
fn lt_accepts(s: SymString, m: u32, cls: u32) -> bool {
    var q = dfa_table_step(dfa_table_step(dfa_table_start(), SYM_E), cls);
    for (var j = m - 1u; j >= 1u; j--) {
        q = dfa_table_step(q, sym_get(s, j));
    }
    return dfa_table_is_accepting(dfa_table_step(q, SYM_L));
}

// State of a light subpath at its current vertex ym (m ≥ 1).
struct LightWalk {
    // Light-side throughput (importance) in the path's colour lanes.
    beta: vec4<f32>,
    // Only the hero wavelength is carried (a dispersive vertex was crossed).
    collapsed: bool,
    m: u32,
    // p_light(y0): pick/area (area light) or pick (punctual).
    p_light: f32,
    area_light: bool,
    // |n(y0)·ω0|, cosine at the light of the first segment.
    cos_emit: f32,
    // p←-side (light walk) area densities of y_{m-1} and ym.
    pl_prev: f32,
    pl_cur: f32,
    // |ng(y_{m-1})·d| on the segment y_{m-1} → ym, and its squared length.
    cos_prev: f32,
    t2: f32,
    // Π_{j=1..m-2} pC(yj)/pL(yj): camera-side over light-side densities of earlier vertices.
    prod: f32,
    // Camera-side density of y0 (sampled from y1), known once y1 scattered.
    pc_y0: f32,
    y1_delta: bool,
    syms: SymString,
    // The ray leaving ym (y0 before the first hit), the solid-angle pdf and delta-ness of the
    // sample that produced it, and |ng(ym)·d| at its start.
    o: vec3<f32>,
    d: vec3<f32>,
    prev_pdf: f32,
    prev_delta: bool,
    cos_out: f32,
    // The media the walk is inside (HAS_NESTED: false hits passed, distance through them).
    media: MediumStack,
    false_hits: u32,
    t_pass: f32,
}

// The light subpath leaving the emitted ray `le` of `light`: β1 = Le cosθ / (p_light p_dir)
// (area lights; cosθ = 1 on the bounding disk of a light at infinity), I / (p_light p_dir)
// (punctual). Veach 1997 §10.2; PBR 3rd ed. §16.3.1 (`GenerateLightSubpath`).
fn light_walk_new(light: Light, le: LightLeSample, sp: Spectral) -> LightWalk {
    var lw: LightWalk;
    lw.collapsed = false;
    lw.m = 0u;
    lw.prod = 1.0;
    lw.pl_prev = 0.0;
    lw.pl_cur = 0.0;
    lw.pc_y0 = 0.0;
    lw.y1_delta = false;
    lw.syms = SymString(array<u32, 4>(0u, 0u, 0u, 0u));
    lw.p_light = le.pdf_pos;
    lw.area_light = !le.delta_pos;
    lw.cos_emit = le.cos_n;
    if le.delta_pos {
        lw.beta = spectral_c(sp, le.l) / (lw.p_light * le.pdf_dir);
    } else {
        lw.beta = spectral_c(sp, le.l) * (le.cos_n / (lw.p_light * le.pdf_dir));
    }
    lw.o = light_le_sample_origin(light, le);
    lw.d = le.dir;
    lw.prev_pdf = le.pdf_dir;
    lw.prev_delta = false;
    lw.cos_out = lw.cos_emit;
    lw.media = medium_stack_new();
    lw.false_hits = 0u;
    lw.t_pass = 0.0;
    return lw;
}

// Beer–Lambert over a segment of length `t` in the walk's medium.
fn light_walk_attenuate(lw: ptr<function, LightWalk>, t: f32, sp: Spectral) {
    let medium = medium_current(lw.media);
    if HAS_ABSORPTION && medium != NO_MEDIUM {
        lw.beta *= medium_transmittance(materials[medium], t, sp);
    }
}

// What a light walk's ray met at `hit` among nested media (only with HAS_NESTED): a real
// interface (`enclosing` set to the medium around it, `hit.t` extended by the false hits
// passed since the last vertex), a false hit the walk has moved past (no vertex), or a walk
// lost after FALSE_HIT_LIMIT false hits. Shared by `lt_vertex` and `photon_trace`.
const WALK_HIT_REAL: u32 = 0u;
const WALK_HIT_PASSED: u32 = 1u;
const WALK_HIT_LOST: u32 = 2u;

fn light_walk_interface(lw: ptr<function, LightWalk>, mat: Material, hit: ptr<function, SurfaceHit>, enclosing: ptr<function, u32>) -> u32 {
    let c = medium_interface(lw.media, mat, hit.material, lw.d, hit.ng);
    if !c.real {
        lw.media = c.after;
        lw.false_hits++;
        if lw.false_hits > FALSE_HIT_LIMIT {
            return WALK_HIT_LOST;
        }
        lw.t_pass += hit.t;
        lw.o = offset_ray_origin_towards(hit.p, hit.ng, dot3(lw.d, hit.ng));
        return WALK_HIT_PASSED;
    }
    *enclosing = c.enclosing;
    hit.t += lw.t_pass;
    lw.t_pass = 0.0;
    return WALK_HIT_REAL;
}

// Arrival at ym = `hit` (hit.t: the distance from y_{m-1}): the light-side density of ym
// (1 after a delta vertex).
fn light_walk_arrive(lw: ptr<function, LightWalk>, hit: SurfaceHit, sp: Spectral) {
    lw.m += 1u;
    let t2 = hit.t * hit.t;
    lw.pl_prev = lw.pl_cur;
    if lw.prev_delta {
        lw.pl_cur = 1.0;
    } else {
        lw.pl_cur = lw.prev_pdf * abs(dot3(hit.ng, lw.d)) / t2;
    }
    lw.cos_prev = lw.cos_out;
    lw.t2 = t2;
}

// Connect light vertex ym (non-delta BSDF `bsdf` at `hit`) to the camera and splat its
// MIS-weighted contribution. Returns 1 if the value was rejected by the firewall.
// `dispersive`: ym's BSDF depends on the wavelength (the contribution keeps the hero lane).
fn lt_connect(lw: LightWalk, hit: SurfaceHit, mat: Material, ng: vec3<f32>, ns: vec3<f32>, frame: Frame, wo_w: vec3<f32>, wo: vec3<f32>, bsdf: Bsdf, sp: Spectral, dispersive: bool) -> u32 {
    let s = lt_splat(lw, hit, mat, ng, ns, frame, wo_w, wo, bsdf, sp, dispersive);
    if !s.ok || bvh_occluded(s.origin, params.cam_pos.xyz - s.origin, 1.0) {
        return 0u;
    }
    return lt_splat_add(s);
}

// A light vertex's connection to the camera, computed up to its shadow ray: the MIS-weighted
// value `v` for film pixel `pixel` if the ray from `origin` to the camera is unoccluded
// (ok = false: no connection).
struct LtSplat {
    ok: bool,
    pixel: u32,
    origin: vec3<f32>,
    v: vec3<f32>,
}

// Splat `s` (its shadow ray unoccluded) after the film firewall (sample_is_valid: spectral
// estimates may be negative in RGB) and the fixed-point range; 1 if rejected.
fn lt_splat_add(s: LtSplat) -> u32 {
    if !sample_is_valid(s.v) || max_element3(abs(s.v)) > SPLAT_MAX {
        return 1u;
    }
    splat_add(s.pixel, s.v);
    return 0u;
}

// The connection of `lt_connect` without its shadow ray (the wavefront's `lt_shade` hands it
// to `lt_connect_splat`). The value is computed before the ray is traced: the same
// operations as after it.
fn lt_splat(lw: LightWalk, hit: SurfaceHit, mat: Material, ng: vec3<f32>, ns: vec3<f32>, frame: Frame, wo_w: vec3<f32>, wo: vec3<f32>, bsdf: Bsdf, sp: Spectral, dispersive: bool) -> LtSplat {
    var none: LtSplat;
    let to_cam = params.cam_pos.xyz - hit.p;
    let d2 = dot3(to_cam, to_cam);
    if !(d2 > 0.0) {
        return none;
    }
    let wc = to_cam / sqrt(d2);
    let r = camera_raster(-wc);
    if !r.ok {
        return none;
    }
    let side_o = dot3(wo_w, ng);
    let side_i = dot3(wc, ng);
    if side_i == 0.0 || (!(side_o * side_i > 0.0) && !bsdf_can_transmit(bsdf)) {
        return none;
    }
    let wi = frame_to_local(frame, wc);
    var f: vec4<f32>;
    if HAS_FILTER {
        let lv = bsdf_eval_lobes(bsdf, wo, wi, MODE_IMPORTANCE);
        f = select(vec4<f32>(0.0), lv.d, lt_accepts(lw.syms, lw.m, SYM_D)) + select(vec4<f32>(0.0), lv.g, lt_accepts(lw.syms, lw.m, SYM_G));
    } else {
        f = bsdf_eval(bsdf, wo, wi, MODE_IMPORTANCE);
    }
    if !(max_element4(f) > 0.0) {
        return none;
    }
    // We·G for a pinhole with the adjoint shading correction: |ωc·ns|·corr / (d² A cos³θ)
    // = |ωc·ng| |ωo·ns| / (|ωo·ng| d² A cos³θ).
    let corr_cos = ratio(abs(dot3(wc, ng)) * abs(dot3(wo_w, ns)), abs(dot3(wo_w, ng)));
    let c = r.cos_theta;
    let we_g = corr_cos / (d2 * camera_a_plane() * c * c * c);
    var v4 = lw.beta * f * we_g;
    if !lw.collapsed && dispersive {
        v4 = spectral_collapse(v4);
    }
    if !(max_element4(v4) > 0.0) {
        return none;
    }
    let origin = offset_ray_origin_towards(hit.p, ng, side_i);
    // Absorption along the connection to the camera (a camera inside absorbing glass).
    v4 *= connection_transmittance(medium_towards(lw.media, mat, hit.material, ng, wo_w, wc), sqrt(d2), sp);
    // MIS: densities of the other strategies relative to this one (p_t1).
    let pc_m = camera_pdf_dir(c) * abs(dot3(ng, wc)) / d2;
    let pc_back = bsdf_pdf(bsdf, wi, wo);
    var l: f32;
    var pc0: f32;
    if lw.m == 1u {
        l = ratio(pc_m, lw.pl_cur);
        pc0 = pc_back * lw.cos_emit / lw.t2;
    } else {
        l = lw.prod * ratio(pc_back * lw.cos_prev / lw.t2, lw.pl_prev) * ratio(pc_m, lw.pl_cur);
        pc0 = lw.pc_y0;
    }
    var r_s1 = l;
    if lw.y1_delta && lw.m > 1u {
        r_s1 = 0.0;
    }
    var r_s0 = 0.0;
    if lw.area_light {
        r_s0 = l * ratio(pc0, lw.p_light);
    }
    var v = v4.xyz;
    if HAS_SPECTRAL && sp.on {
        v = spectrum_sample_to_rgb(sp.lambdas, v4);
    }
    v *= mis_weight3(r_s0, r_s1);
    return LtSplat(true, r.pixel, origin, v);
}

// Continue the light subpath by sampling the adjoint BSDF at ym = `hit` (MODE_IMPORTANCE,
// with the shading-normal correction of Veach 1997 eq. 5.19): throughput, the camera-side
// density of y_{m-1}, the Heckbert symbol, medium and the next ray. STEP_* as the camera walk.
fn light_walk_scatter(lw: ptr<function, LightWalk>, hit: SurfaceHit, mat: Material, on: Oriented, frame: Frame, wo: vec3<f32>, bsdf: Bsdf, dispersive: bool, uc: f32, u2: vec2<f32>) -> u32 {
    let ng = on.ng;
    let wo_w = -lw.d;
    let b = interaction_sample(bsdf, frame, ng, wo_w, wo, uc, u2, MODE_IMPORTANCE);
    if b.step != STEP_CONTINUE {
        return b.step;
    }
    let s = b.s;
    let wi_w = b.wi_w;
    let side_i = b.side_i;
    lw.beta *= s.weight * shading_correction(wo_w, wi_w, on.ns, ng);
    if dispersive && !lw.collapsed {
        // Only the hero wavelength follows this direction.
        lw.beta = spectral_collapse(lw.beta);
        lw.collapsed = true;
    }
    // Camera-side density of the previous vertex, sampled from ym towards it.
    var pc_back = 1.0;
    if lw.m == 1u {
        if !s.is_delta {
            pc_back = bsdf_pdf(bsdf, s.wi, wo) * lw.cos_emit / lw.t2;
        }
        lw.pc_y0 = pc_back;
        lw.y1_delta = s.is_delta;
    } else {
        if !s.is_delta {
            pc_back = bsdf_pdf(bsdf, s.wi, wo) * lw.cos_prev / lw.t2;
        }
        lw.prod *= ratio(pc_back, lw.pl_prev);
    }
    if lw.m <= LT_MAX_SYMBOLS {
        let j = lw.m - 1u;
        lw.syms.w[j / 16u] |= (s.lobe + 1u) << (2u * (j % 16u));
    }
    if s.event == EVENT_TRANSMIT {
        lw.media = medium_after_transmit(lw.media, mat, hit.material, wi_w, hit.ng);
    }
    lw.prev_pdf = s.pdf;
    lw.prev_delta = s.is_delta;
    lw.cos_out = abs(dot3(hit.ng, wi_w));
    lw.o = offset_ray_origin_towards(hit.p, ng, side_i);
    lw.d = wi_w;
    return STEP_CONTINUE;
}

// Trace one light subpath and connect its vertices to the camera; returns rejected samples.
// Random dimensions: light pick (1), u_pos (2), u_dir (2), hero wavelengths (1, spectral),
// the emitting side (1, double-sided area lights); per vertex uc, u2 (2); Russian roulette (1).
fn lt_path(sampler: ptr<function, Sampler>) -> u32 {
    var lw: LightWalk;
    var sp: Spectral;
    if !lt_begin(sampler, &lw, &sp) {
        return 0u;
    }
    var rejected = 0u;
    loop {
        let h = bvh_intersect(lw.o, lw.d, F32_MAX);
        segments++;
        if lt_vertex(&lw, sampler, sp, h, WALK_WHOLE, &rejected) != VERTEX_NEXT {
            break;
        }
    }
    return rejected;
}

// Start a light subpath: pick a light, its hero wavelengths, an emitted ray. False when the
// subpath carries nothing (no light, a light at infinity, an invalid or black sample).
fn lt_begin(sampler: ptr<function, Sampler>, lw: ptr<function, LightWalk>, sp: ptr<function, Spectral>) -> bool {
    if params.light_count == 0u {
        return false;
    }
    let pick = light_set_pick(sampler_next_1d(sampler));
    let u_pos = sampler_next_2d(sampler);
    let u_dir = sampler_next_2d(sampler);
    // No light subpath starts at a light at infinity: lt+pt's strategies are those of the CPU
    // bdpt it stands for, where such a light is only connected to by next-event estimation
    // (`bdpt::light_path`, `Bdpt::infinite_weight`), so its paths keep the path tracer's
    // two-strategy weights (integrator_light_mis, integrator_add_escaped).
    if pick.prob <= 0.0 || light_is_infinite(pick.light) {
        return false;
    }
    *sp = spectral_new(sampler);
    let le = light_sample_le(pick.light, u_pos, u_dir, sampler, pick.prob);
    if !le.valid {
        return false;
    }
    *lw = light_walk_new(pick.light, le, *sp);
    return max_element4(lw.beta) > 0.0;
}

// `WALK_SHADE`'s connection to the camera, left for its shadow ray (ok = false: none).
var<private> LT_SPLAT: LtSplat;

// The light subpath in `lw` arriving at the closest hit `h` of its ray (not found: it
// escaped): the vertex's connection to the camera — splatted (`WALK_WHOLE`) or left in
// `LT_SPLAT` (`WALK_SHADE`) — then its BSDF sample and Russian roulette; `rejected` counts
// firewall rejections. VERTEX_NEXT: the walk goes on along (lw.o, lw.d).
fn lt_vertex(lw: ptr<function, LightWalk>, sampler: ptr<function, Sampler>, sp: Spectral, h: Hit, mode: u32, rejected: ptr<function, u32>) -> u32 {
    if !h.found {
        return VERTEX_END;
    }
    var hit = integrator_surface(h);
    light_walk_attenuate(lw, hit.t, sp);
    let mat = materials[hit.material];
    var enclosing = NO_MEDIUM;
    if HAS_NESTED {
        let crossed = light_walk_interface(lw, mat, &hit, &enclosing);
        if crossed == WALK_HIT_LOST {
            return VERTEX_END;
        }
        if crossed == WALK_HIT_PASSED {
            return VERTEX_NEXT; // a false hit: no vertex; the ray continues past it
        }
    }
    light_walk_arrive(lw, hit, sp);
    let front = dot3(lw.d, hit.ng) < 0.0;
    if (mat.flags & MAT_BLACK_EMITTER) != 0u {
        return VERTEX_END; // emitters are black surfaces otherwise (as in the path tracer)
    }
    let on = orient_normals(mat, hit, front);
    if !on.ok {
        return VERTEX_END;
    }
    let ie = interface_eta(mat, enclosing, sp);
    let dispersive = ie.dispersive;
    let bsdf = material_bsdf(mat, hit.uv, ie.eta, sp);
    let frame = frame_from_normal(on.ns);
    let wo_w = -lw.d;
    let wo = frame_to_local(frame, wo_w);
    // The full path x0 … xk has k = m + 1 segments.
    if !bsdf_is_delta(bsdf) {
        if mode == WALK_WHOLE {
            *rejected += lt_connect(*lw, hit, mat, on.ng, on.ns, frame, wo_w, wo, bsdf, sp, dispersive);
        } else {
            LT_SPLAT = lt_splat(*lw, hit, mat, on.ng, on.ns, frame, wo_w, wo, bsdf, sp, dispersive);
        }
    }
    if lw.m + 1u >= params.max_depth || (HAS_FILTER && lw.m >= LT_MAX_SYMBOLS) {
        return VERTEX_END;
    }
    let uc = sampler_next_1d(sampler);
    let u2 = sampler_next_2d(sampler);
    let step = light_walk_scatter(lw, hit, mat, on, frame, wo, bsdf, dispersive, uc, u2);
    if step == STEP_POISON {
        *rejected += 1u;
        return VERTEX_END;
    }
    if step == STEP_BREAK {
        return VERTEX_END;
    }
    // Russian roulette on the importance throughput (no η² factor: importance does not
    // compress on refraction).
    let q_rr = russian_roulette(lw.beta, 1.0, lw.m, sampler);
    if q_rr <= 0.0 {
        return VERTEX_END;
    }
    lw.beta /= q_rr;
    return VERTEX_NEXT;
}

// One light subpath per invocation per sample of the batch (as many as camera paths).
@compute @workgroup_size(8, 8, 1)
fn light_trace(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(local_invocation_index) lane: u32,
) {
    LANE = lane;
    if !HAS_LT {
        return;
    }
    OFFSET_SCALE = params.offset_scale;
    let x = gid.x;
    let y = gid.y;
    segments = 0u;
    var rejected = 0u;
    // Invocations past the image edge trace nothing but still take part in the reduction.
    if x < params.width && y < params.height {
        let id = y * params.width + x;
        for (var k = 0u; k < params.batch; k++) {
            var sampler = sampler_new(id, params.sample_offset + k, params.seed ^ LT_SEED_MIX);
            rejected += lt_path(&sampler);
        }
    }
    add_counters_workgroup(rejected, segments);
}
