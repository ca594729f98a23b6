//! Scene → GPU arrays: the BVH2 repack (triangles stored in leaf order, consistent with
//! `primitive_indices`), vertex attributes, materials and the light distribution.
//! Pure CPU code (no wgpu), so it is testable without an adapter.

use super::layout::{self, BvhNode, Light, Material, Triangle, Vertex};
use crate::bsdf::{Bsdf, MicrofacetDistribution};
use crate::scene::light::{ImageEnvironment, Light as SceneLight, LightSet};
use crate::scene::material::{Texture, TextureRef, Wrap};
use crate::scene::{Features, MaterialKind, Mesh, Scene};
use anyhow::{Result, bail, ensure};
use glam::{Vec2, Vec3};
use obvhs::{BvhBuildParams, bvh2::Bvh2, triangle::Triangle as ObvhsTriangle};
use std::time::{Duration, Instant};

/// Deepest BVH2 the WGSL traversal stack handles (`BVH_STACK_SIZE` in scene.wgsl).
pub const MAX_BVH_DEPTH: u32 = 64;

/// Traversal stack entries for a BVH2 of `depth` levels (root = 1): an ordered traversal
/// holds at most `depth − 1` entries; rounded up to a multiple of 8 (fewer specialisations),
/// at least 8 (the workgroup counter reduction borrows two entries), at most
/// [`MAX_BVH_DEPTH`].
pub fn bvh_stack_entries(depth: u32) -> u32 {
    depth
        .saturating_sub(1)
        .next_multiple_of(8)
        .clamp(8, MAX_BVH_DEPTH)
}

/// The BVH2 in GPU form.
#[derive(Clone, Debug, Default)]
pub struct GpuBvh {
    pub nodes: Vec<BvhNode>,
    /// Scene triangle of each leaf slot (obvhs `primitive_indices`).
    pub primitive_indices: Vec<u32>,
    /// Leaf slot of each scene triangle (inverse of `primitive_indices`).
    pub slot_of_tri: Vec<u32>,
    pub depth: u32,
    pub build_time: Duration,
    /// The ray-offset scale of the scene (`bvh::offset_scale`, the CPU's rule).
    pub offset_scale: f32,
}

/// Build an obvhs BVH2 over the scene's triangles and repack its nodes.
pub fn build_bvh(scene: &Scene) -> Result<GpuBvh> {
    let start = Instant::now();
    let mesh = &scene.mesh;
    let tris = obvhs_triangles(mesh);
    if tris.is_empty() {
        return Ok(empty_bvh(start));
    }
    let mut core = Duration::ZERO;
    let bvh2 = obvhs::bvh2::builder::build_bvh2_from_tris(
        &tris,
        BvhBuildParams::medium_build(),
        &mut core,
    );
    let nodes = repack_nodes(&bvh2);
    let depth = checked_depth(&nodes, bvh2.primitive_indices.len())?;
    let slot_of_tri = leaf_slots(&bvh2.primitive_indices, tris.len());
    Ok(GpuBvh {
        nodes,
        primitive_indices: bvh2.primitive_indices.clone(),
        slot_of_tri,
        depth,
        build_time: start.elapsed(),
        offset_scale: crate::bvh::offset_scale(mesh),
    })
}

/// The mesh's triangles as obvhs build input, in scene order.
fn obvhs_triangles(mesh: &Mesh) -> Vec<ObvhsTriangle> {
    (0..mesh.triangle_count())
        .map(|t| {
            let [a, b, c] = mesh.tri(t);
            ObvhsTriangle {
                v0: a.into(),
                v1: b.into(),
                v2: c.into(),
            }
        })
        .collect()
}

/// The BVH of a scene without triangles: one leaf with an empty (inverted) box, so every
/// ray misses; `start` is when the build began.
fn empty_bvh(start: Instant) -> GpuBvh {
    GpuBvh {
        nodes: vec![BvhNode {
            lo: [f32::MAX; 3],
            prim_count: 0,
            hi: [-f32::MAX; 3],
            first_index: 0,
        }],
        build_time: start.elapsed(),
        offset_scale: 1.0,
        ..Default::default()
    }
}

/// The obvhs BVH2 nodes in the GPU node layout, in the same order.
fn repack_nodes(bvh2: &Bvh2) -> Vec<BvhNode> {
    bvh2.nodes
        .iter()
        .map(|n| BvhNode {
            lo: n.aabb.min.to_array(),
            prim_count: n.prim_count,
            hi: n.aabb.max.to_array(),
            first_index: n.first_index,
        })
        .collect()
}

