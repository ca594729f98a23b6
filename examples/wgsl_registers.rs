//! Register use of one WGSL file as RADV/ACO compiles it on its null device (no AMD GPU
//! needed) — for trying a change to a kernel without rebuilding the crate: dump a scene's
//! specialised kernel with `dump_kernels`, edit the `.wgsl`, and compile it here.
//!
//! `VK_ICD_FILENAMES=/usr/share/vulkan/icd.d/radeon_icd.x86_64.json RADV_FORCE_FAMILY=navi21
//!  cargo run --release --example wgsl_registers -- DIR/render.wgsl [ENTRY]`
//! (ENTRY defaults to `render`; the buffer bindings are the file's own.)

#[path = "../tests/radv/mod.rs"]
mod radv;

use anyhow::{Context, Result, anyhow};
use refract::gpu::kernels;

/// The statistics printed, in this order.
const KEYS: [&str; 6] = [
    "VGPRs",
    "Pre-Sched VGPRs",
    "Spilled VGPRs",
    "Spilled SGPRs",
    "Subgroups per SIMD",
    "Instructions",
];

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let path = args
        .first()
        .context("usage: wgsl_registers FILE.wgsl [ENTRY]")?;
    let entry = args.get(1).map_or("render", String::as_str);
    let src = std::fs::read_to_string(path).with_context(|| format!("reading {path}"))?;
    let spirv = kernels::spirv_of_wgsl(&src, entry).with_context(|| format!("compiling {path}"))?;
    let bindings = kernels::buffer_bindings_of_wgsl(&src)?;
    for stats in radv::compile_stats(&spirv, entry, &bindings).map_err(|e| anyhow!(e))? {
        let shown: Vec<String> = KEYS
            .iter()
            .map(|k| {
                format!(
                    "{k}={}",
                    stats.get(*k).map_or("?".into(), |v| format!("{v:?}"))
                )
            })
            .collect();
        println!("{entry}: {}", shown.join(" "));
    }
    Ok(())
}
