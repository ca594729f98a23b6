//! What a scene needs, so renderers can skip everything else (specialised kernels).

use super::{MaterialKind, Scene};
use crate::bsdf::{effectively_smooth, roughness_to_alpha};

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Features {
    pub diffuse: bool,
    pub mirror: bool,
    pub glossy_metal: bool,
    pub smooth_glass: bool,
    pub rough_glass: bool,
    pub thin_glass: bool,
    pub metal_rough: bool,
    pub dispersion: bool,
    pub absorption: bool,
    pub textures: bool,
    pub environment: bool,
    pub area_lights: bool,
    pub punctual_lights: bool,
}

pub fn compute(scene: &Scene) -> Features {
    let mut f = Features::default();
    let mut used = vec![false; scene.materials.len()];
    for &m in &scene.mesh.tri_material {
        if let Some(u) = used.get_mut(m as usize) {
            *u = true;
        }
    }
    for (m, _) in scene.materials.iter().zip(&used).filter(|(_, u)| **u) {
        let smooth = effectively_smooth(roughness_to_alpha(m.roughness));
        match m.kind {
            MaterialKind::Diffuse => f.diffuse = true,
            MaterialKind::Mirror => f.mirror = true,
            MaterialKind::GlossyMetal => {
                if smooth {
                    f.mirror = true
                } else {
                    f.glossy_metal = true
                }
            }
            MaterialKind::Glass => {
                if smooth {
                    f.smooth_glass = true
                } else {
                    f.rough_glass = true
                }
                f.absorption |= m.has_absorption();
            }
            MaterialKind::ThinGlass => f.thin_glass = true,
            MaterialKind::MetalRough => f.metal_rough = true,
        }
        if m.is_transmissive() && m.abbe.is_some() {
            f.dispersion = true;
        }
        if m.base_color_texture.is_some() || m.metallic_roughness_texture.is_some() {
            f.textures = true;
        }
        if m.is_emissive() {
            f.area_lights = true;
        }
    }
    f.environment = scene.environment.max_element() > 0.0;
    f.punctual_lights = !scene.punctual_lights.is_empty();
    f
}
