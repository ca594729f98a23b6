//! A material's texture references: base colour, metallic-roughness, normal, emissive and
//! transmission (with the checks that decide whether each is used).

use crate::gltf_io::load::{GLASS_TRANSMISSION_THRESHOLD, Loader};
use crate::scene::TextureRef;
use glam::Vec3;
use gltf::json;

/// The textures of one material (None where it has none or one failed to load).
pub(super) struct MaterialTextures {
    pub(super) base_color: Option<TextureRef>,
    pub(super) metallic_roughness: Option<TextureRef>,
    pub(super) normal: Option<TextureRef>,
    pub(super) normal_scale: f32,
    pub(super) emissive: Option<TextureRef>,
    pub(super) transmission: Option<TextureRef>,
}

impl Loader<'_> {
    /// Every texture of material `m`, loaded in the order the contract reads them (base
    /// colour, metallic-roughness, normal, emissive, transmission).
    pub(super) fn material_textures(
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
}
