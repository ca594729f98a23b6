//! Register use of a scene's GPU kernels as AMD's compiler in Mesa (RADV/ACO) produces it,
//! on RADV's null device (no AMD GPU needed):
//!
//! `VK_ICD_FILENAMES=/usr/share/vulkan/icd.d/radeon_icd.x86_64.json RADV_FORCE_FAMILY=navi21
//!  cargo run --release --example kernel_registers -- [builtin:NAME | --all-features] [--lt | --sppm]`

#[path = "../tests/radv/mod.rs"]
mod radv;

use refract::gpu::kernels;
use refract::gpu::pipeline::Specialization;
use refract::scene::Scene;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let lt = args.iter().any(|a| a == "--lt");
    let sppm = args.iter().any(|a| a == "--sppm");
    let spec = if args.iter().any(|a| a == "--all-features") {
        Specialization::all()
    } else {
        let name = args
            .iter()
            .find(|a| !a.starts_with("--"))
            .map_or("builtin:cornell-glass", |s| s);
        Specialization {
            light_tracing: lt,
            sppm,
            ..Specialization::for_scene(&Scene::load(name)?)?
        }
        .with_wavefront_rule()
    };
    let bindings = kernels::buffer_bindings()?;
    for k in kernels::kernels_of(&spec) {
        let spirv = kernels::spirv(&spec, k)?;
        let stats =
            radv::compile_stats(&spirv, k.entry(), &bindings).map_err(anyhow::Error::msg)?;
        for s in stats {
            println!("{}: {s:?}", k.entry());
        }
    }
    Ok(())
}
