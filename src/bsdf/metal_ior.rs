//! Tabulated complex indices of refraction η − ik of four metals over the visible range, with
//! linear interpolation in λ, and their projection to linear sRGB for RGB rendering.
//!
//! Source: the `data/ior/{Au,Ag,Cu,Al}.{eta,k}.spd` tables Mitsuba 3 ships (their headers: "data
//! from www.luxpop.com database", optical constants n, k; the same tables pbrt-v3 ships as
//! `spds/metals`), restricted to the 42 samples between 354 and 856 nm that cover 360–830 nm.
//! The wavelengths are the tables' own (uniform in photon energy, not in λ). Linear
//! interpolation in λ, as Mitsuba's `IrregularSpectrum` does; outside the table the end value
//! holds.
//!
//! RGB mode: each curve (η and k separately) is projected to linear sRGB, unbounded except
//! for a clamp at 0, as Mitsuba 3 does for its RGB variants (`ior_from_file` →
//! `spectrum_list_to_srgb(…, bounded = false)`): rgb = M · ∫ x̄ȳz̄(λ) v(λ) dλ / ∫ ȳ(λ) dλ over
//! [360, 830] nm (IEC 61966-2-1 §5.2 matrix M, CIE 1931 2° observer), Y-normalised and not
//! white-balanced, so an equal-energy spectrum does not map to exactly (1, 1, 1).

use crate::math::spectrum::{LAMBDA_MAX, LAMBDA_MIN, cie_xyz_cmf, xyz_to_linear_srgb};
use glam::Vec3;
use std::sync::OnceLock;

/// A metal with tabulated spectral η, k (glTF `material.extras.conductor`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum Metal {
    /// Gold, "Au".
    Au,
    /// Silver, "Ag".
    Ag,
    /// Copper, "Cu".
    Cu,
    /// Aluminium, "Al".
    Al,
}

/// Number of tabulated wavelengths.
pub const SAMPLES: usize = 42;

/// Tabulated wavelengths (nm), increasing.
pub const LAMBDA_NM: [f32; SAMPLES] = [
    354.241, 359.374, 364.659, 370.102, 375.71, 381.49, 387.451, 393.601, 399.949, 406.505,
    413.281, 420.285, 427.532, 435.032, 442.801, 450.852, 459.201, 467.865, 476.862, 486.212,
    495.937, 506.058, 516.601, 527.592, 539.062, 551.041, 563.564, 576.671, 590.401, 604.801,
    619.921, 635.816, 652.548, 670.185, 688.801, 708.481, 729.319, 751.419, 774.901, 799.898,
    826.561, 855.063,
];

/// Au: real part η at [`LAMBDA_NM`].
const GOLD_ETA: [f32; SAMPLES] = [
    1.74, 1.72762, 1.716, 1.70588, 1.696, 1.68475, 1.674, 1.666, 1.658, 1.64725, 1.636, 1.628,
    1.616, 1.59625, 1.562, 1.50212, 1.426, 1.34587, 1.242, 1.08675, 0.916, 0.7545, 0.608, 0.49175,
    0.402, 0.3455, 0.306, 0.267625, 0.236, 0.212375, 0.194, 0.17775, 0.166, 0.161, 0.16, 0.160875,
    0.164, 0.1695, 0.176, 0.181375, 0.188, 0.198125,
];
/// Au: extinction coefficient k at [`LAMBDA_NM`].
const GOLD_K: [f32; SAMPLES] = [
    1.848, 1.85238, 1.862, 1.883, 1.906, 1.9225, 1.936, 1.94775, 1.956, 1.95938, 1.958, 1.95138,
    1.94, 1.9245, 1.904, 1.87587, 1.846, 1.81462, 1.796, 1.79737, 1.84, 1.9565, 2.12, 2.32625,
    2.54, 2.73062, 2.88, 2.94062, 2.97, 3.015, 3.06, 3.07, 3.15, 3.44581, 3.8, 4.08769, 4.357,
    4.61019, 4.86, 5.12581, 5.39, 5.63125,
];

/// Ag: real part η at [`LAMBDA_NM`].
const SILVER_ETA: [f32; SAMPLES] = [
    0.209, 0.194813, 0.186, 0.192063, 0.2, 0.198063, 0.192, 0.182, 0.173, 0.172625, 0.173,
    0.166688, 0.16, 0.1585, 0.157, 0.151063, 0.144, 0.137313, 0.132, 0.13025, 0.13, 0.129938, 0.13,
    0.130063, 0.129, 0.124375, 0.12, 0.119313, 0.121, 0.1255, 0.131, 0.136125, 0.14, 0.140063,
    0.14, 0.144313, 0.148, 0.145875, 0.143, 0.142563, 0.145, 0.151938,
];
/// Ag: extinction coefficient k at [`LAMBDA_NM`].
const SILVER_K: [f32; SAMPLES] = [
    1.44, 1.53375, 1.61, 1.64187, 1.67, 1.735, 1.81, 1.87875, 1.95, 2.02937, 2.11, 2.18625, 2.26,
    2.32938, 2.4, 2.47875, 2.56, 2.64, 2.72, 2.79813, 2.88, 2.97375, 3.07, 3.15937, 3.25, 3.34813,
    3.45, 3.55375, 3.66, 3.76625, 3.88, 4.01063, 4.15, 4.29312, 4.44, 4.58625, 4.74, 4.90813, 5.09,
    5.28875, 5.5, 5.72062,
];

