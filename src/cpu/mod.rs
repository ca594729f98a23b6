//! The CPU reference renderer (rayon over rows): path tracing with next-event estimation and
//! multiple importance sampling.

pub mod bdpt;
pub mod integrator;
pub mod render;

pub use integrator::{Integrator, SurfaceHit};
pub use render::Renderer;
