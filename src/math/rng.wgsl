// rng.wgsl — counter-based random numbers, bit-identical twin of src/math/rng.rs.
// WGSL u32 arithmetic wraps, like Rust's wrapping_* calls.

// PCG-RXS-M-XS 32-bit hash.
// Jarzynski & Olano 2020, "Hash Functions for GPU Rendering" (JCGT 9(3)), `pcg`.
fn pcg_hash(v: u32) -> u32 {
    let state = v * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// Map the top 24 bits of a u32 to a float in [0, 1).
fn u32_to_unit_f32(x: u32) -> f32 {
    return f32(x >> 8u) * (1.0 / 16777216.0);
}

// Per-(pixel, sample) stream; `next` draws dimension after dimension.
struct Sampler {
    base: u32,
    dim: u32,
}

// Stream for `pixel` (linear index), `sample` index and `seed`.
fn sampler_new(pixel: u32, sample: u32, seed: u32) -> Sampler {
    let base = pcg_hash(pcg_hash(pixel ^ pcg_hash(seed)) + sample);
    return Sampler(base, 0u);
}

// Next uniform float in [0, 1).
fn sampler_next_1d(s: ptr<function, Sampler>) -> f32 {
    let d = (*s).dim;
    (*s).dim = d + 1u;
    return u32_to_unit_f32(pcg_hash((*s).base ^ pcg_hash(d + 0x9e3779b9u)));
}

// Two uniform floats.
fn sampler_next_2d(s: ptr<function, Sampler>) -> vec2<f32> {
    let a = sampler_next_1d(s);
    let b = sampler_next_1d(s);
    return vec2<f32>(a, b);
}
