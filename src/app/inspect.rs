//! The viewer's Inspect mode: Alt+click (or click, with the mode on) a pixel and N camera
//! paths through it are traced by the CPU path tracer's own walk (`cpu::inspect`) on a helper
//! thread, drawn over the image (`inspect_overlay`) and listed vertex by vertex
//! (`panels::inspect`). Any edit re-traces the same pixel, so the paths follow the camera.

use crate::cpu::Renderer;
use crate::cpu::inspect::{DEFAULT_PATHS, PixelTrace, trace_pixel};
use crate::render::RenderOptions;
use crate::scene::{Camera, Scene};
use eframe::egui::Rect;
use std::sync::mpsc;

/// A finished trace and the view it was traced in (for projecting its vertices).
#[derive(Clone, Debug)]
pub struct Traced {
    pub trace: PixelTrace,
    pub camera: Camera,
    /// Image size of the trace (the pixel's grid).
    pub size: (u32, u32),
}

/// State of the Inspect mode.
pub struct Inspector {
    /// A plain click inspects (Alt+click always does).
    pub enabled: bool,
    /// Paths per trace.
    pub paths: u32,
    /// The film point being inspected, (0,0) = top left, (1,1) = bottom right: the pixel
    /// under it is traced at whatever resolution the viewer renders.
    pub film: Option<(f32, f32)>,
    pub traced: Option<Traced>,
    /// The path the list highlights (the others are drawn faint).
    pub highlight: Option<usize>,
    pub error: Option<String>,
    /// The path and vertex whose BSDF lobe the panel draws (the first scattering vertex at
    /// or after `lobe_vertex`).
    pub lobe_path: usize,
    pub lobe_vertex: usize,
    /// Where the image was drawn last frame (tests click into it).
    pub image_rect: Option<Rect>,
    /// The scene generation the current or pending trace was made for.
    traced_generation: Option<u64>,
    pending: Option<mpsc::Receiver<anyhow::Result<Traced>>>,
}

impl Default for Inspector {
    fn default() -> Self {
        Inspector {
            enabled: false,
            paths: DEFAULT_PATHS,
            film: None,
            traced: None,
            highlight: None,
            error: None,
            lobe_path: 0,
            lobe_vertex: 1,
            image_rect: None,
            traced_generation: None,
            pending: None,
        }
    }
}

impl Inspector {
    /// Inspect the pixel under film point (sx, sy) ∈ [0,1]².
    pub fn request(&mut self, film: (f32, f32)) {
        self.film = Some((film.0.clamp(0.0, 1.0), film.1.clamp(0.0, 1.0)));
        self.highlight = None;
        self.traced_generation = None;
    }

    /// Inspect pixel (x, y) of a `(w, h)` image (its centre).
    pub fn request_pixel(&mut self, (x, y): (u32, u32), (w, h): (u32, u32)) {
        self.request(((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32));
    }

    /// Forget the pixel and its paths.
    pub fn clear(&mut self) {
        self.film = None;
        self.traced = None;
        self.highlight = None;
        self.error = None;
        self.traced_generation = None;
    }

    /// A trace is under way.
    pub fn is_tracing(&self) -> bool {
        self.pending.is_some()
    }

    /// Collect a finished trace; start one when the pixel, the scene or the options changed
    /// (`generation` counts the viewer's edits) and none is running. `options` is called only
    /// when a trace starts.
    pub fn update(
        &mut self,
        scene: &Scene,
        generation: u64,
        options: impl FnOnce() -> anyhow::Result<RenderOptions>,
    ) {
        self.collect();
        let Some(film) = self.film else { return };
        if self.pending.is_some() || self.traced_generation == Some(generation) {
            return;
        }
        self.traced_generation = Some(generation);
        match options() {
            Ok(o) => {
                let pixel = pixel_of(film, (o.width, o.height));
                self.start(scene.clone(), o, pixel)
            }
            Err(e) => self.error = Some(format!("{e:#}")),
        }
    }

    fn collect(&mut self) {
        let Some(rx) = &self.pending else { return };
        match rx.try_recv() {
            Ok(result) => {
                self.pending = None;
                match result {
                    Ok(t) => {
                        self.traced = Some(t);
                        self.error = None;
                    }
                    Err(e) => self.error = Some(format!("{e:#}")),
                }
            }
            Err(mpsc::TryRecvError::Empty) => {}
            Err(mpsc::TryRecvError::Disconnected) => {
                self.pending = None;
                self.error = Some("the path inspector's thread stopped".into());
            }
        }
    }

    fn start(&mut self, scene: Scene, opts: RenderOptions, pixel: (u32, u32)) {
        let (tx, rx) = mpsc::channel();
        let paths = self.paths;
        let spawned = std::thread::Builder::new()
            .name("refract-inspect".into())
            .spawn(move || {
                let _ = tx.send(trace(scene, &opts, pixel, paths));
            });
        match spawned {
            Ok(_) => self.pending = Some(rx),
            Err(e) => self.error = Some(format!("cannot start the path inspector: {e}")),
        }
    }
}

/// The pixel of a `(w, h)` image under film point (sx, sy).
pub fn pixel_of((sx, sy): (f32, f32), (w, h): (u32, u32)) -> (u32, u32) {
    let x = ((sx * w as f32) as u32).min(w.saturating_sub(1));
    let y = ((sy * h as f32) as u32).min(h.saturating_sub(1));
    (x, y)
}

/// Trace `paths` paths through `pixel` of `scene` as `opts` renders it.
fn trace(
    scene: Scene,
    opts: &RenderOptions,
    pixel: (u32, u32),
    paths: u32,
) -> anyhow::Result<Traced> {
    let camera = scene.camera;
    let renderer = Renderer::new(scene)?;
    let trace = trace_pixel(&renderer, opts, pixel, paths)?;
    Ok(Traced {
        trace,
        camera,
        size: (opts.width, opts.height),
    })
}
