//! Error metrics of a measured image against the reference, and the time a curve takes
//! to reach an error.

use super::BenchPoint;
use glam::Vec3;

/// Relative MSE: mean over pixels and channels of (x − ref)² / (ref² + 1e-2).
pub fn rel_mse(x: &[Vec3], reference: &[Vec3]) -> f64 {
    let mut s = 0.0f64;
    for (a, r) in x.iter().zip(reference) {
        for k in 0..3 {
            let (a, r) = (a[k] as f64, r[k] as f64);
            s += (a - r) * (a - r) / (r * r + 1e-2);
        }
    }
    s / (3 * x.len().max(1)) as f64
}

/// Root mean squared error over pixels and channels.
pub fn rmse(x: &[Vec3], reference: &[Vec3]) -> f64 {
    let mut s = 0.0f64;
    for (a, r) in x.iter().zip(reference) {
        s += (*a - *r).as_dvec3().length_squared();
    }
    (s / (3 * x.len().max(1)) as f64).sqrt()
}

pub(super) fn mean_luminance(x: &[Vec3]) -> f64 {
    x.iter()
        .map(|p| crate::math::color::luminance(*p) as f64)
        .sum::<f64>()
        / x.len().max(1) as f64
}

/// Time at which the curve first reaches `target` (log-log interpolation between points).
pub fn time_to(points: &[BenchPoint], target: f64) -> Option<f64> {
    for w in points.windows(2) {
        let (p, q) = (&w[0], &w[1]);
        if p.rel_mse <= target {
            return Some(p.seconds);
        }
        if q.rel_mse <= target && p.rel_mse > 0.0 && q.rel_mse > 0.0 {
            let (lt0, lt1) = (p.seconds.ln(), q.seconds.ln());
            let (le0, le1) = (p.rel_mse.ln(), q.rel_mse.ln());
            let f = (target.ln() - le0) / (le1 - le0);
            return Some((lt0 + f * (lt1 - lt0)).exp());
        }
    }
    match points {
        [p] if p.rel_mse <= target => Some(p.seconds),
        _ => None,
    }
}