/// Depth of the BVH2 rooted at `nodes[0]` (root = 1), after checking that every child
/// index and every leaf range (into `primitive_count` primitive indices) is in range and
/// that the depth fits the fixed-size WGSL traversal stack.
fn checked_depth(nodes: &[BvhNode], primitive_count: usize) -> Result<u32> {
    let mut depth = 0u32;
    let mut stack = vec![(0u32, 1u32)];
    while let Some((i, d)) = stack.pop() {
        depth = depth.max(d);
        let n = nodes
            .get(i as usize)
            .ok_or_else(|| anyhow::anyhow!("BVH node index {i} out of range"))?;
        if n.prim_count == 0 {
            ensure!(
                (n.first_index as usize + 1) < nodes.len(),
                "BVH child index out of range"
            );
            stack.push((n.first_index, d + 1));
            stack.push((n.first_index + 1, d + 1));
        } else {
            ensure!(
                (n.first_index as u64 + n.prim_count as u64) <= primitive_count as u64,
                "BVH leaf range out of range"
            );
        }
    }
    if depth > MAX_BVH_DEPTH {
        bail!("BVH depth {depth} exceeds the GPU traversal stack ({MAX_BVH_DEPTH})");
    }
    Ok(depth)
}

/// Leaf slot of each of `tri_count` scene triangles: the first slot of `primitive_indices`
/// that holds it (`u32::MAX` for a triangle in no leaf).
fn leaf_slots(primitive_indices: &[u32], tri_count: usize) -> Vec<u32> {
    let mut slot_of_tri = vec![u32::MAX; tri_count];
    for (slot, &t) in primitive_indices.iter().enumerate() {
        if let Some(s) = slot_of_tri.get_mut(t as usize)
            && *s == u32::MAX
        {
            *s = slot as u32;
        }
    }
    slot_of_tri
}

/// Triangles in leaf order with the light-selection probabilities of `lights`.
pub fn pack_triangles(scene: &Scene, bvh: &GpuBvh, lights: &LightSet) -> Vec<Triangle> {
    let mesh = &scene.mesh;
    let mut out: Vec<Triangle> = bvh
        .primitive_indices
        .iter()
        .map(|&t| {
            let t = t as usize;
            let [i0, i1, i2] = mesh.indices[t];
            let [p0, p1, p2] = mesh.tri(t);
            Triangle {
                p0: p0.to_array(),
                material: mesh.tri_material[t],
                p1: p1.to_array(),
                scene_tri: t as u32,
                p2: p2.to_array(),
                pick_prob: lights.tri_pick_prob.get(t).copied().unwrap_or(0.0),
                i0,
                i1,
                i2,
                area: mesh.area(t),
            }
        })
        .collect();
    if out.is_empty() {
        out.push(Triangle::default()); // bindings must not be empty
    }
    out
}

/// Per-vertex normals, uvs and tangents (zero when the mesh has none).
pub fn pack_vertices(scene: &Scene) -> Vec<Vertex> {
    let m = &scene.mesh;
    let mut out: Vec<Vertex> = m
        .normals
        .iter()
        .zip(&m.uvs)
        .enumerate()
        .map(|(i, (n, uv))| {
            let t = m.tangents.get(i).copied().unwrap_or_default();
            Vertex {
                normal: n.to_array(),
                u: uv.x,
                v: uv.y,
                tangent_w: t.w,
                tangent: t.truncate().to_array(),
            }
        })
        .collect();
    if out.is_empty() {
        out.push(Vertex::default());
    }
    out
}

