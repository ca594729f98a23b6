//! Built-in scenes (`builtin:NAME`), constructed in code (fast, exact). The same scenes are
//! committed as `assets/NAME.glb` (written by `examples/export_builtins.rs`) for Blender.
//!
//! 1 unit = 1 m, +Y up. Every scene sets its own [`RenderSettings`]. Geometry helpers keep
//! shared edges bit-identical (spheres share seam and pole vertices; boxes and prisms copy
//! each face's corners from one corner array), so a watertight intersector sees no cracks.

use super::{Camera, Material, MaterialKind, Mesh, RenderSettings, Scene};
use crate::bsdf::{Metal, MicrofacetDistribution};
use glam::{Quat, Vec2, Vec3};
use std::f32::consts::PI;

pub mod glass_of_water;
pub mod khronos;

/// Names accepted by [`load`] (the first is the default scene).
pub const NAMES: &[&str] = &[
    "cornell-glass",
    "glass-slab",
    "furnace",
    "rough-glass",
    "prism",
    "caustic",
    "materials",
    "caustic-mirror",
    "glass-of-water",
    "env-spheres",
    "sun-sky",
    "ior-grid",
    "transmission-roughness",
    "metals",
];

pub fn load(name: &str) -> anyhow::Result<Scene> {
    match name {
        "cornell-glass" => Ok(cornell_glass()),
        "glass-slab" => Ok(glass_slab()),
        "furnace" => Ok(furnace()),
        "rough-glass" => Ok(rough_glass()),
        "prism" => Ok(prism()),
        "caustic" => Ok(caustic()),
        "materials" => Ok(materials()),
        "caustic-mirror" => Ok(caustic_mirror()),
        "glass-of-water" => Ok(glass_of_water::glass_of_water()),
        "env-spheres" => Ok(env_spheres()),
        "sun-sky" => Ok(sun_sky()),
        "ior-grid" => Ok(khronos::ior_grid()),
        "transmission-roughness" => Ok(khronos::transmission_roughness()),
        "metals" => Ok(metals()),
        _ => anyhow::bail!(
            "unknown built-in scene '{name}' (available: {})",
            NAMES.join(", ")
        ),
    }
}

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

fn scene(
    name: &str,
    mesh: Mesh,
    materials: Vec<Material>,
    camera: Camera,
    environment: Vec3,
    settings: RenderSettings,
) -> Scene {
    Scene {
        name: name.into(),
        mesh,
        materials,
        textures: vec![],
        punctual_lights: vec![],
        camera,
        environment,
        env_map: None,
        settings,
        warnings: vec![],
    }
}

fn settings(width: u32, height: u32) -> RenderSettings {
    RenderSettings {
        width,
        height,
        ..Default::default()
    }
}

/// Rough dielectric (solid, GGX).
pub fn rough_glass_material(name: &str, ior: f32, roughness: f32) -> Material {
    Material {
        roughness,
        ..Material::glass(name, ior)
    }
}

/// Glossy metal: microfacet reflection with reflectance `color`, α = roughness².
pub fn glossy_metal(name: &str, color: Vec3, roughness: f32) -> Material {
    Material {
        name: name.into(),
        kind: MaterialKind::GlossyMetal,
        base_color: color,
        metallic: 1.0,
        roughness,
        ..Default::default()
    }
}

/// glTF metallic-roughness dielectric ("plastic"): metallic 0.
pub fn plastic(name: &str, color: Vec3, roughness: f32) -> Material {
    Material {
        name: name.into(),
        kind: MaterialKind::MetalRough,
        base_color: color,
        metallic: 0.0,
        roughness,
        ..Default::default()
    }
}

