// wavefront.wgsl — the camera walk of `render` split into kernels with the path state in
// memory between them (Laine, Karras & Aila 2013, "Megakernels Considered Harmful: Wavefront
// Path Tracing on GPUs"). The megakernel carries every path's state in registers around its
// bounce loop; with every feature compiled in that is 216 VGPRs on RDNA2 (4 waves per SIMD),
// while one bounce with the state loaded and stored needs 112 (README "Register pressure").
//
// A submission covers the paths of its rows from `tile_y0`, `batch` per pixel:
// path g is sample k = g mod batch of pixel g / batch of the band. They run in chunks of whole
// pixels (`wf_chunk`: a uniform bound at a dynamic offset per chunk) whose states fit one
// buffer; thread i of a chunk runs path g = wf_chunk.first + i. `wf_start` starts them;
// then, `max_depth` (+ false hits) times: `wf_extend` traces each live path's ray,
// `wf_nee` computes next-event estimation at the vertex from the state before the bounce,
// `wf_shade` runs the rest of the vertex (`integrator_vertex`, `WALK_SHADE`) and `wf_connect`
// traces the estimate's shadow ray and adds it — the megakernel's operations, in its order,
// on the same random numbers; `wf_finish` then folds each pixel's `batch` samples into the
// film exactly as `render_pixel` does. Images are the megakernel's, bit for bit.

// The state of one path between kernels: `PathState` and its sampler (bools as u32), the
// closest hit of its ray and its pending next-event estimate.
struct WfPath {
    lambdas: vec4<f32>,
    l: vec4<f32>,
    beta: vec4<f32>,
    media_ids: vec4<u32>,
    // The ray's closest hit: bits of t, leaf slot (WF_NO_HIT: none), bits of b1 and b2.
    hit: vec4<u32>,
    // The pending next-event estimate (0: none) and its shadow ray.
    nee_c: vec4<f32>,
    o: vec3<f32>,
    sp_on: u32,
    d: vec3<f32>,
    collapsed: u32,
    nee_o: vec3<f32>,
    nee_tmax: f32,
    nee_d: vec3<f32>,
    status: u32,
    prev_pdf: f32,
    prev_delta: u32,
    eta_scale: f32,
    media_len: u32,
    false_hits: u32,
    t_pass: f32,
    depth: u32,
    q: u32,
    chain: u32,
    lt_ok: u32,
    lt_first: u32,
    lt_prod: f32,
    lt_pf_prev: f32,
    lt_pf_cur: f32,
    lt_cos_prev: f32,
    lt_t_prev: f32,
    s_base: u32,
    s_dim: u32,
    _pad0: u32,
    _pad1: u32,
}

@group(0) @binding(13) var<storage, read_write> wf_paths: array<WfPath>;

// The chunk of the submission's paths this dispatch runs (`first` a multiple of `batch`).
struct WfChunk {
    first: u32,
    count: u32,
    _pad0: u32,
    _pad1: u32,
}

@group(0) @binding(14) var<uniform> wf_chunk: WfChunk;

// The live paths of the running chunk, compacted bounce by bounce (the queues of Laine,
// Karras & Aila 2013: each kernel runs one thread per queued path, not one per path ever
// started). Two queues alternate: the running bounce's (parity `cur`), read by its kernels,
// and the next one's, to which the bounce's last kernel (`wf_connect`, `lt_wf_splat`) and
// the start kernels append the paths that go on. `wf_advance` then makes the next queue
// current and writes its dispatch size to `wf_args`, the indirect argument of the next
// bounce's kernels (bound in a group of `wf_advance`'s own: a buffer the running kernel binds
// as storage cannot be its indirect argument). Shared by the light wavefront, which runs
// before the camera one.
struct WfQueue {
    count: array<atomic<u32>, 2>,
    cur: u32,
    _pad: u32,
    // Parity p's queue at [p · capacity, (p + 1) · capacity).
    items: array<u32>,
}

@group(0) @binding(16) var<storage, read_write> wf_queue: WfQueue;
// (workgroups, 1, 1, queued paths) of the running bounce.
@group(1) @binding(0) var<storage, read_write> wf_args: vec4<u32>;

