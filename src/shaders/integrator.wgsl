// integrator.wgsl — the path-tracing kernel, twin of `cpu::Integrator::li` (src/cpu/integrator.rs):
// unidirectional path tracing with next-event estimation on area and punctual lights and
// MIS (power heuristic) between light and BSDF sampling. Veach 1997, ch. 9–10;
// PBR 4th ed. §13.4 (`PathIntegrator`). Depth and Russian roulette follow Mitsuba 3's `path`
// integrator: `max_depth` 1 = emitters seen directly, 2 = direct lighting, RR from `rr_depth`.
// Random dimensions are consumed in the CPU's order: jitter (2); per vertex uc, u2 (2),
// ul, ul2 (2); Russian roulette (1).

// Pipeline specialisation (absent features compiled out; values never specialised).
override HAS_LIGHTS: bool = true;
override HAS_PUNCTUAL: bool = true;
override HAS_ENVIRONMENT: bool = true;
override HAS_ABSORPTION: bool = true;
// Heckbert path filter (the table is a uniform; only its presence is specialised).
override HAS_FILTER: bool = true;
// Hero-wavelength spectral transport (scenes with a dispersive material).
override HAS_SPECTRAL: bool = true;
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
    _pad: u32,
}

struct Stats {
    dropped_lo: atomic<u32>,
    dropped_hi: atomic<u32>,
    segments_lo: atomic<u32>,
    segments_hi: atomic<u32>,
    debug: array<vec4<f32>>,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(6) var<storage, read_write> accum: array<vec4<f32>>;
@group(0) @binding(7) var<storage, read_write> stats: Stats;

// The reversed DFA of the Heckbert filter (`PathFilter::reversed().words()`, 168 words; see
// src/paths.rs "Table layout": a uniform needs a 16-byte stride, so words are read as
// t[i / 4][i % 4]).
struct PathFilterTable {
    t: array<vec4<u32>, 42>,
}
@group(0) @binding(9) var<uniform> path_filter: PathFilterTable;

// Symbols (paths::Symbol): L=0 D=1 G=2 S=3 E=4; a lobe's symbol is LOBE_* + 1.
const SYM_L: u32 = 0u;
const SYM_D: u32 = 1u;
const SYM_G: u32 = 2u;
const SYM_E: u32 = 4u;
const DFA_TRANSITIONS: u32 = 160u;

fn dfa_word(i: u32) -> u32 {
    return path_filter.t[i / 4u][i % 4u];
}

// The state after reading `symbol` in `state`; out-of-range states go to the dead state.
// Twin of `DfaTable::step`.
fn dfa_table_step(state: u32, symbol: u32) -> u32 {
    if state >= dfa_word(DFA_TRANSITIONS + 4u) {
        return dfa_word(DFA_TRANSITIONS + 3u);
    }
    return dfa_word(state * 5u + symbol);
}

// Twin of `DfaTable::is_accepting`.
fn dfa_table_is_accepting(state: u32) -> bool {
    return state < dfa_word(DFA_TRANSITIONS + 4u) && ((dfa_word(DFA_TRANSITIONS) >> state) & 1u) == 1u;
}

// Twin of `DfaTable::can_reach_accept`.
fn dfa_table_can_reach_accept(state: u32) -> bool {
    return state < dfa_word(DFA_TRANSITIONS + 4u) && ((dfa_word(DFA_TRANSITIONS + 1u) >> state) & 1u) == 1u;
}

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

// Colour representation of one path (cpu::Spectral): RGB (w = 0) or four hero wavelengths.
struct Spectral {
    on: bool,
    lambdas: vec4<f32>,
}

// RGB parameter → the path's colour lanes (smooth uplift in spectral mode). Twin of `Spectral::c`.
fn spectral_c(sp: Spectral, rgb: vec3<f32>) -> vec4<f32> {
    if HAS_SPECTRAL && sp.on {
        return rgb_to_spectrum4(rgb, sp.lambdas);
    }
    return vec4<f32>(rgb, 0.0);
}

// Debug records per path vertex (gpu::renderer::DebugPath reads them).
const DEBUG_MAX_VERTICES: u32 = 16u;
const DEBUG_STRIDE: u32 = 3u;

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
    if all(ns == vec3<f32>(0.0)) || !is_finite_v3(ns) {
        ns = ng;
    } else if dot3(ns, ng) < 0.0 {
        ns = -ns;
    }
    let uv = vec2<f32>(va.u, va.v) * b0 + vec2<f32>(vb.u, vb.v) * h.b1 + vec2<f32>(vc.u, vc.v) * h.b2;
    return SurfaceHit(p, ng, ns, uv, h.slot, tri.scene_tri, tri.material, h.t);
}