/// The BSDF kind of a material: decided by the CPU's own `Material::bsdf` mapping, so CPU and
/// GPU can never disagree about which BSDF a material gets. A new `Bsdf` variant fails to
/// compile here until its WGSL twin exists.
pub fn bsdf_kind(scene: &Scene, m: &crate::scene::Material) -> (u32, Vec3) {
    match m.bsdf(&scene.textures, Vec2::ZERO, m.ior) {
        Bsdf::Lambert(_) => (layout::BSDF_LAMBERT, m.base_color),
        Bsdf::Mirror(_) => (layout::BSDF_MIRROR, m.base_color),
        Bsdf::SmoothDielectric(_) => (layout::BSDF_SMOOTH_DIELECTRIC, m.base_color),
        Bsdf::ThinDielectric(_) => (layout::BSDF_THIN_DIELECTRIC, m.base_color),
        Bsdf::RoughDielectric(_) => (layout::BSDF_ROUGH_DIELECTRIC, m.base_color),
        Bsdf::RoughConductor(_) => (layout::BSDF_ROUGH_CONDUCTOR, m.base_color),
        Bsdf::MetalRough(_) => (layout::BSDF_METAL_ROUGH, m.base_color),
        Bsdf::SmoothConductor(_) => (layout::BSDF_SMOOTH_CONDUCTOR, m.base_color),
        Bsdf::RoughFresnelConductor(_) => (layout::BSDF_ROUGH_FRESNEL_CONDUCTOR, m.base_color),
    }
}

/// `DIST_*` of a microfacet distribution.
pub fn dist_code(d: MicrofacetDistribution) -> u32 {
    match d {
        MicrofacetDistribution::Ggx => layout::DIST_GGX,
        MicrofacetDistribution::Beckmann => layout::DIST_BECKMANN,
    }
}

/// Reject what the GPU kernel cannot render. Every material kind, textures, dispersion and
/// the path filter are supported; what is left are limits (checked when buffers are built).
pub fn check_supported(scene: &Scene) -> Result<()> {
    let f = scene.features();
    let conductors = Features::SMOOTH_CONDUCTOR | Features::ROUGH_FRESNEL_CONDUCTOR;
    ensure!(
        !(f.intersects(conductors) && f.contains(Features::DISPERSION)),
        "the GPU renderer has no spectral (hero-wavelength) conductor yet: this scene has a tabulated metal (extras.conductor) and a dispersive material; render it on the CPU"
    );
    ensure!(
        scene.settings.light_line_nm.is_none(),
        "the GPU renderer has no light line yet (light_line_nm = {} nm): render it on the CPU (--device cpu)",
        scene.settings.light_line_nm.unwrap_or_default()
    );
    if let Some(m) = scene
        .materials
        .iter()
        .find(|m| m.is_transmissive() && m.transmission_texture.is_some())
    {
        bail!(
            "the GPU renderer has no transmission texture yet (material '{}'): render it on the CPU (--device cpu)",
            m.name
        );
    }
    for (i, t) in scene.textures.iter().enumerate() {
        ensure!(
            (t.width as u64) < (1 << 30) && (t.height as u64) < (1 << 30),
            "texture {i} is too large for the GPU renderer ({}x{})",
            t.width,
            t.height
        );
    }
    Ok(())
}

/// Texture references and texels in one `vec4<f32>` array (scene.wgsl `texels`): reference
/// slot r is 3 vec4s at 3r (header `[offset, width, height, flags]` as u32 bits, the
/// `KHR_texture_transform` matrix columns, the translation), then the texels of every
/// texture (row-major, linear RGBA). Returns (array, each material's reference slots).
pub fn pack_textures(scene: &Scene) -> (Vec<[f32; 4]>, Vec<TexSlots>) {
    let (refs, slots) = texture_slots(scene);
    let header = 3 * refs.len();
    let mut offsets = Vec::with_capacity(scene.textures.len());
    let mut total = header;
    for t in &scene.textures {
        offsets.push(total as u32);
        total += texel_count(t);
    }
    let mut out = vec![[0.0f32; 4]; total.max(1)];
    for (i, r) in refs.iter().enumerate() {
        let t = scene.textures.get(r.texture as usize);
        let offset = offsets.get(r.texture as usize).copied().unwrap_or(0);
        out[3 * i..3 * i + 3].copy_from_slice(&texture_reference(r, t, offset));
    }
    for (t, &off) in scene.textures.iter().zip(&offsets) {
        let n = texel_count(t);
        for (o, v) in out[off as usize..off as usize + n]
            .iter_mut()
            .zip(&t.texels)
        {
            *o = v.to_array();
        }
    }
    (out, slots)
}

