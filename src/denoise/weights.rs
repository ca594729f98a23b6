//! The edge-stopping weights of the à-trous filter (Dammertz et al. 2010 §3, with SVGF's
//! variance-scaled luminance term, Schied et al. 2017 §4.4). The WGSL twins are the
//! functions of the same names in `src/denoise/denoise.wgsl`.

use glam::Vec3;

/// B3-spline taps of one à-trous level (1/16, 1/4, 3/8, 1/4, 1/16), index −2..=2.
pub const KERNEL: [f32; 5] = [1.0 / 16.0, 1.0 / 4.0, 3.0 / 8.0, 1.0 / 4.0, 1.0 / 16.0];

/// 3×3 Gaussian taps used to smooth the variance before the luminance weight (SVGF §4.4).
pub const GAUSS3: [f32; 3] = [0.25, 0.5, 0.25];

/// Luminance (Rec. 709) of a linear RGB colour.
#[inline]
pub fn luma(c: Vec3) -> f32 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}

/// Normal weight: max(0, n_p·n_q)^σ_n; zero normals (no surface) match nothing.
#[inline]
pub fn w_normal(np: Vec3, nq: Vec3, sigma_n: f32) -> f32 {
    np.dot(nq).max(0.0).powf(sigma_n)
}

/// Depth weight: |z_p − z_q| measured against σ_z × the local depth change over the
/// distance between the pixels (`grad` per pixel × `dist`).
#[inline]
pub fn w_depth(zp: f32, zq: f32, grad: f32, dist: f32, sigma_z: f32) -> f32 {
    let tol = sigma_z * grad * dist + 1e-3 * zp.abs().max(1e-3);
    (-(zp - zq).abs() / tol).exp()
}

/// Luminance weight: |l_p − l_q| against σ_l standard deviations of the noise at p.
#[inline]
pub fn w_luma(lp: f32, lq: f32, std_dev: f32, sigma_l: f32) -> f32 {
    (-(lp - lq).abs() / (sigma_l * std_dev + 1e-4)).exp()
}

/// Specular weight: pixels whose first hits were specular in different proportions (the
/// guides then describe different things) do not mix.
#[inline]
pub fn w_specular(sp: f32, sq: f32) -> f32 {
    (-8.0 * (sp - sq).abs()).exp()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_fall_off_across_edges() {
        let n = Vec3::Z;
        assert_eq!(w_normal(n, n, 128.0), 1.0);
        assert!(w_normal(n, Vec3::X, 128.0) < 1e-6);
        assert_eq!(w_normal(Vec3::ZERO, Vec3::ZERO, 128.0), 0.0);
        assert!(w_depth(1.0, 1.0, 0.01, 2.0, 1.0) > 0.999);
        assert!(w_depth(1.0, 2.0, 0.01, 2.0, 1.0) < 1e-6);
        assert!(w_luma(1.0, 1.05, 0.1, 4.0) > 0.8);
        assert!(w_luma(1.0, 5.0, 0.1, 4.0) < 1e-3);
        assert!(w_specular(0.0, 1.0) < 1e-3);
        assert!((KERNEL.iter().sum::<f32>() - 1.0).abs() < 1e-6);
    }
}
