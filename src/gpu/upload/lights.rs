//! The light distribution in GPU form (entries with their CDF) and the environment image's
//! block in `texels`.

use super::GpuBvh;
use crate::gpu::layout::Light;
use crate::scene::light::{ImageEnvironment, Light as SceneLight, LightSet};

/// The light distribution with its CDF. Returns (entries, light count); the array has at
/// least one (unused) entry.
pub fn pack_lights(bvh: &GpuBvh, lights: &LightSet, env_offset: u32) -> (Vec<Light>, u32) {
    let mut out: Vec<Light> = lights
        .lights
        .iter()
        .zip(&lights.cdf)
        .map(|(l, &cdf)| pack_light(bvh, l, cdf, env_offset))
        .collect();
    let count = out.len() as u32;
    if out.is_empty() {
        out.push(Light::default());
    }
    (out, count)
}

/// One entry of the light distribution: light `l` with its CDF value `cdf` (`env_offset`:
/// the environment image's block, see [`pack_environment`]).
fn pack_light(bvh: &GpuBvh, l: &SceneLight, cdf: f32, env_offset: u32) -> Light {
    let mut g = Light {
        cdf,
        kind: l.gpu_kind(),
        ..Default::default()
    };
    match l {
        SceneLight::Triangle(t) => {
            g.index = bvh.slot_of_tri.get(t.tri as usize).copied().unwrap_or(0);
        }
        SceneLight::Point(p) => {
            g.position = p.position.to_array();
            g.intensity = p.intensity.to_array();
        }
        SceneLight::Spot(s) => {
            g.position = s.position.to_array();
            g.direction = s.direction.to_array();
            g.intensity = s.intensity.to_array();
            g.cos_inner = s.cos_inner;
            g.cos_outer = s.cos_outer;
        }
        SceneLight::Directional(d) => {
            g.direction = d.direction.to_array();
            g.intensity = d.irradiance.to_array();
            (g.position, g.radius) = (d.center.to_array(), d.radius);
        }
        // Not in the distribution: escaping rays read the environment uniform.
        SceneLight::Environment(_) => {}
        SceneLight::Image(e) => image_light(&mut g, e, env_offset),
    }
    g
}

/// Fill `g` (kind set) for the environment image `e`: the image's block in `texels`
/// (`pack_environment`), strength, rotation.
fn image_light(g: &mut Light, e: &ImageEnvironment, env_offset: u32) {
    g.index = env_offset;
    g.intensity = [e.image.strength; 3];
    g.direction = [
        e.cos_rot,
        e.sin_rot,
        if e.image.importance { 1.0 } else { 0.0 },
    ];
    (g.position, g.radius) = (e.center.to_array(), e.radius);
}

/// Append the environment image of `lights` (if any) to the `texels` array (scene.wgsl) and
/// return the offset of its block (0 when there is none): a header `[W, H, texel offset,
/// float offset]` (u32 bits); W·H texels `(r, g, b, p(u,t))` row-major from the top, p the
/// piecewise-constant density of `Distribution2D::pdf`; then, four to a vec4, the H
/// conditional CDFs (W + 1 floats each) and the marginal CDF (H + 1 floats).
/// PBR 4th ed. §A.5.6 (`PiecewiseConstant2D`). Twin: `light_image_*` in light.wgsl.
pub fn pack_environment(lights: &LightSet, texels: &mut Vec<[f32; 4]>) -> u32 {
    let SceneLight::Image(e) = &lights.environment else {
        return 0;
    };
    let m = &e.image.map;
    let (w, h) = (m.width as usize, m.height as usize);
    let offset = texels.len() as u32;
    let tex = offset + 1;
    let floats = tex + (w * h) as u32;
    let bits = |x: u32| f32::from_bits(x);
    texels.push([bits(m.width), bits(m.height), bits(tex), bits(floats)]);
    let marginal = m.dist.marginal.integral;
    for (i, t) in m.texels.iter().enumerate() {
        let (row, col) = (i / w, i % w);
        let p = if marginal > 0.0 {
            m.dist.conditional[row].func[col] / marginal
        } else {
            1.0
        };
        texels.push([t.x, t.y, t.z, p]);
    }
    let mut fl: Vec<f32> = Vec::with_capacity(h * (w + 1) + h + 1);
    for c in &m.dist.conditional {
        fl.extend_from_slice(&c.cdf);
    }
    fl.extend_from_slice(&m.dist.marginal.cdf);
    for chunk in fl.chunks(4) {
        let mut v = [0.0f32; 4];
        v[..chunk.len()].copy_from_slice(chunk);
        texels.push(v);
    }
    offset
}
