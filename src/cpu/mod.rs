//! The CPU reference renderer (rayon over rows): path tracing with next-event estimation and
//! multiple importance sampling, bidirectional path tracing and light tracing. Every walk
//! shares the per-vertex step (`interaction`, `path_state`, `medium`, `spectral`) and reaches
//! lights only through `scene::light::Light`.

pub mod aov;
pub mod bdpt;
pub mod camera_ray;
pub mod decompose;
pub mod gather;
pub mod inspect;
pub mod integrator;
pub mod interaction;
pub mod layers;
pub mod medium;
pub mod observer;
pub mod path_state;
pub mod polarized;
pub mod render;
pub mod spectral;
mod splat_buffer;
pub mod sppm;
pub mod walk_spec;

pub use integrator::Integrator;
pub use interaction::SurfaceHit;
pub use render::Renderer;
