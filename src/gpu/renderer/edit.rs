//! Parameter edits (material, estimator, wavefront, environment, camera, options, scene,
//! path filter) and the respecialisation and buffer fitting they entail.

use super::{GpuRenderer, film_bytes, gpu_plan, photon_paths, splat_film};
use crate::gpu::buffers::{checked_bytes, storage, zeroed_storage};
use crate::gpu::layout;
use crate::gpu::photons::PhotonStore;
use crate::gpu::pipeline::Specialization;
use crate::gpu::upload::{self, GpuBvh};
use crate::paths::{DfaTable, PathFilter};
use crate::render::{Estimator, EstimatorPlan, Polarization, RenderOptions};
use crate::scene::{Camera, Checked, Features, Material, Scene, light::LightSet};
use anyhow::{Result, ensure};
use glam::{Vec3, Vec4};

/// What polarised transport (`pol`) needs of the render: a finite filter angle, the path
/// estimator (as planned for the GPU) and no path filter.
pub(super) fn check_polarization(
    pol: Option<Polarization>,
    opts: &RenderOptions,
    scene: &Scene,
) -> Result<()> {
    let Some(p) = pol else {
        return Ok(());
    };
    ensure!(
        p.filter.is_none_or(f32::is_finite),
        "the polarising filter's angle must be finite"
    );
    let runs = gpu_plan(opts, scene).runs;
    ensure!(
        runs == Estimator::Path,
        "polarised transport runs the path estimator on the GPU, not {runs}"
    );
    ensure!(
        opts.filter.is_none(),
        "polarised transport renders every path: clear the path filter first"
    );
    ensure!(
        !scene.features().contains(Features::IRIDESCENCE),
        "polarised thin films run on the CPU (--device cpu): the GPU's Mueller events have no thin film"
    );
    Ok(())
}

impl GpuRenderer {
    /// Change material `index` (colour, IOR, roughness, emission …): buffers are rewritten in
    /// place, the BVH is kept, and the pipeline is only switched if the material's *kind*
    /// changes the specialisation (then compiled once and cached). Accumulation restarts.
    pub fn set_material(&mut self, index: usize, material: Material) -> Result<()> {
        self.set_checked_material(index, Checked::new(material)?)
    }

    /// [`GpuRenderer::set_material`] with a material validated where it was edited
    /// (`scene::Checked`): not validated again.
    pub fn set_checked_material(
        &mut self,
        index: usize,
        material: Checked<Material>,
    ) -> Result<()> {
        let material = material.into_inner();
        ensure!(
            index < self.scene.materials.len(),
            "material index {index} out of range ({} materials)",
            self.scene.materials.len()
        );
        let emission_changed = self.scene.materials[index].emission != material.emission
            || self.scene.materials[index].double_sided != material.double_sided;
        let old = std::mem::replace(&mut self.scene.materials[index], material);
        let supported = upload::check_supported(&self.scene)
            .and_then(|()| check_polarization(self.polarization, &self.opts, &self.scene));
        if let Err(e) = supported {
            self.scene.materials[index] = old;
            return Err(e);
        }
        let textures_changed = {
            let (a, b) = (&old, &self.scene.materials[index]);
            a.base_color_texture != b.base_color_texture
                || a.metallic_roughness_texture != b.metallic_roughness_texture
                || a.emissive_texture != b.emissive_texture
                || a.normal_texture != b.normal_texture
                || a.iridescence.and_then(|i| i.thickness_texture)
                    != b.iridescence.and_then(|i| i.thickness_texture)
                || a.kind != b.kind
        };
        if textures_changed {
            self.repack_textures()?;
        }
        self.write_material(index);
        if emission_changed {
            self.rebuild_lights()?;
        } else {
            self.fit_photon_aim();
        }
        self.features = self.scene.features();
        self.respecialize();
        self.fit_film()?;
        self.fit_photon_store()?;
        self.reset();
        Ok(())
    }

