//! Scenes of the lecture on BRDFs ("Rendering: Materials"): the three BRDF types, importance
//! sampling of the diffuse BRDF, the perfect mirror as a Dirac delta, and Fresnel for three
//! indices of refraction. Each is small (fast on a laptop) and shows one idea.

use super::{checkerboard, glossy_metal, rect, scene, settings, sphere};
use crate::scene::{Camera, Material, Mesh, Scene};
use glam::Vec3;

/// A floor checkerboard (materials 0 and 1) and a back wall (2); material 3 is the light
/// (radiance 30), placed by the caller. The camera looks at three spheres' places.
fn stage(m: &mut Mesh) -> (Vec<Material>, Camera) {
    checkerboard(m, Vec3::ZERO, 8.0, 16, 0, 1);
    rect(m, Vec3::new(0.0, 1.5, -1.5), Vec3::Z, 8.0, 3.0, 2);
    let materials = vec![
        Material::diffuse("floor-light", Vec3::splat(0.7)),
        Material::diffuse("floor-dark", Vec3::splat(0.15)),
        Material::diffuse("wall", Vec3::splat(0.5)),
        Material::emitter("light", Vec3::splat(30.0)),
    ];
    let cam = Camera::look_at(
        Vec3::new(0.0, 1.1, 3.4),
        Vec3::new(0.0, 0.35, 0.0),
        Vec3::Y,
        0.6,
    );
    (materials, cam)
}

/// The three BRDF types side by side, from rough to smooth: a diffuse (Lambert, albedo
/// 0.8), a glossy metal (GGX, roughness 0.3) and a perfect mirror (reflectance 0.95)
/// sphere, r = 0.35 m, under a 0.6 × 0.6 m ceiling light 2.2 m up. The glossy one is in the
/// middle, where a narrow (portrait) viewport still shows it.
pub fn brdf_types() -> Scene {
    let mut m = Mesh::default();
    let (mut materials, cam) = stage(&mut m);
    rect(&mut m, Vec3::new(0.0, 2.2, 0.5), Vec3::NEG_Y, 0.6, 0.6, 3);
    materials.extend([
        Material::diffuse("diffuse", Vec3::splat(0.8)),
        glossy_metal("glossy", Vec3::splat(0.9), 0.3),
        Material::mirror("mirror", Vec3::splat(0.95)),
    ]);
    for k in 0..3 {
        let x = -0.9 + 0.9 * k as f32;
        sphere(&mut m, Vec3::new(x, 0.35, 0.0), 0.35, 48, 96, 4 + k);
    }
    scene(
        "brdf-types",
        m,
        materials,
        cam,
        Vec3::splat(0.1),
        settings(480, 270),
    )
}

/// Importance sampling: two identical diffuse spheres (albedo 0.8) under a uniform white
/// sky on a grey floor; the left one samples its BRDF uniformly over the hemisphere (the
/// teaching switch `Material::uniform_sampling`), the right one cosine-weighted. Same mean,
/// more noise on the left at equal samples.
pub fn importance() -> Scene {
    let mut m = Mesh::default();
    rect(&mut m, Vec3::ZERO, Vec3::Y, 30.0, 30.0, 0);
    sphere(&mut m, Vec3::new(-0.5, 0.4, 0.0), 0.4, 48, 96, 1);
    sphere(&mut m, Vec3::new(0.5, 0.4, 0.0), 0.4, 48, 96, 2);
    let uniform = Material {
        uniform_sampling: true,
        ..Material::diffuse("uniform", Vec3::splat(0.8))
    };
    let materials = vec![
        Material::diffuse("floor", Vec3::splat(0.5)),
        uniform,
        Material::diffuse("cosine", Vec3::splat(0.8)),
    ];
    let cam = Camera::look_at(
        Vec3::new(0.0, 0.9, 2.6),
        Vec3::new(0.0, 0.35, 0.0),
        Vec3::Y,
        0.6,
    );
    scene(
        "importance",
        m,
        materials,
        cam,
        Vec3::ONE,
        settings(400, 225),
    )
}

/// The perfect mirror as a Dirac delta: a 25 × 25 cm mirror (reflectance 0.95) lies on the
/// floor; a 15 × 15 cm light (radiance 300) 0.6 m up shines down at it, and the mirror throws
/// the light's image onto the back wall as a bright quadrilateral. That patch is lit only
/// along the one mirrored direction, which a shadow ray towards the light never takes: the
/// path tracer finds it by sampling the mirror's direction (LSDE), NEE cannot.
pub fn mirror_delta() -> Scene {
    let mut m = Mesh::default();
    let (mut materials, cam) = stage(&mut m);
    materials[3].emission = Vec3::splat(300.0);
    materials.push(Material::mirror("mirror", Vec3::splat(0.95)));
    let (light, mirror) = (Vec3::new(-0.3, 0.6, 0.6), Vec3::new(0.0, 0.0, -0.2));
    rect(&mut m, light, mirror - light, 0.15, 0.15, 3);
    // A one-sided mirror 2 mm above the floor: no face coincides with it.
    rect(
        &mut m,
        mirror + Vec3::new(0.0, 0.002, 0.0),
        Vec3::Y,
        0.25,
        0.25,
        4,
    );
    scene(
        "mirror-delta",
        m,
        materials,
        cam,
        Vec3::splat(0.02),
        settings(480, 270),
    )
}

/// Fresnel for the lecture's three indices: smooth glass spheres of n = 1.025 (liquid
/// helium), 1.5 (glass) and 2.5 (diamond), r = 0.35 m, on a checkerboard under the generated
/// sun-and-sky: the reflection at normal incidence ((n−1)/(n+1))² is 0.015 %, 4 % and 18 %.
pub fn fresnel_three() -> Scene {
    let mut m = Mesh::default();
    checkerboard(&mut m, Vec3::ZERO, 12.0, 24, 0, 1);
    let materials = vec![
        Material::diffuse("floor-light", Vec3::splat(0.7)),
        Material::diffuse("floor-dark", Vec3::splat(0.1)),
        Material::glass("helium-1.025", 1.025),
        Material::glass("glass-1.5", 1.5),
        Material::glass("diamond-2.5", 2.5),
    ];
    for k in 0..3 {
        let x = -0.9 + 0.9 * k as f32;
        sphere(&mut m, Vec3::new(x, 0.36, 0.0), 0.35, 48, 96, 2 + k as u32);
    }
    let cam = Camera::look_at(
        Vec3::new(0.0, 1.0, 3.2),
        Vec3::new(0.0, 0.35, 0.0),
        Vec3::Y,
        0.6,
    );
    let mut s = scene(
        "fresnel-three",
        m,
        materials,
        cam,
        Vec3::ZERO,
        settings(480, 270),
    );
    s.env_map = Some(crate::scene::hdri::sun_sky_env());
    s
}