// Solid-angle pdf with which next-event estimation would have chosen the point `hit`
// seen from direction `dir` at distance `hit.t`. Twin of `Integrator::light_pdf`.
fn integrator_light_pdf(hit: SurfaceHit, dir: vec3<f32>) -> f32 {
    let tri = triangles[hit.slot];
    let p_pick = tri.pick_prob;
    if p_pick <= 0.0 {
        return 0.0;
    }
    let area = tri.area;
    let cos_l = abs(dot3(hit.ng, dir));
    if cos_l <= 0.0 || area <= 0.0 {
        return 0.0;
    }
    return p_pick / area * hit.t * hit.t / cos_l;
}

// Index of refraction at wavelength `lambda_nm` (Abbe-number dispersion). Twin of `Material::ior_at`.
fn material_ior_at(m: Material, lambda_nm: f32) -> f32 {
    if m.abbe > 0.0 {
        return cauchy_from_abbe(m.eta, m.abbe, lambda_nm);
    }
    return m.eta;
}

// The BSDF at a hit: base colour × texture, metal-rough metallic/roughness × texture,
// `eta` already chosen for the path's wavelength, colours mapped to the path's lanes.
// Twin of `scene::Material::bsdf` (+ `metal_rough_at`, `base_color_at`) and `Bsdf::map_colors`.
fn material_bsdf(m: Material, uv: vec2<f32>, eta: f32, sp: Spectral) -> Bsdf {
    var base = v3(m.base_color);
    if HAS_TEXTURES && m.base_tex != NO_TEXTURE {
        base = base * sample_texture(m.base_tex, uv).xyz;
    }
    var b = Bsdf(m.bsdf, spectral_c(sp, base), eta, m.alpha, m.dist, 0.0, 1.5, 1.0, vec4<f32>(1.0, 1.0, 1.0, 0.0));
    if HAS_METAL_ROUGH && m.bsdf == BSDF_METAL_ROUGH {
        var metallic = m.metallic;
        var roughness = m.roughness;
        if HAS_TEXTURES && m.mr_tex != NO_TEXTURE {
            let t = sample_texture(m.mr_tex, uv);
            metallic *= t.z;
            roughness *= t.y;
        }
        b.alpha = max(roughness_to_alpha(roughness), SMOOTH_ALPHA);
        b.metallic = clamp(metallic, 0.0, 1.0);
        // Metal-rough uses the material's own IOR (not the wavelength's).
        b.ior = m.eta;
        b.specular_factor = m.specular_factor;
        b.specular_color = spectral_c(sp, v3(m.specular_color));
    }
    return b;
}

struct LightPick {
    index: u32,
    prob: f32,
}