/// Cu: real part η at [`LAMBDA_NM`].
const COPPER_ETA: [f32; SAMPLES] = [
    1.29, 1.28156, 1.27, 1.24906, 1.225, 1.2, 1.18, 1.17437, 1.175, 1.1775, 1.18, 1.17813, 1.175,
    1.17281, 1.17, 1.16531, 1.16, 1.15531, 1.15, 1.14281, 1.135, 1.13156, 1.12, 1.09244, 1.04,
    0.950375, 0.826, 0.645875, 0.468, 0.35125, 0.272, 0.230813, 0.214, 0.20925, 0.213, 0.21625,
    0.223, 0.2365, 0.25, 0.254188, 0.26, 0.28,
];
/// Cu: extinction coefficient k at [`LAMBDA_NM`].
const COPPER_K: [f32; SAMPLES] = [
    1.916, 1.93169, 1.95, 1.97244, 2.015, 2.12156, 2.21, 2.17719, 2.13, 2.16006, 2.21, 2.24994,
    2.289, 2.326, 2.362, 2.39763, 2.433, 2.46919, 2.504, 2.53587, 2.564, 2.58962, 2.605, 2.59556,
    2.583, 2.5765, 2.599, 2.67806, 2.809, 3.01075, 3.24, 3.45819, 3.67, 3.86313, 4.05, 4.23956,
    4.43, 4.61956, 4.817, 5.03413, 5.26, 5.48562,
];

/// Al: real part η at [`LAMBDA_NM`].
const ALUMINIUM_ETA: [f32; SAMPLES] = [
    0.385, 0.39575, 0.407, 0.419125, 0.432, 0.445688, 0.46, 0.474688, 0.49, 0.506188, 0.523,
    0.540063, 0.558, 0.577313, 0.598, 0.620313, 0.644, 0.668625, 0.695, 0.72375, 0.755, 0.789,
    0.826, 0.867, 0.912, 0.963, 1.02, 1.08, 1.15, 1.22, 1.3, 1.39, 1.49, 1.6, 1.74, 1.91, 2.14,
    2.41, 2.63, 2.8, 2.74, 2.58,
];
/// Al: extinction coefficient k at [`LAMBDA_NM`].
#[allow(clippy::approx_constant)] // measured data: 6.28 is a k value, not τ
const ALUMINIUM_K: [f32; SAMPLES] = [
    4.3, 4.365, 4.43, 4.49375, 4.56, 4.63375, 4.71, 4.78437, 4.86, 4.93813, 5.02, 5.10875, 5.2,
    5.29, 5.38, 5.48, 5.58, 5.69, 5.8, 5.915, 6.03, 6.15, 6.28, 6.42, 6.55, 6.7, 6.85, 7.0, 7.15,
    7.31, 7.48, 7.65, 7.82, 8.01, 8.21, 8.39, 8.57, 8.62, 8.6, 8.45, 8.31, 8.21,
];

impl Metal {
    /// Every metal, in the order of [`Metal::index`].
    pub const ALL: [Metal; 4] = [Metal::Au, Metal::Ag, Metal::Cu, Metal::Al];

    /// The chemical symbol (the glTF `extras.conductor` value, Mitsuba's `material`).
    pub fn symbol(self) -> &'static str {
        match self {
            Metal::Au => "Au",
            Metal::Ag => "Ag",
            Metal::Cu => "Cu",
            Metal::Al => "Al",
        }
    }

    /// The metal named by its chemical symbol (exact, case-sensitive as in Mitsuba).
    pub fn from_symbol(s: &str) -> Option<Metal> {
        Metal::ALL.into_iter().find(|m| m.symbol() == s)
    }

    /// Position in [`Metal::ALL`] (the GPU's metal code is this + 1; 0 = none).
    pub fn index(self) -> usize {
        self as usize
    }

    fn tables(self) -> (&'static [f32; SAMPLES], &'static [f32; SAMPLES]) {
        match self {
            Metal::Au => (&GOLD_ETA, &GOLD_K),
            Metal::Ag => (&SILVER_ETA, &SILVER_K),
            Metal::Cu => (&COPPER_ETA, &COPPER_K),
            Metal::Al => (&ALUMINIUM_ETA, &ALUMINIUM_K),
        }
    }

    /// (η, k) at `lambda_nm`, linearly interpolated; the end values hold outside the table.
    pub fn ior_at(self, lambda_nm: f32) -> (f32, f32) {
        let (eta, k) = self.tables();
        (lerp_table(eta, lambda_nm), lerp_table(k, lambda_nm))
    }

    /// Per-channel linear-sRGB (η, k) for RGB rendering (module docs), computed once.
    pub fn rgb(self) -> (Vec3, Vec3) {
        static RGB: OnceLock<[(Vec3, Vec3); 4]> = OnceLock::new();
        RGB.get_or_init(|| {
            Metal::ALL.map(|m| {
                let (eta, k) = m.tables();
                (project_to_srgb(eta), project_to_srgb(k))
            })
        })[self.index()]
    }
}

