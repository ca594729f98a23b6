//! The WGSL filter (`src/denoise/denoise.wgsl`) on a wgpu device: the same passes as the CPU twin
//! ([`super::atrous`]) in one submission, reading the image and guides from buffers it owns
//! and writing the result to another (never to a renderer's accumulation).

use super::atrous::depth_gradient;
use super::{DenoiseParams, Guides};
use crate::gpu::GpuContext;
use crate::gpu::pipeline::create_module;
use anyhow::{Result, ensure};
use glam::{Vec3, Vec4};
use wgpu::util::DeviceExt;

const SOURCE: &str = include_str!("denoise.wgsl");

/// The uniform block of `denoise.wgsl` (`Params`).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Params {
    width: u32,
    height: u32,
    step: i32,
    has_variance: u32,
    sigma_l: f32,
    sigma_n: f32,
    sigma_z: f32,
    _pad: f32,
}

/// The filter's three pipelines (`prepare`, `level`, `finish`) and their bind group layout.
pub struct GpuDenoiser {
    layout: wgpu::BindGroupLayout,
    prepare: wgpu::ComputePipeline,
    level: wgpu::ComputePipeline,
    finish: wgpu::ComputePipeline,
}

/// Binding `b` of the layout: the uniform (0), read-only storage (1–4) or the output (5).
fn layout_entry(b: u32) -> wgpu::BindGroupLayoutEntry {
    let ty = match b {
        0 => wgpu::BufferBindingType::Uniform,
        5 => wgpu::BufferBindingType::Storage { read_only: false },
        _ => wgpu::BufferBindingType::Storage { read_only: true },
    };
    wgpu::BindGroupLayoutEntry {
        binding: b,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

impl GpuDenoiser {
    /// Compile the filter on `ctx`.
    pub fn new(ctx: &GpuContext) -> Result<GpuDenoiser> {
        let module = create_module(ctx, "denoise.wgsl", SOURCE.to_string())?;
        let entries: Vec<_> = (0..6).map(layout_entry).collect();
        ctx.scoped("denoise pipelines", || {
            let d = &ctx.device;
            let layout = d.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("denoise"),
                entries: &entries,
            });
            let pl = d.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("denoise"),
                bind_group_layouts: &[Some(&layout)],
                immediate_size: 0,
            });
            let pipeline = |entry: &str| {
                d.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(entry),
                    layout: Some(&pl),
                    module: &module,
                    entry_point: Some(entry),
                    compilation_options: Default::default(),
                    cache: None,
                })
            };
            GpuDenoiser {
                prepare: pipeline("prepare"),
                level: pipeline("level"),
                finish: pipeline("finish"),
                layout,
            }
        })
    }

    /// The denoised image of `img` (as [`super::denoise`] computes it, in f32 on the device).
    pub fn denoise(
        &self,
        ctx: &GpuContext,
        img: &[Vec3],
        variance: Option<&[f32]>,
        g: &Guides,
        p: &DenoiseParams,
    ) -> Result<Vec<Vec3>> {
        let n = g.albedo.len();
        ensure!(img.len() == n && n > 0, "image and guides differ in size");
        ensure!(
            variance.is_none_or(|v| v.len() == n),
            "variance and guides differ in size"
        );
        let d = &ctx.device;
        let storage = |label: &str, bytes: &[u8]| {
            d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytes,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            })
        };
        let a: Vec<Vec4> = g
            .albedo
            .iter()
            .zip(&g.specular)
            .map(|(a, s)| a.extend(*s))
            .collect();
        let nz: Vec<Vec4> = g
            .normal
            .iter()
            .zip(&g.depth)
            .map(|(n, z)| n.extend(*z))
            .collect();
        let src: Vec<Vec4> = (0..n)
            .map(|i| img[i].extend(variance.map_or(0.0, |v| v[i])))
            .collect();
        let bufs = [
            storage("denoise albedo", bytemuck::cast_slice(&a)),
            storage("denoise normal", bytemuck::cast_slice(&nz)),
            storage("denoise grad", bytemuck::cast_slice(&depth_gradient(g))),
            storage("denoise ping", bytemuck::cast_slice(&src)),
            storage("denoise pong", bytemuck::cast_slice(&src)),
        ];
        let out = ctx.scoped("denoise", || {
            self.encode(ctx, &bufs, g, variance.is_some(), p)
        })?;
        let bytes = ctx.read_buffer(&bufs[out], (n * 16) as u64)?;
        let px: Vec<Vec4> = bytemuck::pod_collect_to_vec(&bytes);
        Ok(px.iter().map(|v| v.truncate()).collect())
    }

    /// Record and submit every pass; returns the index in `bufs` of the result.
    fn encode(
        &self,
        ctx: &GpuContext,
        bufs: &[wgpu::Buffer; 5],
        g: &Guides,
        has_variance: bool,
        p: &DenoiseParams,
    ) -> usize {
        let d = &ctx.device;
        let mut enc = d.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
        let steps = std::iter::once(("prepare", 0))
            .chain((0..p.iterations).map(|i| ("level", 1i32 << i)))
            .chain(std::iter::once(("finish", 0)));
        let (mut src, mut dst) = (3usize, 4usize);
        for (entry, step) in steps {
            let params = Params {
                width: g.width,
                height: g.height,
                step,
                has_variance: has_variance as u32,
                sigma_l: p.sigma_l,
                sigma_n: p.sigma_n,
                sigma_z: p.sigma_z,
                _pad: 0.0,
            };
            let ubuf = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("denoise params"),
                contents: bytemuck::bytes_of(&params),
                usage: wgpu::BufferUsages::UNIFORM,
            });
            let bound = [&ubuf, &bufs[0], &bufs[1], &bufs[2], &bufs[src], &bufs[dst]];
            let entries: Vec<_> = (0u32..)
                .zip(bound)
                .map(|(binding, b)| wgpu::BindGroupEntry {
                    binding,
                    resource: b.as_entire_binding(),
                })
                .collect();
            let bg = d.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("denoise"),
                layout: &self.layout,
                entries: &entries,
            });
            let pipeline = match entry {
                "prepare" => &self.prepare,
                "level" => &self.level,
                _ => &self.finish,
            };
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor::default());
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, &bg, &[]);
            pass.dispatch_workgroups(g.width.div_ceil(8), g.height.div_ceil(8), 1);
            drop(pass);
            (src, dst) = (dst, src);
        }
        ctx.queue.submit([enc.finish()]);
        src
    }
}
