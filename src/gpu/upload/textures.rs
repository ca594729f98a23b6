//! Textures in GPU form: each material's texture reference slots and the `texels` array of
//! reference headers and texels.

use crate::gpu::layout;
use crate::scene::material::{Texture, TextureRef, Wrap};
use crate::scene::{MaterialKind, Scene};

/// Texture references and texels in one `vec4<f32>` array (scene.wgsl `texels`): reference
/// slot r is 3 vec4s at 3r (header `[offset, width, height, flags]` as u32 bits, the
/// `KHR_texture_transform` matrix columns, the translation), then the texels of every
/// texture (row-major, linear RGBA). Returns (array, each material's reference slots).
pub fn pack_textures(scene: &Scene) -> (Vec<[f32; 4]>, Vec<TexSlots>) {
    let (refs, slots) = texture_slots(scene);
    let header = 3 * refs.len();
    let mut offsets = Vec::with_capacity(scene.textures.len());
    let mut total = header;
    for t in &scene.textures {
        offsets.push(total as u32);
        total += texel_count(t);
    }
    let mut out = vec![[0.0f32; 4]; total.max(1)];
    for (i, r) in refs.iter().enumerate() {
        let t = scene.textures.get(r.texture as usize);
        let offset = offsets.get(r.texture as usize).copied().unwrap_or(0);
        out[3 * i..3 * i + 3].copy_from_slice(&texture_reference(r, t, offset));
    }
    for (t, &off) in scene.textures.iter().zip(&offsets) {
        let n = texel_count(t);
        for (o, v) in out[off as usize..off as usize + n]
            .iter_mut()
            .zip(&t.texels)
        {
            *o = v.to_array();
        }
    }
    (out, slots)
}

/// Every material's texture references, numbered in order, and each material's slots into
/// them: only what its kind and the mesh can use (the metallic-roughness texture for
/// metal-rough, emission for emitters, normal maps with tangents).
fn texture_slots(scene: &Scene) -> (Vec<TextureRef>, Vec<TexSlots>) {
    let mut refs: Vec<TextureRef> = Vec::new();
    let mut slots = Vec::with_capacity(scene.materials.len());
    let mut slot_of = |r: &Option<TextureRef>| -> u32 {
        match r {
            Some(r) => {
                refs.push(*r);
                (refs.len() - 1) as u32
            }
            None => layout::NO_TEXTURE,
        }
    };
    for m in &scene.materials {
        let base = slot_of(&m.base_color_texture);
        // Only metal-rough reads the metallic-roughness texture (`Material::metal_rough_at`).
        let mr = if m.kind == MaterialKind::MetalRough {
            slot_of(&m.metallic_roughness_texture)
        } else {
            layout::NO_TEXTURE
        };
        let emit = slot_of(&m.emissive_texture.filter(|_| m.is_emissive()));
        // Normal maps need the mesh's tangents (`Features::NORMAL_MAP`).
        let normal = if scene.mesh.tangents.is_empty() {
            layout::NO_TEXTURE
        } else {
            slot_of(&m.normal_texture)
        };
        let film = slot_of(&m.iridescence.and_then(|i| i.thickness_texture));
        slots.push(TexSlots {
            base,
            mr,
            emit,
            normal,
            film,
        });
    }
    (refs, slots)
}

/// The texels a texture contributes: width × height, or 0 for one whose texels do not fill
/// its size (its references then read as invalid).
fn texel_count(t: &Texture) -> usize {
    let n = t.width as usize * t.height as usize;
    if n > 0 && t.texels.len() >= n { n } else { 0 }
}

/// The three vec4s of reference `r`: header `[offset, width, height, flags]` (u32 bits; all
/// zero, i.e. not `TEX_VALID`, without a usable texture `t`), the transform's matrix columns
/// and its translation.
fn texture_reference(r: &TextureRef, t: Option<&Texture>, offset: u32) -> [[f32; 4]; 3] {
    let wrap = |w: Wrap| match w {
        Wrap::Repeat => layout::WRAP_REPEAT,
        Wrap::MirroredRepeat => layout::WRAP_MIRRORED_REPEAT,
        Wrap::ClampToEdge => layout::WRAP_CLAMP_TO_EDGE,
    };
    let head = match t {
        Some(t) if texel_count(t) > 0 => [
            offset,
            t.width,
            t.height,
            wrap(t.wrap_s)
                | wrap(t.wrap_t) << 2
                | if t.linear { layout::TEX_LINEAR } else { 0 }
                | layout::TEX_VALID,
        ],
        _ => [0; 4],
    };
    let m = r.transform.matrix2;
    let tr = r.transform.translation;
    [
        head.map(f32::from_bits),
        [m.x_axis.x, m.x_axis.y, m.y_axis.x, m.y_axis.y],
        [tr.x, tr.y, 0.0, 0.0],
    ]
}

/// The texture reference slots of one material ([`layout::NO_TEXTURE`] = none).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TexSlots {
    /// Base colour.
    pub base: u32,
    /// Metallic-roughness (metal-rough materials only).
    pub mr: u32,
    /// Emissive (emitting materials only).
    pub emit: u32,
    /// Tangent-space normal map (when the mesh has tangents).
    pub normal: u32,
    /// A thin film's thickness (green channel).
    pub film: u32,
}
