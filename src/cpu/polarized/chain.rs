//! The Mueller chain of a camera path: the product of the polarising events met so far,
//! with the reference frames turned into each other between them (Wilkie & Weidlich 2012,
//! "Polarised Light in Computer Graphics", §3.4 and §5; Mitsuba 3's polarised path tracer
//! keeps the same product as its throughput).
//!
//! The chain maps a Stokes vector of light travelling back along the current path segment,
//! given with respect to the reference vector `x` (⊥ the segment), to the Stokes vector at
//! the camera in the camera's frame. At the camera x is the camera's right axis (made ⊥ the
//! ray): horizontal polarisation is Q > 0, and angles of polarisation count from the
//! image's horizontal towards its up axis (counter-clockwise on the image).
//!
//! At a vertex the light arrives along −ωi and leaves along ωo (world, both pointing away
//! from the surface). The event's matrix (`bsdf::polarized`) is in the s/p basis with
//! s ∝ ωi × ωo, the normal of the plane of incidence (for a microfacet event too: ωo, ωi and
//! the microfacet normal share that plane); the chain turns its frame from x to s about ωo
//! (`math::mueller::rotator`), multiplies by the event, and continues with x = s, which is
//! ⊥ the new segment.

use crate::bsdf::polarized::MuellerLanes;
use crate::math::Color;
use crate::math::mueller::rotator;
use glam::{Mat4, Vec3, Vec4};

/// Stokes components (I, Q, U, V), each per colour lane.
pub type StokesLanes = [Color; 4];

/// The Mueller product of a camera path and its current reference vector.
#[derive(Clone, Copy, Debug)]
pub struct MuellerChain {
    m: MuellerLanes,
    x: Vec3,
}

/// A unit vector ⊥ `d`, as near `v` as can be (any one when `v` ∥ `d`).
#[inline]
fn perpendicular(v: Vec3, d: Vec3) -> Vec3 {
    (v - v.dot(d) * d)
        .try_normalize()
        .unwrap_or_else(|| d.any_orthonormal_vector())
}

/// The s vector of a scattering event: the unit normal of the plane of (ωi, ωo); when they
/// are parallel (a thin sheet's straight pass, backscatter) that of the plane of (n, ωo), n
/// the surface normal; any unit vector ⊥ ωo at normal incidence, where every plane is one.
#[inline]
pub fn s_vector(wi: Vec3, wo: Vec3, n: Vec3) -> Vec3 {
    let unit = |v: Vec3| (v.length_squared() > 1e-12).then(|| v.normalize());
    unit(wi.cross(wo))
        .or_else(|| unit(n.cross(wo)))
        .unwrap_or_else(|| wo.any_orthonormal_vector())
}

/// The angle θ that turns the reference vector `from` into `to` about the direction of
/// travel `prop` (counter-clockwise looking into the beam): `to` = cos θ from + sin θ
/// (prop × from).
#[inline]
pub fn frame_angle(prop: Vec3, from: Vec3, to: Vec3) -> f32 {
    prop.dot(from.cross(to)).atan2(from.dot(to))
}

impl MuellerChain {
    /// The chain of a camera ray along `dir` for a camera whose right axis is `right`.
    pub fn camera(dir: Vec3, right: Vec3) -> MuellerChain {
        MuellerChain {
            m: [Mat4::IDENTITY; 4],
            x: perpendicular(right, dir),
        }
    }

    /// The current reference vector.
    #[inline]
    pub fn reference(&self) -> Vec3 {
        self.x
    }

    /// The chain as seen from a vertex's outgoing s/p frame: the frame change from s to the
    /// current x about ωo (= `wo`, the light's direction of travel), then the chain.
    #[inline]
    fn at_vertex(&self, wo: Vec3, s: Vec3) -> MuellerLanes {
        // A Stokes vector in frame s re-expressed in frame x: R(angle from s to x).
        let r = rotator(frame_angle(wo, s, self.x));
        std::array::from_fn(|l| self.m[l] * r)
    }

    /// The Stokes vector at the camera of unpolarised radiance `c` (per lane) arriving
    /// along the current segment: c times the chain's first column.
    #[inline]
    pub fn unpolarized(&self, c: Color) -> StokesLanes {
        column_times(&self.m, c)
    }

    /// The event `ev` at a vertex with normal `n` (light in along −`wi`, out along `wo`,
    /// world) joins the chain; the next segment's reference is the event's s.
    pub fn scatter(&mut self, (wo, wi, n): (Vec3, Vec3, Vec3), ev: &MuellerLanes) {
        let s = s_vector(wi, wo, n);
        let here = self.at_vertex(wo, s);
        self.m = std::array::from_fn(|l| here[l] * ev[l]);
        self.x = s;
    }

    /// The Stokes vector at the camera of unpolarised light `c` (per lane) that arrives along
    /// −`wi` and scatters towards `wo` at normal `n` by `ev` (next-event estimation), the
    /// chain unchanged.
    pub fn through(
        &self,
        (wo, wi, n): (Vec3, Vec3, Vec3),
        ev: &MuellerLanes,
        c: Color,
    ) -> StokesLanes {
        let here = self.at_vertex(wo, s_vector(wi, wo, n));
        let m: MuellerLanes = std::array::from_fn(|l| here[l] * ev[l]);
        column_times(&m, c)
    }
}

