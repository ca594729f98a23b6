//! [`Specialization`]: which parts of the kernel a scene needs, the pipeline cache key.

use crate::bsdf::BsdfParts;
use crate::gpu::upload::{BvhLayout, GpuBvh};
use crate::scene::Features;
use crate::scene::light::LightParts;

/// Which parts of the kernel a scene needs (the pipeline cache key). The environment is
/// always compiled in (its radiance is a slider: value edits must not recompile).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Specialization {
    /// The BSDFs compiled in: one part per variant of the BSDF table (`bsdf::family`), each
    /// a `HAS_*` override.
    pub bsdfs: BsdfParts,
    /// Microfacet distributions in use (rough glass / glossy metal; metal-rough is GGX).
    pub ggx: bool,
    pub beckmann: bool,
    /// The lights compiled in: one part per light-table row that owns one
    /// (`scene::light::family`): emissive triangles, punctual lights, the environment image
    /// (next-event estimation samples it; escaping rays weight it). The uniform environment
    /// is always compiled in (`HAS_ENVIRONMENT`).
    pub lights: LightParts,
    /// Solid glass exists (absorption is a slider on it, so keyed by the kind).
    pub absorption: bool,
    /// Some BSDF reads a texture.
    pub textures: bool,
    /// A material has a tangent-space normal map (the mesh carries tangents).
    pub normal_map: bool,
    /// A Heckbert path filter is set (the table itself is data in the parameters: edits do
    /// not recompile).
    pub filter: bool,
    /// Hero-wavelength spectral transport (a dispersive material exists).
    pub spectral: bool,
    /// Light tracing combined with path tracing by MIS (`lt+pt`; the estimator, not the scene).
    pub light_tracing: bool,
    /// Path tracing with photon-mapped caustics (`sppm`; the estimator, not the scene).
    pub sppm: bool,
    /// Nested dielectric volumes: paths keep the medium stack and pass false hits.
    pub nested: bool,
    /// Camera paths by the wavefront kernels (`Kernel::WfStart` … `WfFinish`, and for lt+pt
    /// `LtWfStart` … `LtWfFinish` instead of `light_trace`) instead of `render`:
    /// chosen where the megakernel needs more registers than a GPU can give without
    /// losing occupancy ([`Specialization::wants_wavefront`]).
    pub wavefront: bool,
    /// Traversal stack entries per invocation (`upload::bvh_stack_entries` of the uploaded
    /// tree's depth; the full 64 where the tree is not known). Workgroup memory, so it
    /// bounds occupancy: 64 entries allow 4 subgroups per SIMD on RDNA2, 24 allow 10.
    pub bvh_stack: u32,
    /// The tree is the compressed 8-wide BVH (`upload::BvhLayout::Cwbvh`), not the BVH2.
    pub bvh_wide: bool,
    /// The CWBVH's children are tested four at once in vec4s (`BVH_CHILDREN_X4`): on
    /// CPU-emulated adapters (`GpuContext::is_software`), where it is the faster form; a GPU
    /// tests them one at a time, in fewer registers (docs/gpu.md "The wide BVH").
    pub bvh_x4: bool,
    /// Polarised transport (issue 38): the camera walk carries a row of the Mueller chain
    /// (`cpu/polarized/chain.wgsl`); the path estimator in the megakernel only (the
    /// renderer refuses the others; no wavefront: its path state has no room for the row).
    pub polarized: bool,
}

impl Default for Specialization {
    /// No part compiled in, the full traversal stack.
    fn default() -> Self {
        Specialization::from_features(Features::empty())
    }
}

impl Specialization {
    /// The kernel parts `f` needs (no filter, path tracing).
    pub fn from_features(f: Features) -> Specialization {
        Specialization {
            bsdfs: crate::scene::features::bsdf_parts(f),
            ggx: f.contains(Features::GGX),
            beckmann: f.contains(Features::BECKMANN),
            lights: crate::scene::features::light_parts(f),
            absorption: f
                .intersects(Features::SMOOTH_GLASS | Features::ROUGH_GLASS | Features::IRIDESCENCE),
            textures: f.contains(Features::TEXTURES),
            normal_map: f.contains(Features::NORMAL_MAP),
            filter: false,
            spectral: f.contains(Features::DISPERSION),
            light_tracing: false,
            sppm: false,
            nested: f.contains(Features::NESTED),
            wavefront: false,
            bvh_stack: crate::gpu::upload::MAX_BVH_DEPTH,
            bvh_wide: BvhLayout::default() == BvhLayout::Cwbvh,
            bvh_x4: false,
            polarized: false,
        }
    }

    /// Whether the camera walk should run as a wavefront: where the megakernel needs more
    /// than 128 VGPRs on RADV navi21 (fewer than 8 waves per SIMD) — measured for every
    /// built-in with each GPU estimator and for the all-features worst cases, and checked
    /// against the compiler by `tests/gpu_registers.rs`: the image environment, textures, or
    /// light tracing or photon mapping together with spectral, nested or filtered paths or
    /// the metal-rough material, or light tracing with rough glass. Elsewhere the
    /// megakernel fits and keeps its paths in registers. Never with polarised transport
    /// (the wavefront's stored path state has no room for the chain's row).
    pub fn wants_wavefront(&self) -> bool {
        let joint = self.light_tracing || self.sppm;
        let heavy = self.lights.env_image
            || self.textures
            || (joint && (self.spectral || self.nested || self.filter || self.bsdfs.metal_rough))
            || (self.light_tracing && self.bsdfs.rough_dielectric);
        heavy && !self.polarized
    }