/// Cornell box materials 0..=3 (white, red, green, light) and geometry: x, z ∈ [−1, 1],
/// y ∈ [0, 2], open towards +z; a 0.5 × 0.5 m light 1 mm under the ceiling facing down.
fn cornell_box(m: &mut Mesh) -> Vec<Material> {
    let s = 1.0;
    quad(
        m,
        Vec3::new(-s, 0.0, -s),
        Vec3::Z * 2.0 * s,
        Vec3::X * 2.0 * s,
        0,
    ); // floor, +Y
    quad(
        m,
        Vec3::new(-s, 2.0 * s, -s),
        Vec3::X * 2.0 * s,
        Vec3::Z * 2.0 * s,
        0,
    ); // ceiling, −Y
    quad(
        m,
        Vec3::new(-s, 0.0, -s),
        Vec3::X * 2.0 * s,
        Vec3::Y * 2.0 * s,
        0,
    ); // back, +Z
    quad(
        m,
        Vec3::new(-s, 0.0, -s),
        Vec3::Y * 2.0 * s,
        Vec3::Z * 2.0 * s,
        1,
    ); // left red, +X
    quad(
        m,
        Vec3::new(s, 0.0, -s),
        Vec3::Z * 2.0 * s,
        Vec3::Y * 2.0 * s,
        2,
    ); // right green, −X
    let l = 0.25;
    quad(
        m,
        Vec3::new(-l, 1.999, -l),
        Vec3::X * 2.0 * l,
        Vec3::Z * 2.0 * l,
        3,
    ); // light, −Y
    vec![
        Material::diffuse("white", Vec3::splat(0.75)),
        Material::diffuse("red", Vec3::new(0.63, 0.065, 0.05)),
        Material::diffuse("green", Vec3::new(0.14, 0.45, 0.091)),
        Material::emitter("light", Vec3::splat(17.0)),
    ]
}

fn cornell_camera() -> Camera {
    Camera::look_at(
        Vec3::new(0.0, 1.0, 3.9),
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::Y,
        0.6911,
    )
}

/// Default scene: Cornell box, smooth solid glass sphere (IOR 1.5, r = 0.35 m) and a mirror
/// box (0.55 × 1.1 × 0.5 m) turned 15° about Y.
pub fn cornell_glass() -> Scene {
    let mut m = Mesh::default();
    let mut materials = cornell_box(&mut m);
    materials.push(Material::glass("glass", 1.5));
    materials.push(Material::mirror("mirror", Vec3::splat(0.95)));
    sphere(&mut m, Vec3::new(0.35, 0.35, 0.3), 0.35, 48, 96, 4);
    oriented_box(
        &mut m,
        Vec3::new(-0.45, 0.55, -0.35),
        Vec3::new(0.275, 0.55, 0.25),
        Quat::from_rotation_y(15f32.to_radians()),
        5,
    );
    scene(
        "cornell-glass",
        m,
        materials,
        cornell_camera(),
        Vec3::ZERO,
        settings(512, 512),
    )
}

/// A 1.2 × 0.2 × 0.8 m smooth glass slab (IOR 1.5), tilted ~26° about X and turned 20° about
/// Y, 0.3–0.8 m over a 10 × 10 m checkerboard of 0.25 m squares (albedo 0.8 / 0.05), lit by
/// a 2 × 2 m area light (radiance 6) 3 m up.
pub fn glass_slab() -> Scene {
    let materials = vec![
        Material::diffuse("checker-light", Vec3::splat(0.8)),
        Material::diffuse("checker-dark", Vec3::splat(0.05)),
        Material::glass("glass", 1.5),
        Material::emitter("light", Vec3::splat(6.0)),
    ];
    let mut m = Mesh::default();
    checkerboard(&mut m, Vec3::ZERO, 10.0, 40, 0, 1);
    oriented_box(
        &mut m,
        Vec3::new(0.0, 0.55, 0.0),
        Vec3::new(0.6, 0.1, 0.4),
        Quat::from_rotation_y(20f32.to_radians()) * Quat::from_rotation_x(26f32.to_radians()),
        2,
    );
    rect(&mut m, Vec3::new(-0.6, 3.0, 0.4), Vec3::NEG_Y, 2.0, 2.0, 3);
    let cam = Camera::look_at(
        Vec3::new(0.0, 2.2, 2.4),
        Vec3::new(0.0, 0.3, 0.0),
        Vec3::Y,
        0.75,
    );
    scene(
        "glass-slab",
        m,
        materials,
        cam,
        Vec3::ZERO,
        settings(640, 480),
    )
}

