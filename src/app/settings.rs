//! Every viewer setting in one serde struct: persisted between runs (eframe storage) and
//! written as the `.json` sidecar of a screenshot, so `refract render --settings x.json`
//! re-renders the same image headless. Nothing here needs a window.
//!
//! Edits are stored relative to the scene as loaded (`scene` spec): material overrides by
//! index, light scale/colour/placement, camera orbit, render options and display settings.
//! [`ViewerSettings::apply`] turns (loaded scene, settings) into the scene that is rendered;
//! the viewer and the headless renderer both call it, so they render the same thing.

use crate::bsdf::MicrofacetDistribution;
use crate::cpu::RenderOptions;
use crate::film::ToneMap;
use crate::math::color::{blackbody_rgb, luminance};
use crate::paths::PathFilter;
use crate::scene::{Camera, Material, MaterialKind, Scene};
use anyhow::Context;
use glam::{Quat, Vec3};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Version of the sidecar format (bump on incompatible changes).
pub const FORMAT_VERSION: u32 = 1;

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
}

impl Default for ViewerSettings {
    fn default() -> Self {
        ViewerSettings::for_scene(DEFAULT_SCENE)
    }
}

/// Overrides of one material's editable fields (emission is edited through [`LightEdit`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MaterialEdit {
    pub index: usize,
    /// The material's name when edited (a mismatch on apply gives a warning).
    pub name: String,
    pub kind: MaterialKind,
    pub base_color: [f32; 3],
    pub metallic: f32,
    pub roughness: f32,
    pub distribution: MicrofacetDistribution,
    pub ior: f32,
    /// Abbe number; None = no dispersion.
    pub abbe: Option<f32>,
    pub attenuation_color: [f32; 3],
    /// None = no absorption (infinite distance; JSON has no infinity).
    pub attenuation_distance: Option<f32>,
}

impl MaterialEdit {
    pub fn from_material(index: usize, m: &Material) -> MaterialEdit {
        MaterialEdit {
            index,
            name: m.name.clone(),
            kind: m.kind,
            base_color: m.base_color.to_array(),
            metallic: m.metallic,
            roughness: m.roughness,
            distribution: m.distribution,
            ior: m.ior,
            abbe: m.abbe,
            attenuation_color: m.attenuation_color.to_array(),
            attenuation_distance: m
                .attenuation_distance
                .is_finite()
                .then_some(m.attenuation_distance),
        }
    }

    /// Write the overrides into `m` (emission and textures are left alone).
    pub fn apply_to(&self, m: &mut Material) {
        m.kind = self.kind;
        m.base_color = Vec3::from_array(self.base_color);
        m.metallic = self.metallic;
        m.roughness = self.roughness;
        m.distribution = self.distribution;
        m.ior = self.ior;
        m.abbe = self.abbe;
        m.attenuation_color = Vec3::from_array(self.attenuation_color);
        m.attenuation_distance = self.attenuation_distance.unwrap_or(f32::INFINITY);
    }
}

/// Light edits: emission scale and colour of every light; size and placement of the main
/// area light; environment brightness.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct LightEdit {
    /// Scale of every emitter's radiance and every punctual light's intensity.
    pub intensity: f32,
    /// Linear RGB tint of every light (ignored when `temperature_k` is set).
    pub color: [f32; 3],
    /// Black-body colour temperature in kelvin (replaces `color`), luminance-normalised.
    pub temperature_k: Option<f32>,
    /// Scale of the main area light about its centroid (1 = as loaded).
    pub size: f32,
    /// Direction of the main area light from the scene centre; None = as loaded.
    pub elevation_deg: Option<f32>,
    pub azimuth_deg: Option<f32>,
    /// Luminance of the uniform environment; None = as loaded.
    pub environment: Option<f32>,
}

impl Default for LightEdit {
    fn default() -> Self {
        LightEdit {
            intensity: 1.0,
            color: [1.0; 3],
            temperature_k: None,
            size: 1.0,
            elevation_deg: None,
            azimuth_deg: None,
            environment: None,
        }
    }
}

impl LightEdit {
    /// The RGB factor every light is multiplied by (intensity × colour).
    pub fn tint(&self) -> Vec3 {
        let c = match self.temperature_k {
            Some(t) => blackbody_rgb(t),
            None => Vec3::from_array(self.color),
        };
        let c = if c.is_finite() {
            c.max(Vec3::ZERO)
        } else {
            Vec3::ONE
        };
        let s = if self.intensity.is_finite() {
            self.intensity.max(0.0)
        } else {
            1.0
        };
        c * s
    }
}

/// An orbit camera: position on a sphere around `target`, always upright (+Y up).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Orbit {
    pub target: [f32; 3],
    pub distance: f32,
    /// Rotation about +Y of the camera position seen from the target (0 = on +Z).
    pub yaw_deg: f32,
    /// Elevation of the camera position seen from the target.
    pub pitch_deg: f32,
}