fn wf_queue_capacity() -> u32 {
    return arrayLength(&wf_queue.items) / 2u;
}

// The path that thread j of a bounce's kernel runs, or WF_NO_PATH past the queue's end.
fn wf_queued(j: u32) -> u32 {
    let cur = wf_queue.cur;
    if j >= atomicLoad(&wf_queue.count[cur]) {
        return WF_NO_PATH;
    }
    return wf_queue.items[cur * wf_queue_capacity() + j];
}

// Append path i to the next bounce's queue when `keep`: lane 0 numbers the workgroup's
// kept paths and reserves their slots with one global atomic add. The lanes' flags and slots
// live in the traversal stack's workgroup memory, as in `add_counters_workgroup` (more
// workgroup memory would cost occupancy): each lane first writes only its own entry 0 (at
// index `lane`), and lane 0 touches the others' entries after the barrier, when every lane's
// traversal is done. Every lane of the workgroup must call it (it holds barriers).
fn wf_enqueue(i: u32, keep: bool, lane: u32) {
    BVH_STACK[lane] = u32(keep);
    workgroupBarrier();
    if lane == 0u {
        var n = 0u;
        for (var l = 0u; l < WORKGROUP_LANES; l++) {
            let k = BVH_STACK[l];
            BVH_STACK[l] = n;
            n += k;
        }
        var base = 0u;
        if n > 0u {
            base = atomicAdd(&wf_queue.count[1u - wf_queue.cur], n);
        }
        BVH_STACK[WORKGROUP_LANES] = base;
    }
    workgroupBarrier();
    if keep {
        let slot = BVH_STACK[WORKGROUP_LANES] + BVH_STACK[lane];
        wf_queue.items[(1u - wf_queue.cur) * wf_queue_capacity() + slot] = i;
    }
}

// Between bounces (one thread): the next queue becomes the running one.
@compute @workgroup_size(1, 1, 1)
fn wf_advance() {
    let cur = wf_queue.cur;
    let next = 1u - cur;
    let n = atomicLoad(&wf_queue.count[next]);
    wf_args = vec4<u32>((n + 63u) / 64u, 1u, 1u, n);
    atomicStore(&wf_queue.count[cur], 0u);
    wf_queue.cur = next;
}

// `WfPath.status`.
const WF_LIVE: u32 = 0u;
const WF_DONE: u32 = 1u;
const WF_POISONED: u32 = 2u;
const WF_NO_HIT: u32 = 0xffffffffu;
const WF_NO_PATH: u32 = 0xffffffffu;

fn wf_path_count() -> u32 {
    return wf_chunk.count;
}

// Image pixel (linear) of the chunk's path i.
fn wf_pixel(i: u32) -> u32 {
    return params.tile_y0 * params.width + (wf_chunk.first + i) / params.batch;
}

fn wf_load(i: u32) -> PathState {
    let w = wf_paths[i];
    var ps: PathState;
    ps.sp = Spectral(w.sp_on != 0u, w.lambdas);
    ps.collapsed = w.collapsed != 0u;
    ps.l = w.l;
    ps.beta = w.beta;
    ps.o = w.o;
    ps.d = w.d;
    ps.prev_pdf = w.prev_pdf;
    ps.prev_delta = w.prev_delta != 0u;
    ps.eta_scale = w.eta_scale;
    ps.media = MediumStack(w.media_ids, w.media_len);
    ps.false_hits = w.false_hits;
    ps.t_pass = w.t_pass;
    ps.depth = w.depth;
    ps.lt = LtMis(w.lt_ok != 0u, w.lt_first != 0u, w.lt_prod, w.lt_pf_prev, w.lt_pf_cur, w.lt_cos_prev, w.lt_t_prev);
    ps.q = w.q;
    ps.chain = w.chain;
    return ps;
}

