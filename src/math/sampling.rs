//! Warps from the unit square to directions and points, and MIS weights.

use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_1_PI, FRAC_PI_2, FRAC_PI_4, PI};

/// Concentric square→disk map. Shirley & Chiu 1997, "A Low Distortion Map Between Disk and Square".
#[inline]
pub fn concentric_disk(u: Vec2) -> Vec2 {
    let o = 2.0 * u - Vec2::ONE;
    if o.x == 0.0 && o.y == 0.0 {
        return Vec2::ZERO;
    }
    // Both wedges computed and one selected: the comparison is a coin toss per sample, so a
    // branch on it was mispredicted about half the time.
    let x_wedge = o.x.abs() > o.y.abs();
    let (a, b) = (FRAC_PI_4 * (o.y / o.x), FRAC_PI_2 - FRAC_PI_4 * (o.x / o.y));
    let r = std::hint::select_unpredictable(x_wedge, o.x, o.y);
    let theta = std::hint::select_unpredictable(x_wedge, a, b);
    r * Vec2::new(theta.cos(), theta.sin())
}

/// Cosine-weighted hemisphere (Malley's method). PBR 4th ed. §A.5.3.
#[inline]
pub fn cosine_hemisphere(u: Vec2) -> Vec3 {
    let d = concentric_disk(u);
    let z = (1.0 - d.x * d.x - d.y * d.y).max(0.0).sqrt();
    Vec3::new(d.x, d.y, z)
}

/// pdf of `cosine_hemisphere` w.r.t. solid angle: cosθ/π. PBR 4th ed. §A.5.3.
#[inline]
pub fn cosine_hemisphere_pdf(cos_theta: f32) -> f32 {
    cos_theta.max(0.0) * FRAC_1_PI
}

/// Uniform direction on the unit sphere. PBR 4th ed. §A.5.2.
#[inline]
pub fn uniform_sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// pdf of `uniform_sphere`: 1/(4π).
pub const UNIFORM_SPHERE_PDF: f32 = 0.25 * FRAC_1_PI;

/// Uniform direction on the hemisphere around +z. PBR 4th ed. §A.5.2.
#[inline]
pub fn uniform_hemisphere(u: Vec2) -> Vec3 {
    let z = u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// pdf of `uniform_hemisphere`: 1/(2π).
pub const UNIFORM_HEMISPHERE_PDF: f32 = 0.5 * FRAC_1_PI;

/// Uniform direction in a cone around +z with cosθ ≥ cos_max. PBR 4th ed. §A.5.4.
#[inline]
pub fn uniform_cone(u: Vec2, cos_max: f32) -> Vec3 {
    let cos_t = (1.0 - u.x) + u.x * cos_max;
    let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3::new(phi.cos() * sin_t, phi.sin() * sin_t, cos_t)
}

/// Uniform barycentrics on a triangle (b1, b2); b0 = 1 − b1 − b2.
/// Heitz 2019, "A Low-Distortion Map Between Triangle and Square" would be lower distortion;
/// we use the classic square-root parametrisation, PBR 4th ed. §6.5.4 (Turk 1990).
#[inline]
pub fn uniform_triangle(u: Vec2) -> Vec2 {
    let su0 = u.x.sqrt();
    Vec2::new(1.0 - su0, u.y * su0)
}

/// Power heuristic with β = 2. Veach 1997, §9.2.4.
#[inline]
pub fn power_heuristic(pdf_a: f32, pdf_b: f32) -> f32 {
    let a = pdf_a * pdf_a;
    let b = pdf_b * pdf_b;
    if a == 0.0 && b == 0.0 {
        return 0.0;
    }
    if a.is_infinite() {
        return 1.0;
    }
    a / (a + b)
}
