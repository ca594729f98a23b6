//! The KHR_materials_* extensions a material's factors come from: transmission, IOR,
//! volume, specular, dispersion and iridescence (each read and checked, with warnings).

use super::clamp01;
use crate::gltf_io::load::Loader;
use crate::scene::{Iridescence, TextureRef};
use glam::Vec3;
use gltf::json;

/// The largest IOR accepted (as for a sidecar's IOR edit; the densest real glass is ≈ 2.4 and
/// far larger values only break the Fresnel arithmetic).
const MAX_IOR: f32 = 1e3;
/// The largest `KHR_materials_dispersion.dispersion` (20 / V_d) kept: V_d ≥ 1, where the
/// Cauchy fit stays positive over the visible range for any IOR up to 3.
const MAX_DISPERSION: f64 = 20.0;

/// `KHR_materials_volume` as the scene contract uses it.
pub(super) struct Volume {
    pub(super) thickness: f32,
    pub(super) attenuation_color: Vec3,
    pub(super) attenuation_distance: f32,
}

/// `KHR_materials_specular`: (specularFactor, specularColorFactor), (1, white) without it.
pub(super) fn specular(ext: Option<&json::extensions::material::Material>) -> (f32, Vec3) {
    let spec = ext.and_then(|e| e.specular.as_ref());
    let factor = spec.map(|s| s.specular_factor.0).unwrap_or(1.0);
    let color = spec
        .map(|s| Vec3::from(s.specular_color_factor.0))
        .unwrap_or(Vec3::ONE);
    (factor, color)
}

impl Loader<'_> {
    /// `KHR_materials_transmission.transmissionFactor` (0 without the extension), clamped to
    /// [0, 1] with a warning.
    pub(super) fn transmission_factor(
        &mut self,
        ext: Option<&json::extensions::material::Material>,
        name: &str,
    ) -> f32 {
        let transmission = ext
            .and_then(|e| e.transmission.as_ref())
            .map(|t| t.transmission_factor.0)
            .unwrap_or(0.0);
        clamp01(transmission, name, "transmissionFactor", &mut self.warnings)
    }

    /// `KHR_materials_ior` (1.5 when absent). Not a positive finite number: an error naming the
    /// JSON pointer (docs/scene-contract.md: invalid IOR is an error); between 0 and 1 (no real dielectric
    /// against air): a warning, and 1.5.
    pub(super) fn ior(
        &mut self,
        ext: Option<&json::extensions::material::Material>,
        name: &str,
        i: usize,
    ) -> anyhow::Result<f32> {
        let ior = ext
            .and_then(|e| e.ior.as_ref())
            .map(|i| i.ior.0)
            .unwrap_or(1.5);
        anyhow::ensure!(
            ior.is_finite() && ior > 0.0 && ior <= MAX_IOR,
            "material {i} ('{name}'): /materials/{i}/extensions/KHR_materials_ior/ior is {ior}; \
             an index of refraction must be a positive finite number, at most {MAX_IOR}"
        );
        if ior < 1.0 {
            self.warnings.push(format!(
                "material '{name}': IOR {ior} is not ≥ 1; using 1.5"
            ));
            return Ok(1.5);
        }
        Ok(ior)
    }

    /// `KHR_materials_volume` (no attenuation when absent or invalid).
    pub(super) fn volume(
        &mut self,
        ext: Option<&json::extensions::material::Material>,
        name: &str,
    ) -> Volume {
        let volume = ext.and_then(|e| e.volume.as_ref());
        let mut thickness = volume.map(|v| v.thickness_factor.0).unwrap_or(0.0);
        if thickness.is_nan() || thickness < 0.0 {
            self.warnings.push(format!(
                "material '{name}': KHR_materials_volume thicknessFactor {thickness} is not a \
                 non-negative number; using 0 (thin-walled)"
            ));
            thickness = 0.0;
        }
        let mut attenuation_color = volume
            .map(|v| Vec3::from(v.attenuation_color.0))
            .unwrap_or(Vec3::ONE);
        let mut attenuation_distance = volume
            .map(|v| v.attenuation_distance.0)
            .unwrap_or(f32::INFINITY);
        if attenuation_distance.is_nan() || attenuation_distance <= 0.0 {
            self.warnings.push(format!(
                "material '{name}': KHR_materials_volume attenuationDistance \
                 {attenuation_distance} must be positive; attenuation ignored"
            ));
            attenuation_color = Vec3::ONE;
            attenuation_distance = f32::INFINITY;
        }
        if !(attenuation_color.is_finite() && attenuation_color.min_element() >= 0.0) {
            self.warnings.push(format!(
                "material '{name}': KHR_materials_volume attenuationColor {attenuation_color} \
                 must be finite and non-negative; attenuation ignored"
            ));
            attenuation_color = Vec3::ONE;
            attenuation_distance = f32::INFINITY;
        } else if attenuation_color.max_element() > 1.0 {
            self.warnings.push(format!(
                "material '{name}': KHR_materials_volume attenuationColor {attenuation_color} \
                 above 1 would amplify light; clamped to [0, 1]"
            ));
            attenuation_color = attenuation_color.min(Vec3::ONE);
        }
        Volume {
            thickness,
            attenuation_color,
            attenuation_distance,
        }
    }

    /// KHR_materials_dispersion from the raw extension JSON: the Abbe number (None = none).
    pub(super) fn dispersion_abbe(
        &mut self,
        ext: Option<&json::extensions::material::Material>,
        name: &str,
    ) -> Option<f32> {
        let mut abbe = None;
        if let Some(d) = ext.and_then(|e| e.others.get("KHR_materials_dispersion")) {
            match d.get("dispersion").map(|v| v.as_f64()) {
                None => {}
                Some(Some(x)) if x.is_finite() && x > MAX_DISPERSION => {
                    self.warnings.push(format!(
                        "material '{name}': KHR_materials_dispersion.dispersion {x} is above \
                         {MAX_DISPERSION} (Abbe number below 1); clamped to {MAX_DISPERSION}"
                    ));
                    abbe = Some((20.0 / MAX_DISPERSION) as f32);
                }
                Some(Some(x)) if x.is_finite() && x >= 0.0 => {
                    // dispersion 0 = none; otherwise V_d = 20 / dispersion.
                    abbe = (x > 0.0).then(|| (20.0 / x) as f32);
                }
                Some(_) => self.warnings.push(format!(
                    "material '{name}': KHR_materials_dispersion.dispersion must be a number ≥ 0; ignored"
                )),
            }
        }
        abbe
    }
}

