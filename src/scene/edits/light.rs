//! Light edits: [`LightEdit`] (scale, colour, spectrum, environment and the main light's size
//! and placement) and the [`LightSpectrum`] it asks for, with the helpers that apply them.

use super::MainLight;
use crate::math::color::{blackbody_rgb, luminance};
use crate::scene::Scene;
use glam::{Quat, Vec3};
use serde::{Deserialize, Serialize};

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
        use crate::scene::PunctualLight as P;
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