    /// Repack the textures and every material (their texture slots may move) after a material
    /// edit and rebind; the lights too when the environment's block in `texels` moves.
    fn repack_textures(&mut self) -> Result<()> {
        let (mut texels, slots) = upload::pack_textures(&self.scene);
        let env_offset = upload::pack_environment(&self.light_set, &mut texels);
        self.buffers.texels = storage(
            &self.ctx,
            "texels",
            checked_bytes("textures", &texels, self.ctx.max_binding_bytes())?,
        );
        let mats = upload::pack_materials(&self.scene, &slots);
        self.ctx.queue.write_buffer(
            &self.buffers.materials,
            0,
            checked_bytes("materials", &mats, self.ctx.max_binding_bytes())?,
        );
        self.tex_slots = slots;
        self.bind_group = Self::bind(&self.ctx, &self.pipelines, &self.buffers);
        if env_offset != self.buffers.env_offset {
            self.buffers.env_offset = env_offset;
            self.rebuild_lights()?;
        }
        Ok(())
    }

    /// Rewrite material `index` in place in the materials buffer.
    fn write_material(&self, index: usize) {
        let packed = upload::pack_material(
            &self.scene,
            &self.scene.materials[index],
            self.tex_slots[index],
        );
        self.ctx.queue.write_buffer(
            &self.buffers.materials,
            (index * std::mem::size_of::<layout::Material>()) as u64,
            bytemuck::bytes_of(&packed),
        );
    }

    /// The kernel parts for `features` with the filter and estimator of `opts`.
    pub(super) fn specialization_for(
        features: Features,
        opts: &RenderOptions,
        scene: &Scene,
        bvh: &GpuBvh,
        (wavefront, polarized): (Option<bool>, bool),
        software: bool,
    ) -> Specialization {
        let mut spec = Specialization::from_features(features).with_bvh(bvh);
        spec.bvh_x4 = spec.bvh_wide && software;
        spec.filter = opts.filter.is_some();
        let plan = gpu_plan(opts, scene);
        spec.light_tracing = plan.light_tracing();
        spec.sppm = plan.sppm();
        // `set_polarization` admits it only with the path estimator and no filter.
        spec.polarized = polarized && !spec.light_tracing && !spec.sppm && !spec.filter;
        match wavefront {
            Some(w) => Specialization {
                wavefront: w && !spec.polarized,
                ..spec
            },
            None => spec.with_wavefront_rule(),
        }
    }

    /// Give the accumulation and splat films the sizes the current specialisation needs (the
    /// splat film: the film's rows with light tracing, one pixel's worth otherwise; a tiled
    /// image's tile holds fewer rows with light tracing) and rebind when they change. A new
    /// accumulation film starts the tiles' CPU copy afresh (the caller resets).
    fn fit_film(&mut self) -> Result<()> {
        let (accum, splats) = film_bytes(&self.ctx, &self.scene, &self.opts, self.tiles_allowed())?;
        if accum == self.buffers.accum.size() && splats == self.buffers.splats.size() {
            return Ok(());
        }
        if accum != self.buffers.accum.size() {
            let copyable = wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST;
            self.buffers.accum = self.ctx.scoped("cannot create the film", || {
                zeroed_storage(&self.ctx, "accum", accum, copyable)
            })?;
            self.fit_tiles();
        }
        if splats != self.buffers.splats.size() {
            self.buffers.splats = self.ctx.scoped("cannot create the splat film", || {
                splat_film(&self.ctx, splats)
            })?;
        }
        self.bind_group = Self::bind(&self.ctx, &self.pipelines, &self.buffers);
        Ok(())
    }

    /// Give the photon store the size the current specialisation needs (one slot per pixel
    /// with sppm, a placeholder otherwise) and rebind when it changes.
    fn fit_photon_store(&mut self) -> Result<()> {
        let paths = photon_paths(self.spec.sppm, &self.opts).max(1);
        if paths == self.buffers.photon_store.requested {
            return Ok(());
        }
        self.buffers.photon_store = self.ctx.scoped("cannot create the photon store", || {
            PhotonStore::new(&self.ctx, paths)
        })??;
        self.bind_group = Self::bind(&self.ctx, &self.pipelines, &self.buffers);
        Ok(())
    }

