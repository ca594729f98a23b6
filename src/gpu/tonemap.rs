//! GPU tone mapping for display: the renderer's accumulation buffer (mean radiance) →
//! exposure → tone curve → sRGB-encoded bytes in an `Rgba8Unorm` storage texture
//! (`src/film/tonemap.wgsl`, the twin of `film::to_srgb8`). Where the adapter has
//! `DownlevelFlags::VIEW_FORMATS` the texture may also be viewed as `Rgba8UnormSrgb`, so a UI
//! that samples it as an sRGB texture shows exactly those bytes. Elsewhere (wgpu's GL backend)
//! the bytes are copied, unchanged, through a buffer into an `Rgba8UnormSrgb` texture of their
//! own (sRGB encoding happens in the shader either way; no conversion on the copy).

use super::GpuContext;
use super::layout::GpuLayout;
use crate::film::{ToneMap, exposure_scale};
use anyhow::{Context as _, Result};

const TONEMAP_WGSL: &str = include_str!("../film/tonemap.wgsl");

/// Uniforms of `tonemap.wgsl` (`ToneParams`).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct ToneParams {
    width: u32,
    height: u32,
    /// 0 = clamp, 1 = Reinhard, 2 = ACES.
    tone: u32,
    /// 2^exposure (finite).
    scale: f32,
}

impl GpuLayout for ToneParams {
    const WGSL_NAME: &'static str = "ToneParams";
    fn fields() -> Vec<(&'static str, u32)> {
        vec![
            ("width", std::mem::offset_of!(ToneParams, width) as u32),
            ("height", std::mem::offset_of!(ToneParams, height) as u32),
            ("tone", std::mem::offset_of!(ToneParams, tone) as u32),
            ("scale", std::mem::offset_of!(ToneParams, scale) as u32),
        ]
    }
}

/// The tone-mapped image: an `Rgba8Unorm` storage texture holding sRGB-encoded bytes, with
/// `Rgba8UnormSrgb` allowed as a view format, or (without view formats) a copy of it in an
/// `Rgba8UnormSrgb` texture.
pub struct ToneTarget {
    pub texture: wgpu::Texture,
    pub size: [u32; 2],
    /// Without view formats: the staging buffer (rows padded to `COPY_BYTES_PER_ROW_ALIGNMENT`)
    /// and the `Rgba8UnormSrgb` texture the UI samples.
    copy: Option<(wgpu::Buffer, wgpu::Texture)>,
}

impl ToneTarget {
    /// The texture a UI samples: the copy where there is one, else the storage texture.
    fn shown(&self) -> &wgpu::Texture {
        self.copy.as_ref().map_or(&self.texture, |(_, t)| t)
    }
}

/// The uniforms of one tone map of an image of `size` pixels.
fn tone_params(size: [u32; 2], tone_map: ToneMap, exposure: f32) -> ToneParams {
    ToneParams {
        width: size[0],
        height: size[1],
        tone: match tone_map {
            ToneMap::Clamp => 0,
            ToneMap::Reinhard => 1,
            ToneMap::Aces => 2,
        },
        scale: exposure_scale(exposure),
    }
}

/// Without view formats: record the copy of the tone-mapped bytes, through the staging
/// buffer, into the `Rgba8UnormSrgb` texture the UI samples (nothing otherwise).
fn encode_copy(enc: &mut wgpu::CommandEncoder, target: &ToneTarget) {
    let size = target.size;
    if let Some((buffer, shown)) = &target.copy {
        enc.copy_texture_to_buffer(
            texel_copy(&target.texture),
            buffer_copy(buffer, size),
            extent(size),
        );
        enc.copy_buffer_to_texture(buffer_copy(buffer, size), texel_copy(shown), extent(size));
    }
}

/// Bytes per row of an RGBA8 image `width` wide, padded for buffer ↔ texture copies.
fn padded_row(width: u32) -> u32 {
    (width * 4).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT
}

fn extent(size: [u32; 2]) -> wgpu::Extent3d {
    wgpu::Extent3d {
        width: size[0],
        height: size[1],
        depth_or_array_layers: 1,
    }
}

fn texel_copy(texture: &wgpu::Texture) -> wgpu::TexelCopyTextureInfo<'_> {
    wgpu::TexelCopyTextureInfo {
        texture,
        mip_level: 0,
        origin: wgpu::Origin3d::ZERO,
        aspect: wgpu::TextureAspect::All,
    }
}

