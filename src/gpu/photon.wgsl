// photon.wgsl — the GPU twin of `cpu::sppm` (src/cpu/sppm/): caustic photons, their hash grid
// and the density estimate at the camera walk's diffuse vertices (`sppm`, HAS_SPPM).
//
// Iteration s is sample index s. A submission runs `batch` iterations at once (gpu::photons):
// the photon grid's counter and bucket heads are cleared, `photon_trace` traces the photon
// paths of every iteration (one per invocation, the iteration in z) through specular vertices
// only and stores each where it first reaches a Lambert surface after k ≥ 1 specular vertices
// (the paths L S^k D, Jensen 1996's caustic photon map; twin of `sppm::photon::trace_photon`),
// pushing it onto its bucket's linked list in its iteration's own grid (`atomicExchange` on the
// head); then the camera walk (`render` or the wavefront) traces `batch` samples per pixel,
// sample j gathering iteration j's photons (`SPPM_ITER`), and leaves out the paths they stand
// for. Hash and 2r cells as `sppm::grid::HashGrid` (Teschner et al. 2003; Hachisuka & Jensen
// 2009 §4.2): a query visits 2 × 2 × 2 cells, each bucket once.
//
// `photon_grid` words: [PHOTON_COUNT] photons stored by the submission, [PHOTON_OVERFLOW]
// photons that found the store full (cumulative; never written out of bounds), then one `next`
// link per photon slot, then per iteration of the batch grid_mask + 1 bucket heads. Links and
// heads hold index + 1 (0 = end: the buffer is cleared to zero).

// Photon-mapped caustics in the camera walk (`sppm`; the estimator, not the scene).
override HAS_SPPM: bool = false;

// One stored photon (gpu::layout::Photon; cpu `sppm::photon::Photon`).
struct Photon {
    px: f32,
    py: f32,
    pz: f32,
    // k (specular vertices, bits 0..30) | collapsed << 31
    kflags: u32,
    // Light-subpath throughput on arrival (the path's colour lanes), not yet divided by N.
    beta: vec4<f32>,
    // Direction back towards where the photon came from (world, unit).
    wx: f32,
    wy: f32,
    wz: f32,
    // Geometric normal on the arrival side, octahedral, pack2x16snorm.
    ng: u32,
}

@group(0) @binding(11) var<storage, read_write> photon_grid: array<atomic<u32>>;
@group(0) @binding(12) var<storage, read_write> photons: array<Photon>;

// PHOTON_SAME_SURFACE_COS (photons on a surface turned further than this from the query's
// are another surface, `lookup::SAME_SURFACE_COS`) and PHOTON_DIMS (the sampler's dimension
// where photon paths start, `sppm::PHOTON_DIMS`) come from the prelude.
const COLLAPSED_BIT: u32 = 0x80000000u;

// Octahedral unit-vector encoding (Meyer et al. 2010; Cigolle et al. 2014, JCGT 3(2), §3.1).
fn oct_encode(n: vec3<f32>) -> vec2<f32> {
    let p = n.xy / (abs(n.x) + abs(n.y) + abs(n.z));
    if n.z >= 0.0 {
        return p;
    }
    return (1.0 - abs(p.yx)) * select(vec2<f32>(-1.0), vec2<f32>(1.0), p >= vec2<f32>(0.0));
}

fn oct_decode(e: vec2<f32>) -> vec3<f32> {
    var v = vec3<f32>(e, 1.0 - abs(e.x) - abs(e.y));
    if v.z < 0.0 {
        v = vec3<f32>((1.0 - abs(v.yx)) * select(vec2<f32>(-1.0), vec2<f32>(1.0), v.xy >= vec2<f32>(0.0)), v.z);
    }
    return normalize3(v);
}

// The iteration of the batch the running photon path or camera sample belongs to (0 ≤ j <
// batch: sample index sample_offset + j).
var<private> SPPM_ITER: u32;