impl Orbit {
    pub const MAX_PITCH: f32 = 89.0;

    /// The orbit that reproduces `cam`'s position and viewing direction (roll is dropped),
    /// pivoting at the point along the view direction nearest the scene centre.
    pub fn from_camera(cam: &Camera, scene_centre: Vec3, scene_radius: f32) -> Orbit {
        let fwd = cam.forward().normalize_or(Vec3::NEG_Z);
        let t = (scene_centre - cam.position)
            .dot(fwd)
            .max(0.1 * scene_radius.max(1e-3));
        let back = -fwd;
        Orbit {
            target: (cam.position + fwd * t).to_array(),
            distance: t,
            yaw_deg: back.x.atan2(back.z).to_degrees(),
            pitch_deg: back
                .y
                .clamp(-1.0, 1.0)
                .asin()
                .to_degrees()
                .clamp(-Self::MAX_PITCH, Self::MAX_PITCH),
        }
    }

    pub fn position(&self) -> Vec3 {
        let (y, p) = (self.yaw_deg.to_radians(), self.pitch_deg.to_radians());
        let dir = Vec3::new(p.cos() * y.sin(), p.sin(), p.cos() * y.cos());
        Vec3::from_array(self.target) + dir * self.distance
    }

    pub fn camera(&self, yfov: f32) -> Camera {
        Camera::look_at(
            self.position(),
            Vec3::from_array(self.target),
            Vec3::Y,
            yfov,
        )
    }

    /// Keep the orbit usable whatever was typed or dragged.
    pub fn sanitize(&mut self, fallback: &Orbit) {
        let ok = Vec3::from_array(self.target).is_finite()
            && self.distance.is_finite()
            && self.distance > 0.0
            && self.yaw_deg.is_finite()
            && self.pitch_deg.is_finite();
        if !ok {
            *self = *fallback;
        }
        self.distance = self.distance.clamp(1e-4, 1e6);
        self.pitch_deg = self.pitch_deg.clamp(-Self::MAX_PITCH, Self::MAX_PITCH);
        self.yaw_deg = self.yaw_deg.rem_euclid(360.0);
    }
}

/// Camera edits; all None = the scene's camera exactly.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct CameraEdit {
    pub orbit: Option<Orbit>,
    /// Full vertical field of view in degrees.
    pub yfov_deg: Option<f32>,
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
    /// Rendered resolution relative to the scene's width × height (interactivity on a CPU).
    pub render_scale: f32,
    /// Light-transport estimator ("auto" picks by scene features).
    pub estimator: EstimatorChoice,
}

/// The estimator selector of the viewer.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum EstimatorChoice {
    /// Light + path tracing (MIS) when the scene has glass and a small or delta light
    /// (caustics), else path tracing.
    #[default]
    Auto,
    Path,
    Bdpt,
    Lt,
    /// Light tracing and path tracing combined by MIS (the GPU's caustic estimator; the CPU
    /// backend renders it with bdpt, a superset).
    #[serde(rename = "lt+pt", alias = "ltpt")]
    LtPt,
}

