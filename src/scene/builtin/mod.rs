//! Built-in scenes (`builtin:NAME`), constructed in code (fast, exact). The same scenes are
//! committed as `assets/NAME.glb` (written by `examples/export_builtins.rs`) for Blender.
//!
//! 1 unit = 1 m, +Y up. Every scene sets its own [`RenderSettings`]. Geometry helpers keep
//! shared edges bit-identical (spheres share seam and pole vertices; boxes and prisms copy
//! each face's corners from one corner array), so a watertight intersector sees no cracks.

//!
//! Files: `shapes` (mesh helpers), `presets` (material presets), one file per family of
//! scenes (`brewster`, `cornell`, `prism`, `caustic`, `showcase`, `glass_of_water`, `khronos`, and the
//! lecture's `lecture` and `optics`), `lathe` (surfaces of revolution).

use super::{Camera, Material, Mesh, RenderSettings, Scene};
use glam::Vec3;

pub mod brewster;
mod caustic;
mod cornell;
pub mod glass_of_water;
pub mod khronos;
mod lathe;
mod lecture;
pub mod optics;
mod presets;
mod prism;
pub(crate) mod shapes;
mod showcase;
pub mod thin_film;

pub use caustic::{caustic, caustic_mirror};
pub use cornell::{cornell_glass, furnace, glass_slab, rough_glass};
pub use lathe::lathe;
pub use lecture::{brdf_types, fresnel_three, importance, mirror_delta};
pub use optics::{convex_lens, snell_window, wine_glass};
pub use presets::{glossy_metal, plastic, rough_glass_material};
pub use prism::{
    PRISM_APEX_DEG, PRISM_DESIGN_N_D, PRISM_WALL_DISTANCE, PrismLayout, prism, prism_layout,
};
pub use shapes::{
    checkerboard, convex_polyhedron, cuboid, oriented_box, quad, rect, sphere, triangular_prism,
};
pub use showcase::{env_spheres, materials, metals, sun_sky};

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
    "frosted-panes",
    "metals",
    "brdf-types",
    "importance",
    "mirror-delta",
    "fresnel-three",
    "snell-window",
    "convex-lens",
    "wine-glass",
    "thin-film",
    "brewster",
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
        "frosted-panes" => Ok(khronos::frosted_panes()),
        "metals" => Ok(metals()),
        "brdf-types" => Ok(brdf_types()),
        "importance" => Ok(importance()),
        "mirror-delta" => Ok(mirror_delta()),
        "fresnel-three" => Ok(fresnel_three()),
        "snell-window" => Ok(snell_window()),
        "convex-lens" => Ok(convex_lens()),
        "wine-glass" => Ok(wine_glass()),
        "thin-film" => Ok(thin_film::thin_film()),
        "brewster" => Ok(brewster::brewster()),
        _ => anyhow::bail!(
            "unknown built-in scene '{name}' (available: {})",
            NAMES.join(", ")
        ),
    }
}

pub(super) fn scene(
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

pub(super) fn settings(width: u32, height: u32) -> RenderSettings {
    RenderSettings {
        width,
        height,
        ..Default::default()
    }
}
