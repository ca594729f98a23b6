// interaction.wgsl — the per-vertex step shared by every GPU walk (the camera walk in
// integrator.wgsl and the light walk in light_tracing.wgsl): normal orientation, the
// consistency of a sampled event with the geometric normal, spawning rays off the surface,
// the medium stack with Beer–Lambert transmittance, and Russian roulette.

// Absorption inside solid glass (a slider on it, so keyed by the kind).
override HAS_ABSORPTION: bool = true;
// A material has a tangent-space normal map (the vertices carry tangents).
override HAS_NORMAL_MAP: bool = true;

// No absorbing medium around the ray (the medium is a material index otherwise).
const NO_MEDIUM: u32 = 0xffffffffu;

// The shading normal n (interpolated, unit) bent by material `m`'s normal map at uv, with the
// tangent interpolated by the barycentrics w (`perturb_normal`); n itself when the material has
// none or the vertices no tangent frame, or when the map bends it below the interpolated
// surface. Twin of `cpu::interaction::normal_mapped`.
fn normal_mapped(m: u32, va: Vertex, vb: Vertex, vc: Vertex, w: vec3<f32>, n: vec3<f32>, uv: vec2<f32>) -> vec3<f32> {
    let mat = materials[m];
    if !HAS_NORMAL_MAP || mat.normal_tex == NO_TEXTURE {
        return n;
    }
    let t = vec4<f32>(v3(va.tangent), va.tangent_w) * w.x + vec4<f32>(v3(vb.tangent), vb.tangent_w) * w.y + vec4<f32>(v3(vc.tangent), vc.tangent_w) * w.z;
    // The bitangent sign is per vertex (±1); a triangle's corners share it (MikkTSpace).
    let texel = sample_texture(mat.normal_tex, uv).xyz;
    let p = perturb_normal(n, vec4<f32>(t.xyz, va.tangent_w), texel, mat.normal_scale);
    if p.w > 0.0 && dot3(p.xyz, n) > 0.0 {
        return p.xyz;
    }
    return n;
}

struct Oriented {
    ok: bool,
    ng: vec3<f32>,
    ns: vec3<f32>,
}

// Orient normals: opaque double-sided materials shade both sides alike; one-sided opaque back
// faces are black (ok = false: the walk ends); dielectrics keep the outward normal (eta
// convention).
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

// What a BSDF-sampling step decided (the walks' scatter steps return these too).
const STEP_CONTINUE: u32 = 0u;
const STEP_BREAK: u32 = 1u;
const STEP_POISON: u32 = 2u;

// What a BSDF sample at an interaction leads to (twin of `Bounce`): STEP_CONTINUE along
// wi_w (world; side_i = ωi·ng); STEP_BREAK when there is no valid direction (no sample, or
// one inconsistent with the geometric normal); STEP_POISON when the BSDF returned a
// non-finite weight (the sample must be dropped and counted).
struct Bounce {
    step: u32,
    s: BsdfSample,
    wi_w: vec3<f32>,
    side_i: f32,
}