fn buffer_copy(buffer: &wgpu::Buffer, size: [u32; 2]) -> wgpu::TexelCopyBufferInfo<'_> {
    wgpu::TexelCopyBufferInfo {
        buffer,
        layout: wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(padded_row(size[0])),
            rows_per_image: Some(size[1]),
        },
    }
}

/// The tone-map compute pipeline and its target texture.
pub struct ToneMapper {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    params: wgpu::Buffer,
    target: Option<ToneTarget>,
    /// Whether the storage texture may be viewed as `Rgba8UnormSrgb` (else it is copied).
    view_formats: bool,
}

impl ToneMapper {
    /// A tone mapper that views its target as sRGB where the adapter allows it
    /// (`DownlevelFlags::VIEW_FORMATS`) and copies it into an sRGB texture elsewhere.
    pub fn new(ctx: &GpuContext) -> Result<ToneMapper> {
        let flags = ctx.adapter.get_downlevel_capabilities().flags;
        Self::with_view_formats(ctx, flags.contains(wgpu::DownlevelFlags::VIEW_FORMATS))
    }

    /// A tone mapper that uses an sRGB view format (`view_formats`, which the adapter must
    /// support) or the copy (always possible; tests force it to check it on any adapter).
    pub fn with_view_formats(ctx: &GpuContext, view_formats: bool) -> Result<ToneMapper> {
        // In error scopes: a validation or out-of-memory error is an `Err`, not a panic.
        ctx.scoped("cannot build the GPU tone map", || {
            Self::build(ctx, view_formats)
        })?
    }

