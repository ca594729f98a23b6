//! The kernels' WGSL sources: the shader files, assembled behind the generated prelude,
//! and their compilation into a validated module.

use crate::gpu::GpuContext;
use anyhow::Result;

const COMMON: &str = include_str!("../../math/common.wgsl");
const RNG: &str = include_str!("../../math/rng.wgsl");
const SPECTRUM: &str = include_str!("../../math/spectrum.wgsl");
// The BSDFs' shared files (the variants' own come from the table, `bsdf::family`).
const BSDF: &str = include_str!("../../bsdf/bsdf.wgsl");
const FRESNEL: &str = include_str!("../../bsdf/fresnel.wgsl");
const MICROFACET: &str = include_str!("../../bsdf/microfacet.wgsl");
const THIN_FILM: &str = include_str!("../../bsdf/thin_film.wgsl");
const POLARIZED: &str = include_str!("../../bsdf/polarized.wgsl");
const POLARIZED_CHAIN: &str = include_str!("../../cpu/polarized/chain.wgsl");
const SCENE: &str = include_str!("../../gpu/scene.wgsl");
const CWBVH: &str = include_str!("../../gpu/cwbvh.wgsl");
const LIGHT: &str = include_str!("../../scene/light/light.wgsl");
const SPECTRAL: &str = include_str!("../../cpu/spectral.wgsl");
const MATERIAL: &str = include_str!("../../scene/material.wgsl");
const PATH_FILTER: &str = include_str!("../../paths/path_filter.wgsl");
const INTERACTION: &str = include_str!("../../cpu/interaction.wgsl");
const INTEGRATOR: &str = include_str!("../../gpu/integrator.wgsl");
const LIGHT_TRACING: &str = include_str!("../../gpu/light_tracing.wgsl");
const PHOTON: &str = include_str!("../../gpu/photon.wgsl");
const WAVEFRONT: &str = include_str!("../../gpu/wavefront.wgsl");
const LIGHT_WAVEFRONT: &str = include_str!("../../gpu/light_wavefront.wgsl");
const PROBE: &str = include_str!("../../gpu/probe.wgsl");
const LIGHT_PROBE: &str = include_str!("../../gpu/light_probe.wgsl");
const BVH_PROBE: &str = include_str!("../../gpu/bvh_probe.wgsl");

/// The maths shared by every kernel (twins of src/math and src/bsdf): these, then the BSDF
/// table's variant files (`bsdf::family::WGSL_FILES`).
const MATHS: &[&str] = &[
    COMMON,
    RNG,
    SPECTRUM,
    BSDF,
    FRESNEL,
    MICROFACET,
    THIN_FILM,
    POLARIZED,
    POLARIZED_CHAIN,
];

/// [`MATHS`], then the BSDF variants' files.
fn maths() -> Vec<&'static str> {
    let variants = crate::bsdf::family::WGSL_FILES
        .iter()
        .map(|&(_, text)| text);
    MATHS.iter().copied().chain(variants).collect()
}

const VARIANT_FILES: &[(&str, &str)] = crate::bsdf::family::WGSL_FILES;

/// Every kernel source file by name (tests check that none defines a prelude constant): the
/// BSDF table's variant files, then the others.
pub const SHADER_FILES: &[(&str, &str)] = &crate::gpu::prelude::concat::<
    _,
    { VARIANT_FILES.len() + OTHER_FILES.len() },
>(VARIANT_FILES, OTHER_FILES, ("", ""));

const OTHER_FILES: &[(&str, &str)] = &[
    ("common.wgsl", COMMON),
    ("rng.wgsl", RNG),
    ("spectrum.wgsl", SPECTRUM),
    ("bsdf.wgsl", BSDF),
    ("fresnel.wgsl", FRESNEL),
    ("microfacet.wgsl", MICROFACET),
    ("thin_film.wgsl", THIN_FILM),
    ("polarized.wgsl", POLARIZED),
    ("chain.wgsl", POLARIZED_CHAIN),
    ("scene.wgsl", SCENE),
    ("cwbvh.wgsl", CWBVH),
    ("light.wgsl", LIGHT),
    ("spectral.wgsl", SPECTRAL),
    ("material.wgsl", MATERIAL),
    ("path_filter.wgsl", PATH_FILTER),
    ("interaction.wgsl", INTERACTION),
    ("integrator.wgsl", INTEGRATOR),
    ("light_tracing.wgsl", LIGHT_TRACING),
    ("photon.wgsl", PHOTON),
    ("wavefront.wgsl", WAVEFRONT),
    ("light_wavefront.wgsl", LIGHT_WAVEFRONT),
    ("probe.wgsl", PROBE),
    ("light_probe.wgsl", LIGHT_PROBE),
    ("bvh_probe.wgsl", BVH_PROBE),
];

/// The generated prelude, then `parts`, then the BSDF table's generated dispatch
/// (`bsdf::family_wgsl`).
fn assemble(parts: &[&str]) -> String {
    let mut s = crate::gpu::prelude::wgsl_prelude();
    for p in parts {
        s.push('\n');
        s.push_str(p);
    }
    s.push('\n');
    s.push_str(&crate::bsdf::family_wgsl::wgsl_dispatch());
    s
}

/// The integrator kernel's full WGSL source: prelude, maths, scene, lights (`light.wgsl` and
/// the light table's generated dispatch, `scene::light::family_wgsl`), the per-vertex
/// step, then the walks (camera, light, photon).
pub fn integrator_source() -> String {
    let lights = crate::scene::light::family_wgsl::wgsl_dispatch();
    let kernel = [
        SCENE,
        CWBVH,
        LIGHT,
        &lights,
        SPECTRAL,
        MATERIAL,
        PATH_FILTER,
        INTERACTION,
        INTEGRATOR,
        LIGHT_TRACING,
        PHOTON,
        WAVEFRONT,
        LIGHT_WAVEFRONT,
    ];
    assemble(&[&maths()[..], &kernel].concat())
}

/// The probe kernel's full WGSL source (prelude and maths only, no scene).
pub fn probe_source() -> String {
    assemble(&[&maths()[..], &[PROBE]].concat())
}

/// The light probe kernel's full WGSL source: prelude, maths, scene bindings, lights.
pub fn light_probe_source() -> String {
    let lights = crate::scene::light::family_wgsl::wgsl_dispatch();
    assemble(&[&maths()[..], &[SCENE, CWBVH, LIGHT, &lights, LIGHT_PROBE]].concat())
}

/// The traversal probe's full WGSL source: prelude, maths, scene bindings, both traversals.
pub fn bvh_probe_source() -> String {
    assemble(&[&maths()[..], &[SCENE, CWBVH, BVH_PROBE]].concat())
}

/// Compile a WGSL module, turning validation errors into `Err` instead of a panic.
pub fn create_module(ctx: &GpuContext, label: &str, source: String) -> Result<wgpu::ShaderModule> {
    // Validate with naga first: a clear error message, and wgpu would panic on a bad module.
    let module = naga::front::wgsl::parse_str(&source)
        .map_err(|e| anyhow::anyhow!("{label}: {}", e.emit_to_string(&source)))?;
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .map_err(|e| anyhow::anyhow!("{label}: {}", e.emit_to_string(&source)))?;
    Ok(ctx
        .device
        .create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(label),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        }))
}
