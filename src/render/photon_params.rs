//! Numbers the CPU and GPU photon mappers share beyond the radius schedule
//! (`photon_radius`): both walks read them from here (the GPU through the WGSL prelude).

/// The sampler's dimension where photon paths start (the camera's start at 0).
pub const PHOTON_DIMS: u32 = 1 << 17;

/// Photons landing on a surface turned by more than this from the query's surface (cosine
/// of the normals) are another surface (a corner, the far side of a thin wall).
pub const SAME_SURFACE_COS: f32 = 0.5;