    fn build(ctx: &GpuContext, view_formats: bool) -> Result<ToneMapper> {
        let device = &ctx.device;
        let module = super::pipeline::create_module(ctx, "tonemap.wgsl", TONEMAP_WGSL.into())?;
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("tonemap"),
            layout: None,
            module: &module,
            entry_point: Some("tonemap"),
            compilation_options: Default::default(),
            cache: None,
        });
        let layout = pipeline.get_bind_group_layout(0);
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("tonemap params"),
            size: std::mem::size_of::<ToneParams>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Ok(ToneMapper {
            pipeline,
            layout,
            params,
            target: None,
            view_formats,
        })
    }

    /// The current target texture (None before the first [`ToneMapper::ensure_target`]).
    pub fn target(&self) -> Option<&ToneTarget> {
        self.target.as_ref()
    }

    /// Make sure the target texture has `size`. True when it was (re)created: views of the
    /// old texture no longer show the image.
    pub fn ensure_target(&mut self, ctx: &GpuContext, size: [u32; 2]) -> bool {
        if self.target.as_ref().is_some_and(|t| t.size == size) {
            return false;
        }
        let srgb = [wgpu::TextureFormat::Rgba8UnormSrgb];
        let texture = ctx.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("refract image"),
            size: extent(size),
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba8Unorm,
            usage: wgpu::TextureUsages::STORAGE_BINDING
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
            view_formats: if self.view_formats { &srgb } else { &[] },
        });
        let copy = (!self.view_formats).then(|| {
            let buffer = ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("refract image (copy)"),
                size: padded_row(size[0]) as u64 * size[1] as u64,
                usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            });
            let shown = ctx.device.create_texture(&wgpu::TextureDescriptor {
                label: Some("refract image (sRGB)"),
                size: extent(size),
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: wgpu::TextureFormat::Rgba8UnormSrgb,
                usage: wgpu::TextureUsages::TEXTURE_BINDING
                    | wgpu::TextureUsages::COPY_DST
                    | wgpu::TextureUsages::COPY_SRC,
                view_formats: &[],
            });
            (buffer, shown)
        });
        self.target = Some(ToneTarget {
            texture,
            size,
            copy,
        });
        true
    }

    /// A sampled `Rgba8UnormSrgb` view of the target: a UI that samples it as linear colour
    /// (as egui does its own sRGB textures) decodes our sRGB bytes exactly as its own.
    pub fn srgb_view(&self) -> Option<wgpu::TextureView> {
        let t = self.target.as_ref()?;
        Some(t.shown().create_view(&wgpu::TextureViewDescriptor {
            label: Some("refract image (sRGB view)"),
            format: Some(wgpu::TextureFormat::Rgba8UnormSrgb),
            // Sampled only: sRGB formats cannot be storage-bound.
            usage: Some(wgpu::TextureUsages::TEXTURE_BINDING),
            ..Default::default()
        }))
    }

    /// Queue the tone map of `accum` (the target's size in pixels) into the target texture,
    /// with `exposure` in stops. Nothing happens before [`ToneMapper::ensure_target`].
    pub fn run(&self, ctx: &GpuContext, accum: &wgpu::Buffer, tone_map: ToneMap, exposure: f32) {
        let Some(target) = &self.target else { return };
        let p = tone_params(target.size, tone_map, exposure);
        ctx.queue
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&p));
        let bind_group = self.bind_group(ctx, accum, target);
        let mut enc = ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("tonemap"),
            });
        self.encode_dispatch(&mut enc, &bind_group, target.size);
        encode_copy(&mut enc, target);
        ctx.queue.submit([enc.finish()]);
    }

    /// The bind group of one tone map: `accum`, the parameters and a storage view of the
    /// target texture.
    fn bind_group(
        &self,
        ctx: &GpuContext,
        accum: &wgpu::Buffer,
        target: &ToneTarget,
    ) -> wgpu::BindGroup {
        let view = target.texture.create_view(&wgpu::TextureViewDescriptor {
            label: Some("refract image (storage view)"),
            format: Some(wgpu::TextureFormat::Rgba8Unorm),
            usage: Some(wgpu::TextureUsages::STORAGE_BINDING),
            ..Default::default()
        });
        ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("tonemap"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: accum.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: self.params.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::TextureView(&view),
                },
            ],
        })
    }

    /// Record the tone-map compute pass over an image of `size` pixels (8×8 workgroups).
    fn encode_dispatch(
        &self,
        enc: &mut wgpu::CommandEncoder,
        bind_group: &wgpu::BindGroup,
        size: [u32; 2],
    ) {
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("tonemap"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, bind_group, &[]);
        pass.dispatch_workgroups(size[0].div_ceil(8), size[1].div_ceil(8), 1);
    }

    /// Read back the texture a UI samples: (width, height, RGBA8 sRGB bytes). Blocking; for
    /// tests and debugging only.
    pub fn read_pixels(&self, ctx: &GpuContext) -> Result<(u32, u32, Vec<u8>)> {
        let (buf, size) = self.queue_readback(ctx, false)?;
        let bytes = ctx.read_buffer(&buf, buf.size())?;
        Ok((size[0], size[1], unpad_rows(&bytes, size)))
    }

    /// Queue a copy of the texture a UI samples into a new buffer (rows padded to wgpu's
    /// copy alignment: read them with [`unpad_rows`]); and the image size. `mappable`: the
    /// buffer can be mapped for reading once the queue gets there, else copied from.
    pub fn queue_readback(
        &self,
        ctx: &GpuContext,
        mappable: bool,
    ) -> Result<(wgpu::Buffer, [u32; 2])> {
        let t = self.target.as_ref().context("no tone-mapped image yet")?;
        let size = padded_row(t.size[0]) as u64 * t.size[1] as u64;
        let buf = ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("texture readback"),
            size,
            usage: wgpu::BufferUsages::COPY_DST
                | if mappable {
                    wgpu::BufferUsages::MAP_READ
                } else {
                    wgpu::BufferUsages::COPY_SRC
                },
            mapped_at_creation: false,
        });
        let mut enc = ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
        enc.copy_texture_to_buffer(
            texel_copy(t.shown()),
            buffer_copy(&buf, t.size),
            extent(t.size),
        );
        ctx.queue.submit([enc.finish()]);
        Ok((buf, t.size))
    }
}

/// The RGBA8 pixels of an image of `size` read back with rows padded to wgpu's copy
/// alignment ([`ToneMapper::queue_readback`]), rows packed.
pub fn unpad_rows(padded: &[u8], size: [u32; 2]) -> Vec<u8> {
    let (w, h) = (size[0] as usize, size[1] as usize);
    let row = padded_row(size[0]) as usize;
    let mut out = Vec::with_capacity(w * h * 4);
    for y in 0..h {
        let start = y * row;
        out.extend_from_slice(&padded[start..start + w * 4]);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tone_params_match_the_wgsl_layout() {
        super::super::layout::check_layout::<ToneParams>(TONEMAP_WGSL).unwrap();
    }
}
