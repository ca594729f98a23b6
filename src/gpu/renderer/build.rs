//! Construction of a [`GpuRenderer`]: checks, specialisation, scene buffers and bind groups.

use super::edit::check_polarization;
use super::{
    BATCHES_IN_FLIGHT, Buffers, BuiltBuffers, GpuRenderer, STATS_BYTES, film_bytes, gpu_plan,
    photon_paths, splat_film, wavefront, wavefront_override_from_env,
};
use crate::gpu::GpuContext;
use crate::gpu::buffers::{checked_storage, zeroed_storage};
use crate::gpu::layout::{GpuLayout, Params};
use crate::gpu::photons::PhotonStore;
use crate::gpu::pipeline::{Pipelines, Specialization};
use crate::gpu::submissions::Submissions;
use crate::gpu::upload::{self, GpuBvh};
use crate::render::photon_aim::PhotonTargets;
use crate::render::{Polarization, RenderOptions};
use crate::scene::{Scene, light::LightSet};
use anyhow::Result;
use std::time::Duration;

impl GpuRenderer {
    pub(super) fn build(
        ctx: GpuContext,
        scene: Scene,
        opts: RenderOptions,
        (background_compile, tiles): (bool, bool),
        polarization: Option<Polarization>,
    ) -> Result<GpuRenderer> {
        Self::check_renderable(&scene, &opts)?;
        check_polarization(polarization, &opts, &scene)?;
        let features = scene.features();
        // The tree first: its depth sizes the kernels' traversal stack.
        let bvh = upload::build_gpu_bvh(&scene, upload::BvhLayout::from_env())?;
        let wavefront_override = wavefront_override_from_env();
        let software = ctx.is_software();
        let spec = Self::specialization_for(
            features,
            &opts,
            &scene,
            &bvh,
            (wavefront_override, polarization.is_some()),
            software,
        );
        let pipelines = Self::compiled_pipelines(&ctx, spec, background_compile)?;
        let light_set = LightSet::build(&scene);
        let (buffers, light_count, tex_slots) =
            Self::create_buffers(&ctx, &scene, &bvh, &light_set, &opts, tiles)?;
        let (bind_group, wf_args) = Self::create_bind_groups(&ctx, &pipelines, &buffers)?;
        let mut r = GpuRenderer {
            ctx,
            scene,
            opts,
            bvh,
            light_set,
            light_count,
            pipelines,
            spec,
            buffers,
            bind_group,
            spp: 0,
            elapsed: Duration::ZERO,
            submissions: Submissions::default(),
            debug_pixel: u32::MAX,
            tex_slots,
            features,
            photon_r0: 0.0,
            photon_aim: Default::default(),
            background_compile,
            general_only: false,
            clear_pending: false,
            batches_in_flight: BATCHES_IN_FLIGHT,
            tiled: None,
            film_y0: 0,
            tiles,
            wavefront_override,
            wavefront_indirect: false,
            polarization,
            analyzer: None,
            wf_args,
        };
        r.fit_to_scene();
        Ok(r)
    }

    /// The checks before any GPU work: a valid scene the kernels support and valid options
    /// (every estimator has a GPU plan, `render::estimator_plan`).
    fn check_renderable(scene: &Scene, opts: &RenderOptions) -> Result<()> {
        scene.validate()?;
        upload::check_supported(scene)?;
        opts.check()?;
        Ok(())
    }

    /// The pipeline layouts (in an error scope) with the kernels of `spec` compiled now, or
    /// on a worker thread when `background_compile`.
    fn compiled_pipelines(
        ctx: &GpuContext,
        spec: Specialization,
        background_compile: bool,
    ) -> Result<Pipelines> {
        let mut pipelines = ctx.scoped("cannot create the GPU pipeline layout", || {
            Pipelines::new(ctx)
        })??;
        if background_compile {
            super::submit::compile_family_in_background(&mut pipelines, spec)?;
        } else {
            pipelines.compile(spec)?;
        }
        Ok(pipelines)
    }

    /// The integrator's bind group over `buffers` and the wavefront's dispatch-size
    /// arguments, in an error scope.
    fn create_bind_groups(
        ctx: &GpuContext,
        pipelines: &Pipelines,
        buffers: &Buffers,
    ) -> Result<(wgpu::BindGroup, wavefront::AdvanceArgs)> {
        ctx.scoped("cannot bind the GPU buffers", || {
            (
                Self::bind(ctx, pipelines, buffers),
                wavefront::AdvanceArgs::new(ctx, pipelines),
            )
        })
    }

    /// Settle a freshly assembled renderer: indirect wavefront dispatch, tiles and wavefront
    /// sized to the image, the SPPM start radius and the filter table.
    fn fit_to_scene(&mut self) {
        self.set_wavefront_indirect(true);
        self.fit_tiles();
        self.fit_wavefront();
        self.photon_r0 = self.sppm_radius0();
        self.fit_photon_aim();
    }

