//! What a polarised render puts in front of the sensor (issue 38; docs/polarization.md),
//! shared by the CPU walk (`cpu::polarized`) and the GPU kernel
//! (`cpu/polarized/chain.wgsl`, `gpu::GpuRenderer::set_polarization`).

use crate::math::mueller::linear_polarizer;
use glam::Vec4;

/// The sensor's filter of a polarised render.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Polarization {
    /// An ideal linear polariser whose axis is at this angle (radians) from the image's
    /// horizontal, counter-clockwise; None: no filter (the beauty is I).
    pub filter: Option<f32>,
}

impl Polarization {
    /// Row 0 of the filter's Mueller matrix: the intensity it passes is this · S.
    pub fn filter_row(&self) -> Vec4 {
        match self.filter {
            Some(a) => linear_polarizer(a).row(0),
            None => Vec4::X,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_row_passes_half_of_unpolarized_light_and_all_of_light_along_its_axis() {
        let p = Polarization { filter: Some(0.5) };
        let row = p.filter_row();
        assert!((row.dot(Vec4::X) - 0.5).abs() < 1e-6);
        let along = Vec4::new(1.0, 1.0f32.cos(), 1.0f32.sin(), 0.0); // χ = 0.5: 2χ = 1
        assert!((row.dot(along) - 1.0).abs() < 1e-6, "{row}");
        assert_eq!(Polarization::default().filter_row(), Vec4::X);
    }
}
