//! Every viewer setting in one serde struct: persisted between runs (eframe storage) and
//! written as the `.json` sidecar of a screenshot, so `refract render --settings x.json`
//! re-renders the same image headless. Nothing here needs a window.
//!
//! Edits are stored relative to the scene as loaded (`scene` spec): material overrides by
//! index, light scale/colour/placement, camera orbit (`scene::edits`), render options and
//! display settings. [`ViewerSettings::apply`] turns (loaded scene, settings) into the scene
//! that is rendered and [`ViewerSettings::render_options`] into the options; the viewer and
//! the headless renderer both call them, so they render the same thing.

use super::{Estimator, RenderOptions};
use crate::film::ToneMap;
use crate::paths::PathFilter;
use crate::scene::edits::{CameraEdit, LightEdit, MaterialEdit, apply_materials};
use crate::scene::{Material, Scene};
pub use crate::text::abbreviate;
use anyhow::Context;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Version of the sidecar format (bump on incompatible changes).
pub const FORMAT_VERSION: u32 = 1;
/// The most bytes a settings sidecar may have (a real one is a few kB).
pub const MAX_SETTINGS_BYTES: u64 = 16 << 20;

/// The scene the viewer opens without arguments.
pub const DEFAULT_SCENE: &str = "builtin:cornell-glass";

/// All viewer settings (see the module documentation).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct ViewerSettings {
    pub format: u32,
    /// `builtin:NAME` or a path to a .glb/.gltf file.
    pub scene: String,
    /// Material overrides, by index into the loaded scene's materials.
    pub materials: Vec<MaterialEdit>,
    pub light: LightEdit,
    pub camera: CameraEdit,
    pub render: RenderEdit,
    pub display: DisplaySettings,
    /// Only in a screenshot sidecar: what was captured.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub capture: Option<CaptureInfo>,
    /// Only in a screenshot sidecar: the environment image that lit the capture (the viewer
    /// keeps it in its loaded scene), so `render --settings` lights the scene the same way.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub environment: Option<EnvironmentSetting>,
    /// The viewer's image area in physical pixels, once it has been laid out (never saved:
    /// a sidecar records the captured size instead).
    #[serde(skip)]
    pub viewport: Option<(u32, u32)>,
}

impl Default for ViewerSettings {
    fn default() -> Self {
        ViewerSettings::for_scene(DEFAULT_SCENE)
    }
}

/// Render options (None = the scene's own value).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct RenderEdit {
    pub max_depth: Option<u32>,
    pub rr_depth: Option<u32>,
    pub seed: u32,
    /// Heckbert path expression (always a valid one; empty = all paths).
    pub paths: String,
    /// Stop accumulating at this many samples per pixel (0 = never stop).
    pub spp_target: u64,
    /// Rendered resolution relative to the viewport's physical pixels (or, with
    /// `fit_viewport` off or no viewport yet, the scene's width × height).
    pub render_scale: f32,
    /// Render the viewport's size (HiDPI aware) rather than the scene's resolution.
    pub fit_viewport: bool,
    /// Light-transport estimator ("auto" picks by scene features).
    pub estimator: Estimator,
    /// A linear polariser in front of the sensor, its axis in degrees from the image's
    /// horizontal (docs/polarization.md); absent: unpolarised transport. The viewer writes
    /// it into a screenshot's sidecar, and `render --settings` renders behind it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub polarizer: Option<f32>,
}

impl Default for RenderEdit {
    fn default() -> Self {
        RenderEdit {
            max_depth: None,
            rr_depth: None,
            seed: 0,
            paths: String::new(),
            spp_target: 0,
            render_scale: 0.5,
            fit_viewport: true,
            estimator: Estimator::Auto,
            polarizer: None,
        }
    }
}

/// How the accumulated radiance is shown (never restarts accumulation).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct DisplaySettings {
    /// Exposure in stops.
    pub exposure: f32,
    pub tone_map: ToneMap,
}

impl Default for DisplaySettings {
    fn default() -> Self {
        DisplaySettings {
            exposure: 0.0,
            tone_map: ToneMap::Clamp,
        }
    }
}

