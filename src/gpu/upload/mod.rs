//! Scene → GPU arrays: the BVH2 repack (triangles stored in leaf order, consistent with
//! `primitive_indices`), vertex attributes, materials and the light distribution.
//! Pure CPU code (no wgpu), so it is testable without an adapter.
//!
//! One concept per file: `bvh` (build and repack, the layout switch), `cwbvh` (the
//! compressed wide BVH), `geometry` (triangles, vertices),
//! `textures`, `materials`, `lights` (with the environment image) and `support` (what the
//! GPU cannot render).

mod bvh;
mod cwbvh;
mod geometry;
mod lights;
mod materials;
mod support;
mod textures;

pub use bvh::{
    BvhLayout, GpuBvh, MAX_BVH_DEPTH, build_bvh, build_gpu_bvh, build_wide_bvh, bvh_stack_entries,
    cwbvh_params,
};
pub use cwbvh::{MAX_CWBVH_DEPTH, cwbvh_stack_words, decode as cwbvh_decode};
pub use geometry::{pack_triangles, pack_vertices};
pub use lights::{pack_environment, pack_lights};
pub use materials::{bsdf_kind, dist_code, pack_material, pack_materials};
pub use support::check_supported;
pub use textures::{TexSlots, pack_textures};
