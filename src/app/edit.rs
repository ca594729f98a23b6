//! Viewer edits as data. The panels, the viewport and the keyboard shortcuts push an [`Edit`]
//! ([`ViewerApp::push`]); [`ViewerApp::apply`] is the one place that writes it into the
//! settings and the rendered scene and decides what follows: the light distribution and the
//! picking BVH are rebuilt when emitters move, the backend gets the material, lights, camera,
//! options or whole scene that changed (it restarts accumulation, and the GPU backend
//! respecialises its kernel when a material kind, the filter or the estimator asks for it).

use super::{Messages, ViewerApp};
use crate::bvh::Bvh;
use crate::paths::PathFilter;
use crate::render::Estimator;
use crate::render::settings::{DisplaySettings, RenderEdit, ViewerSettings};
use crate::scene::edits::{LightEdit, Orbit};
use crate::scene::{Checked, Material, Scene};
use std::time::{Duration, Instant};

/// One change the user asked for.
#[derive(Clone, Debug, PartialEq)]
pub enum Edit {
    /// Material `index` becomes `material` (an invalid one is refused with a message).
    Material {
        index: usize,
        material: Box<Material>,
    },
    /// Light scale and colour, size and placement of the main area light, environment.
    Light(LightEdit),
    /// Full vertical field of view in degrees.
    FieldOfView(f32),
    /// The orbit the camera moves on (drag, scroll or typed values; already sanitised).
    Orbit(Orbit),
    /// Back to the scene's own camera.
    ResetCamera,
    /// Depth limits, seed, estimator, render scale, spp target.
    Render(RenderEdit),
    /// Path filter text as typed: a valid expression replaces the filter, an invalid one
    /// shows its message and the last valid filter keeps rendering.
    PathFilter(String),
    /// Exposure and tone map (the samples stay).
    Display(DisplaySettings),
    /// Open a scene (`builtin:NAME` or a path); on failure the current one stays.
    OpenScene(String),
    /// Forget every edit and setting: the scene as loaded, default options.
    ResetAll,
    /// Stop or continue adding samples (the image keeps its samples).
    Pause(bool),
    /// Drop every sample and start again.
    Restart,
    /// Load an environment image or change its strength and rotation.
    Environment(EnvEdit),
}

/// An environment-image edit (the image lives in the loaded scene, `ViewerApp::base`).
#[derive(Clone, Debug, PartialEq)]
pub enum EnvEdit {
    /// Load this `.hdr`/`.exr` file (on failure the current lighting stays).
    Load(String),
    /// Strength and rotation (degrees about +Y) of the current image.
    Adjust { strength: f32, rotation: f32 },
}

impl ViewerApp {
    /// Queue `edit`; it is applied later in the same frame.
    pub fn push(&mut self, edit: Edit) {
        self.edits.push(edit);
    }

    /// What `auto` picks for the scene as it is, and why (`Estimator::resolve_why`),
    /// recomputed after an edit and at most once a second otherwise.
    pub fn auto_choice(&mut self) -> (Estimator, &'static str) {
        match self.auto_memo {
            Some((at, choice)) if at.elapsed() < Duration::from_secs(1) => choice,
            _ => {
                let choice = Estimator::Auto.resolve_why(&self.scene);
                self.auto_memo = Some((Instant::now(), choice));
                choice
            }
        }
    }

    /// Apply the queued edits in order.
    pub(super) fn apply_queued(&mut self) {
        for edit in std::mem::take(&mut self.edits) {
            self.apply(edit);
        }
    }

    /// Apply one edit and whatever it implies (see the module documentation).
    pub fn apply(&mut self, edit: Edit) {
        self.auto_memo = None;
        match edit {
            Edit::Material { index, material } => self.apply_material(index, *material),
            Edit::Light(light) => {
                self.settings.light = light;
                self.lights_follow();
            }
            Edit::FieldOfView(deg) => {
                self.settings.camera.yfov_deg = Some(deg);
                self.camera_follows();
            }
            Edit::Orbit(orbit) => {
                self.orbit = orbit;
                self.settings.camera.orbit = Some(orbit);
                self.camera_follows();
            }
            Edit::ResetCamera => {
                self.settings.camera = Default::default();
                self.orbit = self.settings.camera.orbit(&self.base);
                self.camera_follows();
            }
            Edit::Render(render) => {
                self.settings.render = render;
                self.options_follow();
            }
            Edit::PathFilter(text) => self.apply_filter_text(text),
            Edit::Display(display) => self.settings.display = display,
            Edit::OpenScene(spec) => self.open_scene(&spec),
            Edit::ResetAll => self.reset_all(),
            Edit::Pause(paused) => {
                self.paused = paused;
                self.backend.set_paused(paused);
            }
            Edit::Restart => self.backend.reset(),
            Edit::Environment(e) => self.apply_environment(e),
        }
    }