/// The environment image of a screenshot (sidecar only): `--env FILE --env-strength S
/// --env-rotation R` of `render`, recorded.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EnvironmentSetting {
    /// The `.hdr`/`.exr` file (absolute, or relative to the sidecar's folder); None: the
    /// scene's own image (its `extras.environment` or a built-in's generated sky).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub uri: Option<String>,
    /// Radiance multiplier.
    pub strength: f32,
    /// Rotation about +Y in degrees.
    pub rotation: f32,
}

impl EnvironmentSetting {
    /// The setting of `scene`'s environment image (None without one); the file is recorded
    /// when the image was read from one (its absolute path).
    pub fn of(scene: &Scene) -> Option<EnvironmentSetting> {
        let img = scene.env_map.as_ref()?;
        let file = Path::new(&img.map.name);
        let uri = file
            .is_file()
            .then(|| std::fs::canonicalize(file).unwrap_or_else(|_| file.to_owned()))
            .map(|p| p.display().to_string());
        Some(EnvironmentSetting {
            uri,
            strength: img.strength,
            rotation: img.rotation,
        })
    }

    /// Light `scene` with this image: load `uri` (relative to `dir`, the sidecar's folder)
    /// and set strength and rotation (errors name the file or the value).
    pub fn apply(&self, scene: &mut Scene, dir: &Path) -> anyhow::Result<Vec<String>> {
        let file = self.uri.as_ref().map(|u| dir.join(u));
        crate::scene::env_map::override_environment(
            scene,
            file.as_deref(),
            Some(self.strength),
            Some(self.rotation),
        )
        .context("environment")
    }
}

/// What a screenshot captured (sidecar only).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CaptureInfo {
    /// Rendered resolution.
    pub width: u32,
    pub height: u32,
    /// Samples per pixel accumulated in the image.
    pub spp: u64,
    /// Samples dropped by the NaN/negative firewall.
    pub dropped: u64,
    pub device: String,
    /// Render time of the accumulated samples in seconds.
    pub elapsed_s: f64,
    /// File names (relative to the sidecar) of the PNG and EXR.
    pub png: String,
    pub exr: String,
}

impl ViewerSettings {
    /// Defaults for a scene.
    pub fn for_scene(spec: &str) -> ViewerSettings {
        ViewerSettings {
            format: FORMAT_VERSION,
            scene: spec.to_owned(),
            materials: Vec::new(),
            light: LightEdit::default(),
            camera: CameraEdit::default(),
            render: RenderEdit::default(),
            display: DisplaySettings::default(),
            capture: None,
            environment: None,
            viewport: None,
        }
    }

    /// Forget everything that belongs to one scene (materials, light, camera), keeping the
    /// render and display settings.
    pub fn clear_scene_edits(&mut self) {
        self.materials.clear();
        self.light = LightEdit::default();
        self.camera = CameraEdit::default();
    }

    /// Read a sidecar: a regular file (a FIFO or `/dev/zero` is refused before reading) of at
    /// most `MAX_SETTINGS_BYTES`.
    pub fn load(path: &Path) -> anyhow::Result<ViewerSettings> {
        let bytes = crate::files::read_regular_file(path, MAX_SETTINGS_BYTES, "settings")
            .map_err(anyhow::Error::msg)?;
        let text = std::str::from_utf8(&bytes)
            .with_context(|| format!("settings '{}' is not UTF-8 text", path.display()))?;
        Self::parse(text)
            .with_context(|| format!("'{}' is not a refract settings file", path.display()))
    }

    /// Parse a sidecar's JSON text (the fuzz target's entry point: any text gives `Ok` or an
    /// error, never a panic).
    pub fn parse(text: &str) -> anyhow::Result<ViewerSettings> {
        let s: ViewerSettings = serde_json::from_str(text)?;
        anyhow::ensure!(
            s.format <= FORMAT_VERSION,
            "it has settings format {}, this build reads up to {FORMAT_VERSION}",
            s.format
        );
        Ok(s)
    }

    pub fn save(&self, path: &Path) -> anyhow::Result<()> {
        let text = serde_json::to_string_pretty(self)?;
        crate::film::write_atomically(path, |tmp| {
            std::fs::write(tmp, text).with_context(|| format!("cannot write '{}'", path.display()))
        })
    }

    /// Record the current state of material `index` as an override.
    pub fn set_material(&mut self, index: usize, m: &Material) {
        let edit = MaterialEdit::from_material(index, m);
        match self.materials.iter_mut().find(|e| e.index == index) {
            Some(e) => *e = edit,
            None => self.materials.push(edit),
        }
    }

