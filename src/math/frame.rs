//! Orthonormal shading frames (z = normal).

use glam::Vec3;

/// An orthonormal basis with `n` as its z axis.
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    pub s: Vec3,
    pub t: Vec3,
    pub n: Vec3,
}

impl Frame {
    /// The world axes (x, y, z): a placeholder for vertices without a surface.
    pub const WORLD: Frame = Frame {
        s: Vec3::X,
        t: Vec3::Y,
        n: Vec3::Z,
    };

    /// Branchless ONB from a unit normal.
    /// Duff et al. 2017, "Building an Orthonormal Basis, Revisited" (JCGT 6(1)), listing 3.
    #[inline]
    pub fn from_normal(n: Vec3) -> Self {
        let sign = 1.0f32.copysign(n.z);
        let a = -1.0 / (sign + n.z);
        let b = n.x * n.y * a;
        let s = Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
        let t = Vec3::new(b, sign + n.y * n.y * a, -n.y);
        Frame { s, t, n }
    }

    /// World → local.
    #[inline]
    pub fn to_local(&self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.s), v.dot(self.t), v.dot(self.n))
    }

    /// Local → world.
    #[inline]
    pub fn to_world(&self, v: Vec3) -> Vec3 {
        self.s * v.x + self.t * v.y + self.n * v.z
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orthonormal_for_many_normals() {
        let mut worst: f32 = 0.0;
        for i in 0..1000 {
            let u = (i as f32 + 0.5) / 1000.0;
            let v = ((i * 7919) % 1000) as f32 / 1000.0;
            let n = crate::math::sampling::uniform_sphere(glam::Vec2::new(u, v));
            let f = Frame::from_normal(n);
            worst = worst
                .max(f.s.dot(f.t).abs())
                .max(f.s.dot(f.n).abs())
                .max(f.t.dot(f.n).abs())
                .max((f.s.length() - 1.0).abs())
                .max((f.t.length() - 1.0).abs())
                .max((f.s.cross(f.t).dot(n) - 1.0).abs());
            let w = Vec3::new(0.3, -0.5, 0.81).normalize();
            worst = worst.max((f.to_world(f.to_local(w)) - w).length());
        }
        assert!(worst < 1e-5, "worst orthonormality error {worst}");
    }
}