    /// Select the specialisation for the current features, filter and estimator, and have
    /// its pipelines compiled (cached; on a worker thread with background compilation).
    pub(super) fn respecialize(&mut self) {
        self.spec = Self::specialization_for(
            self.features,
            &self.opts,
            &self.scene,
            &self.bvh,
            (self.wavefront_override, self.polarization.is_some()),
            self.ctx.is_software(),
        );
        self.fit_wavefront();
        self.request_pipelines();
    }

    /// The general kernel of the family `scene` rendered with `opts` would run here
    /// (`Specialization::general`: what renders while its own specialisation compiles).
    pub fn general_kernel_for(&self, scene: &Scene, opts: &RenderOptions) -> Specialization {
        Self::specialization_for(
            scene.features(),
            opts,
            scene,
            &self.bvh,
            (self.wavefront_override, self.polarization.is_some()),
            self.ctx.is_software(),
        )
        .general()
    }

    /// Compile ahead of need the general kernel `scene` with `opts` would run (a lecture's
    /// next demo): opening that scene then renders at once with it while its own
    /// specialisation compiles. Nothing happens where compiling ahead is off (software
    /// drivers, by default).
    pub fn compile_ahead_for(&mut self, scene: &Scene, opts: &RenderOptions) -> Result<()> {
        let spec = self.general_kernel_for(scene, opts);
        self.pipelines.compile_ahead(spec)
    }

    /// Whether the pipelines of `spec` are compiled (e.g. [`GpuRenderer::general_kernel_for`]
    /// compiled ahead), collecting finished background compilations first.
    pub fn is_compiled(&mut self, spec: Specialization) -> bool {
        if let Err(e) = self.pipelines.poll() {
            super::super::context::record(&self.ctx.errors, format!("{e:#}"));
        }
        self.pipelines.is_ready(spec)
    }

    /// Run the camera walk as a wavefront (`Some(true)`), as the megakernel (`Some(false)`) or
    /// as `Specialization::wants_wavefront` decides (`None`); accumulation restarts.
    pub fn set_wavefront(&mut self, wavefront: Option<bool>) {
        self.wavefront_override = wavefront;
        self.respecialize();
        self.reset();
    }

    /// Size the wavefront's bounces by indirect dispatch (`true`, the default, where the
    /// adapter has `DownlevelFlags::INDIRECT_EXECUTION`) or dispatch every bounce over the
    /// whole chunk (`false`; for tests: the same image either way).
    pub fn set_wavefront_indirect(&mut self, on: bool) {
        let flags = self.ctx.adapter.get_downlevel_capabilities().flags;
        self.wavefront_indirect = on && flags.contains(wgpu::DownlevelFlags::INDIRECT_EXECUTION);
    }

    /// Choose the estimator (planned by `render::estimator_plan`: `auto` resolves for the
    /// scene, bdpt and lt run as lt+pt); compiles its pipelines on first use; accumulation
    /// restarts.
    pub fn set_estimator(&mut self, estimator: Estimator) -> Result<()> {
        // Refused before anything changes: the films the estimator needs must fit (in tiles
        // where the renderer may tile).
        let opts = RenderOptions {
            estimator,
            ..self.opts
        };
        film_bytes(&self.ctx, &self.scene, &opts, self.tiles_allowed())?;
        if self.polarization.is_some() {
            let runs = gpu_plan(&opts, &self.scene).runs;
            ensure!(
                runs == Estimator::Path,
                "polarised transport runs the path estimator on the GPU, not {runs}: take the \
                 polarising filter away first"
            );
        }
        self.opts.estimator = estimator;
        self.respecialize();
        self.fit_film()?;
        self.fit_photon_store()?;
        self.reset();
        Ok(())
    }

