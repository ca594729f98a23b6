//! Mesh helpers for the built-in scenes: quads, spheres, boxes and prisms whose shared
//! edges are bit-identical (see the module above).

use crate::scene::Mesh;
use glam::{Quat, Vec2, Vec3};
use std::f32::consts::PI;

/// Append a quad (p, p+u, p+u+v, p+v), CCW seen from the side `u × v` points to.
pub fn quad(mesh: &mut Mesh, p: Vec3, u: Vec3, v: Vec3, material: u32) {
    let n = u.cross(v).normalize();
    let base = mesh.positions.len() as u32;
    for (q, uv) in [
        (p, Vec2::new(0.0, 0.0)),
        (p + u, Vec2::new(1.0, 0.0)),
        (p + u + v, Vec2::new(1.0, 1.0)),
        (p + v, Vec2::new(0.0, 1.0)),
    ] {
        mesh.positions.push(q);
        mesh.normals.push(n);
        mesh.uvs.push(uv);
    }
    mesh.indices.push([base, base + 1, base + 2]);
    mesh.indices.push([base, base + 2, base + 3]);
    mesh.tri_material.extend([material, material]);
}

/// Append a `w × h` rectangle centred at `c` whose front face (CCW side) looks along `normal`.
pub fn rect(mesh: &mut Mesh, c: Vec3, normal: Vec3, w: f32, h: f32, material: u32) {
    let n = normal.normalize();
    // Pick "up" for the rectangle's second side: world Y unless the normal is (nearly) vertical.
    let up = if n.y.abs() > 0.9 { Vec3::Z } else { Vec3::Y };
    let u = up.cross(n).normalize() * w; // u × v ∥ n
    let v = n.cross(u).normalize() * h;
    quad(mesh, c - 0.5 * u - 0.5 * v, u, v, material);
}

/// Append a watertight UV sphere with smooth normals, CCW from outside: one vertex per pole
/// and `segments` vertices per ring shared across the seam (U jumps from 1 − 1/segments
/// back to 0 there).
pub fn sphere(mesh: &mut Mesh, c: Vec3, r: f32, rings: u32, segments: u32, material: u32) {
    let rings = rings.max(2);
    let segments = segments.max(3);
    let base = mesh.positions.len() as u32;
    let mut push = |n: Vec3, uv: Vec2| {
        mesh.positions.push(c + r * n);
        mesh.normals.push(n);
        mesh.uvs.push(uv);
    };
    push(Vec3::Y, Vec2::new(0.5, 0.0));
    for i in 1..rings {
        let theta = PI * i as f32 / rings as f32;
        for j in 0..segments {
            let phi = 2.0 * PI * j as f32 / segments as f32;
            let n = Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                -theta.sin() * phi.sin(),
            );
            push(
                n,
                Vec2::new(j as f32 / segments as f32, i as f32 / rings as f32),
            );
        }
    }
    push(Vec3::NEG_Y, Vec2::new(0.5, 1.0));
    let north = base;
    let south = base + 1 + (rings - 1) * segments;
    let ring = |i: u32, j: u32| base + 1 + (i - 1) * segments + (j % segments);
    for j in 0..segments {
        mesh.indices.push([north, ring(1, j), ring(1, j + 1)]);
        mesh.tri_material.push(material);
    }
    for i in 1..rings - 1 {
        for j in 0..segments {
            let (a, b, c, d) = (
                ring(i, j),
                ring(i + 1, j),
                ring(i + 1, j + 1),
                ring(i, j + 1),
            );
            mesh.indices.push([a, b, c]);
            mesh.indices.push([a, c, d]);
            mesh.tri_material.extend([material, material]);
        }
    }
    for j in 0..segments {
        mesh.indices
            .push([south, ring(rings - 1, j + 1), ring(rings - 1, j)]);
        mesh.tri_material.push(material);
    }
}

