//! [`CpuBackend`]: the CPU path tracer (`cpu::Renderer`, rayon) on a background thread, in
//! short passes that an edit can cancel mid-pass. Every edit bumps a generation counter:
//! samples rendered for an older generation never reach the published image.

mod render_loop;

use super::{Accumulated, Backend, DisplayParams, DisplayTexture};
use crate::app::layer_view::ViewMode;
use crate::film::exposure_scale;
use crate::math::color::linear_to_srgb;
use crate::render::RenderOptions;
use crate::scene::{Camera, Checked, Material, Scene};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::time::Duration;

enum Command {
    Scene(Box<Scene>),
    Material(usize, Box<Checked<Material>>),
    Lights(Box<Scene>, bool),
    Camera(Checked<Camera>),
}

/// State shared by the UI handle and the render thread.
struct State {
    /// Commands not yet applied by the render thread, in order.
    commands: Vec<Command>,
    options: Option<RenderOptions>,
    interactive: bool,
    paused: bool,
    spp_target: u64,
    quit: bool,
    /// Latest finished pass of the current generation.
    published: Option<Arc<Accumulated>>,
    /// Materials as applied by the render thread.
    materials: Vec<Material>,
    /// The render thread is waiting (paused, target reached, nothing to render).
    idle: bool,
    /// What the published image shows: with a layer view the passes also accumulate the
    /// layers (`app::layer_view`), otherwise they pay nothing for them.
    view: ViewMode,
    /// A polarising filter in front of the sensor (radians; None: unpolarised transport).
    polarizer: Option<f32>,
}

struct Shared {
    state: Mutex<State>,
    wake: Condvar,
    /// Bumped (under the state lock) by every edit; read lock-free by the pass to cancel.
    generation: AtomicU64,
}

impl Shared {
    fn lock(&self) -> MutexGuard<'_, State> {
        // A panic on the render thread must not take the UI down with it.
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }
}

/// Interactive CPU rendering on a background thread (see the module documentation).
pub struct CpuBackend {
    shared: Arc<Shared>,
    thread: Option<std::thread::JoinHandle<()>>,
    texture: Option<eframe::egui::TextureHandle>,
    /// (generation, spp, display) of the uploaded texture.
    shown: Option<(u64, u64, [u32; 2], DisplayParams)>,
    threads: usize,
}

impl CpuBackend {
    /// Start the render thread. `repaint` (if given) is asked to repaint after every pass.
    pub fn new(repaint: Option<eframe::egui::Context>) -> CpuBackend {
        let shared = Arc::new(Shared {
            state: Mutex::new(State {
                commands: Vec::new(),
                options: None,
                interactive: false,
                paused: false,
                spp_target: 0,
                quit: false,
                published: None,
                materials: Vec::new(),
                idle: true,
                view: ViewMode::Beauty,
                polarizer: None,
            }),
            wake: Condvar::new(),
            generation: AtomicU64::new(0),
        });
        let s = Arc::clone(&shared);
        let thread = std::thread::Builder::new()
            .name("refract-render".into())
            .spawn(move || render_loop::render_thread(&s, repaint))
            .ok();
        CpuBackend {
            shared,
            thread,
            texture: None,
            shown: None,
            threads: rayon::current_num_threads(),
        }
    }

    /// Apply `f` to the state, bump the generation and wake the render thread.
    fn edit(&self, f: impl FnOnce(&mut State)) {
        let mut st = self.shared.lock();
        f(&mut st);
        self.shared.generation.fetch_add(1, Ordering::SeqCst);
        st.published = None;
        st.idle = false;
        drop(st);
        self.shared.wake.notify_all();
    }

    fn published(&self) -> Option<Arc<Accumulated>> {
        let st = self.shared.lock();
        st.published
            .clone()
            .filter(|p| p.generation == self.shared.generation.load(Ordering::SeqCst))
    }
}

