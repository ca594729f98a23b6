// common.wgsl — constants, small maths, frames, sampling warps and ray offsets shared by every
// kernel. Each function is the twin of the Rust function with the same name (a Rust method
// `Type::method` is `type_method` here) and carries the same citation line.

const PI: f32 = 3.14159265358979323846;
const FRAC_1_PI: f32 = 0.318309886183790671538;
const FRAC_PI_2: f32 = 1.57079632679489661923;
const FRAC_PI_4: f32 = 0.785398163397448309616;
// Largest finite f32: WGSL has no infinity literal; used as "no upper bound" for t.
const F32_MAX: f32 = 3.40282347e38;

// Transport modes (bsdf::TransportMode).
const MODE_RADIANCE: u32 = 0u;
const MODE_IMPORTANCE: u32 = 1u;
// Events (bsdf::Event) and Heckbert lobes (bsdf::Lobe).
const EVENT_REFLECT: u32 = 0u;
const EVENT_TRANSMIT: u32 = 1u;
const LOBE_D: u32 = 0u;
const LOBE_G: u32 = 1u;
const LOBE_S: u32 = 2u;

// True if x is neither NaN nor ±Inf (bit test: immune to fast-math folding).
fn is_finite_f32(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7f800000u) != 0x7f800000u;
}

fn is_finite_v3(v: vec3<f32>) -> bool {
    return is_finite_f32(v.x) && is_finite_f32(v.y) && is_finite_f32(v.z);
}

fn max_element3(v: vec3<f32>) -> f32 {
    return max(max(v.x, v.y), v.z);
}

