//! Polarised light transport on the CPU (issue 38; docs/polarization.md): a Stokes vector
//! per camera path and a Mueller matrix at every scattering event, with the reference-frame
//! rotations between them (Wilkie & Weidlich 2012, "Polarised Light in Computer Graphics";
//! Mitsuba 3's polarised variants as the model). A separate walk from the unpolarised one
//! (`cpu::integrator`), entered only when a render asks for polarisation, so every other
//! render runs the unpolarised walk unchanged. The GPU's twin is `chain.wgsl` (the filtered
//! intensity only; `gpu::GpuRenderer::set_polarization`).
//!
//! - `chain`: the Mueller product of a path and its reference frames.
//! - `walk`: the polarised path tracer (NEE + MIS).
//! - `render`: passes over the image into a beauty film and a Stokes film.
//! - `view`: degree and angle of polarisation as false colour.

pub mod chain;
pub mod render;
pub mod view;
pub mod walk;

pub use render::{Polarization, STOKES_LAYERS};
pub use walk::PolarizedSample;
