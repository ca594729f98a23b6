// Viewer tone mapping: the GPU renderer's accumulation buffer (per-pixel MEAN radiance,
// linear Rec.709, row-major, top row first) -> exposure -> tone map -> sRGB-encoded 8-bit
// values in an Rgba8Unorm storage texture. The viewer registers an Rgba8UnormSrgb view of it
// (without view formats, e.g. on GL: an Rgba8UnormSrgb copy of its bytes) with egui-wgpu,
// which then samples it exactly like its own (sRGB) textures, so the screen shows the same
// bytes as `film::to_srgb8` / the CPU backend.
//
// Formulas are the twins of `film::ToneMap::apply` and `math::color::linear_to_srgb` (Rust):
// - Reinhard x/(1+x): Reinhard et al. 2002, "Photographic Tone Reproduction for Digital
//   Images".
// - ACES filmic fit: Narkowicz 2015, "ACES Filmic Tone Mapping Curve".
// - sRGB transfer: IEC 61966-2-1.

struct ToneParams {
    width: u32,
    height: u32,
    // 0 = clamp, 1 = Reinhard, 2 = ACES (Narkowicz)
    tone: u32,
    // 2^exposure (computed on the CPU, finite)
    scale: f32,
};

@group(0) @binding(0) var<storage, read> accum: array<vec4<f32>>;
@group(0) @binding(1) var<uniform> tp: ToneParams;
@group(0) @binding(2) var out_tex: texture_storage_2d<rgba8unorm, write>;

fn tone_map(x: f32) -> f32 {
    if tp.tone == 1u {
        return clamp(x / (1.0 + x), 0.0, 1.0);
    }
    if tp.tone == 2u {
        return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
    }
    return clamp(x, 0.0, 1.0);
}

fn linear_to_srgb(x: f32) -> f32 {
    if x <= 0.0031308 {
        return 12.92 * max(x, 0.0);
    }
    return 1.055 * pow(x, 1.0 / 2.4) - 0.055;
}

// One channel to the exact byte `film::to_srgb8` writes ((v·255 + 0.5) truncated, NaN -> 0),
// returned as byte/255 so the unorm8 store reproduces that byte exactly.
fn encode(c: f32) -> f32 {
    let v = linear_to_srgb(tone_map(c * tp.scale));
    // NaN fails every comparison: map it (and anything not in range) to 0 like Rust's `as u8`.
    if !(v >= 0.0) {
        return 0.0;
    }
    let b = min(floor(v * 255.0 + 0.5), 255.0);
    return b / 255.0;
}

@compute @workgroup_size(8, 8, 1)
fn tonemap(@builtin(global_invocation_id) gid: vec3<u32>) {
    if gid.x >= tp.width || gid.y >= tp.height {
        return;
    }
    let m = accum[gid.y * tp.width + gid.x];
    let rgb = vec3<f32>(encode(m.x), encode(m.y), encode(m.z));
    textureStore(out_tex, vec2<i32>(gid.xy), vec4<f32>(rgb, 1.0));
}
