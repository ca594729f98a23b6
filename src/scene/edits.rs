//! Edits of a loaded scene, stored relative to it as loaded: material overrides by index,
//! light scale/colour/placement and the camera orbit. The settings sidecar
//! (`render::settings::ViewerSettings`) holds them; the viewer and `refract render --settings`
//! apply them through the same functions, so both render the same scene.

use super::{Camera, Material, MaterialKind, Scene};
use crate::bsdf::MicrofacetDistribution;
use crate::math::color::{blackbody_rgb, luminance};
use glam::{Quat, Vec3};
use serde::{Deserialize, Serialize};

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

    /// Refuse values that break energy conservation or the arithmetic, naming the field:
    /// IOR finite in 1e-3..=1e3 (the bound keeps η and 1/η far from f32 overflow; any real
    /// material is 1..4), base and absorption colour components finite in 0..=1 (an albedo
    /// above 1 creates energy), metallic and roughness in 0..=1, a positive absorption
    /// distance and an Abbe number ≥ 1. `refract render --settings` calls it on every sidecar edit.
    pub fn check(&self) -> anyhow::Result<()> {
        use anyhow::ensure;
        let unit = |c: [f32; 3]| c.iter().all(|v| (0.0..=1.0).contains(v));
        ensure!(
            (1e-3..=1e3).contains(&self.ior),
            "ior {} is out of range (finite, 1e-3..=1e3)",
            self.ior
        );
        ensure!(
            unit(self.base_color),
            "base_color {:?} is out of range (each component in 0..=1: an albedo above 1 \
             creates energy)",
            self.base_color
        );
        ensure!(
            unit(self.attenuation_color),
            "attenuation_color {:?} is out of range (each component in 0..=1)",
            self.attenuation_color
        );
        for (key, v) in [("metallic", self.metallic), ("roughness", self.roughness)] {
            ensure!(
                (0.0..=1.0).contains(&v),
                "{key} {v} is out of range (0..=1)"
            );
        }
        if let Some(v) = self.attenuation_distance {
            ensure!(
                v.is_finite() && v > 0.0,
                "attenuation_distance {v} must be finite and > 0"
            );
        }
        if let Some(v) = self.abbe {
            // As the glTF loader clamps dispersion: V_d ≥ 1 keeps the Cauchy fit positive.
            ensure!(v.is_finite() && v >= 1.0, "abbe {v} must be finite and ≥ 1");
        }
        Ok(())
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
    /// White light or one spectral line for every emitter (`RenderSettings::light_line_nm`).
    pub spectrum: LightSpectrum,
}

/// The scene-wide light spectrum the viewer (or a sidecar) asks for.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LightSpectrum {
    /// As the scene file says (`extras.render.light_line_nm`, white when missing).
    #[default]
    AsLoaded,
    /// White: every emitter's RGB uplifted over 360–830 nm.
    White,
    /// Every emitter radiates only at this wavelength (nm).
    Line(f32),
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
            spectrum: LightSpectrum::AsLoaded,
        }
    }
}

impl LightEdit {
    /// Refuse values [`LightEdit::tint`] and [`LightEdit::apply`] would silently replace or
    /// that make no light (negative, NaN, infinite), naming the field. `refract render
    /// --settings` calls it; the viewer keeps sanitising them.
    pub fn check(&self) -> anyhow::Result<()> {
        use anyhow::ensure;
        let ok = |v: f32| v.is_finite() && v >= 0.0;
        ensure!(
            ok(self.intensity),
            "intensity {} must be finite and ≥ 0",
            self.intensity
        );
        ensure!(
            self.color.iter().all(|&c| ok(c)),
            "color {:?} must be finite and ≥ 0",
            self.color
        );
        for (key, v) in [
            ("temperature_k", self.temperature_k),
            ("environment", self.environment),
            ("size", Some(self.size)),
        ] {
            if let Some(v) = v {
                ensure!(ok(v), "{key} {v} must be finite and ≥ 0");
            }
        }
        for (key, v) in [
            ("elevation_deg", self.elevation_deg),
            ("azimuth_deg", self.azimuth_deg),
        ] {
            if let Some(v) = v {
                ensure!(v.is_finite(), "{key} {v} must be finite");
            }
        }
        if let LightSpectrum::Line(nm) = self.spectrum {
            crate::math::spectrum::check_light_line(nm, "spectrum.line")
                .map_err(anyhow::Error::msg)?;
        }
        Ok(())
    }

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

    /// Write the light edits into `scene`, a copy of `base` (as loaded) with other edits.
    pub fn apply(&self, base: &Scene, scene: &mut Scene) {
        scene.settings.light_line_nm = self.light_line(base);
        tint_lights(self.tint(), base, scene);
        self.apply_environment(base, scene);
        let size = self.size_factor();
        let moved = self.elevation_deg.is_some() || self.azimuth_deg.is_some();
        if size == 1.0 && !moved {
            return;
        }
        let Some(main) = MainLight::find(base) else {
            return;
        };
        let rot = if moved {
            self.rotation(&main)
        } else {
            Quat::IDENTITY
        };
        place_main_light(base, scene, &main, size, rot);
    }