// glam's evaluation order: x·x' + y·y' + z·z' (left to right), no fused multiply-add intended.
fn dot3(a: vec3<f32>, b: vec3<f32>) -> f32 {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

// glam's cross product component order.
fn cross3(a: vec3<f32>, b: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(a.y * b.z - b.y * a.z, a.z * b.x - b.z * a.x, a.x * b.y - b.x * a.y);
}

// glam's normalize: v · (1/√(v·v)).
fn normalize3(v: vec3<f32>) -> vec3<f32> {
    return v * (1.0 / sqrt(dot3(v, v)));
}

// glam's normalize_or_zero: zero when 1/|v| is not finite or not positive.
fn normalize_or_zero3(v: vec3<f32>) -> vec3<f32> {
    let rcp = 1.0 / sqrt(dot3(v, v));
    if is_finite_f32(rcp) && rcp > 0.0 {
        return v * rcp;
    }
    return vec3<f32>(0.0);
}

fn v3(a: array<f32, 3>) -> vec3<f32> {
    return vec3<f32>(a[0], a[1], a[2]);
}

// ---------------------------------------------------------------------------------------------
// Frames (math::frame)

struct Frame {
    s: vec3<f32>,
    t: vec3<f32>,
    n: vec3<f32>,
}

// Branchless ONB from a unit normal.
// Duff et al. 2017, "Building an Orthonormal Basis, Revisited" (JCGT 6(1)), listing 3.
fn frame_from_normal(n: vec3<f32>) -> Frame {
    // copysign(1, n.z), -0.0 included.
    let sign = bitcast<f32>((bitcast<u32>(n.z) & 0x80000000u) | 0x3f800000u);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    let s = vec3<f32>(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    let t = vec3<f32>(b, sign + n.y * n.y * a, -n.y);
    return Frame(s, t, n);
}

fn frame_to_local(f: Frame, v: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(dot3(v, f.s), dot3(v, f.t), dot3(v, f.n));
}

fn frame_to_world(f: Frame, v: vec3<f32>) -> vec3<f32> {
    return f.s * v.x + f.t * v.y + f.n * v.z;
}

// ---------------------------------------------------------------------------------------------
// Sampling warps (math::sampling)

// Concentric square→disk map. Shirley & Chiu 1997, "A Low Distortion Map Between Disk and Square".
fn concentric_disk(u: vec2<f32>) -> vec2<f32> {
    let o = 2.0 * u - vec2<f32>(1.0);
    if o.x == 0.0 && o.y == 0.0 {
        return vec2<f32>(0.0);
    }
    var r: f32;
    var theta: f32;
    if abs(o.x) > abs(o.y) {
        r = o.x;
        theta = FRAC_PI_4 * (o.y / o.x);
    } else {
        r = o.y;
        theta = FRAC_PI_2 - FRAC_PI_4 * (o.x / o.y);
    }
    return r * vec2<f32>(cos(theta), sin(theta));
}

// Cosine-weighted hemisphere (Malley's method). PBR 4th ed. §A.5.3.
fn cosine_hemisphere(u: vec2<f32>) -> vec3<f32> {
    let d = concentric_disk(u);
    let z = sqrt(max(1.0 - d.x * d.x - d.y * d.y, 0.0));
    return vec3<f32>(d.x, d.y, z);
}

// pdf of `cosine_hemisphere` w.r.t. solid angle: cosθ/π. PBR 4th ed. §A.5.3.
fn cosine_hemisphere_pdf(cos_theta: f32) -> f32 {
    return max(cos_theta, 0.0) * FRAC_1_PI;
}

// Uniform barycentrics on a triangle (b1, b2); b0 = 1 − b1 − b2.
// we use the classic square-root parametrisation, PBR 4th ed. §6.5.4 (Turk 1990).
fn uniform_triangle(u: vec2<f32>) -> vec2<f32> {
    let su0 = sqrt(u.x);
    return vec2<f32>(1.0 - su0, u.y * su0);
}

// Power heuristic with β = 2. Veach 1997, §9.2.4.
fn power_heuristic(pdf_a: f32, pdf_b: f32) -> f32 {
    let a = pdf_a * pdf_a;
    let b = pdf_b * pdf_b;
    if a == 0.0 && b == 0.0 {
        return 0.0;
    }
    if !is_finite_f32(a) {
        return 1.0;
    }
    return a / (a + b);
}

// glTF spot-light angular falloff (KHR_lights_punctual spec, "Spot"): smooth, squared
// linear ramp of cosθ between the outer and inner cone.
fn spot_falloff(cos_theta: f32, cos_inner: f32, cos_outer: f32) -> f32 {
    let scale = 1.0 / max(cos_inner - cos_outer, 1e-3);
    let offset = -cos_outer * scale;
    let a = clamp(cos_theta * scale + offset, 0.0, 1.0);
    return a * a;
}

// ---------------------------------------------------------------------------------------------
// Ray offsets (bvh::offset_ray_origin)

// One coordinate of `offset_ray_origin` (ORIGIN = 1/32, FLOAT_SCALE = 1/65536, INT_SCALE = 256).
fn offset_ray_origin_1(p: f32, n: f32) -> f32 {
    let of_i = i32(256.0 * n);
    let bits = bitcast<i32>(p);
    var moved: i32;
    if p < 0.0 {
        moved = bits - of_i;
    } else {
        moved = bits + of_i;
    }
    if abs(p) < 1.0 / 32.0 {
        return p + (1.0 / 65536.0) * n;
    }
    return bitcast<f32>(moved);
}

// Offset a ray origin off a surface along the geometric normal `n` (pointing to the side
// the ray leaves towards), by a few ULPs of the position's magnitude so that it works at any
// scene scale. Wächter & Binder 2019, "A Fast and Robust Method for Avoiding
// Self-Intersection", Ray Tracing Gems ch. 6, listing 6-1.
fn offset_ray_origin(p: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(
        offset_ray_origin_1(p.x, n.x),
        offset_ray_origin_1(p.y, n.y),
        offset_ray_origin_1(p.z, n.z),
    );
}

fn is_finite_v4(v: vec4<f32>) -> bool {
    return is_finite_f32(v.x) && is_finite_f32(v.y) && is_finite_f32(v.z) && is_finite_f32(v.w);
}
