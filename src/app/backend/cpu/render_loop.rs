//! The CPU backend's render thread: it applies the UI's edits, renders short passes into
//! the film of the current generation (cancelled mid-pass by the next edit) and publishes
//! each finished pass.

use super::{Command, Shared};
use crate::app::backend::Accumulated;
use crate::app::layer_view::{self, ViewMode};
use crate::cpu::Renderer;
use crate::cpu::layers::LayerFilm;
use crate::cpu::polarized::{Polarization, STOKES_LAYERS};
use crate::film::Film;
use crate::render::RenderOptions;
use std::sync::Arc;
use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

/// What the UI asked for, taken at the start of an iteration with the generation it makes up.
struct Pending {
    generation: u64,
    options: Option<RenderOptions>,
    interactive: bool,
    paused: bool,
    target: u64,
    view: ViewMode,
    polarizer: Option<f32>,
}

/// The render thread's own state: the renderer and the film (and layers) it accumulates.
struct RenderLoop {
    renderer: Option<Renderer>,
    film: Option<Film>,
    /// The layer views' layers, alongside `film` (None in the beauty view).
    layers: Option<LayerFilm>,
    /// The Stokes layers of a polarised beauty view (None without a polariser).
    stokes: Option<LayerFilm>,
    /// The generation `film` accumulates (`u64::MAX`: none, or a discarded partial pass).
    film_gen: u64,
    /// Render time of the film's samples.
    elapsed: Duration,
    /// Samples and time of the last pass, which size the next one.
    last_pass: Option<(u32, Duration)>,
}

/// The render thread's body: until `quit`, apply the edits, render a pass, publish it.
pub(super) fn render_thread(shared: &Shared, repaint: Option<eframe::egui::Context>) {
    let mut rl = RenderLoop {
        renderer: None,
        film: None,
        layers: None,
        stokes: None,
        film_gen: u64::MAX,
        elapsed: Duration::ZERO,
        last_pass: None,
    };
    loop {
        let Some(p) = rl.take_pending(shared) else {
            return;
        };
        let Some(opts) = rl.pass_options(&p) else {
            wait_for_edit(shared, p.generation);
            continue;
        };
        let spp = rl.ensure_film(&opts, &p);
        if p.paused || (p.target > 0 && spp >= p.target) {
            wait_for_edit_or_resume(shared, p.generation);
            continue;
        }
        let Some(acc) = rl.pass(shared, &opts, &p) else {
            continue;
        };
        {
            let mut st = shared.lock();
            if shared.generation.load(Ordering::SeqCst) == p.generation {
                st.published = Some(acc);
            }
        }
        if let Some(ctx) = &repaint {
            ctx.request_repaint();
        }
    }
}

impl RenderLoop {
    /// Take the pending edits and the generation they make up, atomically, and apply them;
    /// None on quit.
    fn take_pending(&mut self, shared: &Shared) -> Option<Pending> {
        let (commands, p) = {
            let mut st = shared.lock();
            if st.quit {
                return None;
            }
            let p = Pending {
                generation: shared.generation.load(Ordering::SeqCst),
                options: st.options,
                interactive: st.interactive,
                paused: st.paused,
                target: st.spp_target,
                view: st.view,
                polarizer: st.polarizer,
            };
            (std::mem::take(&mut st.commands), p)
        };
        let mut applied_materials = None;
        for c in commands {
            apply_command(&mut self.renderer, c);
            applied_materials = self.renderer.as_ref().map(|r| r.scene.materials.clone());
        }
        if let Some(m) = applied_materials {
            shared.lock().materials = m;
        }
        Some(p)
    }

    /// The options of the next pass; None while there is no scene or no options yet.
    fn pass_options(&self, p: &Pending) -> Option<RenderOptions> {
        let (Some(_), Some(mut opts)) = (self.renderer.as_ref(), p.options) else {
            return None;
        };
        if p.interactive {
            // Quarter resolution while dragging: 1/16 of the work per pass.
            opts.width = (opts.width / 4).max(1);
            opts.height = (opts.height / 4).max(1);
        }
        if p.view != ViewMode::Beauty || p.polarizer.is_some() {
            // The layers come from the path tracer's walk over every path.
            opts.estimator = crate::render::Estimator::Path;
            opts.set_filter(None);
        }
        Some(opts)
    }

