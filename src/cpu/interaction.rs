//! The surface-interaction record and the per-vertex work every CPU walk shares (path
//! tracing, both subpaths of BDPT, light tracing): normal orientation, the BSDF at the
//! path's wavelength, event consistency and ray spawning with the offset rule. The WGSL
//! twins are `orient_normals`, `event_is_consistent` and `offset_ray_origin_towards`.

use super::medium::{Medium, medium_ior};
use super::spectral::Spectral;
use crate::bsdf::{Bsdf, BsdfSample, BxDF, Event, TransportMode};
use crate::bvh::offset_ray_origin;
use crate::math::Frame;
use crate::scene::{Material, Scene};
use glam::{Vec2, Vec3};

/// Everything known about a ray/surface intersection.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceHit {
    pub p: Vec3,
    /// Unit geometric normal of the CCW triangle (front face side).
    pub ng: Vec3,
    /// Unit shading normal (interpolated), on the same side as `ng`.
    pub ns: Vec3,
    pub uv: Vec2,
    pub tri: u32,
    pub material: u32,
    pub t: f32,
}

/// Reconstruct the surface record of a BVH hit.
#[inline]
pub fn surface(scene: &Scene, hit: &crate::bvh::Hit) -> SurfaceHit {
    surface_with(scene, hit, true)
}

/// [`surface`], inlined into its caller, interpolating uv only when `with_uv` (else zero:
/// for walks over scenes without textures whose observers do not read it).
#[inline(always)]
pub fn surface_with(scene: &Scene, hit: &crate::bvh::Hit, with_uv: bool) -> SurfaceHit {
    let mesh = &scene.mesh;
    let t = hit.tri as usize;
    let [i0, i1, i2] = mesh.indices[t];
    let (i0, i1, i2) = (i0 as usize, i1 as usize, i2 as usize);
    let (p0, p1, p2) = (mesh.positions[i0], mesh.positions[i1], mesh.positions[i2]);
    let b0 = 1.0 - hit.b1 - hit.b2;
    // Barycentric hit point (more accurate than o + t·d; PBR 4th ed. §6.8.4).
    let p = p0 * b0 + p1 * hit.b1 + p2 * hit.b2;
    let ng = (p1 - p0).cross(p2 - p0).normalize_or_zero();
    let mut ns = (mesh.normals[i0] * b0 + mesh.normals[i1] * hit.b1 + mesh.normals[i2] * hit.b2)
        .normalize_or_zero();
    let uv = if with_uv {
        mesh.uvs[i0] * b0 + mesh.uvs[i1] * hit.b1 + mesh.uvs[i2] * hit.b2
    } else {
        Vec2::ZERO
    };
    if with_uv && !mesh.tangents.is_empty() && ns != Vec3::ZERO {
        let w = [b0, hit.b1, hit.b2];
        ns = normal_mapped(scene, mesh.tri_material[t], [i0, i1, i2], w, ns, uv);
    }
    // `cmpeq(..).all()` tests all three components (`==` stops at the first non-zero one,
    // a data-dependent branch on axis-aligned walls).
    if ns.cmpeq(Vec3::ZERO).all() || !ns.is_finite() {
        ns = ng;
    } else if ns.dot(ng) < 0.0 {
        ns = -ns;
    }
    SurfaceHit {
        p,
        ng,
        ns,
        uv,
        tri: hit.tri,
        material: mesh.tri_material[t],
        t: hit.t,
    }
}