/// The `KHR_materials_iridescence` extension name.
pub const IRIDESCENCE: &str = "KHR_materials_iridescence";

impl Loader<'_> {
    /// `KHR_materials_iridescence` from the raw extension JSON: the film (None without the
    /// extension or with `iridescenceFactor` 0, the extension's default). Invalid numbers are
    /// an error naming the material and the field; `iridescenceTexture` (a per-texel factor)
    /// is ignored with a warning, `iridescenceThicknessTexture` is read (green channel).
    pub(super) fn iridescence(
        &mut self,
        ext: Option<&json::extensions::material::Material>,
        name: &str,
        i: usize,
    ) -> anyhow::Result<Option<Iridescence>> {
        let Some(v) = ext.and_then(|e| e.others.get(IRIDESCENCE)) else {
            return Ok(None);
        };
        let path = format!("/materials/{i}/extensions/{IRIDESCENCE}");
        let d = Iridescence::default();
        let num = |key: &str, default: f32| -> anyhow::Result<f32> {
            match v.get(key) {
                None => Ok(default),
                Some(x) => x
                    .as_f64()
                    .map(|x| x as f32)
                    .filter(|x| x.is_finite())
                    .ok_or_else(|| {
                        anyhow::anyhow!("material '{name}': {path}/{key} is {x}, not a number")
                    }),
            }
        };
        let film = Iridescence {
            factor: num("iridescenceFactor", 0.0)?,
            ior: num("iridescenceIor", d.ior)?,
            thickness_min: num("iridescenceThicknessMinimum", d.thickness_min)?,
            thickness_max: num("iridescenceThicknessMaximum", d.thickness_max)?,
            thickness_texture: self.texture_info(v.get("iridescenceThicknessTexture"), name)?,
        };
        film.validate(name)
            .map_err(|e| anyhow::anyhow!("{e} ({path})"))?;
        if v.get("iridescenceTexture").is_some() {
            self.warnings.push(format!(
                "material '{name}': {IRIDESCENCE}.iridescenceTexture is ignored (the factor is \
                 uniform)"
            ));
        }
        Ok((film.factor > 0.0).then_some(film))
    }

    /// A textureInfo given as raw JSON (an extension the typed glTF crate does not know).
    fn texture_info(
        &mut self,
        v: Option<&serde_json::Value>,
        name: &str,
    ) -> anyhow::Result<Option<TextureRef>> {
        let Some(v) = v else { return Ok(None) };
        let info: json::texture::Info = serde_json::from_value(v.clone()).map_err(|e| {
            anyhow::anyhow!("material '{name}': {IRIDESCENCE} texture reference: {e}")
        })?;
        self.texture_ref(&info, false, name)
    }
}
