//! GPU buffer layouts: `#[repr(C)]` + `bytemuck::Pod` twins of the WGSL structs in
//! `src/shaders/*.wgsl`. No `vec3` in storage buffers: three-component values are `[f32; 3]`
//! (`array<f32, 3>` in WGSL). `tests/gpu.rs` checks every struct's size and field offsets
//! against the WGSL via naga reflection ([`wgsl_struct_layout`]).

/// Size and field offsets of a GPU struct, for the layout check.
pub trait GpuLayout: bytemuck::Pod {
    /// Name of the WGSL struct.
    const WGSL_NAME: &'static str;
    /// (field name, byte offset) in declaration order.
    fn fields() -> Vec<(&'static str, u32)>;
    fn size() -> u32 {
        std::mem::size_of::<Self>() as u32
    }
}

macro_rules! gpu_struct {
    ($(#[$m:meta])* pub struct $name:ident { $($(#[$fm:meta])* pub $f:ident : $t:ty),* $(,)? }) => {
        $(#[$m])*
        #[repr(C)]
        #[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
        pub struct $name { $($(#[$fm])* pub $f: $t),* }
        impl GpuLayout for $name {
            const WGSL_NAME: &'static str = stringify!($name);
            fn fields() -> Vec<(&'static str, u32)> {
                vec![$((stringify!($f), std::mem::offset_of!($name, $f) as u32)),*]
            }
        }
    };
}

gpu_struct! {
    /// BVH2 node (obvhs `Bvh2Node` repacked): inner if `prim_count` = 0 (children at
    /// `first_index` and `first_index + 1`), else a leaf over triangle slots
    /// `first_index .. first_index + prim_count`.
    pub struct BvhNode {
        pub lo: [f32; 3],
        pub prim_count: u32,
        pub hi: [f32; 3],
        pub first_index: u32,
    }
}

gpu_struct! {
    /// A triangle in BVH leaf order (slot k holds scene triangle `primitive_indices[k]`).
    pub struct Triangle {
        pub p0: [f32; 3],
        pub material: u32,
        pub p1: [f32; 3],
        pub scene_tri: u32,
        pub p2: [f32; 3],
        /// `LightSet::tri_pick_prob` of the scene triangle.
        pub pick_prob: f32,
        pub i0: u32,
        pub i1: u32,
        pub i2: u32,
        /// `Mesh::area` of the scene triangle.
        pub area: f32,
    }
}

gpu_struct! {
    /// Per-vertex shading attributes (positions live in [`Triangle`]).
    pub struct Vertex {
        pub normal: [f32; 3],
        pub u: f32,
        pub v: f32,
        pub _pad: u32,
    }
}

gpu_struct! {
    /// A material resolved for the GPU (`bsdf` = one of the `BSDF_*` kinds of bsdf.wgsl).
    pub struct Material {
        pub base_color: [f32; 3],
        pub bsdf: u32,
        pub emission: [f32; 3],
        /// `MAT_*` flags of scene.wgsl.
        pub flags: u32,
        /// Beer–Lambert σ_a (`scene::Material::sigma_a`).
        pub sigma_a: [f32; 3],
        pub eta: f32,
        pub alpha: f32,
        pub metallic: f32,
        pub _pad0: u32,
        pub _pad1: u32,
    }
}

gpu_struct! {
    /// One entry of the light distribution (area triangle or punctual light) with its CDF.
    pub struct Light {
        pub position: [f32; 3],
        pub kind: u32,
        pub direction: [f32; 3],
        /// Leaf slot of the triangle for area lights.
        pub index: u32,
        pub intensity: [f32; 3],
        pub cos_inner: f32,
        pub cdf: f32,
        pub cos_outer: f32,
        pub _pad0: u32,
        pub _pad1: u32,
    }
}

gpu_struct! {
    /// Per-dispatch uniforms of the integrator kernel.
    pub struct Params {
        pub cam_pos: [f32; 4],
        pub cam_right: [f32; 4],
        pub cam_up: [f32; 4],
        pub cam_back: [f32; 4],
        pub environment: [f32; 4],
        pub width: u32,
        pub height: u32,
        pub seed: u32,
        pub max_depth: u32,
        pub rr_depth: u32,
        pub sample_offset: u32,
        pub batch: u32,
        pub light_count: u32,
        pub w_old: f32,
        pub w_new: f32,
        pub debug_pixel: u32,
        pub _pad: u32,
    }
}

gpu_struct! {
    /// Header of the stats buffer (64-bit counters as lo/hi u32 atomics); the debug records
    /// (`vec4<f32>`) follow it.
    pub struct Stats {
        pub dropped_lo: u32,
        pub dropped_hi: u32,
        pub segments_lo: u32,
        pub segments_hi: u32,
    }
}

gpu_struct! {
    /// Input of the probe kernel (src/shaders/probe.wgsl).
    pub struct ProbeCase {
        pub wo: [f32; 3],
        pub uc: f32,
        pub wi: [f32; 3],
        pub eta: f32,
        pub u2: [f32; 2],
        pub kind: u32,
        pub pixel: u32,
        pub sample: u32,
        pub seed: u32,
        pub _pad0: u32,
        pub _pad1: u32,
    }
}

gpu_struct! {
    /// Output of the probe kernel.
    pub struct ProbeOut {
        pub fresnel: [f32; 4],
        pub eta_rel: f32,
        pub refract_ok: f32,
        pub eval_pdf: [f32; 4],
        pub refracted: [f32; 3],
        pub sample_pdf: f32,
        pub sample_wi: [f32; 3],
        pub sample_eta_rel: f32,
        pub sample_weight: [f32; 3],
        pub sample_flags: u32,
        pub rng: [u32; 5],
        pub _pad: u32,
    }
}

/// BSDF kinds (the `BSDF_*` constants of bsdf.wgsl).
pub const BSDF_LAMBERT: u32 = 0;
pub const BSDF_MIRROR: u32 = 1;
pub const BSDF_SMOOTH_DIELECTRIC: u32 = 2;

/// Material flags (the `MAT_*` constants of scene.wgsl).
pub const MAT_EMISSIVE: u32 = 1;
pub const MAT_DOUBLE_SIDED: u32 = 2;
pub const MAT_TRANSMISSIVE: u32 = 4;
pub const MAT_SOLID: u32 = 8;
pub const MAT_BLACK_EMITTER: u32 = 16;
pub const MAT_ABSORBS: u32 = 32;

/// Light kinds (the `LIGHT_*` constants of scene.wgsl).
pub const LIGHT_TRIANGLE: u32 = 0;
pub const LIGHT_POINT: u32 = 1;
pub const LIGHT_SPOT: u32 = 2;
pub const LIGHT_DIRECTIONAL: u32 = 3;

/// Debug records: 1 (camera dir) + 3 per vertex × 16 vertices + 1 (final sample).
pub const DEBUG_MAX_VERTICES: usize = 16;
pub const DEBUG_STRIDE: usize = 3;
pub const DEBUG_RECORDS: usize = 2 + DEBUG_STRIDE * DEBUG_MAX_VERTICES;

/// Size and (member name, offset) list of the WGSL struct `name` in `source`, by naga
/// reflection. `Err` if the source does not parse or has no such struct.
pub fn wgsl_struct_layout(source: &str, name: &str) -> anyhow::Result<(u32, Vec<(String, u32)>)> {
    let module = naga::front::wgsl::parse_str(source)
        .map_err(|e| anyhow::anyhow!("WGSL parse error: {}", e.emit_to_string(source)))?;
    for (_, ty) in module.types.iter() {
        if ty.name.as_deref() == Some(name)
            && let naga::TypeInner::Struct { members, span } = &ty.inner
        {
            let fields = members
                .iter()
                .map(|m| (m.name.clone().unwrap_or_default(), m.offset))
                .collect();
            return Ok((*span, fields));
        }
    }
    anyhow::bail!("no struct '{name}' in the WGSL source")
}

/// Compare a Rust GPU struct with its WGSL twin; `Err` describes the first mismatch.
pub fn check_layout<T: GpuLayout>(source: &str) -> anyhow::Result<()> {
    let (size, fields) = wgsl_struct_layout(source, T::WGSL_NAME)?;
    let rust: Vec<(String, u32)> = T::fields()
        .into_iter()
        .map(|(n, o)| (n.to_string(), o))
        .collect();
    anyhow::ensure!(
        size == T::size(),
        "{}: WGSL size {size} != Rust size {}",
        T::WGSL_NAME,
        T::size()
    );
    anyhow::ensure!(
        fields == rust,
        "{}: WGSL fields {fields:?} != Rust fields {rust:?}",
        T::WGSL_NAME
    );
    Ok(())
}

/// Like [`check_layout`] for a WGSL struct that ends in a runtime-sized array `tail` placed
/// right after the Rust header `T` (the stats buffer).
pub fn check_layout_with_tail<T: GpuLayout>(source: &str, tail: &str) -> anyhow::Result<()> {
    let (_, mut fields) = wgsl_struct_layout(source, T::WGSL_NAME)?;
    let last = fields.pop();
    anyhow::ensure!(
        last == Some((tail.to_string(), T::size())),
        "{}: trailing array {last:?} is not '{tail}' at offset {}",
        T::WGSL_NAME,
        T::size()
    );
    let rust: Vec<(String, u32)> = T::fields()
        .into_iter()
        .map(|(n, o)| (n.to_string(), o))
        .collect();
    anyhow::ensure!(
        fields == rust,
        "{}: WGSL fields {fields:?} != Rust fields {rust:?}",
        T::WGSL_NAME
    );
    Ok(())
}