/// The shading normal `n` (interpolated, unit) bent by the material's normal map at `uv`,
/// with the tangent interpolated by the barycentrics `w` (`perturb_normal`); `n` itself
/// when the material has none or the vertices no tangent frame.
#[inline(never)]
fn normal_mapped(scene: &Scene, m: u32, v: [usize; 3], w: [f32; 3], n: Vec3, uv: Vec2) -> Vec3 {
    let Some(mat) = scene.materials.get(m as usize) else {
        return n;
    };
    let (Some(r), Some(t)) = (
        mat.normal_texture,
        v.iter()
            .zip(w)
            .map(|(&i, w)| scene.mesh.tangents.get(i).map(|t| *t * w))
            .sum::<Option<glam::Vec4>>(),
    ) else {
        return n;
    };
    // The bitangent sign is per vertex (±1); a triangle's corners share it (MikkTSpace).
    let handed = scene.mesh.tangents.get(v[0]).map_or(1.0, |t| t.w);
    let texel = crate::scene::material::sample_texture(&scene.textures, &r, uv).truncate();
    crate::scene::material::perturb_normal(n, t.truncate().extend(handed), texel, mat.normal_scale)
        // A map bending the normal below the interpolated surface is not a usable frame.
        .filter(|p| p.dot(n) > 0.0)
        .unwrap_or(n)
}

/// Orient the normals for shading: opaque double-sided materials shade both sides alike,
/// one-sided opaque back faces are black (`None`), dielectrics keep the outward normal (the
/// eta convention of docs/design.md). `front`: the ray arrived on the side `hit.ng` points to;
/// `transmits`: the material transmits at this point (`Material::transmits_at`).
#[inline]
pub fn orient_normals(
    mat: &Material,
    transmits: bool,
    hit: &SurfaceHit,
    front: bool,
) -> Option<(Vec3, Vec3)> {
    if transmits || front {
        Some((hit.ng, hit.ns))
    } else if mat.double_sided {
        Some((-hit.ng, -hit.ns))
    } else {
        None
    }
}

/// Reflection must stay on the geometric side of ωo, transmission must cross it (a shading
/// normal can propose either wrongly; Veach 1997 §5.3).
#[inline]
pub fn event_is_consistent(event: Event, side_o: f32, side_i: f32) -> bool {
    match event {
        Event::Reflect => side_o * side_i > 0.0,
        Event::Transmit => side_o * side_i < 0.0,
    }
}

/// A ray origin at `p` pushed off the surface to the side of `ng` that `side_i` (= ω·ng)
/// selects (Wächter & Binder 2019, via `offset_ray_origin`, at the scene's offset `scale`).
#[inline]
pub fn offset_ray_origin_towards(p: Vec3, ng: Vec3, side_i: f32, scale: f32) -> Vec3 {
    offset_ray_origin(p, if side_i > 0.0 { ng } else { -ng }, scale)
}

/// What a BSDF sample at an interaction leads to.
pub enum Bounce {
    /// Continue along `wi` (world).
    Continue { s: BsdfSample, wi: Vec3 },
    /// No valid direction (no sample, or one inconsistent with the geometric normal).
    Absorbed,
    /// The BSDF returned a non-finite weight: the sample must be dropped and counted.
    Poisoned,
}

/// A path vertex on a surface, ready to scatter.
#[derive(Clone, Copy, Debug)]
pub struct Interaction<'h> {
    /// The hit, borrowed from the walk (copying it into every interaction was a memcpy per
    /// vertex).
    pub hit: &'h SurfaceHit,
    /// Oriented geometric and shading normals (see `orient_normals`).
    pub ng: Vec3,
    pub ns: Vec3,
    pub frame: Frame,
    /// Direction towards the previous vertex (world, unit) and in the shading frame.
    pub wo_w: Vec3,
    pub wo: Vec3,
    pub bsdf: Bsdf,
    /// The BSDF depends on the wavelength (dispersive glass in a spectral path).
    pub dispersive: bool,
    /// The scene's ray-offset scale (`Bvh::offset_scale`).
    pub offset_scale: f32,
}