/// White furnace: diffuse (albedo 1), mirror (reflectance 1) and smooth glass (IOR 1.5)
/// spheres of radius 0.5 m in a uniform environment of radiance 1; no lights. Every pixel
/// should render exactly 1.
pub fn furnace() -> Scene {
    let materials = vec![
        Material::diffuse("white", Vec3::ONE),
        Material::mirror("mirror", Vec3::ONE),
        Material::glass("glass", 1.5),
    ];
    let mut m = Mesh::default();
    sphere(&mut m, Vec3::new(-1.1, 0.0, 0.0), 0.5, 48, 96, 0);
    sphere(&mut m, Vec3::new(0.0, 0.0, 0.0), 0.5, 48, 96, 1);
    sphere(&mut m, Vec3::new(1.1, 0.0, 0.0), 0.5, 48, 96, 2);
    let cam = Camera::look_at(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, Vec3::Y, 0.7);
    scene("furnace", m, materials, cam, Vec3::ONE, settings(256, 128))
}

/// Cornell box with a rough solid glass sphere (IOR 1.5, roughness 0.3 → α = 0.09, GGX),
/// r = 0.45 m, on the floor in the middle.
pub fn rough_glass() -> Scene {
    let mut m = Mesh::default();
    let mut materials = cornell_box(&mut m);
    let mut g = rough_glass_material("rough-glass", 1.5, 0.3);
    g.distribution = MicrofacetDistribution::Ggx;
    materials.push(g);
    sphere(&mut m, Vec3::new(0.0, 0.45, 0.0), 0.45, 48, 96, 4);
    scene(
        "rough-glass",
        m,
        materials,
        cornell_camera(),
        Vec3::ZERO,
        settings(512, 512),
    )
}

/// Geometry of the prism scene in the xz plane (see [`prism`]).
pub struct PrismLayout {
    /// Unit direction of the incoming beam (xz), 19.3° off the prism base.
    pub beam_in: Vec2,
    /// Unit direction of the beam at minimum deviation after the prism (xz).
    pub beam_out: Vec2,
    pub entry: Vec2,
    pub exit: Vec2,
}

/// A 60° prism of side 0.35 m with its base along x, apex towards +z, centroid at the origin.
pub fn prism_layout(side: f32, n: f32) -> PrismLayout {
    // Minimum deviation of a 60° prism: sin θi = n sin 30°, the inside ray parallel to the base.
    let theta_i = (n * 0.5).asin();
    let tilt = theta_i - 30f32.to_radians();
    let h = side * 3f32.sqrt() / 2.0;
    PrismLayout {
        beam_in: Vec2::new(tilt.cos(), tilt.sin()),
        beam_out: Vec2::new(tilt.cos(), -tilt.sin()),
        entry: Vec2::new(-side / 4.0, h / 6.0),
        exit: Vec2::new(side / 4.0, h / 6.0),
    }
}

/// The prism scene's apex angle (degrees).
pub const PRISM_APEX_DEG: f32 = 60.0;
/// The index the prism scene's beam is aimed at minimum deviation for (n_d of BK7).
pub const PRISM_DESIGN_N_D: f32 = 1.5168;
/// Distance (m) from the prism's exit face to the wall the spectrum lands on.
pub const PRISM_WALL_DISTANCE: f32 = 0.9;

