//! glTF materials → scene materials (the kind decision of the scene contract).

use super::extras::extras_value;
use super::{GLASS_TRANSMISSION_THRESHOLD, Loader, Warnings};
use crate::bsdf::{Metal, MicrofacetDistribution};
use crate::scene::{Material, MaterialKind, TextureRef};
use glam::Vec3;
use gltf::json;
use gltf::json::validation::Checked;
use serde_json::Value;

/// The largest emitted radiance a material may have (far above any real light; beyond ~1e36
/// the light distribution's power sums overflow f32).
const MAX_EMISSION: f32 = 1e20;
/// The largest IOR accepted (as for a sidecar's IOR edit; the densest real glass is ≈ 2.4 and
/// far larger values only break the Fresnel arithmetic).
const MAX_IOR: f32 = 1e3;
/// The largest `KHR_materials_dispersion.dispersion` (20 / V_d) kept: V_d ≥ 1, where the
/// Cauchy fit stays positive over the visible range for any IOR up to 3.
const MAX_DISPERSION: f64 = 20.0;

/// `KHR_materials_volume` as the scene contract uses it.
struct Volume {
    thickness: f32,
    attenuation_color: Vec3,
    attenuation_distance: f32,
}

/// The textures of one material (None where it has none or one failed to load).
struct MaterialTextures {
    base_color: Option<TextureRef>,
    metallic_roughness: Option<TextureRef>,
    normal: Option<TextureRef>,
    normal_scale: f32,
    emissive: Option<TextureRef>,
    transmission: Option<TextureRef>,
}

/// A material's factors and extension values: everything but its textures and kind.
struct Factors {
    base_color: Vec3,
    metallic: f32,
    roughness: f32,
    transmission: f32,
    ior: f32,
    volume: Volume,
    emission: Vec3,
    specular_factor: f32,
    specular_color: Vec3,
    abbe: Option<f32>,
    distribution: MicrofacetDistribution,
    priority: i32,
    conductor: Option<Metal>,
}

/// The scene material named `name` of kind `kind` from its factors `f` and textures `tex`.
fn assemble(
    name: String,
    kind: MaterialKind,
    double_sided: bool,
    f: Factors,
    tex: MaterialTextures,
) -> Material {
    Material {
        name,
        kind,
        base_color: f.base_color,
        base_color_texture: tex.base_color,
        metallic: f.metallic,
        roughness: f.roughness,
        metallic_roughness_texture: tex.metallic_roughness,
        normal_texture: tex.normal,
        normal_scale: tex.normal_scale,
        ior: f.ior,
        abbe: f.abbe,
        distribution: f.distribution,
        emission: f.emission,
        emissive_texture: tex.emissive,
        double_sided,
        attenuation_color: f.volume.attenuation_color,
        attenuation_distance: f.volume.attenuation_distance,
        transmission_factor: f.transmission,
        transmission_texture: tex.transmission,
        specular_factor: f.specular_factor,
        specular_color: f.specular_color,
        priority: f.priority,
        conductor: f.conductor,
    }
}

/// `KHR_materials_specular`: (specularFactor, specularColorFactor), (1, white) without it.
fn specular(ext: Option<&json::extensions::material::Material>) -> (f32, Vec3) {
    let spec = ext.and_then(|e| e.specular.as_ref());
    let factor = spec.map(|s| s.specular_factor.0).unwrap_or(1.0);
    let color = spec
        .map(|s| Vec3::from(s.specular_color_factor.0))
        .unwrap_or(Vec3::ONE);
    (factor, color)
}