fn wf_store(i: u32, ps: PathState, s: Sampler) {
    wf_paths[i].lambdas = ps.sp.lambdas;
    wf_paths[i].sp_on = u32(ps.sp.on);
    wf_paths[i].collapsed = u32(ps.collapsed);
    wf_paths[i].l = ps.l;
    wf_paths[i].beta = ps.beta;
    wf_paths[i].o = ps.o;
    wf_paths[i].d = ps.d;
    wf_paths[i].prev_pdf = ps.prev_pdf;
    wf_paths[i].prev_delta = u32(ps.prev_delta);
    wf_paths[i].eta_scale = ps.eta_scale;
    wf_paths[i].media_ids = ps.media.ids;
    wf_paths[i].media_len = ps.media.len;
    wf_paths[i].false_hits = ps.false_hits;
    wf_paths[i].t_pass = ps.t_pass;
    wf_paths[i].depth = ps.depth;
    wf_paths[i].lt_ok = u32(ps.lt.ok);
    wf_paths[i].lt_first = u32(ps.lt.first);
    wf_paths[i].lt_prod = ps.lt.prod;
    wf_paths[i].lt_pf_prev = ps.lt.pf_prev;
    wf_paths[i].lt_pf_cur = ps.lt.pf_cur;
    wf_paths[i].lt_cos_prev = ps.lt.cos_prev;
    wf_paths[i].lt_t_prev = ps.lt.t_prev;
    wf_paths[i].q = ps.q;
    wf_paths[i].chain = ps.chain;
    wf_paths[i].s_base = s.base;
    wf_paths[i].s_dim = s.dim;
}

fn wf_hit(i: u32) -> Hit {
    return wf_decode_hit(wf_paths[i].hit);
}

// The closest hit of the ray (o, d) in the form a path state stores it (`WfPath.hit`).
fn wf_closest_hit(o: vec3<f32>, d: vec3<f32>) -> vec4<u32> {
    let h = bvh_intersect(o, d, F32_MAX);
    var slot = WF_NO_HIT;
    if h.found {
        slot = h.slot;
    }
    return vec4<u32>(bitcast<u32>(h.t), slot, bitcast<u32>(h.b1), bitcast<u32>(h.b2));
}

fn wf_decode_hit(h: vec4<u32>) -> Hit {
    return Hit(h.y != WF_NO_HIT, bitcast<f32>(h.x), h.y, bitcast<f32>(h.z), bitcast<f32>(h.w));
}

fn wf_sampler(i: u32) -> Sampler {
    return Sampler(wf_paths[i].s_base, wf_paths[i].s_dim);
}

// The debug records of the megakernel: the first sample of the debug pixel.
fn wf_debug(i: u32) {
    debug_on = wf_pixel(i) == params.debug_pixel && (wf_chunk.first + i) % params.batch == 0u;
}

// sppm: path i is sample (first + i) mod batch of its pixel, so it belongs to that iteration
// of the submission and gathers its photons (photon.wgsl `SPPM_ITER`).
fn wf_sppm_iteration(i: u32) {
    if HAS_SPPM {
        SPPM_ITER = (wf_chunk.first + i) % params.batch;
    }
}

// Path i leaves the camera (`render_pixel`'s start of a sample) and joins the first queue.
@compute @workgroup_size(64, 1, 1)
fn wf_start(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) lane: u32) {
    let i = gid.x;
    let started = i < wf_path_count();
    if started {
        wf_begin(i);
    }
    wf_enqueue(i, started, lane);
}

fn wf_begin(i: u32) {
    OFFSET_SCALE = params.offset_scale;
    let pixel = wf_pixel(i);
    let x = pixel % params.width;
    let y = pixel / params.width;
    wf_debug(i);
    wf_sppm_iteration(i);
    var sampler = sampler_new(pixel, params.sample_offset + (wf_chunk.first + i) % params.batch, params.seed);
    let j = sampler_next_2d(&sampler);
    let sx = (f32(x) + j.x) / f32(params.width);
    let sy = (f32(y) + j.y) / f32(params.height);
    let dir = camera_ray_dir(sx, sy);
    debug_write(0u, vec4<f32>(dir, 0.0));
    let ps = path_state_new(params.cam_pos.xyz, dir, &sampler);
    wf_store(i, ps, sampler);
    wf_paths[i].status = WF_LIVE;
    wf_paths[i].nee_c = vec4<f32>(0.0);
}

