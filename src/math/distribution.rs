//! Piecewise-constant 1D and 2D distributions sampled by CDF inversion (PBR 4th ed. §A.5.1
//! `PiecewiseConstant1D`, §A.5.6 `PiecewiseConstant2D`; 3rd ed. §13.6.7 `Distribution2D`).
//! The 2D one samples a row from the rows' marginal, then a column from that row's
//! conditional; both are over [0,1)² with `nu` columns and `nv` rows.

use glam::Vec2;

/// A piecewise-constant density over [0,1) with `func.len()` equal cells.
#[derive(Clone, Debug, PartialEq)]
pub struct Distribution1D {
    /// Non-negative cell values.
    pub func: Vec<f32>,
    /// Inclusive-exclusive CDF: `cdf[0] = 0`, `cdf[n] = 1` (n + 1 entries).
    pub cdf: Vec<f32>,
    /// ∫ func over [0,1) = mean of the cells.
    pub integral: f32,
}

impl Distribution1D {
    /// The CDF of `func` (PBR 4th ed. §A.5.1); an all-zero function becomes uniform.
    pub fn new(func: &[f32]) -> Distribution1D {
        let n = func.len().max(1);
        let func: Vec<f32> = if func.is_empty() {
            vec![0.0]
        } else {
            func.iter().map(|f| f.max(0.0)).collect()
        };
        let mut cdf = Vec::with_capacity(n + 1);
        cdf.push(0.0f64);
        let mut acc = 0.0f64;
        for f in &func {
            acc += *f as f64 / n as f64;
            cdf.push(acc);
        }
        let integral = acc;
        let cdf: Vec<f32> = if integral > 0.0 {
            cdf.iter().map(|c| (c / integral) as f32).collect()
        } else {
            (0..=n).map(|i| i as f32 / n as f32).collect()
        };
        let mut cdf = cdf;
        cdf[n] = 1.0;
        Distribution1D {
            func,
            cdf,
            integral: integral as f32,
        }
    }

    pub fn len(&self) -> usize {
        self.func.len()
    }

    pub fn is_empty(&self) -> bool {
        self.func.is_empty()
    }

    /// Sample x ∈ [0,1) with `u`: (x, density at x, cell index).
    #[inline]
    pub fn sample(&self, u: f32) -> (f32, f32, usize) {
        let n = self.len();
        // The last cell with cdf[i] ≤ u (PBR 4th ed. `FindInterval`).
        let i = self.cdf.partition_point(|&c| c <= u).clamp(1, n) - 1;
        let (c0, c1) = (self.cdf[i], self.cdf[i + 1]);
        let du = if c1 > c0 { (u - c0) / (c1 - c0) } else { 0.5 };
        let x = ((i as f32 + du.clamp(0.0, 1.0)) / n as f32).min(1.0 - f32::EPSILON);
        (x, self.pdf_cell(i), i)
    }

    /// Density of cell `i` (func/integral; uniform 1 for an all-zero function).
    #[inline]
    pub fn pdf_cell(&self, i: usize) -> f32 {
        if self.integral > 0.0 {
            self.func[i] / self.integral
        } else {
            1.0
        }
    }

    /// The cell containing x ∈ [0,1].
    #[inline]
    pub fn cell(&self, x: f32) -> usize {
        ((x * self.len() as f32) as usize).min(self.len() - 1)
    }
}

/// A piecewise-constant density over [0,1)² (columns u, rows v): marginal over rows,
/// conditional over the columns of each row (PBR 4th ed. §A.5.6).
#[derive(Clone, Debug, PartialEq)]
pub struct Distribution2D {
    /// One conditional per row.
    pub conditional: Vec<Distribution1D>,
    pub marginal: Distribution1D,
}

impl Distribution2D {
    /// From `func[row * nu + col]` (non-negative).
    pub fn new(func: &[f32], nu: usize, nv: usize) -> Distribution2D {
        assert_eq!(func.len(), nu * nv, "distribution size");
        let conditional: Vec<Distribution1D> = (0..nv)
            .map(|v| Distribution1D::new(&func[v * nu..(v + 1) * nu]))
            .collect();
        let marginal: Vec<f32> = conditional.iter().map(|c| c.integral).collect();
        Distribution2D {
            conditional,
            marginal: Distribution1D::new(&marginal),
        }
    }

    pub fn nu(&self) -> usize {
        self.conditional[0].len()
    }

    pub fn nv(&self) -> usize {
        self.conditional.len()
    }

    /// A point of [0,1)² and its density (PBR 4th ed. `PiecewiseConstant2D::Sample`).
    #[inline]
    pub fn sample(&self, u: Vec2) -> (Vec2, f32) {
        let (v, pv, row) = self.marginal.sample(u.y);
        let (x, pu, _) = self.conditional[row].sample(u.x);
        (Vec2::new(x, v), pv * pu)
    }

    /// Density at a point of [0,1]² (PBR 4th ed. `PiecewiseConstant2D::PDF`).
    #[inline]
    pub fn pdf(&self, p: Vec2) -> f32 {
        let row = self.marginal.cell(p.y);
        let c = &self.conditional[row];
        let col = c.cell(p.x);
        if self.marginal.integral > 0.0 {
            c.func[col] / self.marginal.integral
        } else {
            1.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_d_samples_follow_the_function() {
        let d = Distribution1D::new(&[1.0, 0.0, 3.0, 4.0]);
        assert!((d.integral - 2.0).abs() < 1e-6);
        let n = 40_000;
        let mut counts = [0usize; 4];
        for k in 0..n {
            let (x, pdf, i) = d.sample((k as f32 + 0.5) / n as f32);
            assert_eq!(d.cell(x), i, "x {x} lies in its cell");
            assert!((pdf - d.func[i] / 2.0).abs() < 1e-6);
            counts[i] += 1;
        }
        assert_eq!(counts[1], 0, "a zero cell is never sampled");
        for (i, c) in counts.iter().enumerate() {
            let expect = n as f32 * d.func[i] / 8.0;
            assert!(
                (*c as f32 - expect).abs() <= 2.0,
                "cell {i}: {c} vs {expect}"
            );
        }
    }

    #[test]
    fn two_d_pdf_matches_sample_and_integrates_to_one() {
        let (nu, nv) = (5, 3);
        let f: Vec<f32> = (0..nu * nv).map(|i| ((i * 7) % 5) as f32).collect();
        let d = Distribution2D::new(&f, nu, nv);
        let mut total = 0.0;
        for v in 0..nv {
            for u in 0..nu {
                let p = Vec2::new((u as f32 + 0.5) / nu as f32, (v as f32 + 0.5) / nv as f32);
                total += d.pdf(p) / (nu * nv) as f32;
            }
        }
        assert!((total - 1.0).abs() < 1e-5, "∫pdf = {total}");
        let mut rng = crate::math::rng::Sampler::new(9, 0, 1);
        for _ in 0..1000 {
            let (p, pdf) = d.sample(rng.next_2d());
            assert!(pdf > 0.0);
            assert!((d.pdf(p) - pdf).abs() <= 1e-5 * pdf, "pdf at {p}");
        }
    }

    #[test]
    fn all_zero_is_uniform() {
        let d = Distribution2D::new(&[0.0; 6], 3, 2);
        let (_, pdf) = d.sample(Vec2::new(0.3, 0.7));
        assert_eq!(pdf, 1.0);
        assert_eq!(d.pdf(Vec2::new(0.9, 0.1)), 1.0);
    }
}
