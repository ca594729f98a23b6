//! glTF materials → scene materials (the kind decision of the scene contract).

mod contract;
pub(super) mod extensions;
mod extras;
mod pbr;
mod textures;

use super::{Loader, Warnings};
use crate::bsdf::{Metal, MicrofacetDistribution};
use crate::scene::{Material, MaterialKind};
use contract::enforce_contract;
use extensions::{Volume, specular};
use extras::conductor;
use glam::Vec3;
use gltf::json;
use gltf::json::validation::Checked;
use textures::MaterialTextures;

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
    uniform_sampling: bool,
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
        uniform_sampling: f.uniform_sampling,
        iridescence: None,
    }
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
        mat.iridescence = self.iridescence(m.extensions.as_ref(), &mat.name, i)?;
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
            uniform_sampling: extras::uniform_sampling(m, name, i)?,
        })
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
}

fn clamp01(x: f32, mat: &str, what: &str, w: &mut Warnings) -> f32 {
    if (0.0..=1.0).contains(&x) {
        x
    } else {
        w.push(format!("material '{mat}': {what} {x} clamped to [0, 1]"));
        if x.is_nan() { 0.0 } else { x.clamp(0.0, 1.0) }
    }
}
