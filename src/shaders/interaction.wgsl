// interaction.wgsl — the per-vertex step shared by every GPU walk (the camera walk in
// integrator.wgsl and the light walk in light_tracing.wgsl): normal orientation, the
// consistency of a sampled event with the geometric normal, spawning rays off the surface,
// the medium stack with Beer–Lambert transmittance, and Russian roulette.

// Absorption inside solid glass (a slider on it, so keyed by the kind).
override HAS_ABSORPTION: bool = true;

// No absorbing medium around the ray (the medium is a material index otherwise).
const NO_MEDIUM: u32 = 0xffffffffu;

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

// The medium after a transmission through material `material` (index) of a solid: entering
// when the new direction points against the outward normal `ng`, leaving otherwise.
fn medium_after_transmit(medium: u32, mat: Material, material: u32, wi_w: vec3<f32>, ng: vec3<f32>) -> u32 {
    if (mat.flags & MAT_SOLID) == 0u {
        return medium;
    }
    if dot3(wi_w, ng) < 0.0 {
        return material;
    }
    return NO_MEDIUM;
}

// The medium a segment leaving a surface along `w` travels in, for a path that arrived from
// `w_prev` in `medium`: the same medium on the arrival side of `ng`, the transmitted one
// across it (cpu::medium::medium_towards). NEE shadow rays and light-tracing connections.
fn medium_towards(medium: u32, mat: Material, material: u32, ng: vec3<f32>, w_prev: vec3<f32>, w: vec3<f32>) -> u32 {
    if dot3(w, ng) * dot3(w_prev, ng) > 0.0 {
        return medium;
    }
    return medium_after_transmit(medium, mat, material, w, ng);
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
