//! The filter's guides: per pixel, the mean over camera samples of the first non-specular
//! hit's albedo, shading normal (facing the ray) and distance along the path, and the
//! fraction of samples whose first hit was specular. Mirrors and smooth glass are followed
//! (the BSDF picks reflection or refraction as the path tracer would), so a floor seen
//! through glass is guided by the floor, not by the glass's flat normal.
//!
//! The guide pass walks its own camera rays (seeded apart from the render's), so it never
//! touches the accumulation film: the unbiased image is the same with or without it.

use crate::bsdf::TransportMode;
use crate::cpu::Renderer;
use crate::cpu::camera_ray::camera_ray;
use crate::cpu::interaction::{Bounce, Interaction, surface};
use crate::cpu::spectral::Spectral;
use crate::math::rng::Sampler;
use crate::scene::camera::CameraRays;
use glam::Vec3;
use rayon::prelude::*;

/// Specular vertices followed before a path's guide gives up (then: no surface).
const MAX_SPECULAR: u32 = 8;
/// Seed offset of the guide rays (apart from the render's sample streams).
const GUIDE_SEED: u32 = 0x6d5a_1e55;

/// Per-pixel guides, row-major, top row first.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Guides {
    pub width: u32,
    pub height: u32,
    /// Mean albedo of the first non-specular hit (1 for emitters and escaped rays).
    pub albedo: Vec<Vec3>,
    /// Mean shading normal there (not renormalised; zero where no surface was found).
    pub normal: Vec<Vec3>,
    /// Mean distance along the path to it (0 where no surface was found).
    pub depth: Vec<f32>,
    /// Fraction of samples whose first hit was specular.
    pub specular: Vec<f32>,
}

/// What one guide sample found.
#[derive(Clone, Copy, Default)]
struct GuideSample {
    albedo: Vec3,
    normal: Vec3,
    depth: f32,
    specular: bool,
}

/// The guides of `renderer`'s scene at `(w, h)`, averaged over `spp` jittered camera rays.
pub fn render_guides(renderer: &Renderer, (w, h): (u32, u32), spp: u32, seed: u32) -> Guides {
    let cam = CameraRays::new(&renderer.scene.camera);
    let spp = spp.max(1);
    let rows: Vec<Vec<(Vec3, Vec3, f32, f32)>> = (0..h)
        .into_par_iter()
        .map(|y| {
            (0..w)
                .map(|x| {
                    let pixel = y * w + x;
                    let mut acc = (Vec3::ZERO, Vec3::ZERO, 0.0f32, 0.0f32);
                    for s in 0..spp {
                        let mut sampler = Sampler::new(pixel, s, seed ^ GUIDE_SEED);
                        let dir = camera_ray(&cam, (x, y), (w, h), &mut sampler);
                        let g = guide_sample(renderer, cam.position, dir, &mut sampler);
                        acc.0 += g.albedo;
                        acc.1 += g.normal;
                        acc.2 += g.depth;
                        acc.3 += g.specular as u32 as f32;
                    }
                    let n = spp as f32;
                    (acc.0 / n, acc.1 / n, acc.2 / n, acc.3 / n)
                })
                .collect()
        })
        .collect();
    let px: Vec<_> = rows.into_iter().flatten().collect();
    Guides {
        width: w,
        height: h,
        albedo: px.iter().map(|p| p.0).collect(),
        normal: px.iter().map(|p| p.1).collect(),
        depth: px.iter().map(|p| p.2).collect(),
        specular: px.iter().map(|p| p.3).collect(),
    }
}

/// Follow one camera ray through specular vertices to its first non-specular hit.
fn guide_sample(r: &Renderer, mut origin: Vec3, mut dir: Vec3, s: &mut Sampler) -> GuideSample {
    let scene = &r.scene;
    let mut g = GuideSample {
        albedo: Vec3::ONE,
        ..GuideSample::default()
    };
    for _ in 0..MAX_SPECULAR {
        let Some(hit) = r.bvh.intersect(origin, dir, f32::INFINITY) else {
            return g;
        };
        let sh = surface(scene, &hit);
        let mat = &scene.materials[sh.material as usize];
        let Some(it) =
            Interaction::new(scene, &sh, dir, &Spectral::RGB, r.bvh.offset_scale(), None)
        else {
            // An emitter or a one-sided back face: a surface without reflectance to divide by.
            g.normal = facing(sh.ns, dir);
            g.depth += sh.t;
            return g;
        };
        g.depth += sh.t;
        if !it.bsdf.is_delta() {
            g.albedo = mat.base_color_at(&scene.textures, sh.uv);
            g.normal = facing(it.ns, dir);
            return g;
        }
        g.specular = true;
        let (uc, u2) = (s.next_1d(), s.next_2d());
        match it.sample(uc, u2, TransportMode::Radiance) {
            Bounce::Continue { wi, .. } => {
                origin = it.spawn(wi);
                dir = wi;
            }
            Bounce::Absorbed | Bounce::Poisoned => break,
        }
    }
    GuideSample {
        albedo: Vec3::ONE,
        specular: true,
        ..GuideSample::default()
    }
}

/// `n` flipped to face the ray travelling along `dir`.
fn facing(n: Vec3, dir: Vec3) -> Vec3 {
    if n.dot(dir) > 0.0 { -n } else { n }
}