    /// Load or adjust the environment image of the loaded scene, then relight.
    fn apply_environment(&mut self, e: EnvEdit) {
        let (file, strength, rotation) = match &e {
            EnvEdit::Load(path) => (Some(std::path::Path::new(path)), None, None),
            EnvEdit::Adjust { strength, rotation } => (None, Some(*strength), Some(*rotation)),
        };
        let mut base = self.base.clone();
        match crate::scene::env_map::override_environment(&mut base, file, strength, rotation)
            .and_then(|w| base.validate().map(|_| w))
        {
            Ok(warnings) => {
                self.base = base;
                self.report_warnings(&warnings);
                self.lights_follow();
            }
            Err(err) => self.messages.error = Some(format!("{err:#}")),
        }
    }

    /// Validate, record and send a material edit: the one validation of an edited material
    /// (`scene::Checked`; the panel, the backends and the renderers do not check it again).
    /// Invalid values (IOR ≤ 0, NaN …) are refused with a message and the previous material
    /// stays.
    fn apply_material(&mut self, index: usize, m: Material) {
        let Some(old) = self.scene.materials.get(index) else {
            return;
        };
        if *old == m {
            return;
        }
        let m = match Checked::new(m) {
            Ok(m) => m,
            Err(e) => {
                self.messages.error = Some(format!("{e:#}"));
                return;
            }
        };
        self.settings.set_material(index, &m);
        self.scene.materials[index] = Material::clone(&m);
        self.backend.update_material(index, &m);
    }

    /// `settings.light` changed: rebuild the lit scene (and the picking BVH if the light
    /// moved); the backend rebuilds its light distribution (and BVH).
    fn lights_follow(&mut self) {
        let (scene, _) = self.settings.apply(&self.base);
        let geometry_changed = scene.mesh.positions != self.scene.mesh.positions;
        self.scene = scene;
        if geometry_changed {
            self.pick_bvh = Bvh::build(&self.scene.mesh);
        }
        self.backend.update_lights(&self.scene, geometry_changed);
    }

    /// `settings.camera` changed.
    /// The camera's one validation (a non-finite orbit is refused; the old camera stays).
    fn camera_follows(&mut self) {
        match Checked::new(self.settings.camera.camera(&self.base)) {
            Ok(c) => {
                self.scene.camera = *c;
                self.backend.update_camera(&c);
            }
            Err(e) => self.messages.error = Some(format!("{e:#}")),
        }
    }

    /// `settings.render` changed: new options and spp target for the backend.
    pub(super) fn options_follow(&mut self) {
        match self.settings.render_options(&self.scene) {
            Ok(o) => self.backend.set_options(&o),
            Err(e) => self.messages.error = Some(format!("{e:#}")),
        }
        self.backend.set_spp_target(self.settings.render.spp_target);
    }

    fn apply_filter_text(&mut self, text: String) {
        match PathFilter::parse(&text) {
            Ok(_) => {
                self.filter_error = None;
                if self.settings.render.paths != text {
                    self.settings.render.paths = text.clone();
                    self.options_follow();
                }
            }
            Err(e) => self.filter_error = Some(e.to_string()),
        }
        self.filter_text = text;
    }

    /// Load a scene; on failure the error is shown and the old scene keeps rendering.
    fn open_scene(&mut self, spec: &str) {
        let spec = spec.trim();
        let loaded =
            Scene::load_with(spec, &self.load_limits).and_then(|s| s.validate().map(|_| s));
        match loaded {
            Ok(base) => {
                let warnings = base.warnings.clone();
                self.base = base;
                self.settings.scene = Scene::canonical_spec(spec);
                self.settings.clear_scene_edits();
                self.settings.capture = None;
                let (scene, w2) = self.settings.apply(&self.base);
                self.scene = scene;
                self.pick_bvh = Bvh::build(&self.scene.mesh);
                self.orbit = self.settings.camera.orbit(&self.base);
                self.selected = None;
                self.messages = Messages::default();
                self.report_warnings(&[warnings, w2].concat());
                self.backend.set_scene(&self.scene);
                self.options_follow();
            }
            Err(e) => {
                self.messages.error = Some(format!(
                    "could not open '{spec}': {e:#}. Still showing '{}'.",
                    self.settings.scene
                ));
            }
        }
    }

    /// Everything back to the scene's defaults (render and display settings too).
    fn reset_all(&mut self) {
        let spec = self.settings.scene.clone();
        self.settings = ViewerSettings::for_scene(&spec);
        let (scene, _) = self.settings.apply(&self.base);
        self.scene = scene;
        self.pick_bvh = Bvh::build(&self.scene.mesh);
        self.orbit = self.settings.camera.orbit(&self.base);
        self.filter_text.clear();
        self.filter_error = None;
        self.paused = false;
        self.backend.set_paused(false);
        self.backend.set_scene(&self.scene);
        self.options_follow();
    }
}