/// Every material's texture references, numbered in order, and each material's slots into
/// them: only what its kind and the mesh can use (the metallic-roughness texture for
/// metal-rough, emission for emitters, normal maps with tangents).
fn texture_slots(scene: &Scene) -> (Vec<TextureRef>, Vec<TexSlots>) {
    let mut refs: Vec<TextureRef> = Vec::new();
    let mut slots = Vec::with_capacity(scene.materials.len());
    let mut slot_of = |r: &Option<TextureRef>| -> u32 {
        match r {
            Some(r) => {
                refs.push(*r);
                (refs.len() - 1) as u32
            }
            None => layout::NO_TEXTURE,
        }
    };
    for m in &scene.materials {
        let base = slot_of(&m.base_color_texture);
        // Only metal-rough reads the metallic-roughness texture (`Material::metal_rough_at`).
        let mr = if m.kind == MaterialKind::MetalRough {
            slot_of(&m.metallic_roughness_texture)
        } else {
            layout::NO_TEXTURE
        };
        let emit = slot_of(&m.emissive_texture.filter(|_| m.is_emissive()));
        // Normal maps need the mesh's tangents (`Features::NORMAL_MAP`).
        let normal = if scene.mesh.tangents.is_empty() {
            layout::NO_TEXTURE
        } else {
            slot_of(&m.normal_texture)
        };
        slots.push(TexSlots {
            base,
            mr,
            emit,
            normal,
        });
    }
    (refs, slots)
}

/// The texels a texture contributes: width × height, or 0 for one whose texels do not fill
/// its size (its references then read as invalid).
fn texel_count(t: &Texture) -> usize {
    let n = t.width as usize * t.height as usize;
    if n > 0 && t.texels.len() >= n { n } else { 0 }
}

/// The three vec4s of reference `r`: header `[offset, width, height, flags]` (u32 bits; all
/// zero, i.e. not `TEX_VALID`, without a usable texture `t`), the transform's matrix columns
/// and its translation.
fn texture_reference(r: &TextureRef, t: Option<&Texture>, offset: u32) -> [[f32; 4]; 3] {
    let wrap = |w: Wrap| match w {
        Wrap::Repeat => layout::WRAP_REPEAT,
        Wrap::MirroredRepeat => layout::WRAP_MIRRORED_REPEAT,
        Wrap::ClampToEdge => layout::WRAP_CLAMP_TO_EDGE,
    };
    let head = match t {
        Some(t) if texel_count(t) > 0 => [
            offset,
            t.width,
            t.height,
            wrap(t.wrap_s)
                | wrap(t.wrap_t) << 2
                | if t.linear { layout::TEX_LINEAR } else { 0 }
                | layout::TEX_VALID,
        ],
        _ => [0; 4],
    };
    let m = r.transform.matrix2;
    let tr = r.transform.translation;
    [
        head.map(f32::from_bits),
        [m.x_axis.x, m.x_axis.y, m.y_axis.x, m.y_axis.y],
        [tr.x, tr.y, 0.0, 0.0],
    ]
}

/// The texture reference slots of one material ([`layout::NO_TEXTURE`] = none).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TexSlots {
    /// Base colour.
    pub base: u32,
    /// Metallic-roughness (metal-rough materials only).
    pub mr: u32,
    /// Emissive (emitting materials only).
    pub emit: u32,
    /// Tangent-space normal map (when the mesh has tangents).
    pub normal: u32,
}

/// One GPU material (`tex` = its texture reference slots from [`pack_textures`]).
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
    let absorbs = m.has_absorption();
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
        ..Default::default()
    };
    match l {
        SceneLight::Triangle(t) => {
            g.kind = layout::LIGHT_TRIANGLE;
            g.index = bvh.slot_of_tri.get(t.tri as usize).copied().unwrap_or(0);
        }
        SceneLight::Point(p) => {
            g.kind = layout::LIGHT_POINT;
            g.position = p.position.to_array();
            g.intensity = p.intensity.to_array();
        }
        SceneLight::Spot(s) => {
            g.kind = layout::LIGHT_SPOT;
            g.position = s.position.to_array();
            g.direction = s.direction.to_array();
            g.intensity = s.intensity.to_array();
            g.cos_inner = s.cos_inner;
            g.cos_outer = s.cos_outer;
        }
        SceneLight::Directional(d) => {
            g.kind = layout::LIGHT_DIRECTIONAL;
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

/// Fill `g` for the environment image `e`: the image's block in `texels`
/// (`pack_environment`), strength, rotation.
fn image_light(g: &mut Light, e: &ImageEnvironment, env_offset: u32) {
    g.kind = layout::LIGHT_IMAGE;
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
