//! Write every built-in scene to `assets/<name>.glb` (run after changing `scene::builtin`):
//! `cargo run --release --example export_builtins`
use refract::gltf_io::export::export_glb;
use refract::scene::builtin;

fn main() -> anyhow::Result<()> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets");
    std::fs::create_dir_all(&dir)?;
    for name in builtin::NAMES {
        let scene = builtin::load(name)?;
        let bytes = export_glb(&scene)?;
        let path = dir.join(format!("{name}.glb"));
        std::fs::write(&path, &bytes)?;
        println!(
            "{} ({} triangles, {} KiB)",
            path.display(),
            scene.mesh.triangle_count(),
            bytes.len() / 1024
        );
    }
    Ok(())
}
