//! The live view's denoiser (off by default): a worker thread runs the à-trous filter
//! (`crate::denoise`) on the backend's accumulated image a few times a second — the WGSL
//! filter on the GPU backend's device (`denoise::gpu`; not on GL, whose one context the
//! renderer's thread holds), the CPU twin elsewhere or where the device refuses — and the
//! viewport shows it right of a split line (raw left) with a "DENOISED" badge. It only reads
//! the accumulation (`Backend::read_image`) and paints over the raw texture: with it off
//! nothing is read, allocated or painted, so the viewport shows the raw accumulation bit for
//! bit. The live view has no second moments per pixel, so the filter
//! estimates the noise from each pixel's neighbourhood (SVGF's spatial estimate).

use super::backend::{Accumulated, Backend, DisplayParams};
use crate::cpu::Renderer;
use crate::denoise::gpu::GpuDenoiser;
use crate::denoise::{DenoiseParams, Guides, badge, denoise, render_guides};
use crate::film::to_srgb8;
use crate::gpu::GpuContext;
use crate::scene::Scene;
use eframe::egui::{self, Color32, Pos2, Rect};
use glam::Vec3;
use std::sync::mpsc::{Receiver, Sender, channel};
use std::time::{Duration, Instant};

/// Guide samples per pixel in the live view (recomputed after every edit).
pub const GUIDE_SPP: u32 = 4;
/// At most one denoised image per this long.
const PERIOD: Duration = Duration::from_millis(300);

/// One image to denoise; `scene` when it changed since the last job.
struct Job {
    generation: u64,
    scene: Option<Box<Scene>>,
    acc: Accumulated,
}

/// Where an image was filtered.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FilterDevice {
    /// The CPU twin (`denoise::atrous`).
    Cpu,
    /// The WGSL filter on the GPU backend's device (`denoise::gpu`).
    Gpu,
}

/// A denoised image of `generation`.
struct Done {
    generation: u64,
    size: [usize; 2],
    pixels: Vec<Vec3>,
    device: FilterDevice,
}

/// The denoised image on screen.
struct Shown {
    generation: u64,
    device: FilterDevice,
    pixels: Vec<Vec3>,
    size: [usize; 2],
    display: DisplayParams,
    texture: egui::TextureHandle,
}

/// The toggle, the split and the worker.
pub struct DenoiseView {
    /// Denoising on (off by default).
    pub on: bool,
    /// Fraction of the image, from the left, kept raw.
    pub split: f32,
    worker: Option<(Sender<Job>, Receiver<Done>)>,
    in_flight: bool,
    sent: Option<(u64, u64, Instant)>,
    shown: Option<Shown>,
}

impl Default for DenoiseView {
    fn default() -> Self {
        DenoiseView {
            on: false,
            split: 0.5,
            worker: None,
            in_flight: false,
            sent: None,
            shown: None,
        }
    }
}

/// The filter on `gpu` where there is one and it succeeds, else the CPU twin.
fn filter(
    gpu: Option<&(GpuContext, GpuDenoiser)>,
    px: &[Vec3],
    g: &Guides,
) -> (Vec<Vec3>, FilterDevice) {
    let p = DenoiseParams::default();
    if let Some((ctx, d)) = gpu
        && let Ok(out) = d.denoise(ctx, px, None, g, &p)
    {
        return (out, FilterDevice::Gpu);
    }
    (denoise(px, None, g, &p), FilterDevice::Cpu)
}

/// The worker: a CPU renderer of the scene (for the guide rays) and the guides, kept while
/// the generation and size stay the same; the WGSL filter's pipelines on `device`, built once.
fn work(jobs: Receiver<Job>, done: Sender<Done>, device: Option<GpuContext>) {
    let gpu = device.and_then(|ctx| GpuDenoiser::new(&ctx).ok().map(|d| (ctx, d)));
    let mut renderer: Option<Renderer> = None;
    let mut guides: Option<(u64, Guides)> = None;
    for job in jobs {
        if let Some(s) = job.scene {
            renderer = Renderer::new(*s).ok();
        }
        let Some(r) = &renderer else { continue };
        let (w, h) = (job.acc.width, job.acc.height);
        let fresh = guides
            .as_ref()
            .is_some_and(|(g, gd)| *g == job.generation && (gd.width, gd.height) == (w, h));
        if !fresh {
            guides = Some((job.generation, render_guides(r, (w, h), GUIDE_SPP, 0)));
        }
        let Some((_, g)) = &guides else { continue };
        let (pixels, device) = filter(gpu.as_ref(), &job.acc.pixels, g);
        let out = Done {
            generation: job.generation,
            size: [w as usize, h as usize],
            pixels,
            device,
        };
        if done.send(out).is_err() {
            return;
        }
    }
}

