// chain.wgsl — the polarised camera walk's Mueller chain on the GPU (issue 38), twin of
// src/cpu/polarized/chain.rs, kept as one row of it: the row r = f · C of the filter in front
// of the sensor (f, row 0 of its Mueller matrix; (1, 0, 0, 0) without a filter) times the
// chain C of the events met so far (Wilkie & Weidlich 2012, "Polarised Light in Computer
// Graphics", §3.4 and §5). Emitters and the environment are unpolarised, so light (L, 0, 0, 0)
// arriving along the current segment passes r₀ L to the sensor: the CPU computes C's first
// column and then f · S, the GPU carries f · C instead — four numbers per colour lane rather
// than sixteen, the same sums in another order. The Stokes views (DoP, AoP) need all of C's
// first column: four renders behind four analysers (`GpuRenderer::set_analyzer`,
// src/cli/gpu_stokes.rs).
//
// Frames as in chain.rs: `x` is the reference vector of the current segment (⊥ it); at a
// vertex the light leaves along wo (world), s = the normal of the plane of (wi, wo), and the
// row turns from x to s about wo (the rotator R(θ), `math::mueller::rotator`), takes the
// event (polarized.wgsl) and continues with x = s.

override HAS_POLARIZATION: bool = false;

// Whether every colour lane of the row holds the same numbers: it starts so (the filter's
// row in each lane) and only a conductor's per-lane complex IOR makes the lanes differ
// (dielectrics, the ideal conductor and the depolariser have one matrix for all lanes; a
// dispersive interface refracts the hero wavelength's η, as on the CPU). Then the row is
// read from lane 0 alone (`pol_lanes`), so the compiler keeps 4 numbers across the bounce
// loop instead of 16 (RADV navi21: the polarised kernels of rough-glass 160 → 144 VGPRs,
// prism 160 → 128, cornell-glass 128 → 112).
override POL_LANES_UNIFORM: bool = !HAS_CONDUCTOR;

struct PolRow {
    // r = (I, Q, U, V) components, one vec4 across the colour lanes each.
    i: vec4<f32>,
    q: vec4<f32>,
    u: vec4<f32>,
    v: vec4<f32>,
    x: vec3<f32>,
}

// The row as its lanes are known to be: lane 0 in every lane where POL_LANES_UNIFORM.
fn pol_lanes(r: PolRow) -> PolRow {
    if POL_LANES_UNIFORM {
        return PolRow(vec4<f32>(r.i.x), vec4<f32>(r.q.x), vec4<f32>(r.u.x), vec4<f32>(r.v.x), r.x);
    }
    return r;
}

// Glam's `any_orthonormal_vector` (Duff et al. 2017, "Building an Orthonormal Basis,
// Revisited"), so that both twins choose the same frame at normal incidence.
fn pol_any_orthonormal(d: vec3<f32>) -> vec3<f32> {
    let sign = select(1.0, -1.0, d.z < 0.0);
    let a = -1.0 / (sign + d.z);
    let b = d.x * d.y * a;
    return vec3<f32>(b, sign + d.y * d.y * a, -d.y);
}

// `v` normalised, or None (w = 0) when |v|² ≤ 1e-12 (chain.rs `s_vector`'s `unit`).
fn pol_unit(v: vec3<f32>) -> vec4<f32> {
    let l2 = dot3(v, v);
    if l2 > 1e-12 {
        return vec4<f32>(v / sqrt(l2), 1.0);
    }
    return vec4<f32>(0.0);
}

// The row leaving the camera along `dir` behind the filter row `f`, its x the camera's
// right axis made ⊥ the ray (`MuellerChain::camera`).
fn pol_camera(dir: vec3<f32>, right: vec3<f32>, f: vec4<f32>) -> PolRow {
    var x = pol_unit(right - dot3(right, dir) * dir);
    if x.w == 0.0 {
        x = vec4<f32>(pol_any_orthonormal(dir), 1.0);
    }
    return PolRow(vec4<f32>(f.x), vec4<f32>(f.y), vec4<f32>(f.z), vec4<f32>(f.w), x.xyz);
}

// The s vector of a scattering event (`s_vector`): the unit normal of the plane of (wi, wo);
// that of (n, wo) when they are parallel; any unit vector ⊥ wo at normal incidence.
fn pol_s_vector(wi: vec3<f32>, wo: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    let a = pol_unit(cross3(wi, wo));
    if a.w != 0.0 {
        return a.xyz;
    }
    let b = pol_unit(cross3(n, wo));
    if b.w != 0.0 {
        return b.xyz;
    }
    return pol_any_orthonormal(wo);
}

// The row in the vertex's outgoing frame s: r · R(θ), θ the angle from s to x about wo
// (`at_vertex`; cos θ = s·x, sin θ = wo·(s × x), both unit and ⊥ wo).
fn pol_at_vertex(row: PolRow, wo: vec3<f32>, s: vec3<f32>) -> PolRow {
    let r = pol_lanes(row);
    let ct = dot3(s, r.x);
    let st = dot3(wo, cross3(s, r.x));
    let c2 = ct * ct - st * st;
    let s2 = 2.0 * st * ct;
    // Row times the rotator's rows (1,0,0,0), (0,c,s,0), (0,−s,c,0), (0,0,0,1).
    return PolRow(r.i, r.q * c2 - r.u * s2, r.q * s2 + r.u * c2, r.v, s);
}

// The row after the event `m` at a vertex (light in along −wi, out along wo, world; n the
// shading normal): r · R · M, and x = s (`MuellerChain::scatter`).
fn pol_scatter(r: PolRow, wo: vec3<f32>, wi: vec3<f32>, n: vec3<f32>, m: Mueller) -> PolRow {
    let h = pol_at_vertex(r, wo, pol_s_vector(wi, wo, n));
    return PolRow(h.i + h.q * m.b, h.i * m.b + h.q * m.a, h.u * m.c - h.v * m.s, h.u * m.s + h.v * m.c, h.x);
}

// The factor per lane on the scalar BSDF value `f` of a next-event connection whose glossy
// part is `f_g` with m₀₁ = `b` (`MuellerChain::through` with `eval_mueller`: D f_d + G f_g,
// first column (1, 0, 0, 0) for D and (1, b, 0, 0) for G): r₀ f + (r R)_Q b f_g.
fn pol_through(r: PolRow, wo: vec3<f32>, wi: vec3<f32>, n: vec3<f32>, b: vec4<f32>, f: vec4<f32>, f_g: vec4<f32>) -> vec4<f32> {
    let h = pol_at_vertex(r, wo, pol_s_vector(wi, wo, n));
    return h.i * f + h.q * b * f_g;
}
