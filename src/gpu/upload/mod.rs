//! Scene → GPU arrays: the BVH2 repack (triangles stored in leaf order, consistent with
//! `primitive_indices`), vertex attributes, materials and the light distribution.
//! Pure CPU code (no wgpu), so it is testable without an adapter.
//!
//! One concept per file: `bvh` (build and repack), `geometry` (triangles, vertices),
//! `textures`, `materials`, `lights` (with the environment image) and `support` (what the
//! GPU cannot render).

mod bvh;
mod geometry;
mod lights;
mod materials;
mod support;
mod textures;

pub use bvh::{GpuBvh, MAX_BVH_DEPTH, build_bvh, bvh_stack_entries};
pub use geometry::{pack_triangles, pack_vertices};
pub use lights::{pack_environment, pack_lights};
pub use materials::{bsdf_kind, dist_code, pack_material, pack_materials};
pub use support::check_supported;
pub use textures::{TexSlots, pack_textures};