impl EstimatorChoice {
    /// The estimator this choice means for `scene`.
    pub fn resolve(self, scene: &Scene) -> crate::cpu::Estimator {
        use crate::cpu::Estimator;
        match self {
            EstimatorChoice::Path => Estimator::Path,
            EstimatorChoice::Bdpt => Estimator::Bdpt,
            EstimatorChoice::Lt => Estimator::Lt,
            EstimatorChoice::LtPt => Estimator::LtPt,
            EstimatorChoice::Auto => {
                let f = scene.features();
                let glass = f.smooth_glass || f.rough_glass || f.thin_glass;
                // "Small" light: the emitters cover < 1% of the scene's bounding-box area, so
                // BSDF-sampled caustic paths rarely hit them.
                let (lo, hi) = scene.bounds();
                let d = hi - lo;
                let box_area = 2.0 * (d.x * d.y + d.y * d.z + d.z * d.x);
                let light_area: f32 = scene
                    .emissive_triangles()
                    .iter()
                    .map(|&t| scene.mesh.area(t as usize))
                    .sum();
                // (No emitter at all, e.g. an environment-lit furnace: nothing to trace from.)
                let small = f.punctual_lights || (light_area > 0.0 && light_area < 0.01 * box_area);
                if glass && small {
                    // lt+pt: the GPU runs light + path tracing, the CPU backend bdpt.
                    Estimator::LtPt
                } else {
                    Estimator::Path
                }
            }
        }
    }
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
            estimator: EstimatorChoice::Auto,
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

/// Facts about the main area light of a scene (the emitter material with the most power).
#[derive(Clone, Debug)]
pub struct MainLight {
    pub material: usize,
    pub triangles: Vec<u32>,
    /// Area-weighted centroid of its triangles.
    pub centroid: Vec3,
    /// Scene bounding-box centre: the light is placed on a sphere around it.
    pub centre: Vec3,
    pub elevation_deg: f32,
    pub azimuth_deg: f32,
}

impl MainLight {
    pub fn find(scene: &Scene) -> Option<MainLight> {
        let mut power = vec![0.0f32; scene.materials.len()];
        for t in scene.emissive_triangles() {
            let mi = scene.mesh.tri_material[t as usize] as usize;
            power[mi] += luminance(scene.materials[mi].emission) * scene.mesh.area(t as usize);
        }
        let (material, &p) = power.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1))?;
        if p.is_nan() || p <= 0.0 {
            return None;
        }
        let triangles: Vec<u32> = (0..scene.mesh.triangle_count() as u32)
            .filter(|&t| scene.mesh.tri_material[t as usize] as usize == material)
            .collect();
        let mut area = 0.0f32;
        let mut c = Vec3::ZERO;
        for &t in &triangles {
            let [a, b, cc] = scene.mesh.tri(t as usize);
            let ar = scene.mesh.area(t as usize);
            area += ar;
            c += ar * (a + b + cc) / 3.0;
        }
        if area <= 0.0 {
            return None;
        }
        let centroid = c / area;
        let (lo, hi) = scene.bounds();
        let centre = 0.5 * (lo + hi);
        let d = (centroid - centre).normalize_or(Vec3::Y);
        Some(MainLight {
            material,
            triangles,
            centroid,
            centre,
            elevation_deg: d.y.clamp(-1.0, 1.0).asin().to_degrees(),
            azimuth_deg: d.x.atan2(d.z).to_degrees(),
        })
    }
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
        }
    }

    /// Forget everything that belongs to one scene (materials, light, camera), keeping the
    /// render and display settings.
    pub fn clear_scene_edits(&mut self) {
        self.materials.clear();
        self.light = LightEdit::default();
        self.camera = CameraEdit::default();
    }

    pub fn load(path: &Path) -> anyhow::Result<ViewerSettings> {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("cannot read settings '{}'", path.display()))?;
        let s: ViewerSettings = serde_json::from_str(&text)
            .with_context(|| format!("'{}' is not a refract settings file", path.display()))?;
        anyhow::ensure!(
            s.format <= FORMAT_VERSION,
            "'{}' has settings format {}, this build reads up to {FORMAT_VERSION}",
            path.display(),
            s.format
        );
        Ok(s)
    }

    pub fn save(&self, path: &Path) -> anyhow::Result<()> {
        let text = serde_json::to_string_pretty(self)?;
        std::fs::write(path, text).with_context(|| format!("cannot write '{}'", path.display()))
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
        for e in &self.materials {
            match scene.materials.get_mut(e.index) {
                Some(m) => {
                    if m.name != e.name {
                        warnings.push(format!(
                            "material {} is '{}' here but '{}' in the settings; applied anyway",
                            e.index, m.name, e.name
                        ));
                    }
                    let before = m.clone();
                    e.apply_to(m);
                    if let Err(err) = m.validate() {
                        warnings.push(format!("material edit skipped: {err}"));
                        *m = before;
                    }
                }
                None => warnings.push(format!(
                    "the scene has no material {} ('{}'); edit skipped",
                    e.index, e.name
                )),
            }
        }
        self.apply_lights(base, &mut scene);
        scene.camera = self.camera_for(base);
        (scene, warnings)
    }

    fn apply_lights(&self, base: &Scene, scene: &mut Scene) {
        let l = &self.light;
        let tint = l.tint();
        for (m, b) in scene.materials.iter_mut().zip(&base.materials) {
            if b.is_emissive() {
                m.emission = b.emission * tint;
            }
        }
        for p in &mut scene.punctual_lights {
            use crate::scene::PunctualLight as P;
            match p {
                P::Point { intensity, .. } | P::Spot { intensity, .. } => *intensity *= tint,
                P::Directional { irradiance, .. } => *irradiance *= tint,
            }
        }
        if let Some(env) = l.environment.filter(|e| e.is_finite() && *e >= 0.0) {
            let lum = luminance(base.environment);
            scene.environment = if lum > 0.0 {
                base.environment / lum * env
            } else {
                Vec3::splat(env)
            };
        }
        let size = if l.size.is_finite() {
            l.size.clamp(0.01, 100.0)
        } else {
            1.0
        };
        let moved = l.elevation_deg.is_some() || l.azimuth_deg.is_some();
        if size == 1.0 && !moved {
            return;
        }
        let Some(main) = MainLight::find(base) else {
            return;
        };
        let rot = if moved {
            let el = l.elevation_deg.unwrap_or(main.elevation_deg).to_radians();
            let az = l.azimuth_deg.unwrap_or(main.azimuth_deg).to_radians();
            let d0 = (main.centroid - main.centre).normalize_or(Vec3::Y);
            let d1 = Vec3::new(el.cos() * az.sin(), el.sin(), el.cos() * az.cos());
            if d1.is_finite() {
                Quat::from_rotation_arc(d0, d1.normalize_or(d0))
            } else {
                Quat::IDENTITY
            }
        } else {
            Quat::IDENTITY
        };
        let mut verts: Vec<u32> = main
            .triangles
            .iter()
            .flat_map(|&t| base.mesh.indices[t as usize])
            .collect();
        verts.sort_unstable();
        verts.dedup();
        for v in verts {
            let p = base.mesh.positions[v as usize];
            let scaled = main.centroid + (p - main.centroid) * size;
            scene.mesh.positions[v as usize] = main.centre + rot * (scaled - main.centre);
            scene.mesh.normals[v as usize] =
                (rot * base.mesh.normals[v as usize]).normalize_or(Vec3::Y);
        }
    }

    /// The camera: the scene's, or the edited orbit, with the edited field of view.
    pub fn camera_for(&self, base: &Scene) -> Camera {
        let yfov = self
            .camera
            .yfov_deg
            .filter(|f| f.is_finite())
            .map(|f| f.clamp(1.0, 170.0).to_radians())
            .unwrap_or(base.camera.yfov);
        match self.camera.orbit {
            Some(o) => {
                let cam = o.camera(yfov);
                if cam.validate().is_ok() {
                    cam
                } else {
                    base.camera
                }
            }
            None => Camera {
                yfov,
                ..base.camera
            },
        }
    }

    /// The orbit the camera controls start from.
    pub fn orbit_for(&self, base: &Scene) -> Orbit {
        self.camera.orbit.unwrap_or_else(|| {
            let (lo, hi) = base.bounds();
            Orbit::from_camera(&base.camera, 0.5 * (lo + hi), 0.5 * (hi - lo).length())
        })
    }

    /// Rendered resolution: the capture's (sidecar) or the scene's × render scale.
    pub fn resolution(&self, scene: &Scene) -> (u32, u32) {
        if let Some(c) = &self.capture {
            return (c.width, c.height);
        }
        let s = if self.render.render_scale.is_finite() {
            self.render.render_scale.clamp(0.05, 2.0)
        } else {
            1.0
        };
        let max = crate::scene::MAX_IMAGE_SIDE;
        let w = ((scene.settings.width as f32 * s).round() as u32).clamp(1, max);
        let h = ((scene.settings.height as f32 * s).round() as u32).clamp(1, max);
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
        let filter = PathFilter::parse(&self.render.paths)
            .map_err(|e| anyhow::anyhow!("invalid path filter '{}': {e}", self.render.paths))?;
        crate::cpu::Renderer::set_filter(&mut opts, Some(&filter));
        opts.estimator = self.render.estimator.resolve(scene);
        Ok(opts)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orbit_reproduces_the_scene_camera() {
        let scene = crate::scene::builtin::cornell_glass();
        let s = ViewerSettings::for_scene(DEFAULT_SCENE);
        let o = s.orbit_for(&scene);
        let cam = o.camera(scene.camera.yfov);
        assert!((cam.position - scene.camera.position).length() < 1e-4);
        assert!((cam.forward() - scene.camera.forward()).length() < 1e-4);
    }

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
        s.camera.orbit = Some(s.orbit_for(&base));
        s.render.paths = "LS+DE".into();
        let text = serde_json::to_string(&s).unwrap();
        let back: ViewerSettings = serde_json::from_str(&text).unwrap();
        assert_eq!(s, back);
        assert_eq!(back.apply(&base).0.materials[4].ior, 1.333);
    }

    /// `auto` picks light + path tracing for glass lit by a small light (caustics), path
    /// tracing otherwise; `lt+pt` survives a settings round trip under its own name.
    #[test]
    fn auto_estimator_picks_by_scene_features() {
        use crate::cpu::Estimator;
        let caustic = Scene::load("builtin:caustic").unwrap();
        let furnace = Scene::load("builtin:furnace").unwrap();
        assert_eq!(EstimatorChoice::Auto.resolve(&caustic), Estimator::LtPt);
        assert_eq!(EstimatorChoice::Auto.resolve(&furnace), Estimator::Path);
        let text = serde_json::to_string(&EstimatorChoice::LtPt).unwrap();
        assert_eq!(text, "\"lt+pt\"");
        let back: EstimatorChoice = serde_json::from_str(&text).unwrap();
        assert_eq!(back, EstimatorChoice::LtPt);
    }
}
