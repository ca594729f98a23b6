//! WGSL assembly, pipeline specialisation and the pipeline cache.
//!
//! The kernel is specialised by WGSL override constants (`HAS_*`), so features a scene lacks
//! are compiled out by the driver. The key is derived from the scene's *kinds* (which BSDFs
//! and light types exist), never from parameter values, so moving a slider (IOR, colour,
//! roughness within a kind, emission, environment) never recompiles. Pipelines are cached per
//! key, in memory and, through the driver's pipeline cache, on disk (`pipeline_cache`).
//! [`Pipelines::compile_in_background`] compiles a specialisation on a worker thread, so the
//! viewer keeps drawing while the driver compiles (seconds for every feature on RADV).
//!
//! Files: `wgsl` (sources, assembly, validated modules), `specialization` (the cache key),
//! `kernel` (entry points), `layouts` (bind group layouts), `probe` (one-shot probe
//! dispatches); this file holds the cache and its background compiler.

use super::GpuContext;
use super::pipeline_cache::DiskPipelineCache;
use anyhow::{Context, Result};
use std::collections::HashMap;
use std::sync::Arc;
use std::time::{Duration, Instant};

mod kernel;
mod layouts;
mod probe;
mod specialization;
mod wgsl;

pub use kernel::{Kernel, kernels_of};
use layouts::{IntegratorLayouts, check_storage_buffer_limit};
pub(crate) use probe::dispatch_once;
pub use probe::run_probe;
pub use specialization::Specialization;
pub use wgsl::{
    SHADER_FILES, bvh_probe_source, create_module, integrator_source, light_probe_source,
    probe_source,
};

/// Storage buffers the integrator binds (group 0: bindings 0–8, 10–13, 15 and 16; and
/// `wf_advance`'s group 1). Sixteen is also what wgpu's GL backend offers on llvmpipe.
pub const STORAGE_BUFFERS: u32 = 16;

/// The most specialisations whose pipelines stay compiled: beyond, the least recently used
/// specialised one is dropped (and compiled again if it is needed again), a family's general
/// kernel only when nothing else is left ([`eviction_victim`]). Unbounded, a long viewer session that
/// visits many scenes, estimators and filters kept every pipeline it ever compiled — on
/// lavapipe, where each is LLVM-compiled machine code, resident memory grew 13 % over 300
/// random edits after a warm-up through every scene (tests/viewer_soak.rs).
pub const MAX_CACHED_SPECIALIZATIONS: usize = 12;

/// Worker threads compiling at once on a software driver (lavapipe): each LLVM compilation
/// holds hundreds of MB and shares the CPU the batches execute on. Unbounded, a burst of edits
/// started one worker per edit — 59 at once after a soak's warm-up, 16 GB resident and
/// killed for memory (tests/viewer_soak.rs).
pub const MAX_WORKERS_SOFTWARE: usize = 1;

/// Worker threads compiling at once on a hardware driver: the specialisation an edit asked
/// for can start while the previous one (or one compiled ahead of need) still compiles.
pub const MAX_WORKERS: usize = 2;

/// The integrator's bind group layout, shader module and specialised pipelines.
pub struct Pipelines {
    pub bind_group_layout: wgpu::BindGroupLayout,
    /// Group 1 of `wf_advance` alone: the wavefront's indirect dispatch size, which the other
    /// kernels' layouts leave out so that it can be their indirect argument in the same pass.
    pub advance_group_layout: wgpu::BindGroupLayout,
    device: wgpu::Device,
    layout: wgpu::PipelineLayout,
    advance_layout: wgpu::PipelineLayout,
    module: wgpu::ShaderModule,
    /// The driver's pipeline cache, kept on disk (None: the device has none).
    disk_cache: Option<Arc<DiskPipelineCache>>,
    cache: HashMap<(Specialization, Kernel), wgpu::ComputePipeline>,
    /// The cached specialisations, least recently used first: at most `capacity`.
    order: std::collections::VecDeque<Specialization>,
    /// The most specialisations kept ([`MAX_CACHED_SPECIALIZATIONS`] unless set).
    capacity: usize,
    /// Specialisations being compiled on worker threads: at most `max_workers`.
    pending: Vec<Pending>,
    /// The most worker threads compiling at once ([`MAX_WORKERS_SOFTWARE`],
    /// [`MAX_WORKERS`]).
    max_workers: usize,
    /// The latest specialisation asked for while every worker was busy: it starts first when
    /// one finishes. A newer request replaces it (an edit supersedes the one before), so a
    /// slider dragged across many kernels compiles the one it rests on, not every one it
    /// passed.
    next: Option<Specialization>,
    /// Specialisations to compile ahead of need, one at a time once nothing else compiles
    /// (`compile_ahead`): compilations running side by side share the CPU the driver
    /// compiles and, on software drivers, executes on.
    ahead: std::collections::VecDeque<Specialization>,
    /// Whether to compile ahead at all: not on software drivers, where a compilation and the
    /// batches share the same CPU cores, so a general kernel could not render while the
    /// specialised one compiles anyway, and compiling it ahead only slows both.
    ahead_enabled: bool,
    /// Number of pipelines compiled so far (tests check that edits do not recompile).
    pub compiled: u32,
    /// Wall time of the last specialisation's pipeline creation (all its kernels).
    pub last_compile: Option<Duration>,
}

