//! refract: a physically based light-transport renderer for teaching how light meets
//! materials. See docs/design.md for the architecture; layers, lowest first: `math`, `bsdf`,
//! `scene`, `bvh`, `paths`, `film`, then the render vocabulary (`render`: options, estimator,
//! stats, device, settings sidecar), then the renderers (`cpu`, `gpu`, which never import
//! each other), then the viewer (`app`), the benchmark and the CLI.

pub mod app;
pub mod bench;
pub mod bsdf;
pub mod bvh;
pub mod cpu;
pub mod denoise;
pub mod files;
pub mod film;
pub mod gltf_io;
pub mod gpu;
pub mod math;
pub mod paths;
pub mod render;
pub mod scene;
pub mod text;
