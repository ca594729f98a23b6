//! refract: a physically based light-transport renderer for teaching how light meets
//! materials. See DESIGN.md for the architecture; layers, lowest first: `math`, `bsdf`,
//! `scene`, `bvh`, `paths`, `film`, then the renderers (`cpu`).

pub mod bsdf;
pub mod math;
pub mod paths;
pub mod scene;
