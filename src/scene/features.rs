//! What a scene needs, so renderers can skip everything else (specialised kernels): computed
//! once here from the materials the mesh uses, read by the CPU renderer (spectral transport),
//! the `auto` estimator rule and the GPU pipeline specialisation.

use super::light::LightParts;
use super::{Material, MaterialKind, Scene};
use crate::bsdf::{Bsdf, BsdfParts, BxDF, MicrofacetDistribution};
use glam::Vec2;

bitflags::bitflags! {
    /// The BSDFs, microfacet distributions, textures, lights and effects a scene uses. The
    /// BSDF flags name what a material becomes (`Material::bsdf`): smooth glossy metal is a
    /// mirror, index-matched rough glass is smooth glass.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
    pub struct Features: u32 {
        /// Lambertian diffuse.
        const DIFFUSE = 1 << 0;
        /// Perfect mirror (also smooth glossy metal).
        const MIRROR = 1 << 1;
        /// Rough conductor (glossy metal above the smoothness threshold).
        const GLOSSY_METAL = 1 << 2;
        /// Smooth dielectric interface (solid glass).
        const SMOOTH_GLASS = 1 << 3;
        /// Rough dielectric interface (solid glass).
        const ROUGH_GLASS = 1 << 4;
        /// Thin-walled dielectric.
        const THIN_GLASS = 1 << 5;
        /// The glTF metallic-roughness BRDF.
        const METAL_ROUGH = 1 << 6;
        /// GGX microfacets (rough glass or glossy metal with GGX, or metal-rough).
        const GGX = 1 << 7;
        /// Beckmann microfacets (rough glass or glossy metal with Beckmann).
        const BECKMANN = 1 << 8;
        /// A transmissive material with an Abbe number: paths carry hero wavelengths.
        const DISPERSION = 1 << 9;
        /// Solid glass with a finite attenuation distance (Beer–Lambert).
        const ABSORPTION = 1 << 10;
        /// A BSDF reads a texture: any base-colour texture, or a metallic-roughness texture
        /// on the metal-rough BRDF (the only one that reads it), or a normal map.
        const TEXTURES = 1 << 11;
        /// A non-black uniform environment or an environment image.
        const ENVIRONMENT = 1 << 12;
        /// Emissive triangles.
        const AREA_LIGHTS = 1 << 13;
        /// Point, spot or directional lights.
        const PUNCTUAL_LIGHTS = 1 << 14;
        /// Nested dielectrics: the bounds of two solid-glass materials overlap, or one sets
        /// `extras.priority` (paths keep a medium stack; `cpu::medium`).
        const NESTED = 1 << 15;
        /// An environment image (importance-sampled, in the light distribution).
        const ENV_IMAGE = 1 << 16;
        /// A smooth tabulated metal with the exact conductor Fresnel term (`extras.conductor`).
        const SMOOTH_CONDUCTOR = 1 << 17;
        /// A rough tabulated metal with the exact conductor Fresnel term (`extras.conductor`).
        const ROUGH_FRESNEL_CONDUCTOR = 1 << 18;
        /// A material with a tangent-space normal map (`normalTexture`).
        const NORMAL_MAP = 1 << 19;
        /// A dielectric or metal under a thin film (`KHR_materials_iridescence`).
        const IRIDESCENCE = 1 << 20;
        /// Rough thin-walled dielectric (a frosted sheet).
        const ROUGH_THIN_GLASS = 1 << 21;
    }
}

