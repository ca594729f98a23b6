//! Measures what dispersion costs: the same scene rendered with its glass dispersive (hero
//! wavelength spectral transport) and non-dispersive (RGB transport, no spectral code runs).
//! Usage: cargo run --release --example dispersion_cost -- [scene] [spp]

use refract::cpu::Renderer;
use refract::render::RenderOptions;
use refract::scene::Scene;

fn main() -> anyhow::Result<()> {
    let spec = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "builtin:cornell-glass".into());
    let spp: u32 = std::env::args()
        .nth(2)
        .and_then(|s| s.parse().ok())
        .unwrap_or(64);
    for dispersive in [false, true, false, true] {
        let mut scene = Scene::load(&spec)?;
        scene.settings.width = 256;
        scene.settings.height = 256;
        for m in scene.materials.iter_mut().filter(|m| m.is_transmissive()) {
            m.abbe = if dispersive { Some(20.0) } else { None };
        }
        let r = Renderer::new(scene)?;
        let o = RenderOptions::from_scene(&r.scene);
        let (_, stats) = r.render(&o, spp, None, |_| {});
        println!(
            "{spec} dispersive={dispersive} spectral={}: {:.3} M samples/s",
            r.spectral,
            stats.samples_per_sec() / 1e6
        );
    }
    Ok(())
}
