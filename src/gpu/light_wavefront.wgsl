// light_wavefront.wgsl — the light subpaths of lt+pt (`light_trace`, light_tracing.wgsl) as a
// wavefront, like the camera walk's (wavefront.wgsl): the walk's state in memory between
// kernels, one light vertex per dispatch. `lt_wf_start` starts the subpaths, then per bounce
// `lt_wf_extend` traces each live subpath's ray (`wf_extend`'s twin), `lt_wf_shade` runs the
// vertex (`lt_vertex`, `WALK_SHADE`: its camera connection computed up to the shadow ray,
// then the BSDF sample and roulette) and `lt_wf_splat` traces the connection's shadow ray and
// splats; `lt_wf_finish` adds the rejected splats to the counters. The same operations on the
// same random numbers as `light_trace`; the splats are integer atomics, so their order does
// not change the film. Path g of a chunk is light subpath k = g mod batch of pixel g / batch
// (its seed), as in `light_trace`.

// The state of one light subpath between kernels (`LightWalk`, its colour lanes and sampler;
// bools as u32), the closest hit of its ray and its pending camera connection.
struct LtPath {
    beta: vec4<f32>,
    lambdas: vec4<f32>,
    media_ids: vec4<u32>,
    syms: vec4<u32>,
    // The ray's closest hit: bits of t, leaf slot (WF_NO_HIT: none), bits of b1 and b2.
    hit: vec4<u32>,
    o: vec3<f32>,
    sp_on: u32,
    d: vec3<f32>,
    collapsed: u32,
    // The pending connection: shadow-ray origin, value, film pixel, whether there is one.
    splat_origin: vec3<f32>,
    splat_pixel: u32,
    splat_v: vec3<f32>,
    splat_ok: u32,
    m: u32,
    p_light: f32,
    area_light: u32,
    cos_emit: f32,
    pl_prev: f32,
    pl_cur: f32,
    cos_prev: f32,
    t2: f32,
    prod: f32,
    pc_y0: f32,
    y1_delta: u32,
    prev_pdf: f32,
    prev_delta: u32,
    cos_out: f32,
    media_len: u32,
    false_hits: u32,
    t_pass: f32,
    status: u32,
    rejected: u32,
    s_base: u32,
    s_dim: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

@group(0) @binding(15) var<storage, read_write> lt_paths: array<LtPath>;

fn lt_wf_load(i: u32) -> LightWalk {
    let p = lt_paths[i];
    var lw: LightWalk;
    lw.beta = p.beta;
    lw.collapsed = p.collapsed != 0u;
    lw.m = p.m;
    lw.p_light = p.p_light;
    lw.area_light = p.area_light != 0u;
    lw.cos_emit = p.cos_emit;
    lw.pl_prev = p.pl_prev;
    lw.pl_cur = p.pl_cur;
    lw.cos_prev = p.cos_prev;
    lw.t2 = p.t2;
    lw.prod = p.prod;
    lw.pc_y0 = p.pc_y0;
    lw.y1_delta = p.y1_delta != 0u;
    lw.syms = SymString(array<u32, 4>(p.syms.x, p.syms.y, p.syms.z, p.syms.w));
    lw.o = p.o;
    lw.d = p.d;
    lw.prev_pdf = p.prev_pdf;
    lw.prev_delta = p.prev_delta != 0u;
    lw.cos_out = p.cos_out;
    lw.media = MediumStack(p.media_ids, p.media_len);
    lw.false_hits = p.false_hits;
    lw.t_pass = p.t_pass;
    return lw;
}

fn lt_wf_store(i: u32, lw: LightWalk, s: Sampler) {
    lt_paths[i].beta = lw.beta;
    lt_paths[i].collapsed = u32(lw.collapsed);
    lt_paths[i].m = lw.m;
    lt_paths[i].p_light = lw.p_light;
    lt_paths[i].area_light = u32(lw.area_light);
    lt_paths[i].cos_emit = lw.cos_emit;
    lt_paths[i].pl_prev = lw.pl_prev;
    lt_paths[i].pl_cur = lw.pl_cur;
    lt_paths[i].cos_prev = lw.cos_prev;
    lt_paths[i].t2 = lw.t2;
    lt_paths[i].prod = lw.prod;
    lt_paths[i].pc_y0 = lw.pc_y0;
    lt_paths[i].y1_delta = u32(lw.y1_delta);
    lt_paths[i].syms = vec4<u32>(lw.syms.w[0], lw.syms.w[1], lw.syms.w[2], lw.syms.w[3]);
    lt_paths[i].o = lw.o;
    lt_paths[i].d = lw.d;
    lt_paths[i].prev_pdf = lw.prev_pdf;
    lt_paths[i].prev_delta = u32(lw.prev_delta);
    lt_paths[i].cos_out = lw.cos_out;
    lt_paths[i].media_ids = lw.media.ids;
    lt_paths[i].media_len = lw.media.len;
    lt_paths[i].false_hits = lw.false_hits;
    lt_paths[i].t_pass = lw.t_pass;
    lt_paths[i].s_base = s.base;
    lt_paths[i].s_dim = s.dim;
}

fn lt_wf_spectral(i: u32) -> Spectral {
    return Spectral(lt_paths[i].sp_on != 0u, lt_paths[i].lambdas);
}

// Light subpath i of the chunk leaves its light (`light_trace`'s start of a subpath) and,
// when it does, joins the first queue (`WfQueue`, shared with the camera wavefront).
@compute @workgroup_size(64, 1, 1)
fn lt_wf_start(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) lane: u32) {
    let i = gid.x;
    var live = false;
    if HAS_LT && i < wf_path_count() {
        live = lt_wf_begin(i);
    }
    wf_enqueue(i, live, lane);
}

