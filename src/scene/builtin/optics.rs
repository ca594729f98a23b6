//! Scenes of the lecture on refraction: Snell's window seen from under water, the chromatic
//! aberration of a convex lens, and the caustics of a wine glass beside a glass ball.

use super::lathe::lathe;
use super::{checkerboard, cuboid, rect, scene, settings, sphere};
use crate::scene::{Camera, Material, Mesh, Scene};
use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_PI_2, PI};

/// IOR of the water in [`snell_window`].
pub const WATER_IOR: f32 = 1.33;

/// Snell's window: a camera 1 m under a calm water surface (IOR 1.33; a 60 × 60 × 4 m solid)
/// looks straight up with a 120° field of view. The whole sky above the horizon arrives in
/// a cone of half-angle asin(1/1.33) = 48.8°, brightened by η² (the BTDF's radiance
/// scaling); outside it the surface totally reflects the dim sand 3 m down.
pub fn snell_window() -> Scene {
    let mut m = Mesh::default();
    cuboid(
        &mut m,
        Vec3::new(-30.0, -4.0, -30.0),
        Vec3::new(30.0, 0.0, 30.0),
        0,
    );
    checkerboard(&mut m, Vec3::new(0.0, -3.0, 0.0), 40.0, 40, 1, 2);
    let materials = vec![
        Material::glass("water", WATER_IOR),
        Material::diffuse("sand-light", Vec3::new(0.35, 0.3, 0.2)),
        Material::diffuse("sand-dark", Vec3::new(0.12, 0.1, 0.07)),
    ];
    let cam = Camera::look_at(
        Vec3::new(0.0, -1.0, 0.0),
        Vec3::ZERO,
        Vec3::NEG_Z,
        120f32.to_radians(),
    );
    let mut s = scene(
        "snell-window",
        m,
        materials,
        cam,
        Vec3::ZERO,
        settings(320, 320),
    );
    s.env_map = Some(crate::scene::hdri::sun_sky_env());
    s
}

/// Radii of curvature of [`convex_lens`]'s two faces (m), its radius and edge thickness.
pub const LENS_R: f32 = 0.6;
pub const LENS_APERTURE: f32 = 0.2;
pub const LENS_EDGE: f32 = 0.01;
/// The lens glass: n_d and Abbe number (a strongly dispersive flint, so the fringes show).
pub const LENS_N_D: f32 = 1.5;
pub const LENS_ABBE: f32 = 20.0;

/// The profile (r, h along the axis) of a symmetric biconvex lens centred at h = 0: the
/// front cap from its vertex out to the edge, the edge, the back cap back to the axis.
pub fn lens_profile(steps: u32) -> Vec<Vec2> {
    let sag = LENS_R - (LENS_R * LENS_R - LENS_APERTURE * LENS_APERTURE).sqrt();
    let cap = |r: f32| 0.5 * LENS_EDGE + sag - (LENS_R - (LENS_R * LENS_R - r * r).sqrt());
    let mut p: Vec<Vec2> = (0..=steps)
        .map(|i| {
            let r = LENS_APERTURE * i as f32 / steps as f32;
            Vec2::new(r, -cap(r))
        })
        .collect();
    p.extend((0..=steps).rev().map(|i| {
        let r = LENS_APERTURE * i as f32 / steps as f32;
        Vec2::new(r, cap(r))
    }));
    p
}

/// Chromatic aberration of a convex lens: a biconvex lens (faces of radius 0.6 m, 0.4 m
/// across, n_d 1.5, V_d 20) on the x axis focuses a small white light 1.5 m in front of it
/// onto a white screen 1 m behind it; blue focuses nearer the lens than red (n falls with
/// wavelength), so the spot on the screen has coloured fringes.
pub fn convex_lens() -> Scene {
    let mut m = Mesh::default();
    lathe(&mut m, Vec3::ZERO, Vec3::X, &lens_profile(48), 96, 0);
    sphere(&mut m, Vec3::new(-1.5, 0.0, 0.0), 0.01, 12, 24, 1);
    rect(&mut m, Vec3::new(1.0, 0.0, 0.0), Vec3::NEG_X, 0.8, 0.8, 2);
    rect(&mut m, Vec3::new(0.0, -0.45, 0.0), Vec3::Y, 6.0, 6.0, 3);
    let lens = Material {
        abbe: Some(LENS_ABBE),
        ..Material::glass("lens", LENS_N_D)
    };
    let materials = vec![
        lens,
        Material::emitter("light", Vec3::splat(40_000.0)),
        Material::diffuse("screen", Vec3::splat(0.9)),
        Material::diffuse("floor", Vec3::splat(0.3)),
    ];
    let cam = Camera::look_at(
        Vec3::new(-0.2, 0.35, 1.5),
        Vec3::new(0.75, 0.0, 0.0),
        Vec3::Y,
        0.7,
    );
    scene(
        "convex-lens",
        m,
        materials,
        cam,
        Vec3::splat(0.01),
        settings(480, 270),
    )
}