// The radius of the running iteration: r₁ (s + 1)^((α − 1)/2) (`render::photon_radius`;
// Knaus & Zwicker 2011, eq. 15 in closed form).
fn photon_radius() -> f32 {
    return params.photon_radius0 * pow(f32(params.sample_offset + SPPM_ITER) + 1.0, params.photon_radius_exp);
}

// The grid cell of `p` for radius r: ⌊p / 2r⌋ (`grid::floor_i`; the conversion saturates like
// the Rust casts).
fn photon_cell(p: vec3<f32>, r: f32) -> vec3<i32> {
    return vec3<i32>(floor(p * (0.5 / r)));
}

// Teschner et al. 2003, the spatial hash (twin of `grid::hash`).
fn photon_hash(c: vec3<i32>) -> u32 {
    let h = (bitcast<u32>(c.x) * 73856093u) ^ (bitcast<u32>(c.y) * 19349663u) ^ (bitcast<u32>(c.z) * 83492791u);
    return h & params.grid_mask;
}

// The links follow the counters; one link per photon slot.
fn photon_next_base() -> u32 {
    return PHOTON_HEADS;
}

// The running iteration's bucket heads, after the links.
fn photon_heads_base() -> u32 {
    return PHOTON_HEADS + arrayLength(&photons) + SPPM_ITER * (params.grid_mask + 1u);
}

// Append a photon and push it onto its bucket's list; a full store counts the overflow.
fn photon_store(p: vec3<f32>, wi: vec3<f32>, ng: vec3<f32>, beta: vec4<f32>, k: u32, collapsed: bool) {
    let idx = atomicAdd(&photon_grid[PHOTON_COUNT], 1u);
    if idx >= arrayLength(&photons) {
        atomicAdd(&photon_grid[PHOTON_OVERFLOW], 1u);
        return;
    }
    let kflags = k | select(0u, COLLAPSED_BIT, collapsed);
    photons[idx] = Photon(p.x, p.y, p.z, kflags, beta, wi.x, wi.y, wi.z, pack2x16snorm(oct_encode(ng)));
    let prev = atomicExchange(&photon_grid[photon_heads_base() + photon_hash(photon_cell(p, photon_radius()))], idx + 1u);
    atomicStore(&photon_grid[photon_next_base() + idx], prev);
}

// Trace one photon path (twin of `sppm::photon::trace_photon` and its `walk`): emitted as a
// light subpath (β = Le cosθ / (p_pos p_dir), light_tracing.wgsl's `light_walk_new`) from any
// light of the distribution — lights at infinity (directional, the environment image) from
// the disk covering the scene's bounding sphere (light.wgsl) — scattered by the adjoint BSDF
// at specular vertices only, stored at the first Lambert surface after k ≥ 1 of them when
// k + 2 segments fit in max_depth.
fn photon_path(sampler: ptr<function, Sampler>, sp: Spectral) {
    if params.light_count == 0u {
        return;
    }
    let pick = light_set_pick(sampler_next_1d(sampler));
    let u_pos = sampler_next_2d(sampler);
    let u_dir = sampler_next_2d(sampler);
    if pick.prob <= 0.0 {
        return;
    }
    var le = light_sample_le(pick.light, u_pos, u_dir, sampler, pick.prob);
    if le.valid && params.target_count > 0u && !light_is_infinite(pick.light) {
        le = photon_aimed(pick.light, le, sampler_next_1d(sampler), u_dir);
    }
    if !le.valid || !(le.pdf_dir > 0.0) || !(le.pdf_pos > 0.0) || !(max_element3(le.l) > 0.0) {
        return;
    }
    var lw = light_walk_new(pick.light, le, sp);
    var k = 0u;
    loop {
        let h = bvh_intersect(lw.o, lw.d, F32_MAX);
        segments++;
        if !h.found {
            return;
        }
        var hit = integrator_surface(h);
        light_walk_attenuate(&lw, hit.t, sp);
        let mat = materials[hit.material];
        var enclosing = NO_MEDIUM;
        if HAS_NESTED {
            let crossed = light_walk_interface(&lw, mat, &hit, &enclosing);
            if crossed == WALK_HIT_LOST {
                return;
            }
            if crossed == WALK_HIT_PASSED {
                continue;
            }
        }
        light_walk_arrive(&lw, hit, sp);
        if (mat.flags & MAT_BLACK_EMITTER) != 0u {
            return;
        }
        let on = orient_normals(mat, hit, dot3(lw.d, hit.ng) < 0.0);
        if !on.ok {
            return;
        }
        let ie = interface_eta(mat, enclosing, sp);
        let bsdf = material_bsdf(mat, hit.uv, ie.eta, sp);
        if bsdf.kind == BSDF_LAMBERT {
            // L S^k D: k + 1 segments from the light; the eye side adds at least one.
            if k >= 1u && k + 2u <= params.max_depth {
                photon_store(hit.p, -lw.d, on.ng, lw.beta, k, lw.collapsed);
            }
            return;
        }
        if !bsdf_is_delta(bsdf) || k + 3u > params.max_depth {
            return;
        }
        let frame = frame_from_normal(on.ns);
        let wo = frame_to_local(frame, -lw.d);
        let uc = sampler_next_1d(sampler);
        let u2 = sampler_next_2d(sampler);
        let step = light_walk_scatter(&lw, hit, mat, on, frame, wo, bsdf, ie.dispersive, uc, u2);
        if step != STEP_CONTINUE || !(max_element4(lw.beta) > 0.0) || !is_finite_v4(lw.beta) {
            return;
        }
        k++;
    }
}

