//! `glass-of-water`: nested dielectrics (Schmidt & Budge 2002). A thick-walled glass
//! (n = 1.5, priority 1) holds water (n = 1.33, priority 0) whose volume reaches 1.5 mm into
//! the glass wall and 1 mm into its base, the usual way to model a liquid in a container
//! without an air gap: inside the glass the water's surfaces are false hits, so the interface
//! between them refracts with η = 1.33/1.5. A striped straw stands tilted in the water; seen
//! from the side it looks broken and displaced at the water line (the bent straw).

use super::{checkerboard, quad, scene, settings};
use crate::scene::{Camera, Material, Mesh, Scene};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// Glass: outer radius, inner radius, height, base thickness (m).
pub const GLASS: (f32, f32, f32, f32) = (0.08, 0.072, 0.24, 0.02);
/// Water: radius (1.5 mm into the wall), bottom (1 mm into the base), surface height (m).
pub const WATER: (f32, f32, f32) = (0.0735, 0.019, 0.15);
/// Segments around every cylinder (shared by adjoining surfaces: bit-identical edges).
const SEG: u32 = 96;

/// The point at angle index `j` on the circle of radius `r` about the Y axis at height `y`.
fn ring(r: f32, y: f32, j: u32) -> Vec3 {
    let phi = 2.0 * PI * (j % SEG) as f32 / SEG as f32;
    Vec3::new(r * phi.cos(), y, -r * phi.sin())
}

/// A vertical cylinder wall about the Y axis from y0 to y1 with smooth radial normals,
/// facing outwards (`out`) or towards the axis.
fn wall(m: &mut Mesh, r: f32, (y0, y1): (f32, f32), out: bool, material: u32) {
    for j in 0..SEG {
        let (a, b) = (ring(r, y0, j), ring(r, y0, j + 1));
        let (c, d) = (ring(r, y1, j + 1), ring(r, y1, j));
        let (na, nb) = (a.with_y(0.0) / r, b.with_y(0.0) / r);
        let s = if out { 1.0 } else { -1.0 };
        let quad = if out { [a, b, c, d] } else { [a, d, c, b] };
        let norms = if out {
            [na, nb, nb, na]
        } else {
            [na, na, nb, nb]
        };
        push_quad(m, quad, norms.map(|n| n * s), material);
    }
}

/// An annulus (r0 < r1; r0 = 0: a disk) at height y facing +Y (`up`) or −Y.
fn annulus(m: &mut Mesh, (r0, r1): (f32, f32), y: f32, up: bool, material: u32) {
    let n = if up { Vec3::Y } else { Vec3::NEG_Y };
    for j in 0..SEG {
        let (a, b) = (ring(r1, y, j), ring(r1, y, j + 1));
        let (c, d) = (ring(r0, y, j + 1), ring(r0, y, j));
        // CCW seen from +Y: outer j → outer j+1 → inner j+1 (φ grows counter-clockwise).
        if r0 == 0.0 {
            push_tri(m, if up { [a, b, c] } else { [a, c, b] }, n, material);
            continue;
        }
        let q = if up { [a, b, c, d] } else { [a, d, c, b] };
        push_quad(m, q, [n; 4], material);
    }
}

/// One flat triangle with normal `n`.
fn push_tri(m: &mut Mesh, t: [Vec3; 3], n: Vec3, material: u32) {
    let base = m.positions.len() as u32;
    for p in t {
        m.positions.push(p);
        m.normals.push(n);
        m.uvs.push(Vec2::ZERO);
    }
    m.indices.push([base, base + 1, base + 2]);
    m.tri_material.push(material);
}

/// Two triangles (q0, q1, q2), (q0, q2, q3) with per-corner normals.
fn push_quad(m: &mut Mesh, q: [Vec3; 4], n: [Vec3; 4], material: u32) {
    let base = m.positions.len() as u32;
    for (p, n) in q.into_iter().zip(n) {
        m.positions.push(p);
        m.normals.push(n);
        m.uvs.push(Vec2::ZERO);
    }
    m.indices.push([base, base + 1, base + 2]);
    m.indices.push([base, base + 2, base + 3]);
    m.tri_material.extend([material, material]);
}

/// The glass: a closed solid (outer wall, bottom, rim, inner wall, inner bottom).
fn glass(m: &mut Mesh, material: u32) {
    let (ro, ri, h, b) = GLASS;
    wall(m, ro, (0.0, h), true, material);
    annulus(m, (0.0, ro), 0.0, false, material);
    annulus(m, (ri, ro), h, true, material);
    wall(m, ri, (b, h), false, material);
    annulus(m, (0.0, ri), b, true, material);
}

/// The water: a closed cylinder overlapping the glass wall and base.
fn water(m: &mut Mesh, material: u32) {
    let (r, y0, y1) = WATER;
    wall(m, r, (y0, y1), true, material);
    annulus(m, (0.0, r), y0, false, material);
    annulus(m, (0.0, r), y1, true, material);
}