/// Dispersion: a 60° triangular prism (side 0.35 m, 0.35 m tall) of dispersive glass
/// (n_d = 1.5168, Abbe V_d = 20) on a floor (albedo 0.5). A black housing (0.4 m deep) holds a
/// 0.04 × 0.2 m emitter of radiance 4000 behind a 12 mm × 0.2 m slit, 0.7 m from the prism,
/// aimed at minimum deviation; the spectrum lands on a white wall (albedo 0.8, 0.6 × 0.6 m)
/// 0.9 m past the prism, perpendicular to the deviated beam. A dim environment (0.02) fills.
pub fn prism() -> Scene {
    let n_d = PRISM_DESIGN_N_D;
    let materials = vec![
        Material::diffuse("floor", Vec3::splat(0.5)),
        Material::diffuse("wall", Vec3::splat(0.8)),
        Material {
            abbe: Some(20.0),
            ..Material::glass("dispersive-glass", n_d)
        },
        Material {
            double_sided: true,
            ..Material::diffuse("housing", Vec3::ZERO)
        },
        Material::emitter("slit-light", Vec3::splat(4000.0)),
    ];
    let mut m = Mesh::default();
    rect(&mut m, Vec3::new(0.0, 0.0, 0.0), Vec3::Y, 4.0, 4.0, 0);

    let side = 0.35;
    let h = side * 3f32.sqrt() / 2.0;
    let tri = [
        Vec2::new(-side / 2.0, -h / 3.0),
        Vec2::new(side / 2.0, -h / 3.0),
        Vec2::new(0.0, 2.0 * h / 3.0),
    ];
    triangular_prism(&mut m, tri, 0.0, 0.35, 2);

    let lay = prism_layout(side, n_d);
    // Wall, perpendicular to the deviated beam, facing back towards the prism.
    let wall_c = lay.exit + PRISM_WALL_DISTANCE * lay.beam_out;
    rect(
        &mut m,
        xz_to_3d(wall_c, 0.3),
        -xz_to_3d(lay.beam_out, 0.0),
        0.6,
        0.6,
        1,
    );
    slit_housing(&mut m, &lay, 3, 4);

    let cam = Camera::look_at(
        Vec3::new(-0.1, 1.2, 1.7),
        Vec3::new(-0.1, 0.1, -0.15),
        Vec3::Y,
        0.75,
    );
    scene(
        "prism",
        m,
        materials,
        cam,
        Vec3::splat(0.02),
        settings(640, 400),
    )
}

/// The point (p.x, y, p.y) of the xz-plane point `p` at height `y`.
fn xz_to_3d(p: Vec2, y: f32) -> Vec3 {
    Vec3::new(p.x, y, p.y)
}

/// Box of the prism's light source in its own frame.
struct Housing {
    /// Centre of the back plate.
    back_c: Vec3,
    /// Forward (along the beam) and sideways (horizontal) unit axes.
    f: Vec3,
    s: Vec3,
    /// Length along `f`; half width along `s`; half height along +Y.
    depth: f32,
    half_w: f32,
    half_h: f32,
}

/// The prism's light source: a black box (material `hm`) whose front plate has the slit,
/// 0.7 m before the entry point along the beam; the emitter (material `em`) sits at the back.
fn slit_housing(m: &mut Mesh, lay: &PrismLayout, hm: u32, em: u32) {
    let f = xz_to_3d(lay.beam_in, 0.0); // forward
    let s = Vec3::new(-lay.beam_in.y, 0.0, lay.beam_in.x); // sideways (horizontal)
    let slit_c = xz_to_3d(lay.entry - 0.7 * lay.beam_in, 0.15);
    let depth = 0.4;
    let hb = Housing {
        back_c: slit_c - depth * f,
        f,
        s,
        depth,
        half_w: 0.03,
        half_h: 0.12,
    };
    housing_walls(m, &hb, hm);
    slit_plate(m, &hb, slit_c, hm);
    // Emitter just in front of the back plate, facing forward.
    rect(m, hb.back_c + 0.002 * f, f, 0.04, 0.2, em);
}

/// Side, top and bottom walls and the back plate of the housing (double-sided black quads).
fn housing_walls(m: &mut Mesh, hb: &Housing, hm: u32) {
    let Housing {
        back_c,
        f,
        s,
        depth,
        half_w,
        half_h,
    } = *hb;
    quad(
        m,
        back_c - half_w * s - half_h * Vec3::Y,
        depth * f,
        2.0 * half_h * Vec3::Y,
        hm,
    );
    quad(
        m,
        back_c + half_w * s - half_h * Vec3::Y,
        2.0 * half_h * Vec3::Y,
        depth * f,
        hm,
    );
    quad(
        m,
        back_c - half_w * s + half_h * Vec3::Y,
        depth * f,
        2.0 * half_w * s,
        hm,
    );
    quad(
        m,
        back_c - half_w * s - half_h * Vec3::Y,
        2.0 * half_w * s,
        depth * f,
        hm,
    );
    // Back plate.
    quad(
        m,
        back_c - half_w * s - half_h * Vec3::Y,
        2.0 * half_h * Vec3::Y,
        2.0 * half_w * s,
        hm,
    );
}