// Cone of target sphere i seen from p: axis, 1 − cos θ_max (2 = every direction: p is inside)
// and solid angle (`PhotonTargets::cone`).
struct AimCone {
    axis: vec3<f32>,
    omc: f32,
    omega: f32,
}

fn photon_aim_cone(i: u32, p: vec3<f32>) -> AimCone {
    let t = params.targets[i];
    let to = t.xyz - p;
    let d2 = dot(to, to);
    let r2 = t.w * t.w;
    if d2 <= r2 {
        return AimCone(vec3<f32>(0.0, 0.0, 1.0), 2.0, 4.0 * PI);
    }
    let sin2 = r2 / d2;
    let omc = sin2 / (1.0 + sqrt(1.0 - sin2));
    return AimCone(to / sqrt(d2), omc, 2.0 * PI * omc);
}

// The emission `le` of `light` redirected towards the photon targets (twin of
// `trace_photon` with `render::photon_aim::PhotonTargets::sample_dir`): the point as
// sampled, a direction uniform in a cone picked by solid angle, density N(ω) / Σ Ω_j with
// N(ω) the cones holding ω; the radiance and cosine along it. Invalid without a direction.
fn photon_aimed(light: Light, le_in: LightLeSample, u_pick: f32, u: vec2<f32>) -> LightLeSample {
    var le = le_in;
    let n = min(params.target_count, PHOTON_TARGETS);
    var total = 0.0;
    for (var i = 0u; i < n; i++) {
        total += photon_aim_cone(i, le.p).omega;
    }
    if !(total > 0.0) || !is_finite_f32(total) {
        le.valid = false;
        return le;
    }
    var rest = u_pick * total;
    var j = n - 1u;
    for (var i = 0u; i < n; i++) {
        let om = photon_aim_cone(i, le.p).omega;
        if rest < om {
            j = i;
            break;
        }
        rest -= om;
    }
    let cj = photon_aim_cone(j, le.p);
    var w: vec3<f32>;
    if cj.omc >= 2.0 {
        w = uniform_sphere(u);
    } else {
        let one_minus_cos = u.x * cj.omc;
        let sin_t = sqrt(max(one_minus_cos * (2.0 - one_minus_cos), 0.0));
        let phi = 2.0 * PI * u.y;
        w = frame_to_world(frame_from_normal(cj.axis), vec3<f32>(sin_t * cos(phi), sin_t * sin(phi), 1.0 - one_minus_cos));
    }
    var holding = 1.0;
    for (var i = 0u; i < n; i++) {
        let c = photon_aim_cone(i, le.p);
        if i != j && (c.omc >= 2.0 || 1.0 - dot(w, c.axis) <= c.omc) {
            holding += 1.0;
        }
    }
    le.dir = w;
    le.pdf_dir = holding / total;
    le.l = light_le(light, le.p, le.n, w);
    if !le.delta_pos {
        // The emitting side faces w (a double-sided emitter; a one-sided one has l = 0 behind).
        if dot(w, le.n) < 0.0 {
            le.n = -le.n;
        }
        le.cos_n = abs(dot(w, le.n));
    }
    return le;
}

