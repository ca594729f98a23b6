//! Colour: the sRGB transfer functions, luminance and black-body colour, in linear Rec.709
//! RGB (the renderer's colour space). The WGSL twin of [`linear_to_srgb`] is in
//! `src/film/tonemap.wgsl`.

use glam::Vec3;

/// Linear → sRGB transfer (IEC 61966-2-1).
#[inline]
pub fn linear_to_srgb(x: f32) -> f32 {
    if x <= 0.003_130_8 {
        12.92 * x.max(0.0)
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    }
}

/// sRGB → linear transfer (IEC 61966-2-1).
#[inline]
pub fn srgb_to_linear(x: f32) -> f32 {
    if x <= 0.040_45 {
        x / 12.92
    } else {
        ((x + 0.055) / 1.055).powf(2.4)
    }
}

/// Luminance of linear Rec.709 RGB (ITU-R BT.709 weights).
#[inline]
pub fn luminance(c: Vec3) -> f32 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}

/// Colour of a black body at `kelvin` as linear Rec.709 RGB with luminance 1: chromaticity of
/// the Planckian locus by the cubic fit of Kim et al. 2002 ("Design of advanced color
/// temperature control system for HDTV applications", J. Korean Phys. Soc. 41(6)), valid
/// 1667–25000 K; xyY → XYZ → linear sRGB with the IEC 61966-2-1 matrix.
pub fn blackbody_rgb(kelvin: f32) -> Vec3 {
    if !kelvin.is_finite() {
        return Vec3::ONE;
    }
    let t = kelvin.clamp(1667.0, 25000.0) as f64;
    let (t2, t3) = (t * t, t * t * t);
    let x = if t <= 4000.0 {
        -0.266_123_9e9 / t3 - 0.234_358_9e6 / t2 + 0.877_695_6e3 / t + 0.179_910
    } else {
        -3.025_846_9e9 / t3 + 2.107_037_9e6 / t2 + 0.222_634_7e3 / t + 0.240_390
    };
    let (x2, x3) = (x * x, x * x * x);
    let y = if t <= 2222.0 {
        -1.106_381_4 * x3 - 1.348_110_20 * x2 + 2.185_558_32 * x - 0.202_196_83
    } else if t <= 4000.0 {
        -0.954_947_6 * x3 - 1.374_185_93 * x2 + 2.091_370_15 * x - 0.167_488_67
    } else {
        3.081_758_0 * x3 - 5.873_386_70 * x2 + 3.751_129_97 * x - 0.370_014_83
    };
    let (cx, cy, cz) = (x / y, 1.0, (1.0 - x - y) / y);
    let r = 3.240_454_2 * cx - 1.537_138_5 * cy - 0.498_531_4 * cz;
    let g = -0.969_266_0 * cx + 1.876_010_8 * cy + 0.041_556_0 * cz;
    let b = 0.055_643_4 * cx - 0.204_025_9 * cy + 1.057_225_2 * cz;
    let c = Vec3::new(r as f32, g as f32, b as f32).max(Vec3::ZERO);
    let l = luminance(c);
    if l > 0.0 && c.is_finite() {
        c / l
    } else {
        Vec3::ONE
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blackbody_is_reddish_when_cool_and_bluish_when_hot() {
        let warm = blackbody_rgb(2700.0);
        let cool = blackbody_rgb(10000.0);
        assert!(warm.x > warm.z, "{warm}");
        assert!(cool.z > cool.x, "{cool}");
        let d65 = blackbody_rgb(6504.0);
        assert!((d65 - Vec3::ONE).abs().max_element() < 0.1, "{d65}");
    }
}