/// The profile of a goblet 0.3 m tall (foot, stem, an elliptic bowl 4 mm thick) as a closed
/// solid, walked with the glass on the left.
pub fn goblet_profile() -> Vec<Vec2> {
    let mut p = vec![
        Vec2::new(0.0, 0.0),
        Vec2::new(0.07, 0.0),
        Vec2::new(0.07, 0.005),
        Vec2::new(0.02, 0.009),
        Vec2::new(0.006, 0.02),
        Vec2::new(0.005, 0.08),
    ];
    // Outer bowl: the lower half of an ellipse (semi-axes 0.072 m, 0.1 m, centre at 0.24 m)
    // from the stem's radius to its equator, then up to the rim.
    let (a, b, hc) = (0.072, 0.1, 0.24);
    let t0 = (0.006f32 / a).asin();
    p.extend((0..=24).map(|i| {
        let t = t0 + (FRAC_PI_2 - t0) * i as f32 / 24.0;
        Vec2::new(a * t.sin(), hc - b * t.cos())
    }));
    p.extend([
        Vec2::new(0.067, 0.30),
        Vec2::new(0.0655, 0.302),
        Vec2::new(0.064, 0.30),
    ]);
    // Inner bowl: a smaller ellipse (0.068 m, 0.09 m, centre 0.245 m) down to the axis.
    let (a, b, hc) = (0.068, 0.09, 0.245);
    p.extend((0..=24).map(|i| {
        let t = FRAC_PI_2 * (1.0 - i as f32 / 24.0);
        Vec2::new(a * t.sin(), hc - b * t.cos())
    }));
    p
}

/// Caustics of a wine glass: a lathe-built goblet (IOR 1.5) and a glass ball (r = 7 cm) on a
/// wooden table under a small light (8 × 8 cm, radiance 800) 1 m away at 40° elevation.
pub fn wine_glass() -> Scene {
    let mut m = Mesh::default();
    rect(&mut m, Vec3::ZERO, Vec3::Y, 4.0, 4.0, 0);
    rect(&mut m, Vec3::new(0.0, 0.6, -0.6), Vec3::Z, 4.0, 1.2, 1);
    lathe(
        &mut m,
        Vec3::new(-0.1, 0.0, 0.0),
        Vec3::Y,
        &goblet_profile(),
        96,
        2,
    );
    sphere(&mut m, Vec3::new(0.17, 0.07, 0.05), 0.07, 48, 96, 2);
    let el = 40f32.to_radians();
    let az = PI * 0.8;
    let to_light = Vec3::new(az.cos() * el.cos(), el.sin(), -az.sin() * el.cos() * 0.3).normalize();
    let c = Vec3::new(0.0, 0.15, 0.0);
    rect(&mut m, c + to_light, -to_light, 0.08, 0.08, 3);
    let materials = vec![
        Material::diffuse("table", Vec3::new(0.55, 0.4, 0.28)),
        Material::diffuse("wall", Vec3::splat(0.5)),
        Material::glass("glass", 1.5),
        Material::emitter("light", Vec3::splat(800.0)),
    ];
    let cam = Camera::look_at(
        Vec3::new(0.2, 0.35, 0.75),
        Vec3::new(0.03, 0.11, 0.0),
        Vec3::Y,
        0.6,
    );
    scene(
        "wine-glass",
        m,
        materials,
        cam,
        Vec3::splat(0.01),
        settings(480, 360),
    )
}