// The running iteration's hero wavelengths, shared by its photons and camera paths (`sppm`:
// `Sampler::new(u32::MAX, s, seed)`, s = sample_offset + SPPM_ITER).
fn photon_spectral() -> Spectral {
    var s = sampler_new(0xffffffffu, params.sample_offset + SPPM_ITER, params.seed);
    return spectral_new(&s);
}

// One photon path per invocation: path gid.y · width + gid.x < photon_paths of iteration gid.z.
@compute @workgroup_size(8, 8, 1)
fn photon_trace(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(local_invocation_index) lane: u32,
) {
    LANE = lane;
    if !HAS_SPPM {
        return;
    }
    OFFSET_SCALE = params.offset_scale;
    segments = 0u;
    SPPM_ITER = gid.z;
    // Invocations past the image edge or the iteration's photon paths trace nothing but still
    // take part in the reduction.
    if gid.x < params.width && gid.y < params.height && gid.y * params.width + gid.x < params.photon_paths {
        var sampler = sampler_new(gid.y * params.width + gid.x, params.sample_offset + gid.z, params.seed);
        sampler.dim = PHOTON_DIMS;
        photon_path(&sampler, photon_spectral());
    }
    add_counters_workgroup(0u, segments);
}

// Bit k set: the string D S^k L read from state `q` passes the filter (k < 32; twin of
// `PhotonLookup::accepted_chains`).
fn photon_accepted_chains(q: u32) -> u32 {
    if !HAS_FILTER {
        return 0xffffffffu;
    }
    var mask = 0u;
    var s = dfa_table_step(q, SYM_D);
    for (var k = 1u; k < 32u; k++) {
        s = dfa_table_step(s, SYM_S);
        if dfa_table_is_accepting(dfa_table_step(s, SYM_L)) {
            mask |= 1u << k;
        }
    }
    return mask;
}

// Is D S^k L from `q` accepted (bit k of `chains`, or walked for k ≥ 32)?
fn photon_chain_accepted(chains: u32, q: u32, k: u32) -> bool {
    if !HAS_FILTER {
        return true;
    }
    if k < 32u {
        return (chains & (1u << k)) != 0u;
    }
    var s = dfa_table_step(q, SYM_D);
    for (var j = 0u; j < k; j++) {
        s = dfa_table_step(s, SYM_S);
    }
    return dfa_table_is_accepting(dfa_table_step(s, SYM_L));
}

// Where and how a camera path meets its gather vertex.
struct GatherPoint {
    p: vec3<f32>,
    ng: vec3<f32>,
    ns: vec3<f32>,
    frame: Frame,
    wo: vec3<f32>,
    // Camera-path depth (segments so far minus one), filter state, hero-lane collapse.
    depth: u32,
    q: u32,
    collapsed: bool,
    // The running iteration's radius (`photon_radius`).
    radius: f32,
}