    /// A fresh film (and layers) for a new generation or size; returns the film's spp.
    fn ensure_film(&mut self, opts: &RenderOptions, p: &Pending) -> u64 {
        let (w, h) = (opts.width, opts.height);
        let fresh = self.film_gen != p.generation
            || self
                .film
                .as_ref()
                .is_none_or(|f| (f.width, f.height) != (w, h));
        if fresh {
            self.film = Some(Film::new(w, h));
            self.layers = p
                .view
                .uses_layers()
                .then(|| LayerFilm::new(w, h, layer_view::layer_count()));
            let polarized = p.view.is_polarized() || p.polarizer.is_some();
            self.stokes =
                (polarized && !p.view.uses_layers()).then(|| LayerFilm::new(w, h, STOKES_LAYERS));
            self.film_gen = p.generation;
            self.elapsed = Duration::ZERO;
        }
        self.film.as_ref().map_or(0, |f| f.spp)
    }

    /// Render one pass into the film; the image to publish, or None when an edit cancelled
    /// the pass (its partial samples are discarded with the film).
    fn pass(
        &mut self,
        shared: &Shared,
        opts: &RenderOptions,
        p: &Pending,
    ) -> Option<Arc<Accumulated>> {
        let (Some(r), Some(f)) = (self.renderer.as_ref(), self.film.as_mut()) else {
            return None;
        };
        let mut n = pass_size(self.last_pass);
        if f.spp == 0 {
            n = 1; // show something as soon as possible after an edit
        }
        if p.target > 0 {
            n = n.min((p.target - f.spp) as u32).max(1);
        }
        let start = Instant::now();
        let cancelled = || shared.generation.load(Ordering::Relaxed) != p.generation;
        let first = f.spp.min(u32::MAX as u64) as u32;
        let complete = match (self.layers.as_mut(), self.stokes.as_mut()) {
            (Some(l), _) => {
                let proto = layer_view::proto();
                r.render_pass_layered(opts, f, l, &proto, (first, n), &cancelled)
            }
            (None, Some(s)) => {
                let pol = Polarization {
                    filter: p.polarizer,
                };
                r.polarized_pass(opts, pol, (f, s), (first, n), &cancelled)
            }
            (None, None) => r.render_pass_cancellable(opts, f, first, n, &cancelled),
        };
        if !complete {
            self.film_gen = u64::MAX; // partial pass: discard
            return None;
        }
        let pixels = self
            .layers
            .as_ref()
            .and_then(|l| layer_view::view_image(p.view, l, f.spp))
            .or_else(|| {
                let s = self.stokes.as_ref()?;
                layer_view::polarized_image(p.view, s, f.spp)
            })
            .unwrap_or_else(|| f.image());
        let t = start.elapsed();
        self.elapsed += t;
        self.last_pass = Some((n, t));
        Some(Arc::new(Accumulated {
            generation: p.generation,
            width: f.width,
            height: f.height,
            pixels,
            spp: f.spp,
            dropped: f.dropped,
            elapsed: self.elapsed,
        }))
    }
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

fn apply_command(renderer: &mut Option<Renderer>, c: Command) {
    match c {
        Command::Scene(scene) => {
            // The caller validated the scene; a failure here leaves the old one rendering.
            if let Ok(r) = Renderer::new(*scene) {
                *renderer = Some(r);
            }
        }
        Command::Material(i, m) => {
            // Checked at the edit (`scene::Checked`): not validated again here.
            if let Some(r) = renderer.as_mut()
                && let Some(slot) = r.scene.materials.get_mut(i)
            {
                let m = m.into_inner();
                // Area lights carry their radiance and sidedness (scene::light::TriangleLight).
                let light_changed =
                    slot.emission != m.emission || slot.double_sided != m.double_sided;
                *slot = m;
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
            if let Some(r) = renderer.as_mut() {
                r.scene.camera = c.into_inner();
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
