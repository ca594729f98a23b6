//! Material showcases: `materials`, `env-spheres`, `sun-sky` and `metals`.

use super::{checkerboard, glossy_metal, plastic, rect, scene, settings, sphere};
use crate::bsdf::Metal;
use crate::scene::{Camera, Material, Mesh, Scene};
use glam::Vec3;

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
    s.env_map = Some(crate::scene::hdri::sun_sky_env());
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
    s.env_map = Some(crate::scene::hdri::sun_sky_env());
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