    /// Forget where `sppm` aims photons (the materials or lights changed): the next `sppm`
    /// submission finds it again ([`GpuRenderer::photon_aim`]).
    pub(super) fn fit_photon_aim(&mut self) {
        self.photon_aim = Default::default();
    }

    /// Where `sppm` aims the photons of finite lights and the share of the power sent there
    /// (`render::photon_aim`), for the current materials and lights.
    pub(super) fn photon_aim(&self) -> &(PhotonTargets, f32) {
        self.photon_aim
            .get_or_init(|| PhotonTargets::with_fraction(&self.scene, &self.light_set))
    }

    /// [`GpuRenderer::build_buffers`] in error scopes: a validation or out-of-memory error is
    /// an `Err`.
    pub(super) fn create_buffers(
        ctx: &GpuContext,
        scene: &Scene,
        bvh: &GpuBvh,
        light_set: &LightSet,
        opts: &RenderOptions,
        tiles: bool,
    ) -> Result<BuiltBuffers> {
        ctx.scoped("cannot create the GPU buffers", || {
            Self::build_buffers(ctx, scene, bvh, light_set, opts, tiles)
        })?
    }

    /// The scene's buffers and a film for `opts`; `tiles`: an image larger than one binding
    /// may render in tiles (headless renders), else it is refused (the viewer).
    fn build_buffers(
        ctx: &GpuContext,
        scene: &Scene,
        bvh: &GpuBvh,
        light_set: &LightSet,
        opts: &RenderOptions,
        tiles: bool,
    ) -> Result<BuiltBuffers> {
        let tris = upload::pack_triangles(scene, bvh, light_set);
        let verts = upload::pack_vertices(scene);
        let (mut texels, tex_slots) = upload::pack_textures(scene);
        let env_offset = upload::pack_environment(light_set, &mut texels);
        let mats = upload::pack_materials(scene, &tex_slots);
        let (lights, light_count) = upload::pack_lights(bvh, light_set, env_offset);
        let (accum_bytes, splat_bytes) = film_bytes(ctx, scene, opts, tiles)?;
        let copyable = wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST;
        let buffers = Buffers {
            params: ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("params"),
                size: Params::size() as u64,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            nodes: checked_storage(ctx, "bvh nodes", "BVH", bvh.node_bytes())?,
            triangles: checked_storage(ctx, "triangles", "triangles", &tris)?,
            vertices: checked_storage(ctx, "vertices", "vertices", &verts)?,
            materials: checked_storage(ctx, "materials", "materials", &mats)?,
            lights: checked_storage(ctx, "lights", "lights", &lights)?,
            accum: zeroed_storage(ctx, "accum", accum_bytes, copyable),
            stats: zeroed_storage(ctx, "stats", STATS_BYTES, copyable),
            texels: checked_storage(ctx, "texels", "textures", &texels)?,
            splats: splat_film(ctx, splat_bytes),
            photon_store: PhotonStore::new(ctx, photon_paths(gpu_plan(opts, scene).sppm(), opts))?,
            env_offset,
            wavefront: wavefront::WavefrontBuffers::placeholder(ctx),
        };
        Ok((buffers, light_count, tex_slots))
    }

    pub(super) fn bind(ctx: &GpuContext, p: &Pipelines, b: &Buffers) -> wgpu::BindGroup {
        let bufs = [
            &b.params,
            &b.nodes,
            &b.triangles,
            &b.vertices,
            &b.materials,
            &b.lights,
            &b.accum,
            &b.stats,
            &b.texels,
        ];
        let mut entries: Vec<wgpu::BindGroupEntry> = bufs
            .iter()
            .enumerate()
            .map(|(i, buf)| wgpu::BindGroupEntry {
                binding: i as u32,
                resource: buf.as_entire_binding(),
            })
            .collect();
        for (binding, buf) in [
            (10, &b.splats),
            (11, &b.photon_store.grid),
            (12, &b.photon_store.photons),
            (13, &b.wavefront.paths),
            (15, &b.wavefront.light_paths),
            (16, &b.wavefront.queue),
        ] {
            entries.push(wgpu::BindGroupEntry {
                binding,
                resource: buf.as_entire_binding(),
            });
        }
        // One chunk entry, at the dynamic offset each dispatch gives.
        entries.push(wgpu::BindGroupEntry {
            binding: 14,
            resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                buffer: &b.wavefront.chunks,
                offset: 0,
                size: wgpu::BufferSize::new(16),
            }),
        });
        ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("integrator"),
            layout: &p.bind_group_layout,
            entries: &entries,
        })
    }
}