// The closest hit of each queued path's ray.
@compute @workgroup_size(64, 1, 1)
fn wf_extend(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) lane: u32) {
    LANE = lane;
    segments = 0u;
    let i = wf_queued(gid.x);
    if i != WF_NO_PATH {
        wf_paths[i].hit = wf_closest_hit(wf_paths[i].o, wf_paths[i].d);
        segments = 1u;
    }
    add_counters_workgroup(0u, segments);
}

// Next-event estimation at each queued path's vertex, from a copy of its state (the vertex
// draws its random numbers again in `wf_shade`, from the same sampler state).
@compute @workgroup_size(64, 1, 1)
fn wf_nee(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = wf_queued(gid.x);
    if i == WF_NO_PATH {
        return;
    }
    OFFSET_SCALE = params.offset_scale;
    wf_debug(i);
    var ps = wf_load(i);
    var sampler = wf_sampler(i);
    NEE_RAY = NeeRay(vec4<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0), 0.0);
    integrator_vertex(&ps, &sampler, wf_hit(i), WALK_NEE);
    wf_paths[i].nee_c = NEE_RAY.c;
    wf_paths[i].nee_o = NEE_RAY.o;
    wf_paths[i].nee_d = NEE_RAY.d;
    wf_paths[i].nee_tmax = NEE_RAY.tmax;
}

// The rest of each queued path's vertex: emission, the BSDF sample, Russian roulette.
@compute @workgroup_size(64, 1, 1)
fn wf_shade(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = wf_queued(gid.x);
    if i == WF_NO_PATH {
        return;
    }
    OFFSET_SCALE = params.offset_scale;
    wf_debug(i);
    wf_sppm_iteration(i);
    var ps = wf_load(i);
    var sampler = wf_sampler(i);
    let v = integrator_vertex(&ps, &sampler, wf_hit(i), WALK_SHADE);
    wf_store(i, ps, sampler);
    if v == VERTEX_END {
        wf_paths[i].status = WF_DONE;
    } else if v == VERTEX_POISON {
        wf_paths[i].status = WF_POISONED;
    }
}

// The pending next-event estimates' shadow rays; an unoccluded estimate joins the path's
// radiance after the vertex's emission and gather, as in the megakernel. (A path of the
// bounce's queue that `wf_shade` ended may still have one.) Then the paths that go on join
// the next queue — here rather than in `wf_shade`, whose registers the queue would cost.
@compute @workgroup_size(64, 1, 1)
fn wf_connect(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) lane: u32) {
    LANE = lane;
    let i = wf_queued(gid.x);
    var next = false;
    if i != WF_NO_PATH {
        wf_connect_path(i);
        next = wf_paths[i].status == WF_LIVE;
    }
    wf_enqueue(i, next, lane);
}

fn wf_connect_path(i: u32) {
    let c = wf_paths[i].nee_c;
    if all(c == vec4<f32>(0.0)) {
        return;
    }
    wf_paths[i].nee_c = vec4<f32>(0.0);
    if !bvh_occluded(wf_paths[i].nee_o, wf_paths[i].nee_d, wf_paths[i].nee_tmax) {
        wf_paths[i].l += c;
    }
}

// Each pixel's `batch` samples folded into the film (`render_pixel`'s end).
@compute @workgroup_size(64, 1, 1)
fn wf_finish(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) lane: u32) {
    LANE = lane;
    var dropped = 0u;
    let p = gid.x;
    if p < wf_chunk.count / params.batch {
        var sum = vec3<f32>(0.0);
        for (var k = 0u; k < params.batch; k++) {
            let i = p * params.batch + k;
            wf_debug(i);
            var v = poison();
            if wf_paths[i].status != WF_POISONED {
                v = spectral_to_rgb(Spectral(wf_paths[i].sp_on != 0u, wf_paths[i].lambdas), wf_paths[i].l);
            }
            debug_write(1u + DEBUG_STRIDE * DEBUG_MAX_VERTICES, vec4<f32>(v, f32(wf_paths[i].s_dim)));
            if sample_is_valid(v) {
                sum += v;
            } else {
                dropped++;
            }
        }
        film_fold(wf_pixel(p * params.batch), sum);
    }
    add_counters_workgroup(dropped, 0u);
}