/// The compiled kernels of one specialisation, and how long their creation took.
type Compiled = Result<(Vec<(Kernel, wgpu::ComputePipeline)>, Duration)>;

/// A specialisation's pipelines being compiled on a worker thread.
struct Pending {
    spec: Specialization,
    thread: std::thread::JoinHandle<Compiled>,
}

/// What a compilation needs (wgpu handles are reference-counted and `Send + Sync`: a worker
/// thread compiles while the caller's thread keeps submitting).
#[derive(Clone)]
struct Compiler {
    device: wgpu::Device,
    layout: wgpu::PipelineLayout,
    advance_layout: wgpu::PipelineLayout,
    module: wgpu::ShaderModule,
    disk_cache: Option<Arc<DiskPipelineCache>>,
}

impl Compiler {
    /// Create the pipelines of `kernels` for `spec` in error scopes (validation and
    /// out-of-memory errors are an `Err`), then write the pipeline cache back to disk (a
    /// failed write is a warning).
    fn compile(&self, spec: Specialization, kernels: &[Kernel]) -> Compiled {
        let start = Instant::now();
        let pipelines =
            super::context::scoped_on(&self.device, "cannot compile the GPU kernels", || {
                kernels
                    .iter()
                    .map(|&k| (k, self.create(spec, k)))
                    .collect::<Vec<_>>()
            })?;
        let took = start.elapsed();
        if let Some(c) = &self.disk_cache
            && let Err(e) = c.save()
        {
            eprintln!("refract: warning: {e:#}");
        }
        Ok((pipelines, took))
    }

    fn create(&self, spec: Specialization, kernel: Kernel) -> wgpu::ComputePipeline {
        let constants = spec.constants();
        self.device
            .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(kernel.entry()),
                layout: Some(if kernel == Kernel::WfAdvance {
                    &self.advance_layout
                } else {
                    &self.layout
                }),
                module: &self.module,
                entry_point: Some(kernel.entry()),
                compilation_options: wgpu::PipelineCompilationOptions {
                    constants: &constants,
                    zero_initialize_workgroup_memory: false,
                },
                cache: self.disk_cache.as_ref().map(|c| &c.cache),
            })
    }
}

impl Pipelines {
    pub fn new(ctx: &GpuContext) -> Result<Pipelines> {
        check_storage_buffer_limit(ctx)?;
        let module = create_module(ctx, "integrator.wgsl", integrator_source())?;
        let layouts = IntegratorLayouts::new(ctx);
        let disk_cache =
            DiskPipelineCache::open(ctx, ctx.pipeline_cache_dir.as_deref()).map(Arc::new);
        Ok(Pipelines {
            bind_group_layout: layouts.bind_group,
            advance_group_layout: layouts.advance_group,
            device: ctx.device.clone(),
            layout: layouts.layout,
            advance_layout: layouts.advance,
            module,
            disk_cache,
            cache: HashMap::new(),
            order: std::collections::VecDeque::new(),
            capacity: MAX_CACHED_SPECIALIZATIONS,
            pending: Vec::new(),
            max_workers: if ctx.is_software() {
                MAX_WORKERS_SOFTWARE
            } else {
                MAX_WORKERS
            },
            next: None,
            ahead: std::collections::VecDeque::new(),
            ahead_enabled: !ctx.is_software(),
            compiled: 0,
            last_compile: None,
        })
    }

    /// The driver pipeline cache in use (None: the device has none, e.g. wgpu's GL backend).
    pub fn disk_cache(&self) -> Option<&DiskPipelineCache> {
        self.disk_cache.as_deref()
    }