    /// The kernel parts `scene` needs (as [`Specialization::from_features`]) with the
    /// traversal sized for the tree the renderer uploads for it (built here, layout by
    /// `BvhLayout::from_env`) and the camera walk's form by
    /// [`Specialization::wants_wavefront`] — what the renderer runs for the path estimator.
    pub fn for_scene(scene: &crate::scene::Scene) -> anyhow::Result<Specialization> {
        let bvh = crate::gpu::upload::build_gpu_bvh(scene, BvhLayout::from_env())?;
        Ok(Specialization::from_features(scene.features())
            .with_bvh(&bvh)
            .with_wavefront_rule())
    }

    /// The same parts with `wavefront` set by [`Specialization::wants_wavefront`].
    pub fn with_wavefront_rule(self) -> Specialization {
        Specialization {
            wavefront: self.wants_wavefront(),
            ..self
        }
    }

    /// The same kernel parts with the traversal stack sized for a BVH2 of `depth` levels.
    pub fn with_bvh_depth(self, depth: u32) -> Specialization {
        Specialization {
            bvh_stack: crate::gpu::upload::bvh_stack_entries(depth),
            bvh_wide: false,
            ..self
        }
    }

    /// The same kernel parts traversing `bvh` (its layout, its stack size).
    pub fn with_bvh(self, bvh: &GpuBvh) -> Specialization {
        Specialization {
            bvh_stack: bvh.stack_words(),
            bvh_wide: bvh.layout == BvhLayout::Cwbvh,
            ..self
        }
    }

    /// Every part compiled in (the worst case for registers), with light tracing as the
    /// estimator: the estimators are exclusive (the renderer sets at most one of
    /// `light_tracing` and `sppm`), so [`Specialization::all_sppm`] is the other worst case.
    pub fn all() -> Specialization {
        Specialization {
            // Films only in their own family's general kernel (`general`).
            bsdfs: BsdfParts {
                iridescence: false,
                ..BsdfParts::ALL
            },
            ggx: true,
            beckmann: true,
            lights: LightParts::ALL,
            absorption: true,
            textures: true,
            normal_map: true,
            filter: true,
            spectral: true,
            light_tracing: true,
            sppm: false,
            nested: true,
            wavefront: true,
            bvh_stack: crate::gpu::upload::MAX_BVH_DEPTH,
            bvh_wide: BvhLayout::default() == BvhLayout::Cwbvh,
            bvh_x4: false,
            polarized: false,
        }
    }

    /// The general kernel of this specialisation's family (issue 36): every material, light,
    /// texture and absorption part compiled in and the full traversal stack, with the same
    /// estimator, colour representation (RGB or spectral), path filter, medium rule,
    /// camera-walk form and tree layout — the parts that change the maths or the buffers. The parts it adds
    /// are all guarded by the scene's data (a material's kind, a light's kind, a texture
    /// slot), so it renders any scene of the family with the same estimator as the
    /// specialised kernel: the viewer runs it while that one compiles. One per family,
    /// whatever the scene, so it is compiled once and kept.
    pub fn general(self) -> Specialization {
        Specialization {
            light_tracing: self.light_tracing,
            sppm: self.sppm,
            filter: self.filter,
            spectral: self.spectral,
            nested: self.nested,
            wavefront: self.wavefront,
            polarized: self.polarized,
            // Films are a family of their own: their shading needs 8–16 more VGPRs than the
            // budget of the general kernels without them (tests/gpu_registers.rs).
            bsdfs: BsdfParts {
                iridescence: self.bsdfs.iridescence,
                ..BsdfParts::ALL
            },
            // The deepest stack either layout uses (both at most `MAX_BVH_DEPTH` words),
            // and the layout of the uploaded tree.
            bvh_stack: crate::gpu::upload::MAX_BVH_DEPTH,
            bvh_wide: self.bvh_wide,
            ..Specialization::all()
        }
    }

    /// Every part compiled in, with photon mapping as the estimator (`sppm`).
    pub fn all_sppm() -> Specialization {
        Specialization {
            light_tracing: false,
            sppm: true,
            ..Specialization::all()
        }
    }

    /// The override constants that specialise the integrator module.
    pub fn constants(&self) -> Vec<(&'static str, f64)> {
        let b = |x: bool| if x { 1.0 } else { 0.0 };
        let tables = self.bsdfs.overrides().into_iter();
        let tables = tables.chain(self.lights.overrides());
        tables
            .map(|(name, x)| (name, b(x)))
            .chain([
                ("HAS_GGX", b(self.ggx)),
                ("HAS_BECKMANN", b(self.beckmann)),
                ("HAS_ENVIRONMENT", 1.0),
                ("HAS_ABSORPTION", b(self.absorption)),
                ("HAS_TEXTURES", b(self.textures)),
                ("HAS_NORMAL_MAP", b(self.normal_map)),
                ("HAS_FILTER", b(self.filter)),
                ("HAS_SPECTRAL", b(self.spectral)),
                ("HAS_LT", b(self.light_tracing)),
                ("HAS_SPPM", b(self.sppm)),
                ("HAS_NESTED", b(self.nested)),
                ("BVH_STACK_SIZE", f64::from(self.bvh_stack)),
                ("BVH_WIDE", b(self.bvh_wide)),
                ("BVH_CHILDREN_X4", b(self.bvh_x4)),
                ("HAS_POLARIZATION", b(self.polarized)),
            ])
            .collect()
    }
}