// Sample the BSDF and check the event against the geometric normal ng (twin of
// `Interaction::sample`; wo_w = ωo in world space, wo in the shading frame).
fn interaction_sample(bsdf: Bsdf, frame: Frame, ng: vec3<f32>, wo_w: vec3<f32>, wo: vec3<f32>, uc: f32, u2: vec2<f32>, mode: u32) -> Bounce {
    let s = bsdf_sample(bsdf, wo, uc, u2, mode);
    if !s.valid {
        return Bounce(STEP_BREAK, s, vec3<f32>(0.0), 0.0);
    }
    let wi_w = frame_to_world(frame, s.wi);
    let side_i = dot3(wi_w, ng);
    let consistent = event_is_consistent(s.event, dot3(wo_w, ng), side_i);
    if !is_finite_v4(s.weight) {
        return Bounce(STEP_POISON, s, wi_w, side_i);
    }
    if !consistent {
        return Bounce(STEP_BREAK, s, wi_w, side_i);
    }
    return Bounce(STEP_CONTINUE, s, wi_w, side_i);
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

// Nested dielectrics (cpu::medium, Schmidt & Budge 2002): the volumes a path is inside,
// oldest first. The medium is the highest-priority entry, the last among equals; a volume's
// surface is a real interface when the volume is (or becomes) that medium and refracts with
// η = n(volume)/n(enclosing); otherwise it is a false hit the ray passes. A push onto a full
// stack forgets the outermost entry. Without HAS_NESTED only ids.x is used: the one-level rule
// (entering makes a volume the medium, leaving any returns to air), as before nesting.
override HAS_NESTED: bool = false;

struct MediumStack {
    ids: vec4<u32>,
    len: u32,
}

// A path in air.
fn medium_stack_new() -> MediumStack {
    return MediumStack(vec4<u32>(NO_MEDIUM), 0u);
}

// Index of the medium among the entries (highest priority, the last among equals);
// MEDIUM_STACK_DEPTH when there is none.
fn medium_stack_top(s: MediumStack) -> u32 {
    var best = MEDIUM_STACK_DEPTH;
    var bp = 0i;
    for (var i = 0u; i < s.len; i++) {
        let p = materials[s.ids[i]].priority;
        if best == MEDIUM_STACK_DEPTH || p >= bp {
            best = i;
            bp = p;
        }
    }
    return best;
}

// The medium the path travels in (NO_MEDIUM = air).
fn medium_current(s: MediumStack) -> u32 {
    if !HAS_NESTED {
        return s.ids.x;
    }
    let i = medium_stack_top(s);
    if i == MEDIUM_STACK_DEPTH {
        return NO_MEDIUM;
    }
    return s.ids[i];
}

// The stack with volume `m` entered (overflow forgets the outermost entry).
fn medium_stack_pushed(s: MediumStack, m: u32) -> MediumStack {
    if !HAS_NESTED {
        return MediumStack(vec4<u32>(m, NO_MEDIUM, NO_MEDIUM, NO_MEDIUM), 1u);
    }
    var r = s;
    if r.len == MEDIUM_STACK_DEPTH {
        r.ids = vec4<u32>(r.ids.y, r.ids.z, r.ids.w, NO_MEDIUM);
        r.len -= 1u;
    }
    r.ids[r.len] = m;
    r.len += 1u;
    return r;
}

// The stack without entry `i`.
fn medium_stack_removed(s: MediumStack, i: u32) -> MediumStack {
    var r = s;
    for (var j = i; j + 1u < MEDIUM_STACK_DEPTH; j++) {
        r.ids[j] = r.ids[j + 1u];
    }
    r.ids.w = NO_MEDIUM;
    r.len -= 1u;
    return r;
}

// What crossing a solid's surface does (twin of `Crossing`): a real interface or a false hit,
// the medium on the volume's other side (η = n(volume)/n(enclosing)), the stack after it.
struct Crossing {
    real: bool,
    enclosing: u32,
    after: MediumStack,
}

// Crossing the surface of solid `m`, entering it when `entering` (MediumStack::crossing).
fn medium_crossing(s: MediumStack, m: u32, entering: bool) -> Crossing {
    if !HAS_NESTED {
        if entering {
            return Crossing(true, NO_MEDIUM, medium_stack_pushed(s, m));
        }
        return Crossing(true, NO_MEDIUM, medium_stack_new());
    }
    if entering {
        let enc = medium_current(s);
        let real = enc == NO_MEDIUM || materials[m].priority >= materials[enc].priority;
        return Crossing(real, enc, medium_stack_pushed(s, m));
    }
    var i = MEDIUM_STACK_DEPTH;
    for (var j = 0u; j < s.len; j++) {
        if s.ids[j] == m {
            i = j;
        }
    }
    if i == MEDIUM_STACK_DEPTH {
        return Crossing(true, medium_current(s), s);
    }
    let after = medium_stack_removed(s, i);
    return Crossing(medium_stack_top(s) == i, medium_current(after), after);
}

// What the surface of material `material` (raw outward normal `ng`) is to a path with stack
// `s` travelling along `d` (PathState::interface): solids cross, other surfaces are real
// interfaces with the current medium on their far side.
fn medium_interface(s: MediumStack, mat: Material, material: u32, d: vec3<f32>, ng: vec3<f32>) -> Crossing {
    if (mat.flags & MAT_SOLID) == 0u {
        return Crossing(true, medium_current(s), s);
    }
    return medium_crossing(s, material, dot3(d, ng) < 0.0);
}

// The stack after a transmission through material `material` (index): entering a solid when
// the new direction points against the outward normal `ng`, leaving it otherwise; other
// surfaces keep it (cpu::medium::medium_after_transmit).
fn medium_after_transmit(s: MediumStack, mat: Material, material: u32, wi_w: vec3<f32>, ng: vec3<f32>) -> MediumStack {
    return medium_interface(s, mat, material, wi_w, ng).after;
}

// The medium a segment leaving a surface along `w` travels in, for a path that arrived from
// `w_prev` with stack `s`: the same medium on the arrival side of `ng`, the transmitted one
// across it (cpu::medium::medium_towards). NEE shadow rays and light-tracing connections.
fn medium_towards(s: MediumStack, mat: Material, material: u32, ng: vec3<f32>, w_prev: vec3<f32>, w: vec3<f32>) -> u32 {
    if dot3(w, ng) * dot3(w_prev, ng) > 0.0 {
        return medium_current(s);
    }
    return medium_current(medium_after_transmit(s, mat, material, w, ng));
}

// The relative IOR at dielectric `mat` with `enclosing` (a medium, NO_MEDIUM = air) on its far
// side: η = n(inside)/n(enclosing), at the hero wavelength when either disperses; `dispersive`:
// only the hero lane follows the sampled direction. Twin of the eta in `Interaction::new`.
struct InterfaceEta {
    eta: f32,
    dispersive: bool,
}

fn interface_eta(mat: Material, enclosing: u32, sp: Spectral) -> InterfaceEta {
    var dispersive = material_is_dispersive(mat, sp);
    var outer = NO_MEDIUM;
    if HAS_NESTED && (mat.flags & MAT_TRANSMISSIVE) != 0u {
        outer = enclosing;
    }
    if outer != NO_MEDIUM && HAS_SPECTRAL && sp.on && materials[outer].abbe > 0.0 {
        dispersive = true;
    }
    var eta = mat.eta;
    if dispersive {
        eta = material_ior_at(mat, sp.lambdas.x);
    }
    if outer != NO_MEDIUM {
        let om = materials[outer];
        var n = om.eta;
        if HAS_SPECTRAL && sp.on {
            n = material_ior_at(om, sp.lambdas.x);
        }
        eta /= n;
    }
    return InterfaceEta(eta, dispersive);
}

// Ray origin at p, pushed off the surface to the side the new direction leaves on
// (side_i = ωi·ng). Wächter & Binder 2019 offsets (`offset_ray_origin`).
fn offset_ray_origin_towards(p: vec3<f32>, ng: vec3<f32>, side_i: f32) -> vec3<f32> {
    if side_i > 0.0 {
        return offset_ray_origin(p, ng);
    }
    return offset_ray_origin(p, -ng);
}

// A ray segment origin + t·dir, t ∈ (0, tmax).
struct Ray {
    o: vec3<f32>,
    d: vec3<f32>,
    tmax: f32,
}

// Shadow ray from the surface point p (geometric normal ng, leaving on the side side_i =
// ωi·ng) to a light sample: both ends offset off their surfaces (t ∈ (0, 1) spans the
// segment), or to infinity along wi. PBR 4th ed. §6.8.6 (`SpawnRayTo`); Wächter & Binder 2019.
fn spawn_ray_to_light(p: vec3<f32>, ng: vec3<f32>, side_i: f32, ls: LightLiSample) -> Ray {
    let origin = offset_ray_origin_towards(p, ng, side_i);
    if ls.infinite {
        return Ray(origin, ls.wi, F32_MAX);
    }
    let pl = p + (ls.p_light - p);
    if ls.is_delta {
        return Ray(origin, pl - origin, 1.0);
    }
    var tn = -ls.n_light;
    if dot3(ls.n_light, -ls.wi) > 0.0 {
        tn = ls.n_light;
    }
    return Ray(origin, offset_ray_origin(pl, tn) - origin, 1.0);
}

// Russian roulette (Mitsuba 3 `path`): from depth `rr_depth` the path survives with
// probability q = min(max(β)·η², 0.95) (one dimension); before it, a path with β = 0 ends.
// Returns the factor to divide β by (1 before rr_depth); 0 = the path ends.
fn russian_roulette(beta: vec4<f32>, eta_scale: f32, depth: u32, sampler: ptr<function, Sampler>) -> f32 {
    if depth >= params.rr_depth {
        let q = min(max_element4(beta) * eta_scale, 0.95);
        if q <= 0.0 || sampler_next_1d(sampler) >= q {
            return 0.0;
        }
        return q;
    }
    if max_element4(beta) <= 0.0 {
        return 0.0;
    }
    return 1.0;
}