/// Linear interpolation of `table` (sampled at [`LAMBDA_NM`]) at `lambda_nm`.
fn lerp_table(table: &[f32; SAMPLES], lambda_nm: f32) -> f32 {
    let l = lambda_nm.clamp(LAMBDA_NM[0], LAMBDA_NM[SAMPLES - 1]);
    // First index whose wavelength exceeds l, kept in 1..SAMPLES.
    let hi = LAMBDA_NM.partition_point(|&x| x <= l).clamp(1, SAMPLES - 1);
    let (l0, l1) = (LAMBDA_NM[hi - 1], LAMBDA_NM[hi]);
    let t = (l - l0) / (l1 - l0);
    table[hi - 1] + t * (table[hi] - table[hi - 1])
}

/// M · ∫ cmf v dλ / ∫ ȳ dλ over [360, 830] nm (module docs), by the midpoint rule with 1 nm
/// steps (f64 sums), clamped at 0.
fn project_to_srgb(table: &[f32; SAMPLES]) -> Vec3 {
    let steps = (LAMBDA_MAX - LAMBDA_MIN) as usize;
    let mut xyz = [0.0f64; 3];
    let mut y_sum = 0.0f64;
    for i in 0..steps {
        let l = LAMBDA_MIN + i as f32 + 0.5;
        let c = cie_xyz_cmf(l);
        let v = lerp_table(table, l) as f64;
        xyz[0] += c.x as f64 * v;
        xyz[1] += c.y as f64 * v;
        xyz[2] += c.z as f64 * v;
        y_sum += c.y as f64;
    }
    let xyz = Vec3::new(xyz[0] as f32, xyz[1] as f32, xyz[2] as f32) / y_sum as f32;
    xyz_to_linear_srgb(xyz).max(Vec3::ZERO)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn symbols_round_trip() {
        for m in Metal::ALL {
            assert_eq!(Metal::from_symbol(m.symbol()), Some(m));
        }
        assert_eq!(Metal::from_symbol("au"), None);
        assert_eq!(Metal::from_symbol("Pt"), None);
    }

    #[test]
    fn table_covers_visible_range_and_interpolates() {
        const { assert!(LAMBDA_NM[0] <= LAMBDA_MIN && LAMBDA_NM[SAMPLES - 1] >= LAMBDA_MAX) };
        assert!(LAMBDA_NM.windows(2).all(|w| w[0] < w[1]));
        // At a sample: the table value; half-way: the mean of the neighbours.
        let (eta, k) = Metal::Au.tables();
        assert_eq!(Metal::Au.ior_at(LAMBDA_NM[10]), (eta[10], k[10]));
        let mid = 0.5 * (LAMBDA_NM[20] + LAMBDA_NM[21]);
        let (e, kk) = Metal::Au.ior_at(mid);
        assert!((e - 0.5 * (eta[20] + eta[21])).abs() < 1e-5);
        assert!((kk - 0.5 * (k[20] + k[21])).abs() < 1e-5);
        // Outside the table the end values hold.
        assert_eq!(Metal::Cu.ior_at(100.0), Metal::Cu.ior_at(LAMBDA_NM[0]));
    }

    /// Mitsuba 3.9.1 `scalar_rgb` `conductor` with `material = Au/Ag/Cu/Al` reports these
    /// `eta.value`, `k.value` (printed by `mi.traverse`); ours use the analytic CIE fit of
    /// `math::spectrum` instead of the tabulated CIE 1931 curves, which moves them by up to
    /// 1.8 % (measured: Au η red 0.1456 vs 0.1430).
    #[test]
    fn rgb_matches_mitsuba_rgb_variants() {
        let mitsuba = [
            (
                Metal::Au,
                [0.143036, 0.375307, 1.44205],
                [3.983, 2.38556, 1.60336],
            ),
            (
                Metal::Ag,
                [0.155276, 0.116728, 0.138388],
                [4.82835, 3.12222, 2.1469],
            ),
            (
                Metal::Cu,
                [0.201005, 0.92375, 1.10222],
                [3.91326, 2.45305, 2.14209],
            ),
            (
                Metal::Al,
                [1.6575, 0.880405, 0.521244],
                [9.22381, 6.2695, 4.837],
            ),
        ];
        for (m, eta, k) in mitsuba {
            let (e, kk) = m.rgb();
            for c in 0..3 {
                let re = (e[c] - eta[c]).abs() / eta[c];
                let rk = (kk[c] - k[c]).abs() / k[c];
                assert!(re < 0.02 && rk < 0.02, "{m:?} channel {c}: η {e} k {kk}");
            }
        }
    }
}
