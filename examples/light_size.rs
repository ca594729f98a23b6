//! The `auto` estimator's measure for each scene given (default: every built-in): the solid
//! angle of the light seen from the caustic casters (`scene::caustic_casters`) and what
//! `auto` picks from it (README, "Choosing the estimator").
//!
//! `cargo run --release --example light_size -- [builtin:NAME | file.glb …]`

use refract::render::Estimator;
use refract::scene::Scene;
use refract::scene::builtin::NAMES;
use refract::scene::caustic_casters::emitter_solid_angle_at_casters;

fn main() -> anyhow::Result<()> {
    let mut scenes: Vec<String> = std::env::args().skip(1).collect();
    if scenes.is_empty() {
        scenes = NAMES.iter().map(|n| format!("builtin:{n}")).collect();
    }
    for name in &scenes {
        let scene = Scene::load(name)?;
        let sr = emitter_solid_angle_at_casters(&scene)
            .map_or("none".to_owned(), |sr| format!("{sr:.4} sr"));
        let (e, why) = Estimator::Auto.resolve_why(&scene);
        println!("{name:32} {sr:>10}  auto = {e} ({why})");
    }
    Ok(())
}