/// Per lane l, c[l] times the first column of m[l], arranged by Stokes component.
#[inline]
fn column_times(m: &MuellerLanes, c: Color) -> StokesLanes {
    let cols: [Vec4; 4] = std::array::from_fn(|l| m[l].x_axis * c[l]);
    std::array::from_fn(|k| Color::new(cols[0][k], cols[1][k], cols[2][k], cols[3][k]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::fresnel_polarized::reflection_mueller;
    use crate::math::complex::Complex;
    use crate::math::mueller::angle_of_polarization;

    #[test]
    fn frame_angle_is_signed_about_the_direction_of_travel() {
        let prop = Vec3::Z;
        assert!((frame_angle(prop, Vec3::X, Vec3::Y) - std::f32::consts::FRAC_PI_2).abs() < 1e-6);
        assert!((frame_angle(prop, Vec3::Y, Vec3::X) + std::f32::consts::FRAC_PI_2).abs() < 1e-6);
        assert_eq!(frame_angle(prop, Vec3::X, Vec3::X), 0.0);
    }

    /// Two reflections at Brewster's angle off glass (a periscope): with the planes of
    /// incidence parallel, unpolarised light leaves with ½ r_s⁴ (the first reflection is all
    /// s, the second reflects s again); crossed at 90° about the middle beam, the first
    /// reflection's s is the second's p, which it does not reflect at all. The unpolarised
    /// product F² lies between. Checks the frame rotation between the two events.
    #[test]
    fn crossed_brewster_reflections_extinguish_and_parallel_ones_do_not() {
        let theta = 1.5f32.atan();
        let (s2, c2) = (2.0 * theta).sin_cos();
        let d2 = Vec3::Z; // the middle beam, from plate A to plate B
        let d3 = Vec3::new(s2, 0.0, -c2); // leaves B; plane of incidence at B: x–z
        let ev = [reflection_mueller(theta.cos(), Complex::real(1.5)); 4];
        let intensity = |d1: Vec3| {
            let mut chain = MuellerChain::camera(-d3, Vec3::Y);
            chain.scatter((d3, -d2, (d3 - d2).normalize()), &ev);
            chain.scatter((d2, -d1, (d2 - d1).normalize()), &ev);
            chain.unpolarized(Color::ONE)[0].x
        };
        // Angles of incidence: θ at both plates for either d1.
        let crossed = -Vec3::new(0.0, s2, c2); // plane of incidence at A: y–z
        let parallel = -Vec3::new(s2, 0.0, c2); // x–z, as at B
        for d1 in [crossed, parallel] {
            assert!(((-d1).dot(d2) - (2.0 * theta).cos()).abs() < 1e-6);
        }
        assert!(((-d2).dot(d3) - (2.0 * theta).cos()).abs() < 1e-6);
        let a = crate::bsdf::fresnel_polarized::fresnel_amplitudes(theta.cos(), Complex::real(1.5));
        let rs2 = a.r_s.norm2();
        let (ic, ip) = (intensity(crossed), intensity(parallel));
        assert!(ic < 1e-7, "crossed: {ic}");
        assert!(
            (ip - 0.5 * rs2 * rs2).abs() < 1e-6,
            "parallel: {ip} vs {}",
            0.5 * rs2 * rs2
        );
        let f = 0.5 * rs2;
        assert!(ic < f * f && f * f < ip);
    }

    /// Light through a level thin glass sheet seen obliquely (ωi = −ωo: no plane of (ωi, ωo))
    /// is partly p-polarised, and p lies in the vertical plane of (n, ωo): vertical on the
    /// image (Q < 0, AoP 90°).
    #[test]
    fn straight_pass_through_a_sheet_takes_its_plane_from_the_normal() {
        use crate::bsdf::fresnel_polarized::transmission_mueller;
        use crate::math::mueller::normalized;
        let dir = Vec3::new(0.0, -0.6, -0.8);
        let mut chain = MuellerChain::camera(dir, Vec3::X);
        let t = transmission_mueller(0.6, 1.5);
        chain.scatter((-dir, dir, Vec3::Y), &[normalized(t * t); 4]);
        let s = chain.unpolarized(Color::ONE);
        let stokes = Vec4::new(s[0].x, s[1].x, s[2].x, s[3].x);
        assert!(stokes.y < -0.01 && stokes.z.abs() < 1e-6, "{stokes}");
        let aop = angle_of_polarization(stokes);
        assert!(
            (aop.abs() - std::f32::consts::FRAC_PI_2).abs() < 1e-4,
            "{aop}"
        );
    }

    /// A horizontal glass floor seen by a level camera: the reflection of unpolarised light is
    /// s-polarised, and s (the normal of the vertical plane of incidence) is the image's
    /// horizontal: Q > 0, AoP 0, whichever way round s came out.
    #[test]
    fn floor_reflection_is_horizontally_polarized_in_the_camera_frame() {
        let dir = Vec3::new(0.0, -0.6, -0.8); // looking down onto the floor, camera right = +x
        let mut chain = MuellerChain::camera(dir, Vec3::X);
        let (wo, wi) = (-dir, Vec3::new(0.0, 0.6, -0.8)); // mirror about the floor's normal +y
        let n = Vec3::Y;
        let cos = wi.dot(n);
        let ev = [reflection_mueller(cos, Complex::real(1.5)); 4];
        chain.scatter((wo, wi, Vec3::Y), &ev);
        let s = chain.unpolarized(Color::ONE);
        let stokes = Vec4::new(s[0].x, s[1].x, s[2].x, s[3].x);
        assert!(stokes.y > 0.0, "{stokes}");
        assert!(angle_of_polarization(stokes).abs() < 1e-4, "{stokes}");
        // The same with the opposite s (ωi, ωo swapped in the cross product): same Stokes.
        let mut other = MuellerChain::camera(dir, Vec3::X);
        other.x = -other.x;
        other.scatter((wo, wi, Vec3::Y), &ev);
        let t = other.unpolarized(Color::ONE);
        for k in 0..4 {
            assert!((t[k].x - s[k].x).abs() < 1e-6);
        }
    }
}