impl DenoiseView {
    /// Once per frame: collect a finished image, send the next one. Nothing when off.
    pub fn step(
        &mut self,
        ctx: &egui::Context,
        backend: &dyn Backend,
        scene: &Scene,
        display: DisplayParams,
    ) {
        if !self.on {
            return;
        }
        let (_, rx) = self.worker.get_or_insert_with(|| {
            let (jtx, jrx) = channel();
            let (dtx, drx) = channel();
            let device = backend.denoise_device();
            std::thread::Builder::new()
                .name("denoise".into())
                .spawn(move || work(jrx, dtx, device))
                .ok();
            (jtx, drx)
        });
        if let Ok(d) = rx.try_recv() {
            self.in_flight = false;
            self.show(ctx, d, display);
        }
        self.retone(display);
        let generation = backend.generation();
        let due = self.sent.is_none_or(|(g, spp, at)| {
            (g != generation || spp != backend.spp()) && at.elapsed() >= PERIOD
        });
        if self.in_flight || !due {
            return;
        }
        let Some(acc) = backend.read_image().filter(|a| a.generation == generation) else {
            return;
        };
        let new_scene = self.sent.is_none_or(|(g, _, _)| g != generation);
        let job = Job {
            generation,
            scene: new_scene.then(|| Box::new(scene.clone())),
            acc,
        };
        self.sent = Some((generation, backend.spp(), Instant::now()));
        self.in_flight = self
            .worker
            .as_ref()
            .is_some_and(|(tx, _)| tx.send(job).is_ok());
        ctx.request_repaint_after(PERIOD);
    }

    /// Tone-map a finished image into the texture (reused: nothing grows per image).
    fn show(&mut self, ctx: &egui::Context, d: Done, display: DisplayParams) {
        let image = color_image(&d.pixels, d.size, display);
        match &mut self.shown {
            Some(s) => {
                s.texture.set(image, egui::TextureOptions::NEAREST);
                (s.generation, s.device, s.pixels, s.size, s.display) =
                    (d.generation, d.device, d.pixels, d.size, display);
            }
            None => {
                let texture = ctx.load_texture("denoised", image, egui::TextureOptions::NEAREST);
                self.shown = Some(Shown {
                    generation: d.generation,
                    device: d.device,
                    pixels: d.pixels,
                    size: d.size,
                    display,
                    texture,
                });
            }
        }
    }

    /// Exposure or tone map changed: tone-map the shown image again.
    fn retone(&mut self, display: DisplayParams) {
        if let Some(s) = &mut self.shown
            && s.display != display
        {
            s.texture.set(
                color_image(&s.pixels, s.size, display),
                egui::TextureOptions::NEAREST,
            );
            s.display = display;
        }
    }

    /// True when [`DenoiseView::paint`] draws over the image of `generation` (on, and a
    /// denoised image of that generation has arrived).
    pub fn showing(&self, generation: u64) -> bool {
        self.on
            && self
                .shown
                .as_ref()
                .is_some_and(|s| s.generation == generation)
    }

    /// The denoised image on screen (linear radiance, width × height) and where it was
    /// filtered; None before the first one arrives.
    pub fn shown(&self) -> Option<(&[Vec3], [usize; 2], FilterDevice)> {
        self.shown
            .as_ref()
            .map(|s| (s.pixels.as_slice(), s.size, s.device))
    }

    /// Paint the denoised part, the split line and the badge over the image in `rect` (only
    /// when on and the denoised image is of the generation on screen).
    pub fn paint(&self, ui: &egui::Ui, rect: Rect, generation: u64) {
        let Some(s) = self
            .shown
            .as_ref()
            .filter(|s| self.on && s.generation == generation)
        else {
            return;
        };
        let painter = ui.painter_at(rect);
        let x = rect.min.x + rect.width() * self.split.clamp(0.0, 1.0);
        let right = Rect::from_min_max(Pos2::new(x, rect.min.y), rect.max);
        let uv = Rect::from_min_max(
            Pos2::new(self.split.clamp(0.0, 1.0), 0.0),
            Pos2::new(1.0, 1.0),
        );
        painter.image(s.texture.id(), right, uv, Color32::WHITE);
        painter.line_segment(
            [Pos2::new(x, rect.min.y), Pos2::new(x, rect.max.y)],
            (2.0, Color32::WHITE),
        );
        let font = egui::FontId::monospace(14.0);
        let at = Pos2::new(rect.max.x - 8.0, rect.min.y + 8.0);
        let galley = painter.layout_no_wrap(badge::BADGE.into(), font, Color32::WHITE);
        let r = egui::Align2::RIGHT_TOP
            .anchor_size(at, galley.size())
            .expand(4.0);
        painter.rect_filled(r, 3.0, Color32::from_gray(24));
        painter.galley(r.min + egui::vec2(4.0, 4.0), galley, Color32::WHITE);
    }
}

/// Linear radiance → an egui image as the backend tone-maps it.
fn color_image(px: &[Vec3], size: [usize; 2], d: DisplayParams) -> egui::ColorImage {
    egui::ColorImage::from_rgba_unmultiplied(size, &to_srgb8(px, d.exposure, d.tone_map))
}

/// A screenshot's denoised image of `acc` (synchronous: guides and filter on this thread).
pub fn denoise_now(scene: &Scene, acc: &Accumulated) -> anyhow::Result<Vec<Vec3>> {
    let r = Renderer::new(scene.clone())?;
    let g = render_guides(&r, (acc.width, acc.height), 16, 0);
    Ok(denoise(&acc.pixels, None, &g, &DenoiseParams::default()))
}