    fn compiler(&self) -> Compiler {
        Compiler {
            device: self.device.clone(),
            layout: self.layout.clone(),
            advance_layout: self.advance_layout.clone(),
            module: self.module.clone(),
            disk_cache: self.disk_cache.clone(),
        }
    }

    /// The kernels of `spec` not compiled yet.
    fn missing(&self, spec: Specialization) -> Vec<Kernel> {
        kernels_of(&spec)
            .into_iter()
            .filter(|&k| !self.cache.contains_key(&(spec, k)))
            .collect()
    }

    /// True when every kernel `spec` dispatches is compiled.
    pub fn is_ready(&self, spec: Specialization) -> bool {
        self.missing(spec).is_empty()
    }

    /// Compile the pipelines `spec` dispatches now, on this thread (waiting for a worker
    /// already compiling them).
    pub fn compile(&mut self, spec: Specialization) -> Result<()> {
        if self.next == Some(spec) {
            self.next = None;
        }
        if let Some(i) = self.pending.iter().position(|p| p.spec == spec) {
            let p = self.pending.swap_remove(i);
            return self.finish(p);
        }
        let missing = self.missing(spec);
        if missing.is_empty() {
            return Ok(());
        }
        let compiled = self.compiler().compile(spec, &missing);
        self.store(spec, compiled)
    }

    /// Start compiling the pipelines `spec` dispatches on a worker thread (nothing to do when
    /// they are compiled or being compiled); [`Pipelines::poll`] collects them. With every
    /// worker busy, `spec` waits as the next to start, replacing the one that waited before.
    pub fn compile_in_background(&mut self, spec: Specialization) -> Result<()> {
        if self.missing(spec).is_empty() || self.pending.iter().any(|p| p.spec == spec) {
            // The latest request is satisfied: whatever waited before it is superseded.
            self.next = None;
            return Ok(());
        }
        if self.pending.len() >= self.max_workers {
            self.next = Some(spec);
            return Ok(());
        }
        self.next = None;
        self.spawn(spec)
    }

    /// The number of worker threads compiling now (at most the adapter's limit).
    pub fn workers(&self) -> usize {
        self.pending.len()
    }

    /// The specialisation waiting for a worker (the latest one asked for while all were busy).
    pub fn waiting(&self) -> Option<Specialization> {
        self.next
    }

    /// Compile `spec`'s missing kernels on a new worker thread.
    fn spawn(&mut self, spec: Specialization) -> Result<()> {
        let missing = self.missing(spec);
        let compiler = self.compiler();
        let thread = std::thread::Builder::new()
            .name("refract-gpu-compile".into())
            .spawn(move || compiler.compile(spec, &missing))
            .context("cannot start the GPU kernel compiler thread")?;
        self.pending.push(Pending { spec, thread });
        Ok(())
    }

    /// Queue `spec` to compile on a worker thread once nothing else compiles (ahead of need:
    /// a general kernel, what an edit may ask for next); [`Pipelines::poll`] starts it.
    pub fn compile_ahead(&mut self, spec: Specialization) -> Result<()> {
        if !self.ahead_enabled {
            return Ok(());
        }
        if !self.ahead.contains(&spec) {
            self.ahead.push_back(spec);
        }
        self.start_ahead()
    }

    /// Compile ahead of need (`on`) or not; the default is on except on software drivers.
    pub fn set_compile_ahead(&mut self, on: bool) {
        self.ahead_enabled = on;
        if !on {
            self.ahead.clear();
        }
    }

    /// Start the specialisation waiting for a worker if one is free, then the next queued
    /// compilation ahead of need if no worker is compiling.
    fn start_ahead(&mut self) -> Result<()> {
        if self.pending.len() < self.max_workers
            && let Some(spec) = self.next.take()
        {
            self.compile_in_background(spec)?;
        }
        while self.pending.is_empty()
            && let Some(spec) = self.ahead.pop_front()
        {
            if !self.missing(spec).is_empty() {
                self.spawn(spec)?;
            }
        }
        Ok(())
    }

    /// True while some specialisation is being compiled on a worker thread (or waits to be,
    /// ahead of need).
    pub fn is_compiling(&self) -> bool {
        !self.pending.is_empty() || self.next.is_some() || !self.ahead.is_empty()
    }

    /// Collect the pipelines of finished worker threads (never waits), and start the next
    /// compilation ahead of need. An `Err` if one failed.
    pub fn poll(&mut self) -> Result<()> {
        let r = self.collect();
        let started = self.start_ahead();
        r.and(started)
    }