    /// The scene to render: `base` (as loaded) with every edit applied. Returns the scene and
    /// warnings about edits that do not fit it (they are skipped).
    pub fn apply(&self, base: &Scene) -> (Scene, Vec<String>) {
        let mut scene = base.clone();
        let mut warnings = Vec::new();
        apply_materials(&self.materials, &mut scene, &mut warnings);
        self.light.apply(base, &mut scene);
        scene.camera = self.camera.camera(base);
        (scene, warnings)
    }

    /// Rendered resolution: the capture's (sidecar), else the viewport's physical pixels (with
    /// `fit_viewport`, once known) or the scene's, × render scale.
    pub fn resolution(&self, scene: &Scene) -> (u32, u32) {
        if let Some(c) = &self.capture {
            return (c.width, c.height);
        }
        let (bw, bh) = match self.viewport {
            Some(v) if self.render.fit_viewport => v,
            _ => (scene.settings.width, scene.settings.height),
        };
        let s = if self.render.render_scale.is_finite() {
            self.render.render_scale.clamp(0.05, 2.0)
        } else {
            1.0
        };
        let max = crate::scene::MAX_IMAGE_SIDE;
        let w = ((bw as f32 * s).round() as u32).clamp(1, max);
        let h = ((bh as f32 * s).round() as u32).clamp(1, max);
        (w, h)
    }

    /// Render options for `scene` (which must be the result of [`ViewerSettings::apply`]).
    pub fn render_options(&self, scene: &Scene) -> anyhow::Result<RenderOptions> {
        let mut opts = RenderOptions::from_scene(scene);
        let (w, h) = self.resolution(scene);
        opts.width = w;
        opts.height = h;
        if let Some(d) = self.render.max_depth {
            opts.max_depth = d.max(1);
        }
        if let Some(r) = self.render.rr_depth {
            opts.rr_depth = r;
        }
        opts.seed = self.render.seed;
        let filter = PathFilter::parse(&self.render.paths).map_err(|e| {
            anyhow::anyhow!(
                "invalid path filter render.paths '{}': {e}",
                abbreviate(&self.render.paths)
            )
        })?;
        opts.set_filter(Some(&filter));
        opts.estimator = self.render.estimator.resolve(scene);
        Ok(opts)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::edits::MainLight;

    #[test]
    fn light_edits_scale_emission_and_move_the_light() {
        let base = crate::scene::builtin::cornell_glass();
        let main = MainLight::find(&base).expect("cornell box has a light");
        assert!((main.elevation_deg - 90.0).abs() < 1.0);
        let mut s = ViewerSettings::for_scene(DEFAULT_SCENE);
        s.light.intensity = 2.0;
        s.light.size = 0.5;
        s.light.elevation_deg = Some(60.0);
        let (scene, w) = s.apply(&base);
        assert!(w.is_empty());
        let m = main.material;
        assert_eq!(
            scene.materials[m].emission,
            base.materials[m].emission * 2.0
        );
        let moved = MainLight::find(&scene).unwrap();
        assert!(
            (moved.elevation_deg - 60.0).abs() < 1.0,
            "{}",
            moved.elevation_deg
        );
        let area = |sc: &Scene| -> f32 {
            main.triangles
                .iter()
                .map(|&t| sc.mesh.area(t as usize))
                .sum()
        };
        assert!((area(&scene) - 0.25 * area(&base)).abs() < 1e-4);
        scene.validate().unwrap();
    }

    #[test]
    fn sidecar_round_trips_through_json() {
        let base = crate::scene::builtin::cornell_glass();
        let mut s = ViewerSettings::for_scene(DEFAULT_SCENE);
        let mut m = base.materials[4].clone();
        m.ior = 1.333;
        m.attenuation_distance = f32::INFINITY;
        s.set_material(4, &m);
        s.camera.orbit = Some(s.camera.orbit(&base));
        s.render.paths = "LS+DE".into();
        let text = serde_json::to_string(&s).unwrap();
        let back: ViewerSettings = serde_json::from_str(&text).unwrap();
        assert_eq!(s, back);
        assert_eq!(back.apply(&base).0.materials[4].ior, 1.333);
    }
}
