//! Development tool: write the sphere-in-tank scene (nested dielectrics: a glass sphere,
//! n = 1.5, inside a water tank, n = 1.33, on a floor under an area light) as a .glb, for the
//! Mitsuba cross-check in docs/user-guide.md ("Nested dielectrics").
//! Usage: cargo run --release --example sphere_in_tank -- /tmp/tank.glb
use glam::Vec3;
use refract::scene::builtin::{cuboid, rect, sphere};
use refract::scene::{Camera, Material, Mesh, RenderSettings, Scene};
fn main() -> anyhow::Result<()> {
    let out = std::env::args()
        .nth(1)
        .ok_or_else(|| anyhow::anyhow!("usage: sphere_in_tank <out.glb>"))?;
    let materials = vec![
        Material::diffuse("floor", Vec3::splat(0.6)),
        Material::diffuse("wall", Vec3::new(0.2, 0.3, 0.7)),
        Material::emitter("light", Vec3::splat(8.0)),
        Material::glass("water", 1.33),
        Material::glass("glass", 1.5),
    ];
    let mut m = Mesh::default();
    rect(&mut m, Vec3::ZERO, Vec3::Y, 6.0, 6.0, 0);
    rect(&mut m, Vec3::new(0.0, 1.5, -1.2), Vec3::Z, 6.0, 3.0, 1);
    rect(
        &mut m,
        Vec3::new(0.6, 2.2, 0.8),
        Vec3::new(-0.3, -1.0, -0.4),
        1.2,
        1.2,
        2,
    );
    cuboid(
        &mut m,
        Vec3::new(-0.5, 0.02, -0.5),
        Vec3::new(0.5, 1.02, 0.5),
        3,
    );
    sphere(&mut m, Vec3::new(0.05, 0.5, 0.0), 0.3, 48, 96, 4);
    let cam = Camera::look_at(
        Vec3::new(0.3, 1.0, 2.6),
        Vec3::new(0.0, 0.5, 0.0),
        Vec3::Y,
        0.6,
    );
    let scene = Scene {
        name: "sphere-in-tank".into(),
        mesh: m,
        materials,
        textures: vec![],
        punctual_lights: vec![],
        camera: cam,
        environment: Vec3::splat(0.1),
        env_map: None,
        settings: RenderSettings {
            width: 128,
            height: 96,
            ..Default::default()
        },
        warnings: vec![],
    };
    let glb = refract::gltf_io::export::export_glb(&scene)?;
    std::fs::write(&out, glb).map_err(|e| anyhow::anyhow!("writing {out}: {e}"))?;
    Ok(())
}