// Pick a light with `u` ∈ [0,1): (light, probability); prob = 0 for none. Twin of
// `LightSet::pick` (first CDF entry > u, clamped to the last light).
fn light_set_pick(u: f32) -> LightPick {
    let n = params.light_count;
    if n == 0u {
        return LightPick(0u, 0.0);
    }
    var lo = 0u;
    var hi = n;
    while lo < hi {
        let mid = (lo + hi) / 2u;
        if lights[mid].cdf <= u {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    let i = min(lo, n - 1u);
    var prev = 0.0;
    if i > 0u {
        prev = lights[i - 1u].cdf;
    }
    return LightPick(i, lights[i].cdf - prev);
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

// One next-event estimate at `hit` (without the path throughput), MIS-weighted.
// Twin of `Integrator::sample_light` (plus the light-tracing strategy when HAS_LT).
fn integrator_sample_light(hit: SurfaceHit, ng: vec3<f32>, frame: Frame, wo: vec3<f32>, wo_w: vec3<f32>, bsdf: Bsdf, ul: f32, ul2: vec2<f32>, mask: ClassMask, sp: Spectral, lt: LtMis) -> vec4<f32> {
    let zero = vec4<f32>(0.0);
    let pick = light_set_pick(ul);
    if pick.prob <= 0.0 {
        return zero;
    }
    let light = lights[pick.index];
    let p_pick = pick.prob;
    let side_o = dot3(wo_w, ng);
    var wi_w: vec3<f32>;
    var li: vec4<f32>;
    var pdf: f32;
    var delta: bool;
    var shadow_dir: vec3<f32>;
    var tmax = 1.0;
    var has_target_n = false;
    var target_n = vec3<f32>(0.0);
    // Light-side solid-angle density of emitting towards hit.p, and the squared distance.
    var emit_pdf = 0.0;
    var dist2_l = 1.0;
    if light.kind == LIGHT_TRIANGLE {
        if !HAS_LIGHTS {
            return zero;
        }
        // sample_triangle: a point sampled uniformly on the triangle.
        let tri = triangles[light.index];
        let a = v3(tri.p0);
        let b = v3(tri.p1);
        let c = v3(tri.p2);
        let bc = uniform_triangle(ul2);
        let pl = a * (1.0 - bc.x - bc.y) + b * bc.x + c * bc.y;
        let nn = cross3(b - a, c - a);
        let len = sqrt(dot3(nn, nn));
        let nl = nn / len;
        let area = 0.5 * len;
        let m = materials[tri.material];
        let to = pl - hit.p;
        let dist2 = dot3(to, to);
        if dist2 <= 0.0 {
            return zero;
        }
        let dist = sqrt(dist2);
        let wi = to / dist;
        var cos_l = -dot3(wi, nl);
        if cos_l <= 0.0 && (m.flags & MAT_DOUBLE_SIDED) == 0u {
            return zero;
        }
        cos_l = abs(cos_l);
        if cos_l <= 0.0 {
            return zero;
        }
        wi_w = wi;
        li = spectral_c(sp, v3(m.emission));
        pdf = p_pick / area * dist2 / cos_l;
        delta = false;
        if HAS_LT {
            emit_pdf = emission_pdf_dir(m, cos_l);
            dist2_l = dist2;
        }
        shadow_dir = to;
        has_target_n = true;
        target_n = nl;
    } else {
        if !HAS_PUNCTUAL {
            return zero;
        }
        let lp = v3(light.position);
        let intensity = v3(light.intensity);
        delta = true;
        pdf = p_pick;
        if light.kind == LIGHT_DIRECTIONAL {
            wi_w = -v3(light.direction);
            li = spectral_c(sp, intensity);
            shadow_dir = wi_w;
            tmax = F32_MAX;
        } else {
            let to = lp - hit.p;
            let d2 = dot3(to, to);
            if d2 <= 0.0 {
                return zero;
            }
            wi_w = to / sqrt(d2);
            shadow_dir = to;
            if HAS_LT {
                emit_pdf = punctual_pdf_dir(light);
                dist2_l = d2;
            }
            if light.kind == LIGHT_SPOT {
                let fall = spot_falloff(dot3(-wi_w, v3(light.direction)), light.cos_inner, light.cos_outer);
                if fall <= 0.0 {
                    return zero;
                }
                li = spectral_c(sp, intensity * fall / d2);
            } else {
                li = spectral_c(sp, intensity / d2);
            }
        }
    }
    let side_i = dot3(wi_w, ng);
    let wi = frame_to_local(frame, wi_w);
    var f: vec4<f32>;
    if mask.d && mask.g {
        f = bsdf_eval(bsdf, wo, wi, MODE_RADIANCE);
    } else {
        let lv = bsdf_eval_lobes(bsdf, wo, wi, MODE_RADIANCE);
        f = select(vec4<f32>(0.0), lv.d, mask.d) + select(vec4<f32>(0.0), lv.g, mask.g);
    }
    // Reflection must stay on the geometric side of wo; transmission must cross it.
    if side_i == 0.0 || max_element4(f) <= 0.0 {
        return zero;
    }
    if !(side_i * side_o > 0.0) && !bsdf_can_transmit(bsdf) {
        return zero;
    }
    let origin = offset_ray_origin_towards(hit.p, ng, side_i);
    var sdir: vec3<f32>;
    if has_target_n {
        let pl = hit.p + shadow_dir;
        var tn = -target_n;
        if dot3(target_n, -wi_w) > 0.0 {
            tn = target_n;
        }
        let tgt = offset_ray_origin(pl, tn);
        sdir = tgt - origin;
    } else if tmax < F32_MAX {
        sdir = hit.p + shadow_dir - origin;
    } else {
        sdir = shadow_dir;
    }
    if bvh_occluded(origin, sdir, tmax) {
        return zero;
    }
    var w = 1.0;
    if HAS_LT {
        // p_t1 / p_s1 = Π_{i=1..j} p←(xi)/p→(xi), xj = this vertex (Veach 1997, §10.2).
        var r_t = 0.0;
        if lt.ok && emit_pdf > 0.0 {
            r_t = ratio(emit_pdf * abs(dot3(hit.ng, wi_w)) / dist2_l, lt.pf_cur);
            if !lt.first {
                let p_back = bsdf_pdf(bsdf, wi, wo) * lt.cos_prev / (lt.t_prev * lt.t_prev);
                r_t *= lt.prod * ratio(p_back, lt.pf_prev);
            }
        }
        var r_0 = 0.0;
        if !delta {
            r_0 = bsdf_pdf(bsdf, wo, wi) / pdf;
        }
        w = mis_weight3(r_0, r_t);
    } else if !delta {
        w = power_heuristic(pdf, bsdf_pdf(bsdf, wo, wi));
    }
    return f * abs(wi.z) * li * (w / pdf);
}

// Beer–Lambert transmittance T = exp(−σ_a t) over distance t inside material `mm`'s medium,
// σ_a = −ln(c)/d (glTF KHR_materials_volume), in the path's colour lanes.
fn medium_transmittance(mm: Material, t: f32, sp: Spectral) -> vec4<f32> {
    if (mm.flags & MAT_ABSORBS) == 0u {
        return vec4<f32>(1.0);
    }
    var sa: vec4<f32>;
    if HAS_SPECTRAL && sp.on {
        let c = max(spectral_c(sp, v3(mm.attenuation_color)), vec4<f32>(1e-6));
        sa = -log(c) / mm.attenuation_distance;
    } else {
        sa = vec4<f32>(v3(mm.sigma_a), 0.0);
    }
    let tr = -sa * t;
    return exp(tr);
}

struct Oriented {
    ok: bool,
    ng: vec3<f32>,
    ns: vec3<f32>,
}

// Orient normals: opaque double-sided materials shade both sides alike; one-sided opaque back
// faces are black (ok = false: the walk ends); dielectrics keep the outward normal (eta
// convention). Shared by the camera and the light walk.
fn orient_normals(mat: Material, hit: SurfaceHit, front: bool) -> Oriented {
    let transmissive = (mat.flags & MAT_TRANSMISSIVE) != 0u;
    if transmissive || front {
        return Oriented(true, hit.ng, hit.ns);
    }
    if (mat.flags & MAT_DOUBLE_SIDED) != 0u {
        return Oriented(true, -hit.ng, -hit.ns);
    }
    return Oriented(false, hit.ng, hit.ns);
}

// A sampled event agrees with the geometric normal: reflection stays on wo's side,
// transmission crosses it (side_o = ωo·ng, side_i = ωi·ng).
fn event_is_consistent(event: u32, side_o: f32, side_i: f32) -> bool {
    if event == EVENT_REFLECT {
        return side_o * side_i > 0.0;
    }
    return side_o * side_i < 0.0;
}

// Ray origin at p, pushed off the surface to the side the new direction leaves on
// (side_i = ωi·ng). Wächter & Binder 2019 offsets (`offset_ray_origin`).
fn offset_ray_origin_towards(p: vec3<f32>, ng: vec3<f32>, side_i: f32) -> vec3<f32> {
    if side_i > 0.0 {
        return offset_ray_origin(p, ng);
    }
    return offset_ray_origin(p, -ng);
}

// A quiet NaN (the film firewall drops and counts it), built at run time.
fn poison() -> vec3<f32> {
    return vec3<f32>(bitcast<f32>(0x7fc00000u + u32(params.width == 0xffffffffu)));
}

// Radiance along the camera ray (origin, dir) — one path sample, RGB. Twin of `Integrator::li`.
fn integrator_li(origin: vec3<f32>, dir: vec3<f32>, sampler: ptr<function, Sampler>) -> vec3<f32> {
    // Hero wavelength sampling, Wilkie et al. 2014, "Hero Wavelength Spectral Sampling".
    var sp = Spectral(false, vec4<f32>(0.0));
    if HAS_SPECTRAL {
        sp = Spectral(true, sample_hero_wavelengths(sampler_next_1d(sampler)));
    }
    var collapsed = false;
    var l = vec4<f32>(0.0);
    var beta = vec4<f32>(1.0);
    var o = origin;
    var d = dir;
    var prev_pdf = 0.0;
    var prev_delta = true;
    var eta_scale = 1.0;
    // Absorbing medium the ray travels in (material index); NO_MEDIUM = none.
    let NO_MEDIUM = 0xffffffffu;
    var medium = NO_MEDIUM;
    var depth = 0u;
    // Light-tracing MIS state (HAS_LT).
    var lt = LtMis(HAS_LT, true, 1.0, 0.0, 0.0, 0.0, 0.0);
    // Path-filter state: the camera vertex is E (reversed DFA reads eye→light).
    var q = 0u;
    if HAS_FILTER {
        q = dfa_table_step(dfa_word(DFA_TRANSITIONS + 2u), SYM_E);
    }
    loop {
        let h = bvh_intersect(o, d, F32_MAX);
        segments++;
        if !h.found {
            // Escaped: uniform environment (not light-sampled, so MIS weight 1).
            if HAS_ENVIRONMENT && integrator_accepts_light(q) {
                l += beta * spectral_c(sp, params.environment.xyz);
            }
            break;
        }
        let hit = integrator_surface(h);
        if HAS_ABSORPTION && medium != NO_MEDIUM {
            beta *= medium_transmittance(materials[medium], hit.t, sp);
        }
        let mat = materials[hit.material];
        let front = dot3(d, hit.ng) < 0.0;
        if HAS_LT {
            // p→ of this vertex (area; 1 after a delta vertex), camera density for x1.
            let cos_here = abs(dot3(hit.ng, d));
            lt.pf_prev = lt.pf_cur;
            lt.first = depth == 0u;
            lt.t_prev = hit.t;
            if depth == 0u {
                lt.pf_cur = camera_pdf_dir(-dot3(d, params.cam_back.xyz)) * cos_here / (hit.t * hit.t);
            } else if prev_delta {
                lt.pf_cur = 1.0;
            } else {
                lt.pf_cur = prev_pdf * cos_here / (hit.t * hit.t);
            }
        }

        // Emission (one-sided unless doubleSided).
        if HAS_LIGHTS && (mat.flags & MAT_EMISSIVE) != 0u && (front || (mat.flags & MAT_DOUBLE_SIDED) != 0u) && integrator_accepts_light(q) {
            var w = 1.0;
            if HAS_LT {
                // Ratios of next-event estimation (s = 1) and light tracing (t = 1) to this
                // BSDF-sampled hit (s = 0); light tracing needs k ≥ 2 and x1 non-delta.
                var r_1 = 0.0;
                if !prev_delta {
                    r_1 = integrator_light_pdf(hit, d) / prev_pdf;
                }
                var r_t = 0.0;
                if lt.ok && depth >= 1u {
                    let tri = triangles[hit.slot];
                    let p_back = emission_pdf_dir(mat, abs(dot3(hit.ng, d))) * lt.cos_prev / (hit.t * hit.t);
                    r_t = lt.prod * ratio(p_back, lt.pf_prev) * ratio(tri.pick_prob / tri.area, lt.pf_cur);
                }
                w = mis_weight3(r_1, r_t);
            } else if !prev_delta {
                w = power_heuristic(prev_pdf, integrator_light_pdf(hit, d));
            }
            l += beta * spectral_c(sp, v3(mat.emission)) * w;
        }
        debug_write(1u + DEBUG_STRIDE * min(depth, DEBUG_MAX_VERTICES - 1u), vec4<f32>(hit.p, hit.t));
        if depth + 1u >= params.max_depth {
            break;
        }

        let transmissive = (mat.flags & MAT_TRANSMISSIVE) != 0u;
        let on = orient_normals(mat, hit, front);
        if !on.ok {
            break;
        }
        let ng = on.ng;
        let ns = on.ns;
        if (mat.flags & MAT_BLACK_EMITTER) != 0u {
            break; // emitters are black surfaces otherwise
        }
        var eta = mat.eta;
        if HAS_SPECTRAL && sp.on && mat.abbe > 0.0 && transmissive {
            eta = material_ior_at(mat, sp.lambdas.x);
            if !collapsed {
                // Wavelength-dependent refraction: only the hero wavelength can follow this
                // direction. Keep lane 0 (×4: it now carries the whole estimate), drop the rest.
                beta = vec4<f32>(4.0 * beta.x, 0.0, 0.0, 0.0);
                collapsed = true;
            }
        }
        let bsdf = material_bsdf(mat, hit.uv, eta, sp);
        let frame = frame_from_normal(ns);
        let wo_w = -d;
        let wo = frame_to_local(frame, wo_w);
        let uc = sampler_next_1d(sampler);
        let u2 = sampler_next_2d(sampler);
        let ul = sampler_next_1d(sampler);
        let ul2 = sampler_next_2d(sampler);

        // Next-event estimation.
        if (HAS_LIGHTS || HAS_PUNCTUAL) && !bsdf_is_delta(bsdf) && params.light_count > 0u {
            let mask = ClassMask(integrator_accepts_light(integrator_step(q, SYM_D)), integrator_accepts_light(integrator_step(q, SYM_G)));
            if mask.d || mask.g {
                l += beta * integrator_sample_light(hit, ng, frame, wo, wo_w, bsdf, ul, ul2, mask, sp, lt);
            }
        }

        // BSDF sampling.
        let s = bsdf_sample(bsdf, wo, uc, u2, MODE_RADIANCE);
        if !s.valid {
            break;
        }
        let wi_w = frame_to_world(frame, s.wi);
        let side_i = dot3(wi_w, ng);
        let consistent = event_is_consistent(s.event, dot3(wo_w, ng), side_i);
        if !is_finite_v4(s.weight) {
            // A broken BSDF value: poison the sample so the firewall drops and counts it.
            return poison();
        }
        if !consistent {
            break;
        }
        if HAS_FILTER {
            q = dfa_table_step(q, s.lobe + 1u);
            if !dfa_table_can_reach_accept(q) {
                break; // nothing this path can still reach counts
            }
        }
        beta *= s.weight;
        if HAS_LT {
            if depth >= 1u {
                // p←(x_{j-1}): this vertex samples the previous one (1 if delta).
                var p_back = 1.0;
                if !s.is_delta {
                    p_back = bsdf_pdf(bsdf, s.wi, wo) * lt.cos_prev / (hit.t * hit.t);
                }
                lt.prod *= ratio(p_back, lt.pf_prev);
            } else if s.is_delta {
                lt.ok = false; // x1 is delta: light tracing cannot connect it to the camera
            }
            lt.cos_prev = abs(dot3(hit.ng, wi_w));
        }
        if s.event == EVENT_TRANSMIT {
            eta_scale *= s.eta_rel * s.eta_rel;
            if (mat.flags & MAT_SOLID) != 0u {
                // Entering when the new direction points against the outward normal.
                if dot3(wi_w, hit.ng) < 0.0 {
                    medium = hit.material;
                } else {
                    medium = NO_MEDIUM;
                }
            }
        }
        prev_pdf = s.pdf;
        prev_delta = s.is_delta;
        o = offset_ray_origin_towards(hit.p, ng, side_i);
        d = wi_w;
        depth++;
        debug_write(2u + DEBUG_STRIDE * min(depth - 1u, DEBUG_MAX_VERTICES - 1u), vec4<f32>(beta.xyz, f32(depth)));
        debug_write(3u + DEBUG_STRIDE * min(depth - 1u, DEBUG_MAX_VERTICES - 1u), vec4<f32>(d, f32(hit.scene_tri)));

        // Russian roulette (Mitsuba 3 `path`: q = min(max(β)·η², 0.95) from rr_depth).
        if depth >= params.rr_depth {
            let q_rr = min(max_element4(beta) * eta_scale, 0.95);
            if q_rr <= 0.0 || sampler_next_1d(sampler) >= q_rr {
                break;
            }
            beta /= q_rr;
        } else if max_element4(beta) <= 0.0 {
            break;
        }
    }
    if HAS_SPECTRAL && sp.on {
        return spectrum_sample_to_rgb(sp.lambdas, l);
    }
    return l.xyz;
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
fn render(@builtin(global_invocation_id) gid: vec3<u32>) {
    let x = gid.x;
    let y = gid.y;
    let w = params.width;
    let h = params.height;
    if x >= w || y >= h {
        return;
    }
    let pixel = y * w + x;
    segments = 0u;
    var sum = vec3<f32>(0.0);
    var dropped = 0u;
    for (var k = 0u; k < params.batch; k++) {
        let s = params.sample_offset + k;
        debug_on = pixel == params.debug_pixel && k == 0u;
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
    if HAS_LT {
        // This batch's light-tracing splats (k light paths per pixel, like the camera paths).
        let lt_sum = splat_take(pixel);
        if is_finite_v3(lt_sum) {
            sum += lt_sum;
        }
    }
    // Fold the batch into the running mean without drift: mean·n/(n+k) + Σ/(n+k).
    let old = accum[pixel];
    accum[pixel] = vec4<f32>(old.xyz * params.w_old + sum * params.w_new, 1.0);
    add_counter_dropped(dropped);
    add_counter_segments(segments);
}