impl<'h> Interaction<'h> {
    /// The interaction of a ray travelling along `d` with `hit`; `None` when the path ends
    /// there (one-sided back face, or an emitter, which is black otherwise). `enclosing`: the
    /// medium on the far side of a dielectric (`PathState::interface`), so that it refracts
    /// with η = n(inside)/n(enclosing) (Schmidt & Budge 2002); `None` = air.
    #[inline(always)]
    pub fn new(
        scene: &Scene,
        hit: &'h SurfaceHit,
        d: Vec3,
        sp: &Spectral,
        offset_scale: f32,
        enclosing: Medium,
    ) -> Option<Interaction<'h>> {
        let mat = &scene.materials[hit.material as usize];
        let front = d.dot(hit.ng) < 0.0;
        let transmissive = mat.transmits_at(&scene.textures, hit.uv);
        let (ng, ns) = orient_normals(mat, transmissive, hit, front)?;
        if mat.is_emissive() && mat.base_color == Vec3::ZERO {
            return None;
        }
        let outer = enclosing.filter(|_| transmissive);
        let outer_dispersive = outer.is_some_and(|e| scene.materials[e as usize].abbe.is_some());
        let dispersive =
            sp.lambdas.is_some() && transmissive && (mat.abbe.is_some() || outer_dispersive);
        let mut eta = match sp.lambdas {
            Some(l) if dispersive => mat.ior_at(l[0]),
            _ => mat.ior,
        };
        if outer.is_some() {
            eta /= medium_ior(scene, outer, sp);
        }
        let mut bsdf = mat.bsdf(&scene.textures, hit.uv, eta);
        if let Some(l) = sp.lambdas {
            bsdf = bsdf.map_colors(|c| sp.c(c.truncate())).at_wavelengths(l);
        }
        let frame = Frame::from_normal(ns);
        let wo_w = -d;
        Some(Interaction {
            hit,
            ng,
            ns,
            frame,
            wo_w,
            wo: frame.to_local(wo_w),
            bsdf,
            dispersive,
            offset_scale,
        })
    }

    /// Sample the BSDF and check the event against the geometric normal.
    #[inline(always)]
    pub fn sample(&self, uc: f32, u2: Vec2, mode: TransportMode) -> Bounce {
        let Some(s) = self.bsdf.sample(self.wo, uc, u2, mode) else {
            return Bounce::Absorbed;
        };
        let wi = self.frame.to_world(s.wi);
        let consistent = event_is_consistent(s.event, self.wo_w.dot(self.ng), wi.dot(self.ng));
        if !s.weight.is_finite() {
            return Bounce::Poisoned;
        }
        if !consistent {
            return Bounce::Absorbed;
        }
        Bounce::Continue { s, wi }
    }

    /// Origin of a ray leaving along `w` (world), offset to the side `w` goes to.
    #[inline]
    pub fn spawn(&self, w: Vec3) -> Vec3 {
        offset_ray_origin_towards(self.hit.p, self.ng, w.dot(self.ng), self.offset_scale)
    }

    /// Can light pass from `wo_w` to `w` here (same side, or a BSDF that transmits)?
    #[inline]
    pub fn geometric_ok(&self, w: Vec3) -> bool {
        let (so, si) = (self.wo_w.dot(self.ng), w.dot(self.ng));
        si != 0.0 && (si * so > 0.0 || self.bsdf.can_transmit())
    }
}

impl Interaction<'_> {
    /// The shadow ray of a light sample: (origin, direction, t_max). Both ends use the offset
    /// rule; the target is rebuilt as p + (p_light − p), the arithmetic the walks have always
    /// used. Infinite lights: along ωi without end.
    #[inline(always)]
    pub fn shadow_ray(&self, ls: &crate::scene::light::LiSample) -> (Vec3, Vec3, f32) {
        let origin = self.spawn(ls.wi);
        if ls.infinite {
            return (origin, ls.wi, f32::INFINITY);
        }
        let pl = self.hit.p + (ls.p_light - self.hit.p);
        let nl = ls.n_light;
        let target = if nl == Vec3::ZERO {
            pl
        } else {
            let n = if nl.dot(-ls.wi) > 0.0 { nl } else { -nl };
            offset_ray_origin(pl, n, self.offset_scale)
        };
        (origin, target - origin, 1.0)
    }
}
