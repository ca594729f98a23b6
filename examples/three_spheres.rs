//! Development tool: write the three-spheres scene of issue 35 (a Cornell box holding a smooth
//! diamond sphere, n = 2.42, a rough water sphere, n = 1.33, and a rough flint sphere,
//! n = 1.62, under the box's small ceiling light) as a .glb, for the sppm cost measurements
//! in docs/performance.md ("sppm's photon pass").
//! Usage: cargo run --release --example three_spheres -- /tmp/three.glb
use glam::Vec3;
use refract::scene::builtin::{quad, rough_glass_material, sphere};
use refract::scene::{Camera, Material, Mesh, RenderSettings, Scene};

fn main() -> anyhow::Result<()> {
    let out = std::env::args()
        .nth(1)
        .ok_or_else(|| anyhow::anyhow!("usage: three_spheres <out.glb>"))?;
    let mut m = Mesh::default();
    let (x, y, z) = (Vec3::X * 2.0, Vec3::Y * 2.0, Vec3::Z * 2.0);
    let c = Vec3::new(-1.0, 0.0, -1.0);
    quad(&mut m, c, z, x, 0); // floor
    quad(&mut m, c + y, x, z, 0); // ceiling
    quad(&mut m, c, x, y, 0); // back
    quad(&mut m, c, y, z, 1); // left, red
    quad(&mut m, Vec3::new(1.0, 0.0, -1.0), z, y, 2); // right, green
    quad(
        &mut m,
        Vec3::new(-0.25, 1.999, -0.25),
        Vec3::X * 0.5,
        Vec3::Z * 0.5,
        3,
    );
    let materials = vec![
        Material::diffuse("white", Vec3::splat(0.75)),
        Material::diffuse("red", Vec3::new(0.63, 0.065, 0.05)),
        Material::diffuse("green", Vec3::new(0.14, 0.45, 0.091)),
        Material::emitter("light", Vec3::splat(17.0)),
        Material::glass("diamond", 2.42),
        rough_glass_material("rough-water", 1.33, 0.3),
        rough_glass_material("rough-flint", 1.62, 0.3),
    ];
    sphere(&mut m, Vec3::new(-0.55, 0.3, 0.1), 0.3, 48, 96, 4);
    sphere(&mut m, Vec3::new(0.0, 0.3, -0.3), 0.3, 48, 96, 5);
    sphere(&mut m, Vec3::new(0.55, 0.3, 0.1), 0.3, 48, 96, 6);
    let scene = Scene {
        name: "three-spheres".into(),
        mesh: m,
        materials,
        textures: vec![],
        punctual_lights: vec![],
        camera: Camera::look_at(
            Vec3::new(0.0, 1.0, 3.9),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::Y,
            0.6911,
        ),
        environment: Vec3::ZERO,
        env_map: None,
        settings: RenderSettings {
            width: 256,
            height: 256,
            ..Default::default()
        },
        warnings: vec![],
    };
    let glb = refract::gltf_io::export::export_glb(&scene)?;
    std::fs::write(&out, glb).map_err(|e| anyhow::anyhow!("writing {out}: {e}"))?;
    Ok(())
}