/// The BSDF parts of `scene::Features` flags, generated from the BSDF table (`bsdf::family`):
/// each row's `feature` flag compiles in its `part`.
macro_rules! parts_of_features {
    ($(
        $(#[$attr:meta])*
        $variant:ident($ty:ident) {
            part: $part:ident, has: $has:ident, feature: $feature:ident,
            $($rest:tt)*
        }
    )*) => {
        /// The BSDFs a kernel for a scene of features `f` compiles in: a part per `Bsdf`
        /// variant, set where the variant's `Features` flag is.
        pub fn bsdf_parts(f: Features) -> BsdfParts {
            BsdfParts {
                $($part: f.contains(Features::$feature),)*
            }
        }

        /// The `Features` flag of a BSDF's variant.
        fn bsdf_flag(b: &Bsdf) -> Features {
            match b {
                $(Bsdf::$variant(_) => Features::$feature,)*
            }
        }
    };
}

crate::bsdf::family::bsdf_table!(parts_of_features);

/// The light parts of `scene::Features` flags, generated from the light table
/// (`scene::light::family`): each row that owns a part has the `feature` flag that sets it.
macro_rules! light_parts_of_features {
    ($(
        $(#[$attr:meta])*
        $variant:ident($ty:ident) {
            $(part: $part:ident = $has:ident, feature: $feature:ident,)?
            $(guard: $guard:ident,)?
            kind: $($rest:tt)*
        }
    )*) => {
        /// The lights a kernel for a scene of features `f` compiles in.
        pub fn light_parts(f: Features) -> LightParts {
            LightParts {
                $($($part: f.contains(Features::$feature),)?)*
            }
        }
    };
}

crate::scene::light::family::light_table!(light_parts_of_features);

/// The features of `scene` (materials no triangle uses are ignored).
pub fn compute(scene: &Scene) -> Features {
    let mut f = Features::empty();
    let used = used_materials(scene);
    for (m, _) in scene.materials.iter().zip(&used).filter(|(_, u)| **u) {
        f |= material_features(scene, m);
    }
    f.set(
        Features::NESTED,
        super::nesting::nested_volumes(scene, &used),
    );
    f.set(
        Features::ENVIRONMENT,
        scene.environment.max_element() > 0.0 || scene.env_map.is_some(),
    );
    f.set(Features::PUNCTUAL_LIGHTS, !scene.punctual_lights.is_empty());
    f.set(Features::ENV_IMAGE, scene.env_map.is_some());
    f
}

/// Per material of `scene`: whether some triangle uses it (out-of-range ids are ignored).
fn used_materials(scene: &Scene) -> Vec<bool> {
    let mut used = vec![false; scene.materials.len()];
    for &m in &scene.mesh.tri_material {
        if let Some(u) = used.get_mut(m as usize) {
            *u = true;
        }
    }
    used
}

/// The features one used material `m` of `scene` needs: its BSDF's, then textures,
/// absorption, dispersion, normal mapping and emission.
fn material_features(scene: &Scene, m: &Material) -> Features {
    let mut f = bsdf_features(scene, m);
    if m.is_transmissive() && m.transmission_texture.is_some() {
        // Masked texels shade with the metal-rough base, read at uv.
        f |= Features::METAL_ROUGH | Features::GGX | Features::TEXTURES;
    }
    if m.kind == MaterialKind::Glass && m.has_absorption() {
        f |= Features::ABSORPTION;
    }
    if m.is_transmissive() && m.abbe.is_some() {
        f |= Features::DISPERSION;
    }
    let film_texture = m.iridescence.is_some_and(|i| i.thickness_texture.is_some());
    if m.base_color_texture.is_some()
        || (m.is_emissive() && m.emissive_texture.is_some())
        || film_texture
    {
        f |= Features::TEXTURES;
    }
    if m.normal_texture.is_some() && !scene.mesh.tangents.is_empty() {
        // Shading reads the normal texture at uv: surface hits must interpolate it.
        f |= Features::NORMAL_MAP | Features::TEXTURES;
    }
    if m.is_emissive() {
        f |= Features::AREA_LIGHTS;
    }
    f
}

/// The BSDF flag of what `m` becomes (`Material::bsdf` at uv 0), with its microfacet
/// distribution, and for the metal-rough BRDF whether it reads a metallic-roughness texture.
pub(crate) fn bsdf_features(scene: &Scene, m: &Material) -> Features {
    let dist = |d: MicrofacetDistribution| match d {
        MicrofacetDistribution::Ggx => Features::GGX,
        MicrofacetDistribution::Beckmann => Features::BECKMANN,
    };
    let b = m.bsdf(&scene.textures, Vec2::ZERO, m.ior);
    let mut f = bsdf_flag(&b) | b.distribution().map_or(Features::empty(), dist);
    if let Bsdf::MetalRough(_) = b {
        // The only BSDF that reads the metallic-roughness texture.
        f.set(Features::TEXTURES, m.metallic_roughness_texture.is_some());
    }
    f
}