// One photon's contribution at `g` (0 if it is too far, filtered, too deep or on another surface).
fn photon_contribution(ph: Photon, g: GatherPoint, bsdf: Bsdf, chains: u32) -> vec4<f32> {
    let zero = vec4<f32>(0.0);
    let d = vec3<f32>(ph.px, ph.py, ph.pz) - g.p;
    let k = ph.kflags & ~COLLAPSED_BIT;
    let r = g.radius;
    if dot3(d, d) > r * r || !photon_chain_accepted(chains, g.q, k) || g.depth + k + 2u > params.max_depth {
        return zero;
    }
    if dot3(oct_decode(unpack2x16snorm(ph.ng)), g.ng) < PHOTON_SAME_SURFACE_COS {
        return zero;
    }
    let wi = vec3<f32>(ph.wx, ph.wy, ph.wz);
    let cos_g = dot3(wi, g.ng);
    if cos_g <= 0.0 {
        return zero;
    }
    let f = bsdf_eval(bsdf, g.wo, frame_to_local(g.frame, wi), MODE_RADIANCE);
    // dΦ/dA counts cosθ against the geometric normal, the BSDF integral the shading normal's
    // (Veach 1997, eq. 5.19's correction at the gather vertex).
    var w = abs(dot3(wi, g.ns)) / cos_g;
    // After a collapse the hero lane stands for the whole estimate, ×4 once per full path. On
    // the GPU `spectral_collapse` puts the ×4 into each side's throughput (the CPU's `weight`
    // applies it once instead), so a path collapsed on both sides has it twice.
    if (ph.kflags & COLLAPSED_BIT) != 0u && g.collapsed {
        w *= 0.25;
    }
    return f * ph.beta * w;
}

// Σ over the iteration's photons within r of g.p, / (N π r²) (Jensen 1996, eq. 8; Hachisuka et
// al. 2008, eq. 5). Twin of `PhotonLookup::gather`, for a Lambert vertex with depth + 3 ≤ max_depth.
fn photon_gather(g: GatherPoint, bsdf: Bsdf) -> vec4<f32> {
    let chains = photon_accepted_chains(g.q);
    let lo = vec3<i32>(floor(g.p * (0.5 / g.radius) - vec3<f32>(0.5)));
    let next = photon_next_base();
    let heads = photon_heads_base();
    let cap = arrayLength(&photons);
    var sum = vec4<f32>(0.0);
    for (var c = 0u; c < 8u; c++) {
        let b = photon_hash(lo + vec3<i32>(vec3<u32>(c & 1u, (c >> 1u) & 1u, c >> 2u)));
        // Two cells hashed to one bucket: visit it once.
        var seen = false;
        for (var e = 0u; e < c; e++) {
            seen = seen || photon_hash(lo + vec3<i32>(vec3<u32>(e & 1u, (e >> 1u) & 1u, e >> 2u))) == b;
        }
        if seen {
            continue;
        }
        var i = atomicLoad(&photon_grid[heads + b]);
        while i != 0u && i <= cap {
            sum += photon_contribution(photons[i - 1u], g, bsdf, chains);
            i = atomicLoad(&photon_grid[next + i - 1u]);
        }
    }
    // 1 / (N π r²) (Jensen 1996, eq. 8).
    return sum * (params.photon_norm0 / (g.radius * g.radius));
}

// Is this camera-path vertex a gather vertex (a Lambert surface with room for D S+ L)?
fn sppm_is_gather_vertex(bsdf: Bsdf, depth: u32) -> bool {
    return HAS_SPPM && bsdf.kind == BSDF_LAMBERT && depth + 3u <= params.max_depth;
}

// The camera walk's `chain` after scattering at a vertex (`Integrator::li_walk`).
fn sppm_chain_next(chain: u32, gathered: bool, delta: bool) -> u32 {
    if gathered {
        return 1u;
    }
    if delta && chain > 0u {
        return chain + 1u;
    }
    return 0u;
}

// Light reached from a gather vertex through k ≥ 1 specular vertices is the photons'.
fn sppm_leaves_out(chain: u32) -> bool {
    return HAS_SPPM && chain >= 2u;
}
