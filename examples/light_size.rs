//! The `auto` estimator's measure for each scene given (default: every built-in): the solid
//! angle of the light seen from the caustic casters (`scene::caustic_casters`) and what
//! `auto` picks from it (docs/estimators.md, "Choosing the estimator"); and where `sppm` aims its photons
//! (`render::photon_aim`: target spheres, the share of the lights' power they take, photon
//! paths per pixel).
//!
//! `cargo run --release --example light_size -- [builtin:NAME | file.glb …]`

use refract::render::Estimator;
use refract::render::photon_aim::{PhotonTargets, photon_paths};
use refract::scene::Scene;
use refract::scene::builtin::NAMES;
use refract::scene::caustic_casters::emitter_solid_angle_at_casters;
use refract::scene::light::LightSet;

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
        let (targets, f) = PhotonTargets::with_fraction(&scene, &LightSet::build(&scene));
        let per_pixel = photon_paths(1_000_000, f) as f64 / 1e6;
        println!(
            "{:32} photons: {} target spheres, {:.2} % of the light's power, {per_pixel:.3} paths per pixel",
            "",
            targets.spheres.len(),
            100.0 * f
        );
    }
    Ok(())
}
