//! Materials in GPU form: the BSDF kind (by the CPU's own mapping), flags and parameters.

use super::TexSlots;
use crate::bsdf::{Bsdf, FilmBase, MicrofacetDistribution};
use crate::gpu::layout::{self, Material};
use crate::scene::{MaterialKind, Scene};
use glam::{Vec2, Vec3};

/// The BSDF kind of a material: decided by the CPU's own `Material::bsdf` mapping, so CPU and
/// GPU can never disagree about which BSDF a material gets; the variant's GPU kind is the BSDF
/// table's (`bsdf::family`).
pub fn bsdf_kind(scene: &Scene, m: &crate::scene::Material) -> (u32, Vec3) {
    let kind = m.bsdf(&scene.textures, Vec2::ZERO, m.ior).gpu_kind();
    (kind, m.base_color)
}

/// `FILM_ON_*` of what a film lies on.
fn film_base_code(base: FilmBase) -> u32 {
    match base {
        FilmBase::Dielectric { .. } => layout::FILM_ON_DIELECTRIC,
        FilmBase::Sheet { .. } => layout::FILM_ON_SHEET,
        FilmBase::Conductor { .. } => layout::FILM_ON_CONDUCTOR,
        FilmBase::Reflectance { .. } => layout::FILM_ON_REFLECTANCE,
    }
}

/// `DIST_*` of a microfacet distribution.
pub fn dist_code(d: MicrofacetDistribution) -> u32 {
    match d {
        MicrofacetDistribution::Ggx => layout::DIST_GGX,
        MicrofacetDistribution::Beckmann => layout::DIST_BECKMANN,
    }
}

/// One GPU material (`tex` = its texture reference slots from
/// [`pack_textures`](super::pack_textures)).
pub fn pack_material(scene: &Scene, m: &crate::scene::Material, tex: TexSlots) -> Material {
    let (bsdf, color) = bsdf_kind(scene, m);
    let sigma_a = m.sigma_a();
    let mut flags = 0;
    if m.is_emissive() {
        flags |= layout::MAT_EMISSIVE;
        if m.base_color == Vec3::ZERO {
            flags |= layout::MAT_BLACK_EMITTER;
        }
    }
    if m.double_sided {
        flags |= layout::MAT_DOUBLE_SIDED;
    }
    if m.is_transmissive() {
        flags |= layout::MAT_TRANSMISSIVE;
    }
    if m.kind == MaterialKind::Glass {
        flags |= layout::MAT_SOLID;
    }
    if m.has_absorption() {
        flags |= layout::MAT_ABSORBS;
    }
    if m.uniform_sampling && m.kind == MaterialKind::Diffuse {
        flags |= layout::MAT_UNIFORM_SAMPLING;
    }
    let absorbs = m.has_absorption();
    let film = match m.bsdf(&scene.textures, Vec2::ZERO, m.ior) {
        Bsdf::Iridescent(b) => m.iridescence.map(|i| (i, film_base_code(b.base))),
        _ => None,
    };
    let cond = m.conductor.map_or((Vec3::ZERO, Vec3::ZERO), |c| c.rgb());
    Material {
        base_color: color.to_array(),
        bsdf,
        emission: m.emission.to_array(),
        flags,
        sigma_a: sigma_a.to_array(),
        eta: m.ior,
        specular_color: m.specular_color.max(Vec3::ZERO).to_array(),
        specular_factor: m.specular_factor.clamp(0.0, 1.0),
        attenuation_color: m.attenuation_color.to_array(),
        attenuation_distance: if absorbs { m.attenuation_distance } else { 0.0 },
        alpha: crate::bsdf::roughness_to_alpha(m.roughness),
        metallic: m.metallic,
        roughness: m.roughness,
        dist: dist_code(m.distribution),
        abbe: m.abbe.filter(|v| *v > 0.0).unwrap_or(0.0),
        base_tex: tex.base,
        mr_tex: tex.mr,
        priority: m.priority,
        cond_eta: cond.0.to_array(),
        metal: m
            .conductor
            .map_or(layout::METAL_NONE, |c| c.index() as u32 + 1),
        cond_k: cond.1.to_array(),
        emit_tex: tex.emit,
        normal_tex: tex.normal,
        normal_scale: m.normal_scale,
        film_ior: film.map_or(0.0, |(i, _)| i.ior),
        film_min: film.map_or(0.0, |(i, _)| i.thickness_min),
        film_max: film.map_or(0.0, |(i, _)| i.thickness_max),
        film_factor: film.map_or(0.0, |(i, _)| i.factor),
        film_tex: tex.film,
        film_base: film.map_or(0, |(_, b)| b),
    }
}

pub fn pack_materials(scene: &Scene, tex: &[TexSlots]) -> Vec<Material> {
    let mut out: Vec<Material> = scene
        .materials
        .iter()
        .zip(tex)
        .map(|(m, &t)| pack_material(scene, m, t))
        .collect();
    if out.is_empty() {
        out.push(Material::default());
    }
    out
}
