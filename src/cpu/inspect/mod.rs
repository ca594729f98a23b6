//! The path inspector: N camera paths through one pixel, traced by the renderer's own walk
//! (`Integrator::li_observed` over `camera_ray`, the same sampler dimensions), with every
//! vertex recorded as the shared step (`Interaction`, `PathState`) saw it. Sample `i` of the
//! inspector is sample `i` of `render` with the same seed, so the mean of the contributions
//! is the rendered pixel's value. The inspector always path-traces (whatever the estimator
//! option says): it shows one walk, not a combination of strategies.

pub mod lobe;
mod record;
mod recorder;
mod table;

pub use record::{
    ConnectionRecord, PathRecord, PixelTrace, ScatterRecord, VertexEvent, VertexRecord,
};
pub use recorder::sample_event;
pub use table::format_table;

use super::Renderer;
use super::camera_ray::camera_ray;
use crate::math::rng::Sampler;
use crate::render::RenderOptions;
use rayon::prelude::*;
use recorder::Recorder;

/// Paths traced when the caller does not say (the viewer, `refract trace`).
pub const DEFAULT_PATHS: u32 = 32;
/// Most paths one trace may record (each keeps every vertex in memory).
pub const MAX_PATHS: u32 = 1 << 16;

/// Trace `paths` camera samples (sample indices `0..paths`, seed `opts.seed`) through pixel
/// `(x, y)` of the `opts.width × opts.height` image and record every vertex.
pub fn trace_pixel(
    renderer: &Renderer,
    opts: &RenderOptions,
    (x, y): (u32, u32),
    paths: u32,
) -> anyhow::Result<PixelTrace> {
    opts.check()?;
    let (w, h) = (opts.width, opts.height);
    anyhow::ensure!(
        x < w && y < h,
        "pixel ({x}, {y}) is outside the {w}x{h} image (x in 0..{w}, y in 0..{h})"
    );
    anyhow::ensure!(
        (1..=MAX_PATHS).contains(&paths),
        "{paths} paths: trace between 1 and {MAX_PATHS}"
    );
    let integ = renderer.integrator(opts);
    let cam = &crate::scene::camera::CameraRays::new(&renderer.scene.camera);
    let (lo, hi) = renderer.scene.bounds();
    let extent = (hi - lo).length().max(1e-3);
    let pixel = y * w + x;
    let records: Vec<PathRecord> = (0..paths)
        .into_par_iter()
        .map(|s| {
            let mut sampler = Sampler::new(pixel, s, opts.seed);
            let dir = camera_ray(cam, (x, y), (w, h), &mut sampler);
            let mut rec = Recorder::new(extent);
            let v = integ.li_observed(cam.position, dir, &mut sampler, &mut rec);
            rec.finish(v)
        })
        .collect();
    Ok(PixelTrace::new([x, y], (w, h), opts.seed, records))
}