impl Drop for CpuBackend {
    fn drop(&mut self) {
        {
            let mut st = self.shared.lock();
            st.quit = true;
        }
        self.shared.generation.fetch_add(1, Ordering::SeqCst);
        self.shared.wake.notify_all();
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

impl Backend for CpuBackend {
    fn set_scene(&mut self, scene: &Scene) {
        let scene = Box::new(scene.clone());
        self.edit(|st| {
            st.commands.push(Command::Scene(scene));
        });
    }

    fn update_material(&mut self, index: usize, material: &Checked<Material>) {
        let m = Box::new(material.clone());
        self.edit(|st| st.commands.push(Command::Material(index, m)));
    }

    fn update_lights(&mut self, scene: &Scene, geometry_changed: bool) {
        let scene = Box::new(scene.clone());
        self.edit(|st| st.commands.push(Command::Lights(scene, geometry_changed)));
    }

    fn update_camera(&mut self, camera: &Checked<Camera>) {
        let c = camera.clone();
        self.edit(|st| st.commands.push(Command::Camera(c)));
    }

    fn set_options(&mut self, options: &RenderOptions) {
        let o = *options;
        self.edit(|st| st.options = Some(o));
    }

    fn set_interactive(&mut self, interactive: bool) {
        if self.shared.lock().interactive != interactive {
            self.edit(|st| st.interactive = interactive);
        }
    }

    fn set_paused(&mut self, paused: bool) {
        // Pausing keeps the samples: no generation bump.
        let mut st = self.shared.lock();
        st.paused = paused;
        st.idle = false;
        drop(st);
        self.shared.wake.notify_all();
    }

    fn set_spp_target(&mut self, spp: u64) {
        let mut st = self.shared.lock();
        st.spp_target = spp;
        st.idle = false;
        drop(st);
        self.shared.wake.notify_all();
    }

    fn reset(&mut self) {
        self.edit(|_| {});
    }

    fn step(&mut self, _frame_budget: Duration) {
        // The CPU backend renders on its own thread; nothing to do on the UI thread.
    }

    fn spp(&self) -> u64 {
        self.published().map_or(0, |p| p.spp)
    }

    fn samples_per_sec(&self) -> f64 {
        self.published().map_or(0.0, |p| {
            (p.spp as f64 * p.width as f64 * p.height as f64) / p.elapsed.as_secs_f64().max(1e-9)
        })
    }

    fn elapsed(&self) -> Duration {
        self.published().map_or(Duration::ZERO, |p| p.elapsed)
    }

    fn dropped(&self) -> u64 {
        self.published().map_or(0, |p| p.dropped)
    }

    fn device_name(&self) -> String {
        format!("CPU, {} threads", self.threads)
    }

    fn is_rendering(&self) -> bool {
        !self.shared.lock().idle
    }

    fn generation(&self) -> u64 {
        self.shared.generation.load(Ordering::SeqCst)
    }

    fn material(&self, index: usize) -> Option<Material> {
        self.shared.lock().materials.get(index).cloned()
    }

    fn display_texture(
        &mut self,
        ctx: &eframe::egui::Context,
        display: &DisplayParams,
    ) -> Option<DisplayTexture> {
        // Keep showing the last image while the first pass of a new generation renders.
        let latest = self.shared.lock().published.clone();
        if let Some(p) = latest {
            let key = (p.generation, p.spp, [p.width, p.height], *display);
            if self.shown != Some(key) {
                let image = tone_map_image(&p, display);
                let opts = eframe::egui::TextureOptions::LINEAR;
                match &mut self.texture {
                    Some(t) => t.set(image, opts),
                    None => self.texture = Some(ctx.load_texture("refract-image", image, opts)),
                }
                self.shown = Some(key);
            }
        }
        let t = self.texture.as_ref()?;
        let (_, _, size, _) = self.shown?;
        Some(DisplayTexture { id: t.id(), size })
    }

    fn read_image(&self) -> Option<Accumulated> {
        self.published().map(|p| (*p).clone())
    }

    fn set_view(&mut self, mode: ViewMode) -> bool {
        if self.shared.lock().view != mode {
            self.edit(|st| st.view = mode);
        }
        true
    }

    fn set_polarizer(&mut self, angle: Option<f32>) -> bool {
        if self.shared.lock().polarizer != angle {
            self.edit(|st| st.polarizer = angle);
        }
        true
    }
}

/// Linear → 8-bit sRGB after tone mapping, through a table (the UI thread does this for up to
/// a megapixel per frame). Screenshots use `film::to_srgb8` instead (exact).
fn tone_map_image(p: &Accumulated, d: &DisplayParams) -> eframe::egui::ColorImage {
    use std::sync::LazyLock;
    const N: usize = 1 << 14;
    static LUT: LazyLock<Vec<u8>> = LazyLock::new(|| {
        (0..N)
            .map(|i| {
                let v = linear_to_srgb(i as f32 / (N - 1) as f32);
                (v * 255.0 + 0.5).clamp(0.0, 255.0) as u8
            })
            .collect()
    });
    let scale = exposure_scale(d.exposure);
    let tone = d.tone_map;
    let lut = &*LUT;
    let map = |c: f32| -> u8 {
        let v = tone.apply(c * scale);
        let v = if v.is_nan() { 0.0 } else { v };
        lut[(v * (N - 1) as f32 + 0.5) as usize]
    };
    let pixels = p
        .pixels
        .iter()
        .map(|c| eframe::egui::Color32::from_rgb(map(c.x), map(c.y), map(c.z)))
        .collect();
    eframe::egui::ColorImage::new([p.width as usize, p.height as usize], pixels)
}
