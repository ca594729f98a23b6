//! The emissive texture of an area light (glTF `emissiveTexture`): the light's radiance at a
//! point is its emission factor × texture(uv).rgb, uv interpolated from the triangle's
//! vertices at the point's barycentric coordinates.

use crate::math::sampling;
use crate::scene::material::{Texture, sample_one};
use glam::{Affine2, Vec2, Vec3};
use std::sync::Arc;

/// Lookups per axis of the stratified average in [`EmissiveTexture::mean`] (8 × 8 points).
const MEAN_STRATA: u32 = 8;

/// One triangle's view of an emissive texture.
#[derive(Clone, Debug)]
pub struct EmissiveTexture {
    /// The texture (shared by every triangle of the material; linear RGB, sRGB-decoded).
    pub texture: Arc<Texture>,
    /// `KHR_texture_transform` of the material's reference.
    pub transform: Affine2,
    /// TEXCOORD_0 of the triangle's three vertices.
    pub uv: [Vec2; 3],
}

impl PartialEq for EmissiveTexture {
    fn eq(&self, o: &Self) -> bool {
        Arc::ptr_eq(&self.texture, &o.texture) && self.transform == o.transform && self.uv == o.uv
    }
}

impl EmissiveTexture {
    /// Texture coordinates at barycentrics `bc` = (b1, b2), the weights of vertices 1 and 2
    /// (PBR 4th ed. §6.5.3: uv = b0·uv0 + b1·uv1 + b2·uv2).
    #[inline]
    pub fn uv_at(&self, bc: Vec2) -> Vec2 {
        let [a, b, c] = self.uv;
        a * (1.0 - bc.x - bc.y) + b * bc.x + c * bc.y
    }

    /// The texture's linear RGB at barycentrics `bc` (`sample_texture`'s lookup).
    #[inline]
    pub fn rgb(&self, bc: Vec2) -> Vec3 {
        sample_one(&self.texture, self.transform, self.uv_at(bc)).truncate()
    }

    /// The texture averaged over the triangle: 8 × 8 stratum centres mapped by the uniform
    /// triangle warp (PBR 4th ed. §6.5.4), so the mean is area-weighted. For the power that
    /// light selection uses only: it need not be exact, only fixed (sampling and pdf read the
    /// same probability).
    pub fn mean(&self) -> Vec3 {
        let n = MEAN_STRATA;
        let mut sum = Vec3::ZERO;
        for j in 0..n {
            for i in 0..n {
                let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                sum += self.rgb(sampling::uniform_triangle(u)).max(Vec3::ZERO);
            }
        }
        sum / (n * n) as f32
    }
}
