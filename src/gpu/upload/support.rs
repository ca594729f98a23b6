//! What the GPU renderer cannot render: the scene checks made before any buffer is built.

use crate::scene::{Features, Scene};
use anyhow::{Result, bail, ensure};

/// Reject what the GPU kernel cannot render. Every material kind, textures, dispersion and
/// the path filter are supported; what is left are limits (checked when buffers are built).
pub fn check_supported(scene: &Scene) -> Result<()> {
    let f = scene.features();
    let conductors = Features::SMOOTH_CONDUCTOR | Features::ROUGH_FRESNEL_CONDUCTOR;
    ensure!(
        !(f.intersects(conductors) && f.contains(Features::DISPERSION)),
        "the GPU renderer has no spectral (hero-wavelength) conductor yet: this scene has a tabulated metal (extras.conductor) and a dispersive material; render it on the CPU"
    );
    ensure!(
        !(f.contains(Features::IRIDESCENCE) && f.contains(Features::DISPERSION)),
        "the GPU renderer has no spectral (hero-wavelength) thin film yet (its films use Belcour & Barla's RGB integral): this scene has a film (KHR_materials_iridescence) and a dispersive material; render it on the CPU (--device cpu)"
    );
    ensure!(
        scene.settings.light_line_nm.is_none(),
        "the GPU renderer has no light line yet (light_line_nm = {} nm): render it on the CPU (--device cpu)",
        scene.settings.light_line_nm.unwrap_or_default()
    );
    if let Some(m) = scene
        .materials
        .iter()
        .find(|m| m.is_transmissive() && m.transmission_texture.is_some())
    {
        bail!(
            "the GPU renderer has no transmission texture yet (material '{}'): render it on the CPU (--device cpu)",
            m.name
        );
    }
    for (i, t) in scene.textures.iter().enumerate() {
        ensure!(
            (t.width as u64) < (1 << 30) && (t.height as u64) < (1 << 30),
            "texture {i} is too large for the GPU renderer ({}x{})",
            t.width,
            t.height
        );
    }
    Ok(())
}