/// Front plate of the housing around a 12 mm × 0.2 m slit centred at `fp`: left, right, top
/// and bottom strips.
fn slit_plate(m: &mut Mesh, hb: &Housing, fp: Vec3, hm: u32) {
    let (s, half_w, half_h) = (hb.s, hb.half_w, hb.half_h);
    let (slit_hw, slit_hh) = (0.006, 0.1);
    let corner = fp - half_w * s - half_h * Vec3::Y;
    quad(
        m,
        corner,
        (half_w - slit_hw) * s,
        2.0 * half_h * Vec3::Y,
        hm,
    );
    quad(
        m,
        fp + slit_hw * s - half_h * Vec3::Y,
        (half_w - slit_hw) * s,
        2.0 * half_h * Vec3::Y,
        hm,
    );
    quad(
        m,
        fp - slit_hw * s + slit_hh * Vec3::Y,
        2.0 * slit_hw * s,
        (half_h - slit_hh) * Vec3::Y,
        hm,
    );
    quad(
        m,
        fp - slit_hw * s - half_h * Vec3::Y,
        2.0 * slit_hw * s,
        (half_h - slit_hh) * Vec3::Y,
        hm,
    );
}

/// Caustics: a smooth glass sphere (r = 0.3 m, IOR 1.5) and an upright glass block
/// (0.1 × 0.4 × 0.6 m) on a 4 × 4 m diffuse floor (albedo 0.8) with a back wall, lit by a
/// 0.1 × 0.1 m light of radiance 1000 at 45° elevation, 2 m from the sphere; the sphere
/// focuses it to a bright spot just beyond its contact point.
pub fn caustic() -> Scene {
    let materials = vec![
        Material::diffuse("floor", Vec3::splat(0.8)),
        Material::glass("glass", 1.5),
        Material::emitter("light", Vec3::splat(1000.0)),
        Material::diffuse("wall", Vec3::splat(0.6)),
    ];
    let mut m = Mesh::default();
    rect(&mut m, Vec3::ZERO, Vec3::Y, 4.0, 4.0, 0);
    rect(&mut m, Vec3::new(0.0, 1.0, -1.5), Vec3::Z, 4.0, 2.0, 3);
    let c = Vec3::new(0.0, 0.3, 0.0);
    sphere(&mut m, c, 0.3, 48, 96, 1);
    oriented_box(
        &mut m,
        Vec3::new(0.75, 0.2, -0.6),
        Vec3::new(0.05, 0.2, 0.3),
        Quat::IDENTITY,
        1,
    );
    let to_light = Vec3::new(-1.0, 1.0, 0.0).normalize();
    let lp = c + 2.0 * to_light;
    rect(&mut m, lp, -to_light, 0.1, 0.1, 2);
    let cam = Camera::look_at(
        Vec3::new(0.3, 1.3, 2.6),
        Vec3::new(0.2, 0.15, -0.2),
        Vec3::Y,
        0.6,
    );
    scene("caustic", m, materials, cam, Vec3::ZERO, settings(640, 480))
}