    /// Collect the pipelines of finished worker threads (never waits).
    fn collect(&mut self) -> Result<()> {
        let mut result = Ok(());
        let mut i = 0;
        while i < self.pending.len() {
            if self.pending[i].thread.is_finished() {
                let p = self.pending.swap_remove(i);
                let r = self.finish(p);
                if result.is_ok() {
                    result = r;
                }
            } else {
                i += 1;
            }
        }
        result
    }

    /// Join the worker compiling `p` and keep its pipelines.
    fn finish(&mut self, p: Pending) -> Result<()> {
        let compiled = p
            .thread
            .join()
            .map_err(|_| anyhow::anyhow!("the GPU kernel compiler thread panicked"))
            .and_then(|r| r);
        self.store(p.spec, compiled)
    }

    fn store(&mut self, spec: Specialization, compiled: Compiled) -> Result<()> {
        let (pipelines, took) = compiled?;
        for (kernel, pipeline) in pipelines {
            self.compiled += 1;
            self.cache.insert((spec, kernel), pipeline);
        }
        self.last_compile = Some(took);
        self.order.retain(|s| *s != spec);
        self.order.push_back(spec);
        self.evict();
        Ok(())
    }

    /// Drop specialisations beyond the capacity ([`eviction_victim`] first).
    fn evict(&mut self) {
        while self.order.len() > self.capacity {
            if let Some(old) = self.order.remove(eviction_victim(&self.order)) {
                self.cache.retain(|(s, _), _| *s != old);
            }
        }
    }

    /// Keep at most `n` (at least 1) specialisations compiled, dropping the excess now. More
    /// than [`MAX_CACHED_SPECIALIZATIONS`] is for measurements that must see no recompiles
    /// (the soak tests); on lavapipe each executed specialisation holds 50–250 MB.
    pub fn set_capacity(&mut self, n: usize) {
        self.capacity = n.max(1);
        self.evict();
    }

    /// The specialisations whose pipelines are compiled now.
    pub fn cached_specializations(&self) -> usize {
        self.order.len()
    }

    /// Mark `spec` as just used (the renderer switched to it): eviction drops the least
    /// recently used first.
    pub fn touch(&mut self, spec: Specialization) {
        if let Some(i) = self.order.iter().position(|s| *s == spec) {
            self.order.remove(i);
            self.order.push_back(spec);
        }
    }

    /// The compiled pipeline of `kernel` for `spec` (None: not compiled, see
    /// [`Pipelines::compile`]).
    pub fn get_kernel(
        &self,
        spec: Specialization,
        kernel: Kernel,
    ) -> Option<&wgpu::ComputePipeline> {
        self.cache.get(&(spec, kernel))
    }
}

/// Which cached specialisation to drop, `order` being least recently used first: the least
/// recently used specialised one, sparing the general kernels (one per family: what renders
/// while any specialisation of the family compiles, so dropping one brings the frozen image
/// back) and the most recent entry (just compiled or just used); the oldest entry when
/// nothing else is left.
pub fn eviction_victim(order: &std::collections::VecDeque<Specialization>) -> usize {
    let candidates = order.len().saturating_sub(1);
    order
        .iter()
        .take(candidates)
        .position(|s| *s != s.general())
        .unwrap_or(0)
}

#[cfg(test)]
mod eviction_tests {
    use super::*;
    use std::collections::VecDeque;

    #[test]
    fn eviction_spares_general_kernels_and_the_newest() {
        let general = Specialization::all().general();
        let a = Specialization {
            bsdfs: crate::bsdf::BsdfParts {
                mirror: false,
                ..general.bsdfs
            },
            ..general
        };
        let b = Specialization {
            bsdfs: crate::bsdf::BsdfParts {
                lambert: false,
                ..general.bsdfs
            },
            ..general
        };
        let spectral_general = Specialization {
            spectral: true,
            ..general
        };
        assert_ne!(a, a.general());
        // The oldest is a general kernel: the oldest specialised one goes instead.
        let order = VecDeque::from([general, spectral_general, a, b]);
        assert_eq!(eviction_victim(&order), 2);
        // Only general kernels and the newest (specialised) one: the newest stays.
        let order = VecDeque::from([general, spectral_general, a]);
        assert_eq!(eviction_victim(&order), 0);
        let order = VecDeque::from([b, a]);
        assert_eq!(eviction_victim(&order), 0);
    }
}
