//! Textures: images from buffer views, `data:` or relative URIs, samplers and
//! `KHR_texture_transform`.

use super::{Loader, uri};
use crate::math::color::srgb_to_linear;
use crate::scene::{MAX_IMAGE_SIDE, Texture, TextureRef, Wrap};
use glam::{Affine2, Mat2, Vec2, Vec4};
use gltf::json;
use gltf::json::validation::Checked;

impl Loader<'_> {
    /// The texture `info` names, loaded once per (texture, colour space); None with a warning
    /// if it cannot be used; an error if it would exceed the texture-pixel budget.
    pub(super) fn texture_ref(
        &mut self,
        info: &json::texture::Info,
        srgb: bool,
        mat: &str,
    ) -> anyhow::Result<Option<TextureRef>> {
        let Some(tex) = self.cached_texture(info.index.value(), srgb, mat)? else {
            return Ok(None);
        };
        let (tex_coord, transform) = self.texture_transform(info, mat);
        if tex_coord != 0 {
            self.warnings.once("texcoord", || {
                "only TEXCOORD_0 is loaded; textures using other sets read TEXCOORD_0".into()
            });
        }
        Ok(Some(TextureRef {
            texture: tex,
            tex_coord,
            transform,
        }))
    }

    /// The slot of glTF texture `ti` in the scene's texture list, loading it on first use
    /// per (texture, colour space). None (remembered, with a warning) when it cannot be used;
    /// an error if it would exceed the texture-pixel budget.
    fn cached_texture(&mut self, ti: usize, srgb: bool, mat: &str) -> anyhow::Result<Option<u32>> {
        if let Some(t) = self.texture_cache.get(&(ti, srgb)) {
            return Ok(*t);
        }
        let t = match self.load_texture(ti, srgb) {
            Ok(t) => {
                self.textures.push(t);
                Some(self.textures.len() as u32 - 1)
            }
            Err(TextureError::OverBudget(e)) => anyhow::bail!("material '{mat}': {e}"),
            Err(TextureError::Unusable(e)) => {
                self.warnings.push(format!(
                    "material '{mat}': texture {ti} cannot be used ({e}); using no texture"
                ));
                None
            }
        };
        self.texture_cache.insert((ti, srgb), t);
        Ok(t)
    }

    /// The texture coordinate set and uv transform of `info`: its own `texCoord` and the
    /// identity, unless `KHR_texture_transform` overrides them (a non-finite transform is
    /// ignored with a warning; its `texCoord` override still applies).
    fn texture_transform(&mut self, info: &json::texture::Info, mat: &str) -> (u32, Affine2) {
        let mut tex_coord = info.tex_coord;
        let mut transform = Affine2::IDENTITY;
        if let Some(tt) = info
            .extensions
            .as_ref()
            .and_then(|e| e.texture_transform.as_ref())
        {
            // KHR_texture_transform: uv' = T · R · S · uv with
            // R = [[cos, sin], [−sin, cos]] (row-major, as in the extension spec).
            let (s, c) = tt.rotation.0.sin_cos();
            let rot = Mat2::from_cols(glam::Vec2::new(c, -s), glam::Vec2::new(s, c));
            let scale = Mat2::from_diagonal(Vec2::from(tt.scale.0));
            transform = Affine2::from_mat2_translation(rot * scale, Vec2::from(tt.offset.0));
            if let Some(tc) = tt.tex_coord {
                tex_coord = tc;
            }
            if !transform.is_finite() {
                self.warnings.push(format!(
                    "material '{mat}': non-finite KHR_texture_transform ignored"
                ));
                transform = Affine2::IDENTITY;
            }
        }
        (tex_coord, transform)
    }

    /// Load glTF texture `ti` (its image decoded, converted to linear when `srgb`, and its
    /// sampler's wrap and filter modes).
    fn load_texture(&mut self, ti: usize, srgb: bool) -> Result<Texture, TextureError> {
        let root = self.root;
        let t = root
            .textures
            .get(ti)
            .ok_or_else(|| "index out of range".to_string())?;
        let ii = t.source.value();
        let bytes = self.image_bytes(ii)?;
        let (w, h, texels) = self.decode_image(ii, &bytes, srgb)?;
        let (wrap_s, wrap_t, linear) = sampler_modes(root, t);
        Ok(Texture {
            width: w,
            height: h,
            texels,
            wrap_s,
            wrap_t,
            linear,
        })
    }

    /// The encoded bytes of image `ii`, from its buffer view or its URI.
    fn image_bytes(&self, ii: usize) -> Result<Vec<u8>, String> {
        let root = self.root;
        let img = root
            .images
            .get(ii)
            .ok_or_else(|| format!("image {ii} does not exist"))?;
        if let Some(vi) = img.buffer_view {
            let view = root
                .buffer_views
                .get(vi.value())
                .ok_or_else(|| format!("image {ii}: buffer view does not exist"))?;
            Ok(self.view_bytes(vi.value(), view)?.to_vec())
        } else if let Some(uri) = &img.uri {
            uri::image_bytes(uri, self.base, ii, &self.limits)
        } else {
            Err(format!("image {ii} has neither bufferView nor uri"))
        }
    }

    /// Decode image `ii` into linear RGBA texels (width, height, texels): its header size
    /// checked and charged against the texture-pixel budget before decoding.
    fn decode_image(
        &mut self,
        ii: usize,
        bytes: &[u8],
        srgb: bool,
    ) -> Result<(u32, u32, Vec<Vec4>), TextureError> {
        let (w, h) = image_size(bytes).map_err(|e| format!("image {ii}: {e}"))?;
        if w == 0 || h == 0 || w > MAX_IMAGE_SIDE || h > MAX_IMAGE_SIDE {
            return Err(format!("image {ii}: size {w}x{h} out of range").into());
        }
        self.charge_texels(ii, w, h)?;
        let dynimg = image::load_from_memory(bytes).map_err(|e| format!("image {ii}: {e}"))?;
        if (dynimg.width(), dynimg.height()) != (w, h) {
            return Err(format!("image {ii}: decoded size differs from its header").into());
        }
        let rgba = dynimg.to_rgba32f();
        let mut texels = Vec::new();
        texels.try_reserve_exact(rgba.pixels().len()).map_err(|_| {
            TextureError::OverBudget(format!("image {ii}: out of memory for {w}x{h} texels"))
        })?;
        texels.extend(rgba.pixels().map(|p| texel(Vec4::from(p.0), srgb)));
        Ok((w, h, texels))
    }
}

