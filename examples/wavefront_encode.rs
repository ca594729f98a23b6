//! Host-side cost of one wavefront submission: the wall time of `GpuRenderer::dispatch`
//! (recording the chunk table, every chunk's passes and dispatches, and the submit — not the
//! GPU's work, which `image` then waits for) at a given size, with the wavefront forced on.
//!
//! `cargo run --release --example wavefront_encode -- [builtin:NAME] [WIDTH HEIGHT]`
//! (default builtin:env-spheres at 1920×1080).

use refract::gpu::GpuContext;
use refract::gpu::renderer::GpuRenderer;
use refract::render::RenderOptions;
use refract::scene::Scene;
use std::time::Instant;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let name = args.first().map_or("builtin:env-spheres", String::as_str);
    let size = |i: usize, d: u32| -> anyhow::Result<u32> {
        Ok(match args.get(i) {
            Some(s) => s.parse()?,
            None => d,
        })
    };
    let (w, h) = (size(1, 1920)?, size(2, 1080)?);
    let scene = Scene::load(name)?;
    let mut opts = RenderOptions::from_scene(&scene);
    opts.width = w;
    opts.height = h;
    let mut g = GpuRenderer::with_context(GpuContext::new()?, scene, opts)?;
    g.set_wavefront(Some(true));
    g.render(1)?; // compile, warm up
    let mut times = Vec::new();
    for _ in 0..5 {
        let start = Instant::now();
        g.dispatch(1);
        times.push(start.elapsed().as_secs_f64() * 1e3);
        g.image()?;
    }
    times.sort_by(f64::total_cmp);
    println!(
        "{name} {w}x{h}, 1 spp, wavefront: recording + submitting one submission took \
         {:.2} ms (median of 5; min {:.2}, max {:.2})",
        times[2], times[0], times[4]
    );
    Ok(())
}
