//! Tone mapping: exposure and a tone curve, then 8-bit sRGB.

use crate::math::color::linear_to_srgb;
use glam::Vec3;

/// Tone mapping for display and PNG output.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ToneMap {
    /// Exposure then clamp (what a physically based comparison wants).
    #[default]
    Clamp,
    /// Reinhard x/(1+x) on each channel.
    Reinhard,
    /// ACES filmic fit (Narkowicz 2015).
    Aces,
}

impl ToneMap {
    #[inline]
    pub fn apply(self, x: f32) -> f32 {
        match self {
            ToneMap::Clamp => x.clamp(0.0, 1.0),
            // Reinhard et al. 2002, "Photographic Tone Reproduction for Digital Images".
            ToneMap::Reinhard => (x / (1.0 + x)).clamp(0.0, 1.0),
            // Narkowicz 2015, "ACES Filmic Tone Mapping Curve".
            ToneMap::Aces => {
                ((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14)).clamp(0.0, 1.0)
            }
        }
    }
}

/// 2^stops for display (non-finite exposure = 1, clamped to ±30 stops), as both viewer
/// backends show it.
pub fn exposure_scale(stops: f32) -> f32 {
    if stops.is_finite() {
        2f32.powf(stops.clamp(-30.0, 30.0))
    } else {
        1.0
    }
}

/// 8-bit sRGB pixels (RGBA) of a linear image after exposure (in stops) and tone mapping.
pub fn to_srgb8(img: &[Vec3], exposure: f32, tone: ToneMap) -> Vec<u8> {
    let scale = 2f32.powf(exposure);
    let mut out = Vec::with_capacity(img.len() * 4);
    for p in img {
        for c in [p.x, p.y, p.z] {
            let v = linear_to_srgb(tone.apply(c * scale));
            out.push((v * 255.0 + 0.5).clamp(0.0, 255.0) as u8);
        }
        out.push(255);
    }
    out
}