/// One decoded texel: non-finite → zero; RGB from sRGB to linear when `srgb` (alpha as is).
fn texel(v: Vec4, srgb: bool) -> Vec4 {
    let v = if v.is_finite() { v } else { Vec4::ZERO };
    if srgb {
        Vec4::new(
            srgb_to_linear(v.x),
            srgb_to_linear(v.y),
            srgb_to_linear(v.z),
            v.w,
        )
    } else {
        v
    }
}

/// The texture's sampler as (wrap S, wrap T, bilinear filtering); repeat and linear when it
/// has none (or names one that does not exist).
fn sampler_modes(root: &json::Root, t: &json::Texture) -> (Wrap, Wrap, bool) {
    let (mut wrap_s, mut wrap_t, mut linear) = (Wrap::Repeat, Wrap::Repeat, true);
    if let Some(si) = t.sampler
        && let Some(s) = root.samplers.get(si.value())
    {
        wrap_s = wrap_mode(&s.wrap_s);
        wrap_t = wrap_mode(&s.wrap_t);
        linear = !matches!(
            s.mag_filter,
            Some(Checked::Valid(json::texture::MagFilter::Nearest))
        );
    }
    (wrap_s, wrap_t, linear)
}

/// Why a texture is not used: a broken image (a warning, the material goes untextured) or
/// the scene's texture-pixel budget (an error: the scene would not render as written).
enum TextureError {
    Unusable(String),
    OverBudget(String),
}

impl From<String> for TextureError {
    fn from(e: String) -> Self {
        TextureError::Unusable(e)
    }
}

impl Loader<'_> {
    /// Count a `w`×`h` image against `limits.max_texture_pixels` before decoding it.
    fn charge_texels(&mut self, ii: usize, w: u32, h: u32) -> Result<(), TextureError> {
        let total = self.texture_pixels + u64::from(w) * u64::from(h);
        let max = self.limits.max_texture_pixels;
        if total > max {
            return Err(TextureError::OverBudget(format!(
                "image {ii} ({w}x{h}) brings the scene's textures to {total} texels, more than \
                 the {max} allowed (raise the budget with --max-texture-pixels)"
            )));
        }
        self.texture_pixels = total;
        Ok(())
    }
}

/// Width and height from an image's header, without decoding it.
fn image_size(bytes: &[u8]) -> Result<(u32, u32), String> {
    image::ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| e.to_string())?
        .into_dimensions()
        .map_err(|e| e.to_string())
}

fn wrap_mode(w: &Checked<json::texture::WrappingMode>) -> Wrap {
    use json::texture::WrappingMode as W;
    match w {
        Checked::Valid(W::ClampToEdge) => Wrap::ClampToEdge,
        Checked::Valid(W::MirroredRepeat) => Wrap::MirroredRepeat,
        _ => Wrap::Repeat,
    }
}