impl Loader<'_> {
    pub(super) fn material_for(&mut self, index: Option<usize>) -> Result<u32, String> {
        match index {
            Some(i) => self
                .material_map
                .get(i)
                .copied()
                .ok_or_else(|| format!("material {i} does not exist (index out of range)")),
            None => {
                if let Some(d) = self.default_material {
                    return Ok(d);
                }
                // glTF default material: base colour 1, metallic 1, roughness 1.
                let m = self
                    .convert_material(usize::MAX, &json::Material::default())
                    .map_err(|e| format!("{e:#}"))?;
                let id = self.materials.len() as u32;
                self.materials.push(Material {
                    name: "default".into(),
                    ..m
                });
                self.default_material = Some(id);
                Ok(id)
            }
        }
    }

    /// Convert glTF material `i` (`usize::MAX`: the default material) to a scene material.
    pub(super) fn convert_material(
        &mut self,
        i: usize,
        m: &json::Material,
    ) -> anyhow::Result<Material> {
        let name = m.name.clone().unwrap_or_else(|| format!("material{i}"));
        let f = self.material_factors(i, m, &name)?;
        let tex = self.material_textures(m, f.emission, f.transmission, &name)?;
        let kind = self.material_kind(
            &name,
            f.transmission,
            f.volume.thickness,
            (f.metallic, f.roughness),
            tex.metallic_roughness.is_some(),
        );
        let mut mat = assemble(name, kind, m.double_sided, f, tex);
        enforce_contract(&mut mat)?;
        Ok(mat)
    }

    /// Every factor and extension value of material `i` (named `name`), read and checked in
    /// the contract's order (which fixes the order of its warnings).
    fn material_factors(
        &mut self,
        i: usize,
        m: &json::Material,
        name: &str,
    ) -> anyhow::Result<Factors> {
        let (base_color, metallic, roughness) = self.pbr_factors(&m.pbr_metallic_roughness, name);
        let ext = m.extensions.as_ref();
        let transmission = self.transmission_factor(ext, name);
        let ior = self.ior(ext, name, i)?;
        let volume = self.volume(ext, name);
        let emission = self.emission(m, ext, name, i)?;
        let (specular_factor, specular_color) = specular(ext);
        self.warn_ignored_features(m, ext, name);
        Ok(Factors {
            base_color,
            metallic,
            roughness,
            transmission,
            ior,
            volume,
            emission,
            specular_factor,
            specular_color,
            abbe: self.dispersion_abbe(ext, name),
            distribution: self.microfacet_distribution(m, name, i)?,
            priority: self.priority(m, name, i)?,
            conductor: conductor(m, name, i)?,
        })
    }

    /// `KHR_materials_transmission.transmissionFactor` (0 without the extension), clamped to
    /// [0, 1] with a warning.
    fn transmission_factor(
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

    /// Every texture of material `m`, loaded in the order the contract reads them (base
    /// colour, metallic-roughness, normal, emissive, transmission).
    fn material_textures(
        &mut self,
        m: &json::Material,
        emission: Vec3,
        transmission: f32,
        name: &str,
    ) -> anyhow::Result<MaterialTextures> {
        let pbr = &m.pbr_metallic_roughness;
        let base_color = match &pbr.base_color_texture {
            Some(t) => self.texture_ref(t, true, name)?,
            None => None,
        };
        let metallic_roughness = match &pbr.metallic_roughness_texture {
            Some(t) => self.texture_ref(t, false, name)?,
            None => None,
        };
        let (normal, normal_scale) = self.normal_texture(m, name)?;
        let emissive = self.emissive_texture(m, emission, name)?;
        let transmission = self.transmission_texture(m.extensions.as_ref(), transmission, name)?;
        Ok(MaterialTextures {
            base_color,
            metallic_roughness,
            normal,
            normal_scale,
            emissive,
            transmission,
        })
    }

    /// `KHR_materials_transmission.transmissionTexture` (linear, red channel): per texel,
    /// factor × texel at or above the glass threshold is glass, below it the opaque base
    /// (`Material::transmits_at`). A factor below the threshold leaves nothing to mask (a
    /// warning); texels strictly between 0 and 1 are thresholded like the factor (a warning:
    /// glTF would mix glass and base there).
    fn transmission_texture(
        &mut self,
        ext: Option<&json::extensions::material::Material>,
        factor: f32,
        name: &str,
    ) -> anyhow::Result<Option<crate::scene::TextureRef>> {
        let Some(info) = ext
            .and_then(|e| e.transmission.as_ref())
            .and_then(|t| t.transmission_texture.as_ref())
        else {
            return Ok(None);
        };
        if factor < GLASS_TRANSMISSION_THRESHOLD {
            self.warnings.push(format!(
                "material '{name}': transmissionTexture has no effect: transmissionFactor \
                 {factor} < {GLASS_TRANSMISSION_THRESHOLD} makes the surface opaque everywhere \
                 (factor × texel decides glass per texel)"
            ));
            return Ok(None);
        }
        let r = self.texture_ref(info, false, name)?;
        if let Some(r) = r {
            let partial = self.textures[r.texture as usize].texels.iter().any(|t| {
                let v = factor * t.x;
                v > 0.02 && v < 0.98
            });
            if partial {
                self.warnings.push(format!(
                    "material '{name}': transmissionTexture has texels between 0 and 1; each \
                     point is glass where factor × texel ≥ {GLASS_TRANSMISSION_THRESHOLD}, the \
                     opaque base elsewhere (a partial mix of the two is not rendered)"
                ));
            }
        }
        Ok(r)
    }

    /// `normalTexture` (linear, not sRGB) and its `scale` (1 when absent; a non-finite scale
    /// is replaced by 1 with a warning).
    fn normal_texture(
        &mut self,
        m: &json::Material,
        name: &str,
    ) -> anyhow::Result<(Option<crate::scene::TextureRef>, f32)> {
        let Some(nt) = &m.normal_texture else {
            return Ok((None, 1.0));
        };
        let mut scale = nt.scale;
        if !scale.is_finite() {
            self.warnings.push(format!(
                "material '{name}': normalTexture.scale {scale} is not finite; using 1"
            ));
            scale = 1.0;
        }
        // The normal texture's index, texCoord and KHR_texture_transform, as a texture info.
        let info = json::texture::Info {
            index: nt.index,
            tex_coord: nt.tex_coord,
            // gltf-json keeps a normal texture's extensions as raw JSON.
            extensions: nt
                .extensions
                .as_ref()
                .and_then(|e| e.others.get("KHR_texture_transform"))
                .and_then(|v| serde_json::from_value(v.clone()).ok())
                .map(|tt| json::extensions::texture::Info {
                    texture_transform: Some(tt),
                    others: Default::default(),
                }),
            extras: Default::default(),
        };
        Ok((self.texture_ref(&info, false, name)?, scale))
    }

    /// `emissiveTexture` (sRGB, like base colour), loaded only when the material emits: glTF
    /// multiplies it by `emissiveFactor` (default 0), so a texture without a factor emits
    /// nothing (a warning says so).
    fn emissive_texture(
        &mut self,
        m: &json::Material,
        emission: Vec3,
        name: &str,
    ) -> anyhow::Result<Option<crate::scene::TextureRef>> {
        let Some(info) = &m.emissive_texture else {
            return Ok(None);
        };
        if emission.max_element() <= 0.0 {
            self.warnings.push(format!(
                "material '{name}': emissiveTexture with emissiveFactor 0 emits nothing \
                 (glTF multiplies the two)"
            ));
            return Ok(None);
        }
        self.texture_ref(info, true, name)
    }

    /// Base colour, metallic and roughness factors (invalid ones replaced, with a warning).
    fn pbr_factors(
        &mut self,
        pbr: &json::material::PbrMetallicRoughness,
        name: &str,
    ) -> (Vec3, f32, f32) {
        let bc = pbr.base_color_factor.0;
        let mut base_color = Vec3::new(bc[0], bc[1], bc[2]);
        if !(base_color.is_finite() && base_color.min_element() >= 0.0) {
            self.warnings.push(format!(
                "material '{name}': invalid baseColorFactor; using white"
            ));
            base_color = Vec3::ONE;
        } else if base_color.max_element() > 1.0 {
            // An albedo above 1 reflects more light than arrives (glTF: factors in [0, 1]).
            self.warnings.push(format!(
                "material '{name}': baseColorFactor {base_color} has a component above 1 (an \
                 albedo above 1 creates energy); clamped to [0, 1]"
            ));
            base_color = base_color.min(Vec3::ONE);
        }
        let metallic = clamp01(
            pbr.metallic_factor.0,
            name,
            "metallicFactor",
            &mut self.warnings,
        );
        let roughness = clamp01(
            pbr.roughness_factor.0,
            name,
            "roughnessFactor",
            &mut self.warnings,
        );
        (base_color, metallic, roughness)
    }

    /// `KHR_materials_ior` (1.5 when absent). Not a positive finite number: an error naming the
    /// JSON pointer (README: invalid IOR is an error); between 0 and 1 (no real dielectric
    /// against air): a warning, and 1.5.
    fn ior(
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
    fn volume(&mut self, ext: Option<&json::extensions::material::Material>, name: &str) -> Volume {
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

    /// `emissiveFactor` × `KHR_materials_emissive_strength` (zero when invalid).
    fn emission(
        &mut self,
        m: &json::Material,
        ext: Option<&json::extensions::material::Material>,
        name: &str,
        i: usize,
    ) -> anyhow::Result<Vec3> {
        let strength = ext
            .and_then(|e| e.emissive_strength.as_ref())
            .map(|s| s.emissive_strength.0)
            .unwrap_or(1.0);
        let mut emission = Vec3::from(m.emissive_factor.0) * strength;
        if !(emission.is_finite() && emission.min_element() >= 0.0) {
            self.warnings.push(format!(
                "material '{name}': emissiveFactor × emissiveStrength = {emission} is negative \
                 or not finite; emission ignored"
            ));
            emission = Vec3::ZERO;
        }
        // Radiance this large overflows f32 in the light's power (π·L·A) and the image: the
        // light would silently render black.
        anyhow::ensure!(
            emission.max_element() <= MAX_EMISSION,
            "material {i} ('{name}'): emission {} (/materials/{i}/emissiveFactor × \
             KHR_materials_emissive_strength) is above {MAX_EMISSION:e}, where f32 light \
             power overflows",
            emission.max_element()
        );
        Ok(emission)
    }

    /// One warning each for the material features the contract ignores.
    fn warn_ignored_features(
        &mut self,
        m: &json::Material,
        ext: Option<&json::extensions::material::Material>,
        name: &str,
    ) {
        let spec = ext.and_then(|e| e.specular.as_ref());
        if spec.is_some_and(|s| s.specular_texture.is_some() || s.specular_color_texture.is_some())
        {
            self.warnings.once("specular-tex", || {
                "KHR_materials_specular textures are ignored".into()
            });
        }
        if m.occlusion_texture.is_some() {
            self.warnings.once("occlusion-tex", || {
                "occlusion textures are ignored: a path tracer computes occlusion itself".into()
            });
        }
        if ext
            .and_then(|e| e.volume.as_ref())
            .is_some_and(|v| v.thickness_texture.is_some())
        {
            self.warnings.push(format!(
                "material '{name}': KHR_materials_volume.thicknessTexture is ignored: a path \
                 tracer measures thickness from the geometry, so only thicknessFactor > 0 \
                 (solid) or 0 (thin-walled) is used"
            ));
        }
        if !matches!(
            m.alpha_mode,
            Checked::Valid(json::material::AlphaMode::Opaque)
        ) {
            self.warnings.once("alpha", || {
                "alpha modes MASK/BLEND are ignored (treated as opaque)".into()
            });
        }
    }

    /// KHR_materials_dispersion from the raw extension JSON: the Abbe number (None = none).
    fn dispersion_abbe(
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

    /// `extras.microfacet_distribution`: "ggx" (default) or "beckmann".
    fn microfacet_distribution(
        &mut self,
        m: &json::Material,
        name: &str,
        i: usize,
    ) -> anyhow::Result<MicrofacetDistribution> {
        let mut distribution = MicrofacetDistribution::Ggx;
        if let Some(x) = extras_value(&m.extras, &format!("/materials/{i}/extras"))? {
            match x.get("microfacet_distribution") {
                None => {}
                Some(Value::String(s)) if s.eq_ignore_ascii_case("ggx") => {}
                Some(Value::String(s)) if s.eq_ignore_ascii_case("beckmann") => {
                    distribution = MicrofacetDistribution::Beckmann
                }
                Some(v) => self.warnings.push(format!(
                    "material '{name}': microfacet_distribution {v} is not \"ggx\" or \"beckmann\"; using GGX"
                )),
            }
        }
        Ok(distribution)
    }

    /// `extras.priority`: an integer (nested dielectrics: where closed volumes overlap, the
    /// higher priority is the medium; Schmidt & Budge 2002). Default 0; anything else is
    /// replaced by 0 with a warning.
    fn priority(&mut self, m: &json::Material, name: &str, i: usize) -> anyhow::Result<i32> {
        let Some(x) = extras_value(&m.extras, &format!("/materials/{i}/extras"))? else {
            return Ok(0);
        };
        let Some(v) = x.get("priority") else {
            return Ok(0);
        };
        match v.as_i64().and_then(|p| i32::try_from(p).ok()) {
            Some(p) => Ok(p),
            None => {
                self.warnings.push(format!(
                    "material '{name}': extras.priority {v} is not a 32-bit integer; using 0"
                ));
                Ok(0)
            }
        }
    }

    /// The contract's material kind from transmission, volume thickness and the
    /// metallic-roughness factors or texture.
    fn material_kind(
        &mut self,
        name: &str,
        transmission: f32,
        thickness: f32,
        (metallic, roughness): (f32, f32),
        has_mr_tex: bool,
    ) -> MaterialKind {
        let eps = 1e-6;
        if transmission >= GLASS_TRANSMISSION_THRESHOLD {
            if thickness > 0.0 {
                MaterialKind::Glass
            } else {
                self.warnings.once("thin-glass", || {
                    format!(
                        "material '{name}' is thin-walled glass (transmission without KHR_materials_volume, as Blender exports glass): rendered as a thin sheet; switch it to solid glass in the viewer if the object is a solid"
                    )
                });
                MaterialKind::ThinGlass
            }
        } else {
            if transmission > 0.0 {
                self.warnings.push(format!(
                    "material '{name}': partial transmission {transmission} (< {GLASS_TRANSMISSION_THRESHOLD}) is ignored; treated as opaque"
                ));
            }
            if has_mr_tex {
                MaterialKind::MetalRough
            } else if (metallic - 1.0).abs() <= eps && roughness <= eps {
                MaterialKind::Mirror
            } else if (metallic - 1.0).abs() <= eps {
                MaterialKind::GlossyMetal
            } else if metallic <= eps && (roughness - 1.0).abs() <= eps && transmission == 0.0 {
                MaterialKind::Diffuse
            } else {
                MaterialKind::MetalRough
            }
        }
    }
}

/// `extras.conductor`: "Au", "Ag", "Cu" or "Al" (a tabulated metal); anything else is an
/// error naming the material and the value.
fn conductor(m: &json::Material, name: &str, i: usize) -> anyhow::Result<Option<Metal>> {
    let Some(x) = extras_value(&m.extras, &format!("/materials/{i}/extras"))? else {
        return Ok(None);
    };
    let known = || Metal::ALL.map(|m| format!("\"{}\"", m.symbol())).join(", ");
    match x.get("conductor") {
        None | Some(Value::Null) => Ok(None),
        Some(Value::String(s)) => Metal::from_symbol(s).map(Some).ok_or_else(|| {
            anyhow::anyhow!(
                "material '{name}': extras.conductor \"{s}\" is not a known metal (known: {})",
                known()
            )
        }),
        Some(v) => anyhow::bail!(
            "material '{name}': extras.conductor must be a string (one of {}), got {v}",
            known()
        ),
    }
}

fn clamp01(x: f32, mat: &str, what: &str, w: &mut Warnings) -> f32 {
    if (0.0..=1.0).contains(&x) {
        x
    } else {
        w.push(format!("material '{mat}': {what} {x} clamped to [0, 1]"));
        if x.is_nan() { 0.0 } else { x.clamp(0.0, 1.0) }
    }
}

/// The scene contract's rules on a converted material: `extras.conductor` needs a metal (an
/// error naming the material); an emitter's surface is otherwise black (its textures
/// dropped).
fn enforce_contract(mat: &mut Material) -> anyhow::Result<()> {
    if mat.conductor.is_some() && !mat.is_metal_kind() {
        anyhow::bail!(
            "material '{}': extras.conductor needs a metallic material (metallicFactor 1, no metallic-roughness texture, no transmission)",
            mat.name
        );
    }
    if mat.is_emissive() {
        mat.kind = MaterialKind::Diffuse;
        mat.base_color = Vec3::ZERO;
        mat.base_color_texture = None;
        mat.metallic_roughness_texture = None;
        mat.normal_texture = None;
        mat.transmission_texture = None;
    }
    Ok(())
}