    /// The estimator asked for.
    pub fn estimator(&self) -> Estimator {
        self.opts.estimator
    }

    /// The estimator the kernels run (the plan the kernels were specialised for).
    pub fn effective_estimator(&self) -> Estimator {
        self.plan().runs
    }

    /// The one estimator decision for the estimator asked and the scene.
    pub fn plan(&self) -> EstimatorPlan {
        gpu_plan(&self.opts, &self.scene)
    }

    /// Light distribution changed (emission edits): rewrite triangles (pick probabilities) and
    /// the light CDF; the BVH is kept.
    fn rebuild_lights(&mut self) -> Result<()> {
        self.light_set = LightSet::build(&self.scene);
        let tris = upload::pack_triangles(&self.scene, &self.bvh, &self.light_set);
        self.ctx.queue.write_buffer(
            &self.buffers.triangles,
            0,
            checked_bytes("triangles", &tris, self.ctx.max_binding_bytes())?,
        );
        let (lights, count) =
            upload::pack_lights(&self.bvh, &self.light_set, self.buffers.env_offset);
        let bytes = checked_bytes("lights", &lights, self.ctx.max_binding_bytes())?;
        if bytes.len() as u64 <= self.buffers.lights.size() {
            self.ctx.queue.write_buffer(&self.buffers.lights, 0, bytes);
        } else {
            self.buffers.lights = storage(&self.ctx, "lights", bytes);
            self.bind_group = Self::bind(&self.ctx, &self.pipelines, &self.buffers);
        }
        self.light_count = count;
        self.fit_photon_aim();
        Ok(())
    }

    /// Uniform environment radiance (no recompilation). Accumulation restarts.
    pub fn set_environment(&mut self, radiance: Vec3) -> Result<()> {
        ensure!(
            radiance.is_finite() && radiance.min_element() >= 0.0,
            "environment radiance must be finite and non-negative"
        );
        self.scene.environment = radiance;
        self.reset();
        Ok(())
    }

    /// Move the camera. Accumulation restarts.
    pub fn set_camera(&mut self, camera: Camera) -> Result<()> {
        self.set_checked_camera(Checked::new(camera)?)
    }

    /// [`GpuRenderer::set_camera`] with a camera validated where it was edited: not again.
    pub fn set_checked_camera(&mut self, camera: Checked<Camera>) -> Result<()> {
        self.scene.camera = camera.into_inner();
        self.reset();
        Ok(())
    }

    /// Change seed, depth limits, batch or image size (size changes reallocate the image
    /// buffer). The filter and estimator stay as they are (see [`GpuRenderer::set_filter`]
    /// and [`GpuRenderer::set_estimator`]).
    pub fn set_options(&mut self, opts: RenderOptions) -> Result<()> {
        opts.check()?;
        let opts = self.keep_filter_and_estimator(opts);
        let resized = (opts.width, opts.height) != (self.opts.width, self.opts.height);
        self.opts = opts;
        if resized {
            let (buffers, count, slots) = Self::create_buffers(
                &self.ctx,
                &self.scene,
                &self.bvh,
                &self.light_set,
                &opts,
                self.tiles_allowed(),
            )?;
            self.buffers = buffers;
            self.light_count = count;
            self.tex_slots = slots;
            self.bind_group = Self::bind(&self.ctx, &self.pipelines, &self.buffers);
            self.fit_tiles();
            self.fit_wavefront();
        }
        self.reset();
        Ok(())
    }

    /// `opts` with the filter and estimator in use.
    fn keep_filter_and_estimator(&self, opts: RenderOptions) -> RenderOptions {
        RenderOptions {
            filter: self.opts.filter,
            filter_forward: self.opts.filter_forward,
            estimator: self.opts.estimator,
            ..opts
        }
    }

