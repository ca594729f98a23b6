//! The dispersion scene `prism`: its layout at minimum deviation and the slit housing.

use super::{quad, rect, scene, settings, triangular_prism};
use crate::scene::{Camera, Material, Mesh, Scene};
use glam::{Vec2, Vec3};

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