// `lt_wf_start` for subpath i: whether it left its light.
fn lt_wf_begin(i: u32) -> bool {
    OFFSET_SCALE = params.offset_scale;
    var sampler = sampler_new(wf_pixel(i), params.sample_offset + (wf_chunk.first + i) % params.batch, params.seed ^ LT_SEED_MIX);
    var lw: LightWalk;
    var sp: Spectral;
    let live = lt_begin(&sampler, &lw, &sp);
    lt_wf_store(i, lw, sampler);
    lt_paths[i].lambdas = sp.lambdas;
    lt_paths[i].sp_on = u32(sp.on);
    lt_paths[i].status = select(WF_DONE, WF_LIVE, live);
    lt_paths[i].splat_ok = 0u;
    lt_paths[i].rejected = 0u;
    return live;
}

// The closest hit of each queued subpath's ray.
@compute @workgroup_size(64, 1, 1)
fn lt_wf_extend(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) lane: u32) {
    LANE = lane;
    segments = 0u;
    let i = wf_queued(gid.x);
    if HAS_LT && i != WF_NO_PATH {
        lt_paths[i].hit = wf_closest_hit(lt_paths[i].o, lt_paths[i].d);
        segments = 1u;
    }
    add_counters_workgroup(0u, segments);
}

// Each queued subpath's vertex: its camera connection left for `lt_wf_splat`, then the BSDF
// sample and roulette.
@compute @workgroup_size(64, 1, 1)
fn lt_wf_shade(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = wf_queued(gid.x);
    if !HAS_LT || i == WF_NO_PATH {
        return;
    }
    OFFSET_SCALE = params.offset_scale;
    var lw = lt_wf_load(i);
    var sampler = Sampler(lt_paths[i].s_base, lt_paths[i].s_dim);
    var rejected = lt_paths[i].rejected;
    let h = wf_decode_hit(lt_paths[i].hit);
    LT_SPLAT = LtSplat(false, 0u, vec3<f32>(0.0), vec3<f32>(0.0));
    let v = lt_vertex(&lw, &sampler, lt_wf_spectral(i), h, WALK_SHADE, &rejected);
    lt_wf_store(i, lw, sampler);
    lt_paths[i].rejected = rejected;
    lt_paths[i].splat_ok = u32(LT_SPLAT.ok);
    lt_paths[i].splat_pixel = LT_SPLAT.pixel;
    lt_paths[i].splat_origin = LT_SPLAT.origin;
    lt_paths[i].splat_v = LT_SPLAT.v;
    if v != VERTEX_NEXT {
        lt_paths[i].status = WF_DONE;
    }
}

// The pending connections' shadow rays to the camera (of the bounce's queue, whose vertices
// `lt_wf_shade` just ran); an unoccluded one is splatted. Then the subpaths that go on join
// the next queue.
@compute @workgroup_size(64, 1, 1)
fn lt_wf_splat(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) lane: u32) {
    LANE = lane;
    let i = wf_queued(gid.x);
    var next = false;
    if HAS_LT && i != WF_NO_PATH {
        lt_wf_splat_path(i);
        next = lt_paths[i].status == WF_LIVE;
    }
    wf_enqueue(i, next, lane);
}

fn lt_wf_splat_path(i: u32) {
    if lt_paths[i].splat_ok == 0u {
        return;
    }
    lt_paths[i].splat_ok = 0u;
    let s = LtSplat(true, lt_paths[i].splat_pixel, lt_paths[i].splat_origin, lt_paths[i].splat_v);
    if !bvh_occluded(s.origin, params.cam_pos.xyz - s.origin, 1.0) {
        lt_paths[i].rejected += lt_splat_add(s);
    }
}

// The subpaths' rejected splats into the dropped-sample counter (`light_trace`'s count).
@compute @workgroup_size(64, 1, 1)
fn lt_wf_finish(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) lane: u32) {
    LANE = lane;
    var rejected = 0u;
    let i = gid.x;
    if HAS_LT && i < wf_path_count() {
        rejected = lt_paths[i].rejected;
    }
    add_counters_workgroup(rejected, 0u);
}
