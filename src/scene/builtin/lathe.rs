//! Surfaces of revolution (a lathe): the lecture's lens and wine glass. A closed profile that
//! starts and ends on the axis sweeps a closed, watertight solid.

use crate::scene::Mesh;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// Profile segments meeting at more than this angle keep their own normals (a crease: the
/// rim of a glass, the edge of a lens); gentler joints share an averaged normal (smooth).
const CREASE_COS: f32 = 0.866; // cos 30°

/// Append the surface swept by revolving `profile` — points (r, h): distance from the axis
/// and height along it — about the axis through `origin` along `axis`, in `segments` steps.
/// Walk the profile with the solid on the left (for a solid that starts and ends on the
/// axis: outwards along the bottom, up the outside, back in over the top); the outward normal
/// is then the profile's right-hand side, and triangles wind CCW seen from outside. Points
/// with r = 0 close the surface at the axis; positions are computed from (r, h, φ) alone, so
/// rings shared by two segments are bit-identical and the solid has no cracks.
pub fn lathe(
    mesh: &mut Mesh,
    origin: Vec3,
    axis: Vec3,
    profile: &[Vec2],
    segments: u32,
    material: u32,
) {
    let segments = segments.max(3);
    let a = axis.normalize();
    let (u, w) = a.any_orthonormal_pair();
    let at = |p: Vec2, phi: f32| origin + p.y * a + p.x * (phi.cos() * u + phi.sin() * w);
    let normal_at =
        |n: Vec2, phi: f32| (n.y * a + n.x * (phi.cos() * u + phi.sin() * w)).normalize();
    let seg_normals: Vec<Vec2> = profile
        .windows(2)
        .map(|s| {
            let d = s[1] - s[0];
            Vec2::new(d.y, -d.x).normalize_or_zero()
        })
        .collect();
    for (k, s) in profile.windows(2).enumerate() {
        if (s[1] - s[0]).length_squared() == 0.0 {
            continue;
        }
        let ends = [
            end_normal(&seg_normals, k, k.checked_sub(1)),
            end_normal(&seg_normals, k, Some(k + 1)),
        ];
        let base = mesh.positions.len() as u32;
        for j in 0..=segments {
            let phi = 2.0 * PI * (j % segments) as f32 / segments as f32;
            for e in 0..2 {
                mesh.positions.push(at(s[e], phi));
                mesh.normals.push(normal_at(ends[e], phi));
                mesh.uvs.push(Vec2::new(
                    j as f32 / segments as f32,
                    (k + e) as f32 / (profile.len() - 1) as f32,
                ));
            }
        }
        for j in 0..segments {
            let (a0, b0) = (base + 2 * j, base + 2 * j + 1);
            let (a1, b1) = (a0 + 2, b0 + 2);
            // Drop the triangle that degenerates where an end lies on the axis.
            if s[0].x != 0.0 {
                push_outward(mesh, [a0, a1, b1], material);
            }
            if s[1].x != 0.0 {
                push_outward(mesh, [a0, b1, b0], material);
            }
        }
    }
}

/// The normal at one end of profile segment `k`: averaged with the neighbour `other` when
/// the joint is smooth, the segment's own across a crease or at the profile's ends.
fn end_normal(normals: &[Vec2], k: usize, other: Option<usize>) -> Vec2 {
    let own = normals[k];
    match other.and_then(|o| normals.get(o)) {
        Some(&n) if n.dot(own) >= CREASE_COS => (n + own).normalize_or_zero(),
        _ => own,
    }
}

/// Push triangle `t`, wound so that its face normal agrees with its vertex normals.
fn push_outward(mesh: &mut Mesh, t: [u32; 3], material: u32) {
    let p = t.map(|i| mesh.positions[i as usize]);
    let n = t.map(|i| mesh.normals[i as usize]);
    let face = (p[1] - p[0]).cross(p[2] - p[0]);
    let t = if face.dot(n[0] + n[1] + n[2]) < 0.0 {
        [t[0], t[2], t[1]]
    } else {
        t
    };
    mesh.indices.push(t);
    mesh.tri_material.push(material);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A cylinder (r 1, h 2) closed at both ends: every edge is shared by exactly two
    /// triangles (watertight) and the normals point away from the axis or along it.
    #[test]
    fn a_closed_profile_sweeps_a_watertight_outward_solid() {
        let profile = [
            Vec2::new(0.0, 0.0),
            Vec2::new(1.0, 0.0),
            Vec2::new(1.0, 2.0),
            Vec2::new(0.0, 2.0),
        ];
        let mut m = Mesh::default();
        lathe(&mut m, Vec3::ZERO, Vec3::Y, &profile, 16, 0);
        let key = |i: u32| m.positions[i as usize].to_array().map(f32::to_bits);
        let mut edges = std::collections::HashMap::new();
        for t in &m.indices {
            for e in 0..3 {
                let (a, b) = (key(t[e]), key(t[(e + 1) % 3]));
                *edges.entry((a.min(b), a.max(b))).or_insert(0) += 1;
            }
            let p = t.map(|i| m.positions[i as usize]);
            let c = (p[0] + p[1] + p[2]) / 3.0;
            let face = (p[1] - p[0]).cross(p[2] - p[0]);
            assert!(
                face.dot(c - Vec3::new(0.0, 1.0, 0.0)) > 0.0,
                "inward face at {c}"
            );
        }
        assert!(
            edges.values().all(|&n| n == 2),
            "open or non-manifold edges"
        );
        // Bottom, side and top: 16 + 32 + 16 triangles.
        assert_eq!(m.indices.len(), 64);
    }
}
