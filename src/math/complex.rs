//! A minimal complex number (f32) for the polarised Fresnel amplitudes: conductors' complex
//! IOR η − ik and the phases of total internal reflection (Born & Wolf, "Principles of
//! Optics", §1.5.4 and §14.2).

use std::ops::{Add, Div, Mul, Neg, Sub};

/// re + i·im.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Complex {
    pub re: f32,
    pub im: f32,
}

impl Complex {
    pub const ZERO: Complex = Complex { re: 0.0, im: 0.0 };
    pub const ONE: Complex = Complex { re: 1.0, im: 0.0 };

    #[inline]
    pub const fn new(re: f32, im: f32) -> Complex {
        Complex { re, im }
    }

    /// A real number.
    #[inline]
    pub const fn real(re: f32) -> Complex {
        Complex { re, im: 0.0 }
    }

    #[inline]
    pub fn conj(self) -> Complex {
        Complex::new(self.re, -self.im)
    }

    /// |z|².
    #[inline]
    pub fn norm2(self) -> f32 {
        self.re * self.re + self.im * self.im
    }

    /// arg z in (−π, π].
    #[inline]
    pub fn arg(self) -> f32 {
        self.im.atan2(self.re)
    }

    /// The principal square root (re ≥ 0), computed without cancellation for either sign of
    /// the real part (Kahan's csqrt recipe, in f64 for the intermediate modulus).
    #[inline]
    pub fn sqrt(self) -> Complex {
        let (x, y) = (self.re as f64, self.im as f64);
        let r = x.hypot(y);
        if r == 0.0 {
            return Complex::ZERO;
        }
        if x >= 0.0 {
            let t = (0.5 * (r + x)).sqrt();
            Complex::new(t as f32, (y / (2.0 * t)) as f32)
        } else {
            let t = (0.5 * (r - x)).sqrt();
            Complex::new((y.abs() / (2.0 * t)) as f32, t.copysign(y) as f32)
        }
    }

    #[inline]
    pub fn recip(self) -> Complex {
        let d = self.norm2();
        Complex::new(self.re / d, -self.im / d)
    }
}

impl Add for Complex {
    type Output = Complex;
    #[inline]
    fn add(self, o: Complex) -> Complex {
        Complex::new(self.re + o.re, self.im + o.im)
    }
}

impl Sub for Complex {
    type Output = Complex;
    #[inline]
    fn sub(self, o: Complex) -> Complex {
        Complex::new(self.re - o.re, self.im - o.im)
    }
}

impl Neg for Complex {
    type Output = Complex;
    #[inline]
    fn neg(self) -> Complex {
        Complex::new(-self.re, -self.im)
    }
}

impl Mul for Complex {
    type Output = Complex;
    #[inline]
    fn mul(self, o: Complex) -> Complex {
        Complex::new(
            self.re * o.re - self.im * o.im,
            self.re * o.im + self.im * o.re,
        )
    }
}

impl Mul<f32> for Complex {
    type Output = Complex;
    #[inline]
    fn mul(self, s: f32) -> Complex {
        Complex::new(self.re * s, self.im * s)
    }
}

impl Div for Complex {
    type Output = Complex;
    #[inline]
    fn div(self, o: Complex) -> Complex {
        let d = o.norm2();
        Complex::new(
            (self.re * o.re + self.im * o.im) / d,
            (self.im * o.re - self.re * o.im) / d,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sqrt_squares_back_on_both_half_planes() {
        for z in [
            Complex::new(4.0, 0.0),
            Complex::new(-4.0, 0.0),
            Complex::new(-3.0, 4.0),
            Complex::new(-3.0, -4.0),
            Complex::new(1e-3, -2.0),
        ] {
            let r = z.sqrt();
            assert!(r.re >= 0.0, "{z:?} → {r:?}");
            let back = r * r;
            assert!((back - z).norm2().sqrt() < 1e-5, "{z:?} → {r:?} → {back:?}");
        }
        assert_eq!(Complex::new(-4.0, 0.0).sqrt(), Complex::new(0.0, 2.0));
    }

    #[test]
    fn division_inverts_multiplication() {
        let (a, b) = (Complex::new(1.5, -0.3), Complex::new(0.2, 3.0));
        let q = (a * b) / b;
        assert!((q - a).norm2() < 1e-10, "{q:?}");
    }
}
