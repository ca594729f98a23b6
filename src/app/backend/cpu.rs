//! [`CpuBackend`]: the CPU path tracer (`cpu::Renderer`, rayon) on a background thread, in
//! short passes that an edit can cancel mid-pass. Every edit bumps a generation counter:
//! samples rendered for an older generation never reach the published image.

use super::{Accumulated, Backend, DisplayParams, DisplayTexture};
use crate::app::layer_view::{self, ViewMode};
use crate::cpu::Renderer;
use crate::cpu::layers::LayerFilm;
use crate::film::{Film, exposure_scale};
use crate::math::color::linear_to_srgb;
use crate::render::RenderOptions;
use crate::scene::{Camera, Material, Scene};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::time::{Duration, Instant};

enum Command {
    Scene(Box<Scene>),
    Material(usize, Box<Material>),
    Lights(Box<Scene>, bool),
    Camera(Camera),
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
            }),
            wake: Condvar::new(),
            generation: AtomicU64::new(0),
        });
        let s = Arc::clone(&shared);
        let thread = std::thread::Builder::new()
            .name("refract-render".into())
            .spawn(move || render_thread(&s, repaint))
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

    fn update_material(&mut self, index: usize, material: &Material) {
        let m = Box::new(material.clone());
        self.edit(|st| st.commands.push(Command::Material(index, m)));
    }

    fn update_lights(&mut self, scene: &Scene, geometry_changed: bool) {
        let scene = Box::new(scene.clone());
        self.edit(|st| st.commands.push(Command::Lights(scene, geometry_changed)));
    }

    fn update_camera(&mut self, camera: &Camera) {
        let c = *camera;
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

/// Samples per pass: aim for ~40 ms passes (responsive, little per-pass overhead).
fn pass_size(last_pass: Option<(u32, Duration)>) -> u32 {
    match last_pass {
        None => 1,
        Some((n, t)) => {
            let per = t.as_secs_f64() / n.max(1) as f64;
            ((0.04 / per.max(1e-6)) as u32).clamp(1, 16)
        }
    }
}

fn render_thread(shared: &Shared, repaint: Option<eframe::egui::Context>) {
    let mut renderer: Option<Renderer> = None;
    let mut film: Option<Film> = None;
    // The layer views' layers, alongside `film` (None in the beauty view).
    let mut layers: Option<LayerFilm> = None;
    let mut film_gen = u64::MAX;
    let mut elapsed = Duration::ZERO;
    let mut last_pass: Option<(u32, Duration)> = None;
    loop {
        // Take the pending edits and the generation they make up, atomically.
        let (commands, generation, options, interactive, paused, target, view) = {
            let mut st = shared.lock();
            if st.quit {
                return;
            }
            (
                std::mem::take(&mut st.commands),
                shared.generation.load(Ordering::SeqCst),
                st.options,
                st.interactive,
                st.paused,
                st.spp_target,
                st.view,
            )
        };
        let mut applied_materials = None;
        for c in commands {
            apply_command(&mut renderer, c);
            applied_materials = renderer.as_ref().map(|r| r.scene.materials.clone());
        }
        if let Some(m) = applied_materials {
            shared.lock().materials = m;
        }
        let (Some(r), Some(mut opts)) = (renderer.as_ref(), options) else {
            wait_for_edit(shared, generation);
            continue;
        };
        if interactive {
            // Quarter resolution while dragging: 1/16 of the work per pass.
            opts.width = (opts.width / 4).max(1);
            opts.height = (opts.height / 4).max(1);
        }
        let fresh = film_gen != generation
            || film
                .as_ref()
                .is_none_or(|f| (f.width, f.height) != (opts.width, opts.height));
        if view != ViewMode::Beauty {
            // The layers come from the path tracer's walk over every path.
            opts.estimator = crate::render::Estimator::Path;
            opts.set_filter(None);
        }
        if fresh {
            film = Some(Film::new(opts.width, opts.height));
            layers = (view != ViewMode::Beauty)
                .then(|| LayerFilm::new(opts.width, opts.height, layer_view::layer_count()));
            film_gen = generation;
            elapsed = Duration::ZERO;
        }
        let Some(f) = film.as_mut() else { continue };
        let done = target > 0 && f.spp >= target;
        if paused || done {
            wait_for_edit_or_resume(shared, generation);
            continue;
        }
        let mut n = pass_size(last_pass);
        if f.spp == 0 {
            n = 1; // show something as soon as possible after an edit
        }
        if target > 0 {
            n = n.min((target - f.spp) as u32).max(1);
        }
        let start = Instant::now();
        let cancelled = || shared.generation.load(Ordering::Relaxed) != generation;
        let first = f.spp.min(u32::MAX as u64) as u32;
        let complete = match layers.as_mut() {
            Some(l) => {
                let proto = layer_view::proto();
                r.render_pass_layered(&opts, f, l, &proto, (first, n), &cancelled)
            }
            None => r.render_pass_cancellable(&opts, f, first, n, &cancelled),
        };
        if !complete {
            film_gen = u64::MAX; // partial pass: discard
            continue;
        }
        let pixels = layers
            .as_ref()
            .and_then(|l| layer_view::view_image(view, l, f.spp))
            .unwrap_or_else(|| f.image());
        let t = start.elapsed();
        elapsed += t;
        last_pass = Some((n, t));
        let acc = Arc::new(Accumulated {
            generation,
            width: f.width,
            height: f.height,
            pixels,
            spp: f.spp,
            dropped: f.dropped,
            elapsed,
        });
        {
            let mut st = shared.lock();
            if shared.generation.load(Ordering::SeqCst) == generation {
                st.published = Some(acc);
            }
        }
        if let Some(ctx) = &repaint {
            ctx.request_repaint();
        }
    }
}

fn apply_command(renderer: &mut Option<Renderer>, c: Command) {
    match c {
        Command::Scene(scene) => {
            // The caller validated the scene; a failure here leaves the old one rendering.
            if let Ok(r) = Renderer::new(*scene) {
                *renderer = Some(r);
            }
        }
        Command::Material(i, m) => {
            if let Some(r) = renderer.as_mut()
                && let Some(slot) = r.scene.materials.get_mut(i)
                && m.validate().is_ok()
            {
                // Area lights carry their radiance and sidedness (scene::light::TriangleLight).
                let light_changed =
                    slot.emission != m.emission || slot.double_sided != m.double_sided;
                *slot = *m;
                r.refresh_features();
                if light_changed {
                    r.lights = crate::scene::light::LightSet::build(&r.scene);
                }
            }
        }
        Command::Lights(scene, geometry_changed) => {
            if let Some(r) = renderer.as_mut() {
                if geometry_changed {
                    if let Ok(new) = Renderer::new(*scene) {
                        *r = new;
                    }
                } else if scene.validate().is_ok() {
                    r.scene.materials = scene.materials;
                    r.scene.punctual_lights = scene.punctual_lights;
                    r.scene.environment = scene.environment;
                    r.scene.env_map = scene.env_map;
                    r.scene.settings.light_line_nm = scene.settings.light_line_nm;
                    r.refresh_features();
                    r.lights = crate::scene::light::LightSet::build(&r.scene);
                }
            }
        }
        Command::Camera(c) => {
            if let Some(r) = renderer.as_mut()
                && c.validate().is_ok()
            {
                r.scene.camera = c;
            }
        }
    }
}

/// Sleep until the generation moves on (or quit).
fn wait_for_edit(shared: &Shared, generation: u64) {
    let mut st = shared.lock();
    st.idle = true;
    while !st.quit && shared.generation.load(Ordering::SeqCst) == generation {
        st = shared.wake.wait(st).unwrap_or_else(|e| e.into_inner());
    }
}

/// Sleep until an edit, an unpause or a target change.
fn wait_for_edit_or_resume(shared: &Shared, generation: u64) {
    let mut st = shared.lock();
    let (p0, t0) = (st.paused, st.spp_target);
    st.idle = true;
    while !st.quit
        && shared.generation.load(Ordering::SeqCst) == generation
        && st.paused == p0
        && st.spp_target == t0
    {
        st = shared.wake.wait(st).unwrap_or_else(|e| e.into_inner());
    }
}
