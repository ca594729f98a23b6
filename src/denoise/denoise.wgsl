// The live view's denoiser: an edge-avoiding à-trous wavelet filter (Dammertz et al. 2010)
// guided by first-hit albedo, normal and depth, with SVGF's variance-guided luminance weight
// (Schied et al. 2017). The CPU twin is src/denoise/atrous.rs (same passes, same weights,
// same order of summation); src/denoise/gpu.rs runs it: `prepare`, `level` × iterations
// (step 1, 2, 4, …), `finish`. Every pass reads `src` and writes `dst`: the accumulation
// buffer is never bound.

struct Params {
    width: u32,
    height: u32,
    step: i32,
    // 1: src.w holds each pixel's measured variance of the mean luminance.
    has_variance: u32,
    sigma_l: f32,
    sigma_n: f32,
    sigma_z: f32,
    _pad: f32,
}

@group(0) @binding(0) var<uniform> params: Params;
// albedo.xyz, fraction of specular first hits.
@group(0) @binding(1) var<storage, read> guide_a: array<vec4<f32>>;
// normal.xyz (mean, not renormalised), depth.
@group(0) @binding(2) var<storage, read> guide_n: array<vec4<f32>>;
// depth gradient per pixel (denoise::atrous::depth_gradient).
@group(0) @binding(3) var<storage, read> grad: array<f32>;
@group(0) @binding(4) var<storage, read> src: array<vec4<f32>>;
@group(0) @binding(5) var<storage, read_write> dst: array<vec4<f32>>;

const MIN_ALBEDO: f32 = 0.01;
const VAR_RADIUS: i32 = 3;

fn luma(c: vec3<f32>) -> f32 {
    return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
}

fn kernel_tap(i: i32) -> f32 {
    switch i {
        case 0, 4: { return 1.0 / 16.0; }
        case 1, 3: { return 1.0 / 4.0; }
        default: { return 3.0 / 8.0; }
    }
}

fn gauss3(i: i32) -> f32 {
    return select(0.25, 0.5, i == 1);
}

fn normalize_or_zero(n: vec3<f32>) -> vec3<f32> {
    let len = length(n);
    return select(vec3<f32>(0.0), n / len, len > 1e-30);
}

fn w_normal(np: vec3<f32>, nq: vec3<f32>, sigma_n: f32) -> f32 {
    let d = max(dot(np, nq), 0.0);
    return select(0.0, pow(d, sigma_n), d > 0.0);
}

fn w_depth(zp: f32, zq: f32, g: f32, dist: f32, sigma_z: f32) -> f32 {
    let tol = sigma_z * g * dist + 1e-3 * max(abs(zp), 1e-3);
    return exp(-abs(zp - zq) / tol);
}

fn w_luma(lp: f32, lq: f32, std_dev: f32, sigma_l: f32) -> f32 {
    return exp(-abs(lp - lq) / (sigma_l * std_dev + 1e-4));
}

fn w_specular(sp: f32, sq: f32) -> f32 {
    return exp(-8.0 * abs(sp - sq));
}

fn guide_weight(ip: u32, iq: u32, dist: f32) -> f32 {
    let np = normalize_or_zero(guide_n[ip].xyz);
    let nq = normalize_or_zero(guide_n[iq].xyz);
    return w_normal(np, nq, params.sigma_n)
        * w_depth(guide_n[ip].w, guide_n[iq].w, grad[ip], dist, params.sigma_z)
        * w_specular(guide_a[ip].w, guide_a[iq].w);
}

fn albedo(i: u32) -> vec3<f32> {
    return max(guide_a[i].xyz, vec3<f32>(MIN_ALBEDO));
}

fn inside(x: i32, y: i32) -> bool {
    return x >= 0 && y >= 0 && x < i32(params.width) && y < i32(params.height);
}

// src: radiance (xyz) and measured variance (w); dst: irradiance and estimated variance.
@compute @workgroup_size(8, 8)
fn prepare(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= params.width || id.y >= params.height { return; }
    let x = i32(id.x);
    let y = i32(id.y);
    let ip = id.y * params.width + id.x;
    var sw = 0.0; var m1 = 0.0; var m2 = 0.0; var mv = 0.0;
    for (var dy = -VAR_RADIUS; dy <= VAR_RADIUS; dy++) {
        for (var dx = -VAR_RADIUS; dx <= VAR_RADIUS; dx++) {
            if !inside(x + dx, y + dy) { continue; }
            let iq = u32(y + dy) * params.width + u32(x + dx);
            let dist = sqrt(f32(dx * dx + dy * dy));
            var wt = 1.0;
            if iq != ip { wt = guide_weight(ip, iq, dist); }
            let l = luma(src[iq].xyz / albedo(iq));
            let la = luma(albedo(iq));
            sw += wt;
            m1 += wt * l;
            m2 += wt * l * l;
            mv += wt * (src[iq].w / (la * la));
        }
    }
    m1 /= sw;
    m2 /= sw;
    let la = luma(albedo(ip));
    var v = max(m2 - m1 * m1, 0.0);
    if params.has_variance == 1u { v = max(mv / sw, src[ip].w / (la * la)); }
    dst[ip] = vec4<f32>(src[ip].xyz / albedo(ip), v);
}

fn blurred_variance(x: i32, y: i32) -> f32 {
    var v = 0.0;
    for (var dy = -1; dy <= 1; dy++) {
        for (var dx = -1; dx <= 1; dx++) {
            let qx = clamp(x + dx, 0, i32(params.width) - 1);
            let qy = clamp(y + dy, 0, i32(params.height) - 1);
            v += gauss3(dx + 1) * gauss3(dy + 1) * src[u32(qy) * params.width + u32(qx)].w;
        }
    }
    return v;
}

// One à-trous level, taps `params.step` apart.
@compute @workgroup_size(8, 8)
fn level(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= params.width || id.y >= params.height { return; }
    let x = i32(id.x);
    let y = i32(id.y);
    let ip = id.y * params.width + id.x;
    let std_dev = sqrt(max(blurred_variance(x, y), 0.0));
    let lp = luma(src[ip].xyz);
    var sw = 0.0; var sc = vec3<f32>(0.0); var sv = 0.0;
    for (var ky = 0; ky < 5; ky++) {
        for (var kx = 0; kx < 5; kx++) {
            let dx = (kx - 2) * params.step;
            let dy = (ky - 2) * params.step;
            if !inside(x + dx, y + dy) { continue; }
            let iq = u32(y + dy) * params.width + u32(x + dx);
            var wt = kernel_tap(kx) * kernel_tap(ky);
            if iq != ip {
                let dist = sqrt(f32(dx * dx + dy * dy));
                wt *= guide_weight(ip, iq, dist) * w_luma(lp, luma(src[iq].xyz), std_dev, params.sigma_l);
            }
            sw += wt;
            sc += wt * src[iq].xyz;
            sv += wt * wt * src[iq].w;
        }
    }
    dst[ip] = vec4<f32>(sc / sw, sv / (sw * sw));
}

// Radiance again: the filtered irradiance times the albedo.
@compute @workgroup_size(8, 8)
fn finish(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= params.width || id.y >= params.height { return; }
    let ip = id.y * params.width + id.x;
    dst[ip] = vec4<f32>(src[ip].xyz * albedo(ip), 0.0);
}
