//! Regenerate the shipped HDRIs `assets/studio.hdr` and `assets/sun-sky.hdr` from
//! `scene::hdri` (tests/env_map.rs checks the files against the generator):
//! `cargo run --release --example gen_hdri`
use refract::scene::hdri::{HDRI_WIDTH, studio, sun_sky};

fn main() -> anyhow::Result<()> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets");
    std::fs::create_dir_all(&dir)?;
    for (name, map) in [
        ("studio", studio(HDRI_WIDTH)),
        ("sun-sky", sun_sky(HDRI_WIDTH)),
    ] {
        let path = dir.join(format!("{name}.hdr"));
        map.write_hdr(&path)?;
        let kib = std::fs::metadata(&path)?.len() / 1024;
        println!(
            "{} ({}×{}, {kib} KiB)",
            path.display(),
            map.width,
            map.height
        );
    }
    Ok(())
}
