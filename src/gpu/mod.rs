//! The GPU progressive renderer: a wgpu compute twin of the CPU path tracer
//! (`cpu::Integrator::li`), with the same estimator and the same counter-based RNG so single
//! paths can be compared. It takes the `render` vocabulary (options, estimator, stats) and
//! depends on `wgpu` directly, never on the viewer. See docs/design.md ("Architecture",
//! "Rendering").
//!
//! - [`context`]: adapter and device (`required_limits = adapter.limits()`).
//! - [`layout`]: `#[repr(C)]` Pod twins of the WGSL structs, naga layout reflection.
//! - [`upload`]: scene → GPU arrays (BVH2 repack in leaf order, materials, light CDF).
//! - [`pipeline`]: WGSL assembly, specialisation by override constants, compiled pipelines
//!   (compiled on a worker thread where the caller asks for it).
//! - [`pipeline_cache`]: wgpu's driver pipeline cache, kept on disk between runs.
//! - [`light_probe`]: the light twin probe (light.wgsl against `scene::light::Light`).
//! - [`bvh_probe`]: the traversal probe (closest hits and work per ray, brute force);
//!   [`probe_rays`]: its ray workloads (camera, bounce and shadow rays of a scene).
//! - [`kernels`]: each entry point of a specialisation as WGSL and SPIR-V (dumps, register budgets).
//! - [`photons`]: the `sppm` photon store (radius schedule, photons, hash grid).
//! - [`prelude`]: the WGSL constants generated from their Rust definitions.
//! - [`renderer`]: [`GpuRenderer`], progressive accumulation, parameter edits, readback.
//! - [`submissions`]: batch and row-band sizes bounded in time per submission.
//! - [`tonemap`]: display tone mapping of the accumulation buffer into an sRGB texture.

pub mod buffers;
pub mod bvh_probe;
pub mod context;
pub mod kernels;
pub mod layout;
pub mod light_probe;
pub mod photons;
pub mod pipeline;
pub mod pipeline_cache;
pub mod prelude;
pub mod probe_rays;
pub mod renderer;
pub mod submissions;
pub mod tonemap;
pub mod upload;

pub use context::GpuContext;
pub use renderer::{GpuImage, GpuRenderer};
pub use submissions::SUBMISSION_BUDGET;
