//! `builtin:caustic` with its light moved from 2 m to D m from the glass ball along the same
//! direction, radiance scaled by (D/2)² so the ball sees the same irradiance: the ball then
//! covers less of what the light emits into (a development scene for photon aiming).
//! `cargo run --release --example caustic_far -- D OUT.glb`
use anyhow::Context;
use glam::Vec3;
use refract::gltf_io::export::export_glb;
use refract::scene::builtin;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let d: f32 = args.first().context("distance D")?.parse()?;
    let out = args.get(1).context("output .glb")?;
    let mut scene = builtin::load("caustic")?;
    let ball = Vec3::new(0.0, 0.3, 0.0);
    let emissive: Vec<usize> = (0..scene.materials.len())
        .filter(|&m| scene.materials[m].is_emissive())
        .collect();
    let mut moved = std::collections::HashSet::new();
    for t in 0..scene.mesh.triangle_count() {
        if emissive.contains(&(scene.mesh.tri_material[t] as usize)) {
            moved.extend(scene.mesh.indices[t]);
        }
    }
    for &i in &moved {
        let p = &mut scene.mesh.positions[i as usize];
        *p = ball + (*p - ball) * (d / 2.0);
    }
    // Keep the light's size: scale its vertices back about their centroid.
    let c = moved
        .iter()
        .map(|&i| scene.mesh.positions[i as usize])
        .sum::<Vec3>()
        / moved.len() as f32;
    for &i in &moved {
        let p = &mut scene.mesh.positions[i as usize];
        *p = c + (*p - c) * (2.0 / d);
    }
    for &m in &emissive {
        scene.materials[m].emission *= (d / 2.0).powi(2);
    }
    std::fs::write(out, export_glb(&scene)?)?;
    Ok(())
}