    /// The light line (nm) the edit asks for, `base`'s when it keeps the loaded one.
    fn light_line(&self, base: &Scene) -> Option<f32> {
        match self.spectrum {
            LightSpectrum::AsLoaded => base.settings.light_line_nm,
            LightSpectrum::White => None,
            // The viewer keeps sanitising: an impossible wavelength is clamped into range.
            LightSpectrum::Line(nm) if nm.is_finite() => Some(nm.clamp(
                crate::math::spectrum::LIGHT_LINE_MIN_NM,
                crate::math::spectrum::LIGHT_LINE_MAX_NM,
            )),
            LightSpectrum::Line(_) => base.settings.light_line_nm,
        }
    }

    /// Scale the environment to the edited luminance (a finite, non-negative one), keeping
    /// `base`'s colour.
    fn apply_environment(&self, base: &Scene, scene: &mut Scene) {
        if let Some(env) = self.environment.filter(|e| e.is_finite() && *e >= 0.0) {
            let lum = luminance(base.environment);
            scene.environment = if lum > 0.0 {
                base.environment / lum * env
            } else {
                Vec3::splat(env)
            };
        }
    }

    /// The main light's size factor, clamped to 0.01..=100 (1 when not finite).
    fn size_factor(&self) -> f32 {
        if self.size.is_finite() {
            self.size.clamp(0.01, 100.0)
        } else {
            1.0
        }
    }

    /// The rotation about the scene centre that moves `main` to the edited elevation and
    /// azimuth (those not edited keep the light's own); identity when not finite.
    fn rotation(&self, main: &MainLight) -> Quat {
        let el = self
            .elevation_deg
            .unwrap_or(main.elevation_deg)
            .to_radians();
        let az = self.azimuth_deg.unwrap_or(main.azimuth_deg).to_radians();
        let d0 = (main.centroid - main.centre).normalize_or(Vec3::Y);
        let d1 = Vec3::new(el.cos() * az.sin(), el.sin(), el.cos() * az.cos());
        if d1.is_finite() {
            Quat::from_rotation_arc(d0, d1.normalize_or(d0))
        } else {
            Quat::IDENTITY
        }
    }
}

/// Multiply every emissive material's and punctual light's emission in `base` by `tint`
/// into `scene`.
fn tint_lights(tint: Vec3, base: &Scene, scene: &mut Scene) {
    for (m, b) in scene.materials.iter_mut().zip(&base.materials) {
        if b.is_emissive() {
            m.emission = b.emission * tint;
        }
    }
    for p in &mut scene.punctual_lights {
        use super::PunctualLight as P;
        match p {
            P::Point { intensity, .. } | P::Spot { intensity, .. } => *intensity *= tint,
            P::Directional { irradiance, .. } => *irradiance *= tint,
        }
    }
}

/// Scale `main`'s vertices (from `base`) by `size` about its centroid and rotate them by
/// `rot` about the scene centre, normals with them, into `scene`.
fn place_main_light(base: &Scene, scene: &mut Scene, main: &MainLight, size: f32, rot: Quat) {
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

impl CameraEdit {
    /// The camera: the scene's, or the edited orbit, with the edited field of view.
    pub fn camera(&self, base: &Scene) -> Camera {
        let yfov = self
            .yfov_deg
            .filter(|f| f.is_finite())
            .map(|f| f.clamp(1.0, 170.0).to_radians())
            .unwrap_or(base.camera.yfov);
        match self.orbit {
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
    pub fn orbit(&self, base: &Scene) -> Orbit {
        self.orbit.unwrap_or_else(|| {
            let (lo, hi) = base.bounds();
            Orbit::from_camera(&base.camera, 0.5 * (lo + hi), 0.5 * (hi - lo).length())
        })
    }
}

/// Write material overrides into `scene`; an edit that does not fit (no such material, a
/// value [`MaterialEdit::check`] refuses, or an invalid result) is skipped with a warning.
pub fn apply_materials(edits: &[MaterialEdit], scene: &mut Scene, warnings: &mut Vec<String>) {
    for e in edits {
        match scene.materials.get_mut(e.index) {
            Some(m) => {
                if m.name != e.name {
                    warnings.push(format!(
                        "material {} is '{}' here but '{}' in the settings; applied anyway",
                        e.index, m.name, e.name
                    ));
                }
                if let Err(err) = e.check() {
                    warnings.push(format!("material edit {} skipped: {err}", e.index));
                    continue;
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orbit_reproduces_the_scene_camera() {
        let scene = crate::scene::builtin::cornell_glass();
        let o = CameraEdit::default().orbit(&scene);
        let cam = o.camera(scene.camera.yfov);
        assert!((cam.position - scene.camera.position).length() < 1e-4);
        assert!((cam.forward() - scene.camera.forward()).length() < 1e-4);
    }

    #[test]
    fn edits_that_break_energy_are_skipped_with_a_warning() {
        let mut scene = crate::scene::builtin::cornell_glass();
        let before = scene.materials.clone();
        let mut ior = MaterialEdit::from_material(0, &scene.materials[0]);
        ior.ior = 1e-30;
        let mut albedo = MaterialEdit::from_material(0, &scene.materials[0]);
        albedo.base_color = [1e30; 3];
        let mut warnings = Vec::new();
        apply_materials(&[ior, albedo], &mut scene, &mut warnings);
        assert_eq!(scene.materials, before);
        assert_eq!(warnings.len(), 2, "{warnings:?}");
        assert!(warnings[0].contains("ior"), "{}", warnings[0]);
        assert!(warnings[1].contains("base_color"), "{}", warnings[1]);
    }
}