/// Append a closed convex polyhedron with flat faces. `faces` list corner indices in cyclic
/// order (either orientation: each face is turned to face away from the centroid). Corner
/// positions are copied from `corners`, so shared edges are bit-identical.
pub fn convex_polyhedron(mesh: &mut Mesh, corners: &[Vec3], faces: &[&[usize]], material: u32) {
    let centroid = corners.iter().copied().sum::<Vec3>() / corners.len().max(1) as f32;
    for face in faces {
        if face.len() < 3 {
            continue;
        }
        let p: Vec<Vec3> = face.iter().map(|&i| corners[i]).collect();
        let mut n = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
        let fc = p.iter().copied().sum::<Vec3>() / p.len() as f32;
        let mut order: Vec<usize> = (0..p.len()).collect();
        if n.dot(fc - centroid) < 0.0 {
            order.reverse();
            n = -n;
        }
        let base = mesh.positions.len() as u32;
        for (k, &o) in order.iter().enumerate() {
            mesh.positions.push(p[o]);
            mesh.normals.push(n);
            let a = 2.0 * PI * k as f32 / order.len() as f32;
            mesh.uvs
                .push(Vec2::new(0.5 + 0.5 * a.cos(), 0.5 + 0.5 * a.sin()));
        }
        for k in 1..order.len() as u32 - 1 {
            mesh.indices.push([base, base + k, base + k + 1]);
            mesh.tri_material.push(material);
        }
    }
}

const BOX_FACES: [&[usize]; 6] = [
    &[0, 1, 3, 2], // −x
    &[4, 5, 7, 6], // +x
    &[0, 1, 5, 4], // −y
    &[2, 3, 7, 6], // +y
    &[0, 2, 6, 4], // −z
    &[1, 3, 7, 5], // +z
];

/// Box with centre `c`, half extents `half`, rotated by `rot`; outward normals.
pub fn oriented_box(mesh: &mut Mesh, c: Vec3, half: Vec3, rot: Quat, material: u32) {
    let corners: Vec<Vec3> = (0..8)
        .map(|k| {
            let s = Vec3::new(
                if k & 4 != 0 { 1.0 } else { -1.0 },
                if k & 2 != 0 { 1.0 } else { -1.0 },
                if k & 1 != 0 { 1.0 } else { -1.0 },
            );
            c + rot * (half * s)
        })
        .collect();
    convex_polyhedron(mesh, &corners, &BOX_FACES, material);
}

/// Axis-aligned box with outward normals.
pub fn cuboid(mesh: &mut Mesh, lo: Vec3, hi: Vec3, material: u32) {
    oriented_box(
        mesh,
        0.5 * (lo + hi),
        0.5 * (hi - lo),
        Quat::IDENTITY,
        material,
    );
}

/// Triangular prism: the triangle `tri` (x, z) extruded from y0 to y1.
pub fn triangular_prism(mesh: &mut Mesh, tri: [Vec2; 3], y0: f32, y1: f32, material: u32) {
    let mut corners = Vec::with_capacity(6);
    for y in [y0, y1] {
        corners.extend(tri.iter().map(|p| Vec3::new(p.x, y, p.y)));
    }
    let faces: [&[usize]; 5] = [
        &[0, 1, 2],
        &[3, 4, 5],
        &[0, 1, 4, 3],
        &[1, 2, 5, 4],
        &[2, 0, 3, 5],
    ];
    convex_polyhedron(mesh, &corners, &faces, material);
}

/// A flat grid of `n × n` cells in y = 0 alternating between two materials, CCW facing +Y.
pub fn checkerboard(mesh: &mut Mesh, center: Vec3, size: f32, n: u32, mat_a: u32, mat_b: u32) {
    let base = mesh.positions.len() as u32;
    let cell = size / n as f32;
    let x0 = center.x - 0.5 * size;
    let z0 = center.z - 0.5 * size;
    for j in 0..=n {
        for i in 0..=n {
            mesh.positions.push(Vec3::new(
                x0 + i as f32 * cell,
                center.y,
                z0 + j as f32 * cell,
            ));
            mesh.normals.push(Vec3::Y);
            mesh.uvs
                .push(Vec2::new(i as f32 / n as f32, j as f32 / n as f32));
        }
    }
    let v = |i: u32, j: u32| base + j * (n + 1) + i;
    for j in 0..n {
        for i in 0..n {
            let m = if (i + j) % 2 == 0 { mat_a } else { mat_b };
            // CCW seen from +Y: (i,j) → (i,j+1) → (i+1,j+1) (x right, z towards the viewer).
            mesh.indices.push([v(i, j), v(i, j + 1), v(i + 1, j + 1)]);
            mesh.indices.push([v(i, j), v(i + 1, j + 1), v(i + 1, j)]);
            mesh.tri_material.extend([m, m]);
        }
    }
}
