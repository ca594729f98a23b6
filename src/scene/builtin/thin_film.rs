//! `thin-film`: wave optics where it matters — thin-film interference (glTF
//! `KHR_materials_iridescence`). A soap bubble (a free-standing water film, thinner at the top
//! where it drains), an oil slick on a pond, anodised metal (an oxide film on a grey metal)
//! smooth and rough, and gold under a clear coat, all under the sun-and-sky HDRI on a dark
//! floor, where the interference colours show best.
//!
//! The film thicknesses come from two procedural textures (green channel, the extension's
//! rule): the bubble's grows from 80 nm at the top to 900 nm at the bottom with swirls, the
//! slick's swirls across the pond. The glb export writes no textures, so `assets/thin-film.glb`
//! has uniform films (each at its maximum thickness).

use super::shapes::{cuboid, rect, sphere};
use super::{scene, settings};
use crate::bsdf::Metal;
use crate::scene::{Camera, Iridescence, Material, MaterialKind, Scene, Texture, TextureRef, Wrap};
use glam::{Affine2, Vec3, Vec4};

/// The soap film's index (water).
pub const SOAP_FILM_IOR: f32 = 1.33;
/// An oil film's index (Belcour & Barla 2017 use ≈ 1.5 for oil-like films).
pub const OIL_FILM_IOR: f32 = 1.47;

/// A thickness texture `n`×`n`, grey = `g(u, v)` ∈ [0, 1] (the green channel is read).
fn thickness_texture(n: u32, g: impl Fn(f32, f32) -> f32) -> Texture {
    let texels = (0..n * n)
        .map(|i| {
            let (u, v) = ((i % n) as f32 + 0.5, (i / n) as f32 + 0.5);
            let t = g(u / n as f32, v / n as f32).clamp(0.0, 1.0);
            Vec4::new(t, t, t, 1.0)
        })
        .collect();
    Texture {
        width: n,
        height: n,
        texels,
        wrap_s: Wrap::Repeat,
        wrap_t: Wrap::ClampToEdge,
        linear: true,
    }
}

fn texture_ref(texture: u32) -> Option<TextureRef> {
    Some(TextureRef {
        texture,
        tex_coord: 0,
        transform: Affine2::IDENTITY,
    })
}

/// A film of index `ior`, `max` nm thick (from `min` where a texture says 0).
fn film(ior: f32, min: f32, max: f32, texture: Option<TextureRef>) -> Option<Iridescence> {
    Some(Iridescence {
        factor: 1.0,
        ior,
        thickness_min: min,
        thickness_max: max,
        thickness_texture: texture,
    })
}

fn materials() -> Vec<Material> {
    let grey = Vec3::splat(0.62);
    vec![
        Material::diffuse("floor", Vec3::splat(0.06)),
        Material {
            iridescence: film(OIL_FILM_IOR, 150.0, 650.0, texture_ref(0)),
            ..Material::glass("oily-water", 1.33)
        },
        Material {
            kind: MaterialKind::ThinGlass,
            iridescence: film(SOAP_FILM_IOR, 80.0, 900.0, texture_ref(1)),
            double_sided: true,
            ..Material::glass("soap-bubble", 1.0)
        },
        Material {
            iridescence: film(2.2, 0.0, 330.0, None),
            ..Material::mirror("anodised", grey)
        },
        Material {
            iridescence: film(2.2, 0.0, 420.0, None),
            ..super::glossy_metal("anodised-rough", grey, 0.35)
        },
        Material {
            conductor: Some(Metal::Au),
            iridescence: film(1.5, 0.0, 260.0, None),
            ..Material::mirror("coated-gold", Vec3::ONE)
        },
        Material::diffuse("pond-bed", Vec3::ZERO),
    ]
}

/// The scene (module docs). Swirls: the drain of a bubble (thin at the top, v = 0) and an
/// oil slick's bands.
pub fn thin_film() -> Scene {
    let tau = std::f32::consts::TAU;
    let slick = thickness_texture(128, |u, v| {
        0.5 + 0.3 * (tau * (2.0 * u + 0.6 * (tau * v).sin())).sin()
            + 0.2 * (tau * (3.0 * v + 0.4 * (tau * 2.0 * u).cos())).sin()
    });
    let bubble = thickness_texture(128, |u, v| {
        v.powf(0.7) + 0.08 * (tau * (3.0 * u + 2.0 * v)).sin() * (std::f32::consts::PI * v).sin()
    });
    let mut m = crate::scene::Mesh::default();
    rect(&mut m, Vec3::ZERO, Vec3::Y, 30.0, 30.0, 0);
    // The pond's bed: black, as a deep pond is (a lit bed would wash out the slick, and its
    // sunlight, found only through the water's delta refraction, is all fireflies).
    rect(&mut m, Vec3::new(0.0, 0.003, 0.9), Vec3::Y, 3.6, 1.6, 6);
    cuboid(
        &mut m,
        Vec3::new(-1.8, 0.006, 0.1),
        Vec3::new(1.8, 0.045, 1.7),
        1,
    );
    sphere(&mut m, Vec3::new(-1.2, 0.6, -0.5), 0.36, 64, 128, 2);
    for (k, mat) in [3u32, 4, 5].into_iter().enumerate() {
        let x = -0.35 + 0.8 * k as f32;
        sphere(&mut m, Vec3::new(x, 0.33, -0.5), 0.33, 48, 96, mat);
    }
    let cam = Camera::look_at(
        Vec3::new(0.0, 1.25, 3.6),
        Vec3::new(0.0, 0.2, -0.2),
        Vec3::Y,
        0.6,
    );
    let mut s = scene(
        "thin-film",
        m,
        materials(),
        cam,
        Vec3::ZERO,
        settings(480, 270),
    );
    s.textures = vec![slick, bubble];
    s.env_map = Some(crate::scene::hdri::sun_sky_env());
    s
}
