//! The project's own HDRIs, generated in code (`assets/studio.hdr`, `assets/sun-sky.hdr` are
//! this module's output; `cargo run --release --example gen_hdri` rewrites them and
//! tests/env_map.rs checks the shipped files against it): a photo studio with soft boxes,
//! and a clear sky with a sun. Both are equirectangular with the mapping of `env_map`.

use super::env_map::{EnvImage, EnvMap, uv_to_dir};
use glam::{Vec2, Vec3};
use std::sync::{Arc, OnceLock};

/// Width of the shipped images (height = width / 2).
pub const HDRI_WIDTH: u32 = 512;

/// Supersamples per texel side (soft box and sun edges are anti-aliased).
const SUPER: u32 = 3;

/// The sun of `sun_sky`: direction (towards the sun), angular radius, radiance.
pub const SUN_ELEVATION_DEG: f32 = 35.0;
pub const SUN_AZIMUTH_DEG: f32 = 120.0;
pub const SUN_RADIUS_DEG: f32 = 1.2;
pub const SUN_RADIANCE: Vec3 = Vec3::new(4000.0, 3800.0, 3400.0);

/// Unit direction at elevation `e` and azimuth `a` (degrees; azimuth = atan2(z, x)).
pub fn direction(e: f32, a: f32) -> Vec3 {
    let (e, a) = (e.to_radians(), a.to_radians());
    Vec3::new(e.cos() * a.cos(), e.sin(), e.cos() * a.sin())
}

/// Render `f(direction)` into a `width × width/2` map, averaging SUPER² samples per texel.
fn generate(width: u32, name: &str, f: impl Fn(Vec3) -> Vec3) -> EnvMap {
    let height = (width / 2).max(1);
    let mut texels = Vec::with_capacity((width * height) as usize);
    for y in 0..height {
        for x in 0..width {
            let mut sum = Vec3::ZERO;
            for sy in 0..SUPER {
                for sx in 0..SUPER {
                    let uv = Vec2::new(
                        (x as f32 + (sx as f32 + 0.5) / SUPER as f32) / width as f32,
                        (y as f32 + (sy as f32 + 0.5) / SUPER as f32) / height as f32,
                    );
                    sum += f(uv_to_dir(uv));
                }
            }
            texels.push(sum / (SUPER * SUPER) as f32);
        }
    }
    EnvMap::from_texels(width, height, texels, name).0
}

/// A soft box: an elevation/azimuth rectangle (degrees) of constant radiance.
struct SoftBox {
    elevation: (f32, f32),
    azimuth: (f32, f32),
    radiance: Vec3,
}

const SOFT_BOXES: [SoftBox; 4] = [
    // key light, front right
    SoftBox {
        elevation: (15.0, 45.0),
        azimuth: (30.0, 60.0),
        radiance: Vec3::new(6.0, 5.7, 5.4),
    },
    // fill, front left, cooler
    SoftBox {
        elevation: (5.0, 35.0),
        azimuth: (110.0, 150.0),
        radiance: Vec3::new(1.8, 1.9, 2.0),
    },
    // rim light behind the subject
    SoftBox {
        elevation: (0.0, 20.0),
        azimuth: (-100.0, -80.0),
        radiance: Vec3::splat(5.0),
    },
    // overhead strip
    SoftBox {
        elevation: (70.0, 85.0),
        azimuth: (-60.0, 60.0),
        radiance: Vec3::splat(4.0),
    },
];

/// Studio radiance towards `d`: dim grey walls, a darker floor, four soft boxes.
fn studio_radiance(d: Vec3) -> Vec3 {
    let e = d.y.clamp(-1.0, 1.0).asin().to_degrees();
    let a = d.z.atan2(d.x).to_degrees();
    for b in &SOFT_BOXES {
        if (b.elevation.0..b.elevation.1).contains(&e) && (b.azimuth.0..b.azimuth.1).contains(&a) {
            return b.radiance;
        }
    }
    if e < 0.0 {
        Vec3::splat(0.02)
    } else {
        Vec3::splat(0.03 + 0.03 * d.y)
    }
}

/// Clear-sky radiance towards `d`: a blue gradient to a pale horizon, a glow around the sun,
/// a brown-grey ground and the sun disk.
fn sun_sky_radiance(d: Vec3) -> Vec3 {
    let sun = direction(SUN_ELEVATION_DEG, SUN_AZIMUTH_DEG);
    let cos_sun = d.dot(sun);
    if cos_sun >= SUN_RADIUS_DEG.to_radians().cos() {
        return SUN_RADIANCE;
    }
    if d.y < 0.0 {
        return Vec3::new(0.06, 0.05, 0.04);
    }
    let zenith = Vec3::new(0.054, 0.096, 0.216);
    let horizon = Vec3::new(0.225, 0.24, 0.27);
    let sky = horizon.lerp(zenith, d.y.sqrt());
    let glow = Vec3::new(1.0, 0.8, 0.5) * (0.6 * (-(1.0 - cos_sun) / 0.02).exp());
    sky + glow
}

/// The studio with soft boxes, `width × width/2`.
pub fn studio(width: u32) -> EnvMap {
    generate(width, "builtin studio", studio_radiance)
}

/// The clear sky with a sun, `width × width/2`.
pub fn sun_sky(width: u32) -> EnvMap {
    generate(width, "builtin sun-sky", sun_sky_radiance)
}

/// The shipped studio map (generated once per process), strength 1, no rotation.
pub fn studio_env() -> EnvImage {
    static MAP: OnceLock<Arc<EnvMap>> = OnceLock::new();
    EnvImage::new(
        MAP.get_or_init(|| Arc::new(studio(HDRI_WIDTH))).clone(),
        1.0,
        0.0,
    )
}

/// The shipped sun-and-sky map (generated once per process), strength 1, no rotation.
pub fn sun_sky_env() -> EnvImage {
    static MAP: OnceLock<Arc<EnvMap>> = OnceLock::new();
    EnvImage::new(
        MAP.get_or_init(|| Arc::new(sun_sky(HDRI_WIDTH))).clone(),
        1.0,
        0.0,
    )
}