    /// Replace the scene: BVH, buffers and (if its features differ) the pipeline are rebuilt;
    /// compiled pipelines stay cached. Options as [`GpuRenderer::set_options`] (the filter
    /// and estimator stay).
    pub fn set_scene(&mut self, scene: Scene, opts: RenderOptions) -> Result<()> {
        scene.validate()?;
        upload::check_supported(&scene)?;
        opts.check()?;
        let opts = self.keep_filter_and_estimator(opts);
        let bvh = upload::build_gpu_bvh(&scene, self.bvh.layout)?;
        let light_set = LightSet::build(&scene);
        let (buffers, count, slots) = Self::create_buffers(
            &self.ctx,
            &scene,
            &bvh,
            &light_set,
            &opts,
            self.tiles_allowed(),
        )?;
        self.tex_slots = slots;
        self.scene = scene;
        self.opts = opts;
        self.bvh = bvh;
        self.light_set = light_set;
        self.buffers = buffers;
        self.light_count = count;
        self.bind_group = Self::bind(&self.ctx, &self.pipelines, &self.buffers);
        self.features = self.scene.features();
        self.fit_photon_aim();
        self.respecialize();
        self.fit_tiles();
        self.reset();
        Ok(())
    }

    /// Set the Heckbert path filter (None or an accept-all filter = every path). Only the
    /// uniform table is rewritten when a filter replaces another; switching between filtered
    /// and unfiltered selects the other specialisation (compiled once, then cached).
    /// Accumulation restarts.
    pub fn set_filter(&mut self, filter: Option<&PathFilter>) {
        self.opts.set_filter(filter);
        if self.opts.filter.is_some() {
            self.polarization = None; // polarised transport renders every path
        }
        self.respecialize();
        self.reset();
    }

    /// Trace polarised light (issue 38; `cpu/polarized/chain.wgsl`) with `pol`'s filter in
    /// front of the sensor (its angle from the image's horizontal; no filter: the image is
    /// the total intensity I), or unpolarised light (None). The image is the intensity
    /// behind the filter, as the CPU's `Renderer::render_polarized` beauty; the Stokes
    /// components take one render each behind an analyser ([`GpuRenderer::set_analyzer`]).
    /// Refused unless the path estimator runs and no path filter is
    /// set (a filter set later turns polarisation off). Selects the polarised kernel
    /// (compiled once, then cached); accumulation restarts when anything changed.
    pub fn set_polarization(&mut self, pol: Option<Polarization>) -> Result<()> {
        check_polarization(pol, &self.opts, &self.scene)?;
        if pol != self.polarization {
            self.polarization = pol;
            self.analyzer = None;
            self.respecialize();
            self.reset();
        }
        Ok(())
    }

    /// Measure with the analyser `row` (row 0 of a Mueller matrix: the sensor reads row · S)
    /// instead of the filter's, with polarised transport on; None: the filter's again. The
    /// Stokes views measure I, Q, U and V as combinations of four such renders with the same
    /// samples (`render --device gpu --aov dop`). The row must be an ideal analyser's, whose
    /// reading is never negative (r₀ ≥ |(r₁, r₂, r₃)|): the kernel clamps a sample's reading
    /// at 0. Accumulation restarts.
    pub fn set_analyzer(&mut self, row: Option<Vec4>) -> Result<()> {
        ensure!(
            self.polarization.is_some(),
            "an analyser needs polarised transport (set_polarization)"
        );
        if let Some(r) = row {
            ensure!(
                r.is_finite() && r.x + 1e-6 >= glam::Vec3::new(r.y, r.z, r.w).length(),
                "analyser row {r} is not a physical one (r₀ ≥ |(r₁, r₂, r₃)|)"
            );
        }
        self.analyzer = row;
        self.reset();
        Ok(())
    }

    /// The sensor's polarising filter (None: unpolarised transport).
    pub fn polarization(&self) -> Option<Polarization> {
        self.polarization
    }

    /// The eye→light table in use (None = unfiltered).
    pub fn filter(&self) -> Option<&DfaTable> {
        self.opts.filter.as_ref()
    }
}
