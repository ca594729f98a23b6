//! Write every compute kernel of a scene's GPU specialisation, one file per entry point:
//! `DIR/render.wgsl`, `DIR/render.spv` (and `light_trace.*` with `--estimator lt+pt`,
//! `photon_trace.*` with `--estimator sppm`).
//!
//! `cargo run --release --example dump_kernels -- --scene builtin:cornell-glass --out DIR
//! [--estimator path|lt+pt|sppm] [--all-features]`

use anyhow::{Context, Result, bail};
use refract::gpu::kernels;
use refract::gpu::pipeline::Specialization;
use refract::scene::Scene;
use std::path::PathBuf;

struct Args {
    scene: String,
    out: PathBuf,
    light_tracing: bool,
    sppm: bool,
    all_features: bool,
}

fn args() -> Result<Args> {
    let mut a = Args {
        scene: "builtin:cornell-glass".into(),
        out: PathBuf::from("kernels"),
        light_tracing: false,
        sppm: false,
        all_features: false,
    };
    let mut it = std::env::args().skip(1);
    while let Some(flag) = it.next() {
        let mut value = || it.next().with_context(|| format!("{flag} needs a value"));
        match flag.as_str() {
            "--scene" => a.scene = value()?,
            "--out" => a.out = PathBuf::from(value()?),
            "--estimator" => match value()?.as_str() {
                "path" => (a.light_tracing, a.sppm) = (false, false),
                "lt+pt" => (a.light_tracing, a.sppm) = (true, false),
                "sppm" => (a.light_tracing, a.sppm) = (false, true),
                e => bail!("--estimator {e}: use path, lt+pt or sppm"),
            },
            "--all-features" => a.all_features = true,
            f => bail!("unknown flag {f} (--scene, --out, --estimator, --all-features)"),
        }
    }
    Ok(a)
}

fn main() -> Result<()> {
    let a = args()?;
    let spec = if a.all_features && a.sppm {
        Specialization::all_sppm()
    } else if a.all_features {
        Specialization::all()
    } else {
        let scene = Scene::load(&a.scene)?;
        Specialization {
            light_tracing: a.light_tracing,
            sppm: a.sppm,
            ..Specialization::for_scene(&scene)?
        }
        .with_wavefront_rule()
    };
    std::fs::create_dir_all(&a.out).with_context(|| format!("--out {}", a.out.display()))?;
    for k in kernels::kernels_of(&spec) {
        let words = kernels::spirv(&spec, k)?;
        let spv = a.out.join(format!("{}.spv", k.entry()));
        std::fs::write(&spv, bytemuck::cast_slice::<u32, u8>(&words))
            .with_context(|| format!("writing {}", spv.display()))?;
        let wgsl = a.out.join(format!("{}.wgsl", k.entry()));
        std::fs::write(&wgsl, kernels::wgsl(&spec, k)?)
            .with_context(|| format!("writing {}", wgsl.display()))?;
        println!(
            "{} ({} SPIR-V words), {}",
            spv.display(),
            words.len(),
            wgsl.display()
        );
    }
    Ok(())
}
