//! Renders the roughness-type comparison of docs/user-guide.md: the `rough-glass` scene with GGX and
//! Beckmann at two roughnesses (and the smooth sphere), into `screenshots/`.
//! Usage: cargo run --release --example roughness_types -- [spp]

use refract::bsdf::MicrofacetDistribution;
use refract::cpu::Renderer;
use refract::film::{ToneMap, save_image};
use refract::render::RenderOptions;
use refract::scene::{MaterialKind, Scene};

fn main() -> anyhow::Result<()> {
    let spp: u32 = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(256);
    let variants = [
        ("smooth", MicrofacetDistribution::Ggx, 0.0f32),
        ("ggx-0.3", MicrofacetDistribution::Ggx, 0.3),
        ("beckmann-0.3", MicrofacetDistribution::Beckmann, 0.3),
        ("ggx-0.6", MicrofacetDistribution::Ggx, 0.6),
        ("beckmann-0.6", MicrofacetDistribution::Beckmann, 0.6),
    ];
    for (name, dist, roughness) in variants {
        let mut scene = Scene::load("builtin:rough-glass")?;
        for m in scene
            .materials
            .iter_mut()
            .filter(|m| m.kind == MaterialKind::Glass)
        {
            m.distribution = dist;
            m.roughness = roughness;
        }
        scene.settings.width = 256;
        scene.settings.height = 256;
        let r = Renderer::new(scene)?;
        let o = RenderOptions::from_scene(&r.scene);
        let (film, stats) = r.render(&o, spp, None, |_| {});
        let path = format!("screenshots/rough-{name}.png");
        save_image(
            path.as_ref(),
            o.width,
            o.height,
            &film.image(),
            0.0,
            ToneMap::Clamp,
        )?;
        eprintln!("{path}: {spp} spp in {:.1} s", stats.elapsed.as_secs_f64());
    }
    Ok(())
}
