//! Register use of a scene's GPU kernels as AMD's compiler in Mesa (RADV/ACO) produces it,
//! on RADV's null device (no AMD GPU needed):
//!
//! `VK_ICD_FILENAMES=/usr/share/vulkan/icd.d/radeon_icd.x86_64.json RADV_FORCE_FAMILY=navi21
//!  cargo run --release --example kernel_registers -- [builtin:NAME | --all-features] [--lt | --sppm]
//!  [--kernel ENTRY] [--off PART]… [--on PART]…`
//!
//! `--kernel wf_shade` compiles that entry point only; `--off iridescence` (or any BSDF part,
//! `bsdf::BsdfParts::NAMES`: `lambert`, `smooth_conductor`, `rough_dielectric`, …; any light
//! part, `scene::light::LightParts::NAMES`: `area_lights`, `env_image`, …; or `textures`,
//! `spectral`, `nested`, `filter`, `polarized`, `light_tracing`, `wavefront`) leaves a part
//! out, to see what it costs; `--on PART` puts one in.

#[path = "../tests/radv/mod.rs"]
mod radv;

use refract::gpu::kernels;
use refract::gpu::pipeline::Specialization;
use refract::scene::Scene;

/// The value after each `name` in `args`.
fn flag_values<'a>(args: &'a [String], name: &'a str) -> impl Iterator<Item = &'a str> {
    args.windows(2)
        .filter(move |w| w[0] == name)
        .map(|w| w[1].as_str())
}

fn flag_value<'a>(args: &'a [String], name: &'a str) -> Option<&'a str> {
    flag_values(args, name).next()
}

/// `spec` with every `--off PART` left out and every `--on PART` put in (the wavefront form
/// kept as chosen).
fn parts_off(mut spec: Specialization, args: &[String]) -> anyhow::Result<Specialization> {
    let off = flag_values(args, "--off").map(|p| (p, false));
    let on = flag_values(args, "--on").map(|p| (p, true));
    for (part, value) in off.chain(on) {
        if let Some(field) = spec.bsdfs.part_mut(part).or(spec.lights.part_mut(part)) {
            *field = value;
            continue;
        }
        let field = match part {
            "textures" => &mut spec.textures,
            "spectral" => &mut spec.spectral,
            "nested" => &mut spec.nested,
            "filter" => &mut spec.filter,
            "polarized" => &mut spec.polarized,
            "light_tracing" => &mut spec.light_tracing,
            "wavefront" => &mut spec.wavefront,
            other => anyhow::bail!("{other}: not a part this example knows"),
        };
        *field = value;
    }
    // Polarised transport runs in the megakernel only (`Specialization::wants_wavefront`).
    spec.wavefront &= !spec.polarized;
    Ok(spec)
}

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let lt = args.iter().any(|a| a == "--lt");
    let sppm = args.iter().any(|a| a == "--sppm");
    let spec = if args.iter().any(|a| a == "--all-features") {
        Specialization {
            light_tracing: !sppm,
            sppm,
            ..Specialization::all()
        }
    } else {
        let name = args
            .iter()
            .find(|a| a.starts_with("builtin:") || a.ends_with(".glb") || a.ends_with(".gltf"))
            .map_or("builtin:cornell-glass", |s| s);
        Specialization {
            light_tracing: lt,
            sppm,
            ..Specialization::for_scene(&Scene::load(name)?)?
        }
        .with_wavefront_rule()
    };
    let spec = parts_off(spec, &args)?;
    let only = flag_value(&args, "--kernel");
    eprintln!("{spec:?}");
    let bindings = kernels::buffer_bindings()?;
    for k in kernels::kernels_of(&spec) {
        if only.is_some_and(|e| e != k.entry()) {
            continue;
        }
        let spirv = kernels::spirv(&spec, k)?;
        let stats =
            radv::compile_stats(&spirv, k.entry(), &bindings).map_err(anyhow::Error::msg)?;
        for s in stats {
            println!("{}: {s:?}", k.entry());
        }
    }
    Ok(())
}