/// A closed straw (tube of radius `r` from `p0` to `p1`, capped), in `stripes` bands
/// alternating between materials `a` and `b`.
fn straw(m: &mut Mesh, (p0, p1): (Vec3, Vec3), r: f32, stripes: u32, (a, b): (u32, u32)) {
    let axis = (p1 - p0).normalize();
    let u = axis.cross(Vec3::Z).normalize();
    let v = axis.cross(u);
    let at = |t: f32, j: u32| {
        let phi = 2.0 * PI * (j % 24) as f32 / 24.0;
        let n = u * phi.cos() + v * phi.sin();
        (p0 + (p1 - p0) * t + n * r, n)
    };
    for k in 0..stripes {
        let (t0, t1) = (k as f32 / stripes as f32, (k + 1) as f32 / stripes as f32);
        let mat = if k % 2 == 0 { a } else { b };
        for j in 0..24 {
            let (pa, na) = at(t0, j);
            let (pb, nb) = at(t0, j + 1);
            let (pc, nc) = at(t1, j + 1);
            let (pd, nd) = at(t1, j);
            // Outward: (pb − pa) × (pd − pa) must point along n.
            let q = [pa, pb, pc, pd];
            if (pb - pa).cross(pd - pa).dot(na) > 0.0 {
                push_quad(m, q, [na, nb, nc, nd], mat);
            } else {
                push_quad(m, [pa, pd, pc, pb], [na, nd, nc, nb], mat);
            }
        }
    }
    for (t, n, mat) in [(0.0, -axis, a), (1.0, axis, a)] {
        for j in 0..24 {
            let (c, (pa, _), (pb, _)) = (p0 + (p1 - p0) * t, at(t, j), at(t, j + 1));
            let tri = if (pa - c).cross(pb - c).dot(n) > 0.0 {
                [c, pa, pb]
            } else {
                [c, pb, pa]
            };
            push_tri(m, tri, n, mat);
        }
    }
}

/// The glass of water with a straw on a checkerboard table before a striped wall, lit by one
/// 0.6 × 0.6 m area light (radiance 20) above and in front.
pub fn glass_of_water() -> Scene {
    let mut m = Mesh::default();
    // The table 1 mm below the glass's base (no coincident surfaces).
    checkerboard(&mut m, Vec3::new(0.0, -0.001, 0.0), 1.6, 16, 0, 1);
    back_wall(&mut m, (2, 3));
    let lc = Vec3::new(0.3, 1.0, 0.6);
    let ln = -lc.normalize();
    super::rect(&mut m, lc, ln, 0.6, 0.6, 4);
    glass(&mut m, 5);
    water(&mut m, 6);
    let ends = (Vec3::new(0.02, 0.03, 0.055), Vec3::new(-0.06, 0.33, 0.0));
    straw(&mut m, ends, 0.005, 12, (7, 8));
    let cam = Camera::look_at(
        Vec3::new(0.0, 0.24, 0.8),
        Vec3::new(0.0, 0.16, 0.0),
        Vec3::Y,
        0.45,
    );
    scene(
        "glass-of-water",
        m,
        materials(),
        cam,
        Vec3::splat(0.05),
        settings(400, 400),
    )
}

/// The scene's materials, indexed by the mesh: 0–1 table checks, 2–3 wall and its stripes,
/// 4 the light, 5 glass (priority 1), 6 water (priority 0, tinted), 7–8 the straw's bands.
fn materials() -> Vec<Material> {
    vec![
        Material::diffuse("table-light", Vec3::splat(0.75)),
        Material::diffuse("table-dark", Vec3::splat(0.15)),
        Material::diffuse("wall", Vec3::splat(0.7)),
        Material::diffuse("wall-stripe", Vec3::new(0.1, 0.15, 0.4)),
        Material::emitter("light", Vec3::splat(20.0)),
        Material {
            priority: 1,
            ..Material::glass("glass", 1.5)
        },
        Material {
            attenuation_color: Vec3::new(0.85, 0.95, 1.0),
            attenuation_distance: 0.3,
            ..Material::glass("water", 1.33)
        },
        Material::diffuse("straw-red", Vec3::new(0.8, 0.08, 0.06)),
        Material::diffuse("straw-white", Vec3::splat(0.85)),
    ]
}

/// The back wall at z = −0.35: 20 pairs of vertical bands 4 cm wide and 0.8 m high from
/// x = −0.8, alternating materials `plain` and `stripe`.
fn back_wall(m: &mut Mesh, (plain, stripe): (u32, u32)) {
    for k in 0..20 {
        let x = -0.8 + 0.08 * k as f32;
        let p = Vec3::new(x, 0.0, -0.35);
        quad(
            m,
            p,
            Vec3::new(0.04, 0.0, 0.0),
            Vec3::new(0.0, 0.8, 0.0),
            plain,
        );
        let p = Vec3::new(x + 0.04, 0.0, -0.35);
        quad(
            m,
            p,
            Vec3::new(0.04, 0.0, 0.0),
            Vec3::new(0.0, 0.8, 0.0),
            stripe,
        );
    }
}