/// The ball-lens caustic seen directly and in a mirror: the glass sphere of [`caustic`]
/// (r = 0.3 m, IOR 1.5) on a 4 × 4 m diffuse floor (albedo 0.8) under a 0.1 × 0.1 m light of
/// radiance 1000 2 m away at about 39° elevation (so the focused spot lies clear of the
/// sphere), and a 1.6 × 0.9 m perfect mirror (reflectance 0.95) standing on the floor 0.45 m
/// behind the sphere, facing the camera. The spot beside the contact point is the path class
/// LS+DE; its reflection in the mirror is LS+DS+E, which no connection of a light subpath to
/// the camera can make.
pub fn caustic_mirror() -> Scene {
    let materials = vec![
        Material::diffuse("floor", Vec3::splat(0.8)),
        Material::glass("glass", 1.5),
        Material::emitter("light", Vec3::splat(1000.0)),
        Material::mirror("mirror", Vec3::splat(0.95)),
    ];
    let mut m = Mesh::default();
    rect(&mut m, Vec3::ZERO, Vec3::Y, 4.0, 4.0, 0);
    let c = Vec3::new(0.0, 0.3, 0.0);
    sphere(&mut m, c, 0.3, 48, 96, 1);
    let to_light = Vec3::new(-1.0, 0.8, 0.0).normalize();
    let lp = c + 2.0 * to_light;
    rect(&mut m, lp, -to_light, 0.1, 0.1, 2);
    rect(&mut m, Vec3::new(0.2, 0.45, -0.45), Vec3::Z, 1.6, 0.9, 3);
    let cam = Camera::look_at(
        Vec3::new(0.9, 1.5, 2.0),
        Vec3::new(0.2, 0.15, -0.35),
        Vec3::Y,
        0.6,
    );
    scene(
        "caustic-mirror",
        m,
        materials,
        cam,
        Vec3::ZERO,
        settings(320, 240),
    )
}

/// Material sweep: back row of gold metal spheres (mirror, GlossyMetal roughness 0.1, 0.3,
/// 0.6), front row of blue metallic-roughness plastic (metallic 0, roughness 0.05, 0.2, 0.45,
/// 0.8); r = 0.2 m, 0.5 m apart (rows at z = −0.5 and 0.3), on a floor (albedo 0.5) with a back wall, under a
/// 1.5 × 0.8 m light of radiance 12 at 2.5 m; environment 0.1.
pub fn materials() -> Scene {
    let gold = Vec3::new(0.95, 0.78, 0.42);
    let blue = Vec3::new(0.1, 0.25, 0.8);
    let mut materials = vec![
        Material::diffuse("floor", Vec3::splat(0.5)),
        Material::emitter("light", Vec3::splat(12.0)),
        Material::mirror("metal-r0", gold),
    ];
    for r in [0.1, 0.3, 0.6] {
        materials.push(glossy_metal(&format!("metal-r{r}"), gold, r));
    }
    for r in [0.05, 0.2, 0.45, 0.8] {
        materials.push(plastic(&format!("plastic-r{r}"), blue, r));
    }
    let mut m = Mesh::default();
    rect(&mut m, Vec3::ZERO, Vec3::Y, 6.0, 4.0, 0);
    rect(&mut m, Vec3::new(0.0, 1.5, -1.5), Vec3::Z, 6.0, 3.0, 0);
    rect(&mut m, Vec3::new(0.0, 2.5, 0.2), Vec3::NEG_Y, 1.5, 0.8, 1);
    for k in 0..4 {
        let x = -0.75 + 0.5 * k as f32;
        sphere(&mut m, Vec3::new(x, 0.2, -0.5), 0.2, 32, 64, 2 + k);
        sphere(&mut m, Vec3::new(x, 0.2, 0.3), 0.2, 32, 64, 6 + k);
    }
    let cam = Camera::look_at(
        Vec3::new(0.0, 1.6, 2.1),
        Vec3::new(0.0, 0.15, -0.15),
        Vec3::Y,
        0.6,
    );
    scene(
        "materials",
        m,
        materials,
        cam,
        Vec3::splat(0.1),
        settings(640, 360),
    )
}

