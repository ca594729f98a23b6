//! Spectral helpers: the Abbe-number dispersion model. (Colour matching and RGB uplift land
//! with the dispersion work.)

/// n(λ) from n_d and Abbe number V_d (DESIGN.md; Cauchy-type fit through the Fraunhofer
/// d, F, C lines: 523655 = (486.1·656.3)²/(656.3²−486.1²)·…; KHR_materials_dispersion spec).
/// n(λ) = max(n_d + (n_d − 1)/V_d · (523655/λ² − 1.5168), 1), λ in nm.
#[inline]
pub fn cauchy_from_abbe(n_d: f32, abbe: f32, lambda_nm: f32) -> f32 {
    (n_d + (n_d - 1.0) / abbe * (523_655.0 / (lambda_nm * lambda_nm) - 1.5168)).max(1.0)
}
