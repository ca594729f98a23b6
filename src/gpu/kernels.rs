//! Each compute kernel of a specialisation on its own, as the driver receives it: the WGSL
//! module with its override constants substituted (naga's `process_overrides`, as wgpu does
//! before handing a module to a backend) and the SPIR-V naga writes for that one entry point.
//! Used by `examples/dump_kernels.rs` and the register-budget test (`tests/gpu_registers.rs`),
//! so what is measured is what the Vulkan backend compiles.

pub use super::pipeline::kernels_of;
use super::pipeline::{Kernel, Specialization, integrator_source};
use anyhow::{Context, Result};

/// The parsed and validated integrator module.
fn module() -> Result<(naga::Module, naga::valid::ModuleInfo)> {
    parse(&integrator_source()).context("integrator WGSL")
}

/// WGSL source parsed and validated.
fn parse(source: &str) -> Result<(naga::Module, naga::valid::ModuleInfo)> {
    let module = naga::front::wgsl::parse_str(source)
        .map_err(|e| anyhow::anyhow!("{}", e.emit_to_string(source)))?;
    let info = validator()
        .validate(&module)
        .context("the module does not validate")?;
    Ok((module, info))
}

fn validator() -> naga::valid::Validator {
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
}

/// The override constants of `spec` in naga's form.
fn constants(spec: &Specialization) -> naga::back::PipelineConstants {
    let mut c = naga::back::PipelineConstants::default();
    for (k, v) in spec.constants() {
        c.insert(k.to_owned(), v);
    }
    c
}

/// The module specialised for `spec` (overrides substituted) for the entry point `kernel`.
fn specialised(
    spec: &Specialization,
    kernel: Kernel,
) -> Result<(naga::Module, naga::valid::ModuleInfo)> {
    let (module, info) = module()?;
    let stage = Some((naga::ShaderStage::Compute, kernel.entry()));
    let (m, i) =
        naga::back::pipeline_constants::process_overrides(&module, &info, stage, &constants(spec))
            .map_err(|e| anyhow::anyhow!("specialising {}: {e}", kernel.entry()))?;
    Ok((m.into_owned(), i.into_owned()))
}

/// SPIR-V of `kernel` specialised for `spec`, written as wgpu's Vulkan backend writes it:
/// SPIR-V 1.3, buffer accesses unchecked (robust buffer access does it), other indexing
/// clamped, loops bounded, workgroup memory not zeroed (as the pipelines ask).
pub fn spirv(spec: &Specialization, kernel: Kernel) -> Result<Vec<u32>> {
    let (module, info) = specialised(spec, kernel)?;
    write_spirv(&module, &info, kernel.entry())
}

/// SPIR-V of the entry point `entry` of a WGSL source (e.g. a kernel `dump_kernels` wrote,
/// edited by hand), written as [`spirv`] writes it — for trying a kernel change on the
/// register tools without rebuilding the crate (`examples/wgsl_registers.rs`).
pub fn spirv_of_wgsl(source: &str, entry: &str) -> Result<Vec<u32>> {
    let (module, info) = parse(source)?;
    write_spirv(&module, &info, entry)
}

fn write_spirv(
    module: &naga::Module,
    info: &naga::valid::ModuleInfo,
    entry: &str,
) -> Result<Vec<u32>> {
    let policies = naga::proc::BoundsCheckPolicies {
        index: naga::proc::BoundsCheckPolicy::Restrict,
        buffer: naga::proc::BoundsCheckPolicy::Unchecked,
        image_load: naga::proc::BoundsCheckPolicy::Restrict,
        binding_array: naga::proc::BoundsCheckPolicy::Unchecked,
    };
    let options = naga::back::spv::Options {
        lang_version: (1, 3),
        flags: naga::back::spv::WriterFlags::empty(),
        bounds_check_policies: policies,
        // The pipelines ask wgpu not to zero workgroup memory
        // (`PipelineCompilationOptions::zero_initialize_workgroup_memory: false`, gpu::pipeline):
        // naga's default polyfill stores a zero into every word of the traversal stacks'
        // workgroup arrays, code the real kernels do not have (RADV: 40 s to compile a
        // 24-VGPR `wf_start` with it).
        zero_initialize_workgroup_memory: naga::back::spv::ZeroInitializeWorkgroupMemoryMode::None,
        ..Default::default()
    };
    let pipeline = naga::back::spv::PipelineOptions {
        shader_stage: naga::ShaderStage::Compute,
        entry_point: entry.to_owned(),
    };
    naga::back::spv::write_vec(module, info, &options, Some(&pipeline))
        .with_context(|| format!("writing SPIR-V of {entry}"))
}

/// WGSL of `kernel` specialised for `spec` (override constants substituted, as naga writes
/// the specialised module back out), headed by the constants used.
pub fn wgsl(spec: &Specialization, kernel: Kernel) -> Result<String> {
    let (module, info) = specialised(spec, kernel)?;
    let body =
        naga::back::wgsl::write_string(&module, &info, naga::back::wgsl::WriterFlags::empty())
            .with_context(|| format!("writing WGSL of {}", kernel.entry()))?;
    let mut s = format!(
        "// refract kernel `{}`, specialisation constants:\n",
        kernel.entry()
    );
    for (k, v) in spec.constants() {
        s.push_str(&format!("//   {k} = {v}\n"));
    }
    s.push_str(&body);
    Ok(s)
}

/// A resource binding of a kernel: (group, binding, is a uniform buffer; else storage).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BufferBinding {
    pub group: u32,
    pub binding: u32,
    pub uniform: bool,
}

/// The buffer bindings of the integrator module (every kernel uses a subset), for building a
/// pipeline layout outside wgpu. Errors on a binding that is not a buffer.
pub fn buffer_bindings() -> Result<Vec<BufferBinding>> {
    let (module, _) = module()?;
    bindings_of(&module)
}

/// The buffer bindings of a WGSL source (e.g. a hand-edited kernel with a binding of its
/// own; `examples/wgsl_registers.rs`).
pub fn buffer_bindings_of_wgsl(source: &str) -> Result<Vec<BufferBinding>> {
    let (module, _) = parse(source)?;
    bindings_of(&module)
}

fn bindings_of(module: &naga::Module) -> Result<Vec<BufferBinding>> {
    let mut out = Vec::new();
    for (_, var) in module.global_variables.iter() {
        let Some(rb) = &var.binding else { continue };
        let uniform = match var.space {
            naga::AddressSpace::Uniform => true,
            naga::AddressSpace::Storage { .. } => false,
            other => anyhow::bail!(
                "binding {}.{} is {other:?}, not a buffer",
                rb.group,
                rb.binding
            ),
        };
        out.push(BufferBinding {
            group: rb.group,
            binding: rb.binding,
            uniform,
        });
    }
    Ok(out)
}