/// Image-based lighting: a white diffuse, a gold glossy metal (roughness 0.3), a smooth glass
/// (IOR 1.5) and a blue plastic sphere (roughness 0.2), r = 0.35 m, on a grey floor
/// (albedo 0.5, 30 × 30 m) under the generated sun-and-sky HDRI (`assets/sun-sky.hdr`, sun at
/// 35° elevation); no other light.
pub fn env_spheres() -> Scene {
    let gold = Vec3::new(0.95, 0.78, 0.42);
    let materials = vec![
        Material::diffuse("floor", Vec3::splat(0.5)),
        Material::diffuse("white", Vec3::splat(0.8)),
        glossy_metal("gold-r0.3", gold, 0.3),
        Material::glass("glass", 1.5),
        plastic("blue-plastic", Vec3::new(0.1, 0.25, 0.8), 0.2),
    ];
    let mut m = Mesh::default();
    rect(&mut m, Vec3::ZERO, Vec3::Y, 30.0, 30.0, 0);
    for k in 0..4 {
        let x = -1.2 + 0.8 * k as f32;
        sphere(&mut m, Vec3::new(x, 0.35, 0.0), 0.35, 48, 96, 1 + k);
    }
    let cam = Camera::look_at(
        Vec3::new(0.0, 1.1, 3.2),
        Vec3::new(0.0, 0.3, 0.0),
        Vec3::Y,
        0.6,
    );
    let mut s = scene(
        "env-spheres",
        m,
        materials,
        cam,
        Vec3::ZERO,
        settings(480, 270),
    );
    s.env_map = Some(super::hdri::sun_sky_env());
    s
}

/// The benchmark of environment importance sampling: a white diffuse, a blue plastic
/// (roughness 0.45) and a gold glossy metal sphere (roughness 0.6), r = 0.35 m, on a grey
/// floor under the generated sun-and-sky HDRI; nothing specular, so no caustic hides the
/// difference the sampling of the sun makes.
pub fn sun_sky() -> Scene {
    let gold = Vec3::new(0.95, 0.78, 0.42);
    let materials = vec![
        Material::diffuse("floor", Vec3::splat(0.5)),
        Material::diffuse("white", Vec3::splat(0.8)),
        plastic("blue-plastic", Vec3::new(0.1, 0.25, 0.8), 0.45),
        glossy_metal("gold-r0.6", gold, 0.6),
    ];
    let mut m = Mesh::default();
    rect(&mut m, Vec3::ZERO, Vec3::Y, 30.0, 30.0, 0);
    for k in 0..3 {
        let x = -0.8 + 0.8 * k as f32;
        sphere(&mut m, Vec3::new(x, 0.35, 0.0), 0.35, 24, 48, 1 + k);
    }
    let cam = Camera::look_at(
        Vec3::new(0.0, 1.1, 3.2),
        Vec3::new(0.0, 0.3, 0.0),
        Vec3::Y,
        0.5,
    );
    let mut s = scene("sun-sky", m, materials, cam, Vec3::ZERO, settings(320, 180));
    s.env_map = Some(super::hdri::sun_sky_env());
    s
}

/// Tabulated metals (`extras.conductor`): gold, silver, copper and aluminium spheres
/// (r = 0.3 m, white base colour = the bare metal), smooth in the front row and rough
/// (roughness 0.3, GGX) behind, on a checkerboard under a uniform white sky (no sun: no
/// caustics or fireflies, so the comparison with Mitsuba measures the conductors).
pub fn metals() -> Scene {
    let mut materials = vec![
        Material::diffuse("checker-light", Vec3::splat(0.7)),
        Material::diffuse("checker-dark", Vec3::splat(0.1)),
    ];
    for m in Metal::ALL {
        materials.push(Material {
            conductor: Some(m),
            ..Material::mirror(m.symbol(), Vec3::ONE)
        });
    }
    for m in Metal::ALL {
        materials.push(Material {
            conductor: Some(m),
            ..glossy_metal(&format!("{}-r0.3", m.symbol()), Vec3::ONE, 0.3)
        });
    }
    let mut mesh = Mesh::default();
    checkerboard(&mut mesh, Vec3::ZERO, 6.0, 12, 0, 1);
    for k in 0..4u32 {
        let x = -1.05 + 0.7 * k as f32;
        sphere(&mut mesh, Vec3::new(x, 0.3, 0.45), 0.3, 24, 48, 2 + k);
        sphere(&mut mesh, Vec3::new(x, 0.3, -0.45), 0.3, 24, 48, 6 + k);
    }
    let cam = Camera::look_at(
        Vec3::new(0.0, 1.3, 3.4),
        Vec3::new(0.0, 0.25, 0.0),
        Vec3::Y,
        0.55,
    );
    scene(
        "metals",
        mesh,
        materials,
        cam,
        Vec3::ONE,
        settings(400, 240),
    )
}
