//! Bidirectional path tracing (Veach 1997, ch. 10; Veach & Guibas 1995, "Bidirectional
//! Estimators for Light Transport") with multiple importance sampling over every connection
//! strategy (s light vertices, t camera vertices), including light-tracing splats (t = 1) to
//! the film, and pure light tracing as a restriction of the same machinery.
//!
//! MIS weights use the power heuristic evaluated with the ratio recurrence of Veach 1997
//! §10.2 (each vertex stores the area densities of being generated from either side; the
//! weight of strategy (s,t) is 1 / Σ_i (p_i/p_s)², delta vertices excluded from connections).
//! Importance transport uses the adjoint BSDF: no 1/η² on refraction and the shading-normal
//! correction |ωo·ns||ωi·ng| / (|ωo·ng||ωi·ns|) (Veach 1997, §5.3, eq. 5.19).
//!
//! Scope: RGB transport (scenes with dispersion fall back to the path tracer); directional
//! lights are connected only by the s = 1 strategy (they cannot start a light subpath here),
//! so their weight is 1; a uniform environment is reached only by camera subpaths (weight 1).

use super::integrator::{Integrator, Spectral, SurfaceHit};
use crate::bsdf::{Bsdf, BxDF, Event, TransportMode};
use crate::bvh::offset_ray_origin;
use crate::math::{Color, Frame, rng::Sampler, sampling};
use crate::paths::{DfaTable, Symbol};
use crate::scene::light::{LightRef, sample_triangle, spot_falloff};
use crate::scene::{Material, PunctualLight};
use glam::Vec3;
use std::f32::consts::{FRAC_1_PI, PI};

/// Which strategies contribute.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BdptMode {
    /// All strategies, MIS-weighted.
    Full,
    /// Only t = 1 (light tracing: every light-subpath vertex connected to the camera), weight 1.
    LightTracing,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    Camera,
    /// Light subpath origin; `delta` = point/spot (delta position), `dir` = directional.
    Light {
        light: LightRef,
        delta_pos: bool,
    },
    Surface,
}

/// One vertex of a camera or light subpath.
#[derive(Clone, Copy, Debug)]
struct Vertex {
    kind: Kind,
    p: Vec3,
    /// Geometric and shading normal, oriented to the side the subpath arrived from for opaque
    /// double-sided materials (outward for dielectrics); zero for camera/point lights.
    ng: Vec3,
    ns: Vec3,
    material: u32,
    bsdf: Option<Bsdf>,
    /// Throughput up to and including this vertex (RGB in lanes xyz).
    beta: Color,
    /// Area density of generating this vertex from its predecessor on its own subpath.
    pdf_fwd: f32,
    /// Area density of generating it from the other direction (filled in by the walk).
    pdf_rev: f32,
    /// The BSDF sample taken at this vertex was a delta lobe (cannot be connected).
    delta: bool,
    /// Heckbert class of the scattering event sampled at this vertex.
    class: Symbol,
    /// Direction towards the predecessor on its subpath (world).
    w_prev: Vec3,
    /// Scene triangle of a surface or area-light vertex.
    tri: u32,
    /// Spectral mode: a dispersive event on this subpath (up to here) left only the hero
    /// wavelength alive (lanes 1–3 are zero; the ×4 is applied once per full path).
    collapsed: bool,
}

impl Vertex {
    /// Origin of a light subpath on a punctual light (delta position) picked with `pick`.
    fn delta_light(light: LightRef, p: Vec3, pick: f32) -> Vertex {
        Vertex {
            kind: Kind::Light {
                light,
                delta_pos: true,
            },
            p,
            ng: Vec3::ZERO,
            ns: Vec3::ZERO,
            material: 0,
            bsdf: None,
            beta: Color::splat(1.0 / pick),
            pdf_fwd: pick,
            pdf_rev: 0.0,
            delta: false,
            class: Symbol::L,
            w_prev: Vec3::ZERO,
            tri: 0,
            collapsed: false,
        }
    }

    fn on_surface(&self) -> bool {
        self.kind == Kind::Surface
            || matches!(
                self.kind,
                Kind::Light {
                    delta_pos: false,
                    ..
                }
            )
    }
    fn connectible(&self) -> bool {
        match self.kind {
            Kind::Surface => !self.delta && self.bsdf.is_some_and(|b| !b.is_delta()),
            _ => true,
        }
    }
}

/// Area density from a solid-angle density at `from` towards `to` (Veach 1997, eq. 8.10).
#[inline]
fn to_area(pdf_w: f32, from: &Vertex, to: &Vertex) -> f32 {
    let d = to.p - from.p;
    let d2 = d.length_squared();
    if d2 <= 0.0 {
        return 0.0;
    }
    let mut pdf = pdf_w / d2;
    if to.on_surface() {
        pdf *= (to.ng.dot(d) / d2.sqrt()).abs();
    }
    pdf
}

/// Ratio helper: delta densities are stored as 0 and count as 1 (Veach 1997, §10.3.5).
#[inline]
fn remap0(x: f32) -> f32 {
    if x != 0.0 { x } else { 1.0 }
}

/// Pinhole camera geometry for importance and raster positions.
#[derive(Clone, Copy)]
struct CameraModel {
    pos: Vec3,
    rot: glam::Mat3,
    tan_half: f32,
    aspect: f32,
    /// Area of the image plane at distance 1.
    a_plane: f32,
    width: u32,
    height: u32,
}

impl CameraModel {
    /// (pixel x, y, cosθ) of the direction `w` from the camera, if it lands on the film.
    fn raster(&self, w: Vec3) -> Option<(u32, u32, f32)> {
        let l = self.rot.transpose() * w;
        if l.z >= 0.0 {
            return None;
        }
        let x = l.x / -l.z / (self.tan_half * self.aspect);
        let y = l.y / -l.z / self.tan_half;
        let sx = 0.5 * (x + 1.0);
        let sy = 0.5 * (1.0 - y);
        if !(0.0..1.0).contains(&sx) || !(0.0..1.0).contains(&sy) {
            return None;
        }
        let px = ((sx * self.width as f32) as u32).min(self.width - 1);
        let py = ((sy * self.height as f32) as u32).min(self.height - 1);
        Some((px, py, -l.z / l.length()))
    }

    /// Solid-angle density of the camera's primary direction `w` (uniform on the image plane):
    /// p(ω) = 1 / (A_plane cos³θ) (PBR 3rd ed. §16.1.1, `PerspectiveCamera::Pdf_We`).
    fn pdf_dir(&self, w: Vec3) -> f32 {
        match self.raster(w) {
            Some((_, _, c)) => 1.0 / (self.a_plane * c * c * c),
            None => 0.0,
        }
    }
}

/// The bidirectional estimator for one prepared scene (shares the path tracer's scene access).
pub struct Bdpt<'a> {
    pub pt: &'a Integrator<'a>,
    pub mode: BdptMode,
    /// Heckbert filter in light→eye order (`PathFilter::forward`); None = all paths.
    pub filter: Option<&'a DfaTable>,
    cam: CameraModel,
}

const MAX_VERTS: usize = 66;

impl<'a> Bdpt<'a> {
    pub fn new(
        pt: &'a Integrator<'a>,
        mode: BdptMode,
        filter: Option<&'a DfaTable>,
        width: u32,
        height: u32,
    ) -> Self {
        let c = pt.scene.camera;
        let tan_half = (0.5 * c.yfov).tan();
        let aspect = width as f32 / height as f32;
        Bdpt {
            pt,
            mode,
            filter,
            cam: CameraModel {
                pos: c.position,
                rot: c.rotation,
                tan_half,
                aspect,
                a_plane: 4.0 * tan_half * tan_half * aspect,
                width,
                height,
            },
        }
    }

    fn material(&self, v: &Vertex) -> &Material {
        &self.pt.scene.materials[v.material as usize]
    }

    /// A surface vertex whose BSDF depends on the wavelength (dispersive glass).
    fn dispersive(&self, v: &Vertex) -> bool {
        v.kind == Kind::Surface && {
            let m = self.material(v);
            m.abbe.is_some() && m.is_transmissive()
        }
    }

    /// Spectral contribution of a full path: after any collapse only the hero lane carries the
    /// estimate, and it now stands for all four wavelengths (×4, once per path).
    fn finish(c: Color, collapse: bool) -> Color {
        if collapse {
            Color::new(4.0 * c.x, 0.0, 0.0, 0.0)
        } else {
            c
        }
    }

    /// Emitted radiance of a surface vertex towards `w` (one-sided unless doubleSided).
    fn le(&self, v: &Vertex, w: Vec3, raw_ng: Vec3, sp: &Spectral) -> Color {
        let m = self.material(v);
        if !m.is_emissive() {
            return Color::ZERO;
        }
        if raw_ng.dot(w) > 0.0 || m.double_sided {
            sp.c(m.emission)
        } else {
            Color::ZERO
        }
    }

    /// Build a surface vertex from a hit; `None` when the path must stop there (one-sided back
    /// face of an opaque material, or an emitter, which is black otherwise).
    fn surface_vertex(
        &self,
        hit: &SurfaceHit,
        d: Vec3,
        beta: Color,
        pdf_fwd: f32,
        sp: &Spectral,
    ) -> (Vertex, bool) {
        let m = &self.pt.scene.materials[hit.material as usize];
        let front = d.dot(hit.ng) < 0.0;
        let mut alive = true;
        let (ng, ns) = if m.is_transmissive() || front {
            (hit.ng, hit.ns)
        } else if m.double_sided {
            (-hit.ng, -hit.ns)
        } else {
            alive = false;
            (hit.ng, hit.ns)
        };
        let black_emitter = m.is_emissive() && m.base_color == Vec3::ZERO;
        let bsdf = if alive && !black_emitter {
            let eta = match sp.lambdas {
                Some(l) if m.abbe.is_some() => m.ior_at(l[0]),
                _ => m.ior,
            };
            let b = m.bsdf(&self.pt.scene.textures, hit.uv, eta);
            Some(if sp.lambdas.is_some() {
                b.map_colors(|c| sp.c(c.truncate()))
            } else {
                b
            })
        } else {
            None
        };
        let v = Vertex {
            kind: Kind::Surface,
            p: hit.p,
            ng,
            ns,
            material: hit.material,
            bsdf,
            beta,
            pdf_fwd,
            pdf_rev: 0.0,
            delta: false,
            class: Symbol::D,
            w_prev: -d,
            tri: hit.tri,
            collapsed: false,
        };
        (v, bsdf.is_some())
    }

    /// Random walk from `v0` in direction `d` with throughput `beta` and solid-angle pdf
    /// `pdf_w` of that direction (PBR 3rd ed. §16.3.2 structure). Appends vertices to `path`.
    #[allow(clippy::too_many_arguments)]
    fn walk(
        &self,
        path: &mut Vec<Vertex>,
        mut o: Vec3,
        mut d: Vec3,
        mut beta: Color,
        mut pdf_w: f32,
        max_verts: usize,
        mode: TransportMode,
        sampler: &mut Sampler,
        sp: &Spectral,
    ) -> Option<(Color, bool)> {
        let mut eta_scale = 1.0f32;
        let mut bounces = 0u32;
        let mut collapsed = path.last().is_some_and(|v| v.collapsed);
        while path.len() < max_verts {
            let Some(h) = self.pt.bvh.intersect(o, d, f32::INFINITY) else {
                return Some((beta, collapsed));
            };
            let hit = self.pt.surface(&h);
            let prev_idx = path.len() - 1;
            let (mut v, alive) = self.surface_vertex(&hit, d, beta, 0.0, sp);
            v.pdf_fwd = to_area(pdf_w, &path[prev_idx], &v);
            v.collapsed = collapsed;
            if !alive {
                // Emitters and black back faces end the walk but still count as vertices
                // (s = 0 strategies hit them).
                if self.material(&v).is_emissive() {
                    v.ng = hit.ng;
                    v.ns = hit.ns;
                    path.push(v);
                }
                break;
            }
            path.push(v);
            if path.len() >= max_verts {
                break;
            }
            let cur = path.len() - 1;
            let bsdf = path[cur].bsdf.expect("alive vertex has a BSDF");
            let frame = Frame::from_normal(path[cur].ns);
            let wo_w = -d;
            let wo = frame.to_local(wo_w);
            let uc = sampler.next_1d();
            let u2 = sampler.next_2d();
            let Some(s) = bsdf.sample(wo, uc, u2, mode) else {
                break;
            };
            let wi_w = frame.to_world(s.wi);
            let ng = path[cur].ng;
            let (side_o, side_i) = (wo_w.dot(ng), wi_w.dot(ng));
            let consistent = match s.event {
                Event::Reflect => side_o * side_i > 0.0,
                Event::Transmit => side_o * side_i < 0.0,
            };
            if !consistent || !s.weight.is_finite() {
                break;
            }
            let mut w = s.weight;
            if mode == TransportMode::Importance {
                w *= shading_correction(wo_w, wi_w, path[cur].ns, ng);
            }
            beta *= w;
            if sp.lambdas.is_some() && self.dispersive(&path[cur]) {
                // Hero wavelength only from here on (Wilkie et al. 2014, §4.2).
                beta = Color::new(beta.x, 0.0, 0.0, 0.0);
                collapsed = true;
            }
            path[cur].class = Symbol::from(s.lobe);
            if s.is_delta {
                path[cur].delta = true;
                pdf_w = 0.0;
                path[cur - 1].pdf_rev = 0.0;
            } else {
                pdf_w = s.pdf;
                let rev = bsdf.pdf(s.wi, wo);
                let (a, b) = (path[cur], path[cur - 1]);
                path[cur - 1].pdf_rev = to_area(rev, &a, &b);
            }
            if s.event == Event::Transmit {
                eta_scale *= s.eta_rel * s.eta_rel;
            }
            o = offset_ray_origin(hit.p, if side_i > 0.0 { ng } else { -ng });
            d = wi_w;
            bounces += 1;
            if bounces >= self.pt.rr_depth {
                let q = (beta.max_element() * eta_scale).min(0.95);
                if q <= 0.0 || sampler.next_1d() >= q {
                    break;
                }
                beta /= q;
            }
        }
        None
    }

    /// Start a light subpath: pick a light, a point on it and an emission direction.
    fn light_path(
        &self,
        path: &mut Vec<Vertex>,
        max_verts: usize,
        sampler: &mut Sampler,
        sp: &Spectral,
    ) {
        let ul = sampler.next_1d();
        let u_pos = sampler.next_2d();
        let u_dir = sampler.next_2d();
        let Some((light, pick)) = self.pt.lights.pick(ul) else {
            return;
        };
        let scene = self.pt.scene;
        match light {
            LightRef::Triangle(t) => {
                let (p, n, area) = sample_triangle(scene, t, u_pos);
                let m = &scene.materials[scene.mesh.tri_material[t as usize] as usize];
                let pdf_pos = pick / area;
                let v0 = Vertex {
                    kind: Kind::Light {
                        light,
                        delta_pos: false,
                    },
                    p,
                    ng: n,
                    ns: n,
                    material: scene.mesh.tri_material[t as usize],
                    bsdf: None,
                    beta: Color::splat(1.0 / pdf_pos),
                    pdf_fwd: pdf_pos,
                    pdf_rev: 0.0,
                    delta: false,
                    class: Symbol::L,
                    w_prev: Vec3::ZERO,
                    tri: t,
                    collapsed: false,
                };
                path.push(v0);
                // Cosine-weighted emission about the emitting side (Lambertian emitter).
                let mut local = sampling::cosine_hemisphere(u_dir);
                let mut side = n;
                if m.double_sided && sampler.next_1d() < 0.5 {
                    side = -n;
                }
                let two = if m.double_sided { 0.5 } else { 1.0 };
                if local.z <= 0.0 {
                    return;
                }
                local.z = local.z.max(1e-7);
                let d = Frame::from_normal(side).to_world(local);
                let pdf_w = two * local.z * FRAC_1_PI;
                // beta1 = Le cosθ / (pdf_pos pdf_dir)
                let beta = path[0].beta * sp.c(m.emission) * (local.z / pdf_w);
                let o = offset_ray_origin(p, side);
                self.walk(
                    path,
                    o,
                    d,
                    beta,
                    pdf_w,
                    max_verts,
                    TransportMode::Importance,
                    sampler,
                    sp,
                );
            }
            LightRef::Punctual(i) => {
                let pl = scene.punctual_lights[i as usize];
                let (p, intensity, d, pdf_w) = match pl {
                    PunctualLight::Point {
                        position,
                        intensity,
                    } => {
                        let d = sampling::uniform_sphere(u_dir);
                        (position, intensity, d, sampling::UNIFORM_SPHERE_PDF)
                    }
                    PunctualLight::Spot {
                        position,
                        direction,
                        intensity,
                        cos_inner,
                        cos_outer,
                    } => {
                        let local = sampling::uniform_cone(u_dir, cos_outer);
                        let d = Frame::from_normal(direction).to_world(local);
                        let pdf = 1.0 / (2.0 * PI * (1.0 - cos_outer).max(1e-7));
                        let fall = spot_falloff(local.z, cos_inner, cos_outer);
                        (position, intensity * fall, d, pdf)
                    }
                    PunctualLight::Directional { .. } => {
                        // Only the s = 1 strategy handles directional lights.
                        path.push(Vertex::delta_light(light, Vec3::ZERO, pick));
                        return;
                    }
                };
                path.push(Vertex::delta_light(light, p, pick));
                if intensity.max_element() <= 0.0 {
                    return;
                }
                let beta = path[0].beta * sp.c(intensity) / pdf_w;
                self.walk(
                    path,
                    p,
                    d,
                    beta,
                    pdf_w,
                    max_verts,
                    TransportMode::Importance,
                    sampler,
                    sp,
                );
            }
        }
    }

    /// Radiance/intensity leaving light vertex `y` towards `w` (unit), before G.
    fn light_emit(&self, y: &Vertex, w: Vec3, sp: &Spectral) -> Color {
        let Kind::Light { light, .. } = y.kind else {
            return Color::ZERO;
        };
        match light {
            LightRef::Triangle(_) => {
                let m = self.material(y);
                if y.ng.dot(w) > 0.0 || m.double_sided {
                    sp.c(m.emission)
                } else {
                    Color::ZERO
                }
            }
            LightRef::Punctual(i) => match self.pt.scene.punctual_lights[i as usize] {
                PunctualLight::Point { intensity, .. } => sp.c(intensity),
                PunctualLight::Spot {
                    direction,
                    intensity,
                    cos_inner,
                    cos_outer,
                    ..
                } => sp.c(intensity * spot_falloff(w.dot(direction), cos_inner, cos_outer)),
                PunctualLight::Directional { irradiance, .. } => sp.c(irradiance),
            },
        }
    }

    /// Solid-angle density with which light vertex `y` emits towards `w`.
    fn light_pdf_dir(&self, y: &Vertex, w: Vec3) -> f32 {
        let Kind::Light { light, .. } = y.kind else {
            return 0.0;
        };
        match light {
            LightRef::Triangle(_) => {
                let m = self.material(y);
                let c = y.ng.dot(w);
                if m.double_sided {
                    0.5 * c.abs() * FRAC_1_PI
                } else if c > 0.0 {
                    c * FRAC_1_PI
                } else {
                    0.0
                }
            }
            LightRef::Punctual(i) => match self.pt.scene.punctual_lights[i as usize] {
                PunctualLight::Point { .. } => sampling::UNIFORM_SPHERE_PDF,
                PunctualLight::Spot {
                    direction,
                    cos_outer,
                    ..
                } => {
                    if w.dot(direction) >= cos_outer {
                        1.0 / (2.0 * PI * (1.0 - cos_outer).max(1e-7))
                    } else {
                        0.0
                    }
                }
                PunctualLight::Directional { .. } => 0.0,
            },
        }
    }

    /// BSDF value at surface vertex `v` for light arriving along `w_in`, leaving along `w_out`
    /// (both pointing away), per Heckbert class; with the adjoint correction in importance mode.
    fn f(
        &self,
        v: &Vertex,
        w_to_prev: Vec3,
        w_to_next: Vec3,
        mode: TransportMode,
    ) -> [(Symbol, Color); 2] {
        let Some(b) = v.bsdf else {
            return [(Symbol::D, Color::ZERO), (Symbol::G, Color::ZERO)];
        };
        let frame = Frame::from_normal(v.ns);
        let (so, si) = (w_to_prev.dot(v.ng), w_to_next.dot(v.ng));
        if so * si <= 0.0 && !b.can_transmit() {
            return [(Symbol::D, Color::ZERO), (Symbol::G, Color::ZERO)];
        }
        let wo = frame.to_local(w_to_prev);
        let wi = frame.to_local(w_to_next);
        let corr = if mode == TransportMode::Importance {
            shading_correction(w_to_prev, w_to_next, v.ns, v.ng)
        } else {
            1.0
        };
        let lv = b.eval_lobes(wo, wi, mode);
        [(Symbol::D, lv.d * corr), (Symbol::G, lv.g * corr)]
    }

    /// Does the full light→eye symbol string pass the filter?
    fn accepted(
        &self,
        light: &[Vertex],
        cy: Option<Symbol>,
        cz: Option<Symbol>,
        cam: &[Vertex],
    ) -> bool {
        let Some(f) = self.filter else {
            return true;
        };
        let mut q = f.step(f.start(), Symbol::L);
        for v in light.iter().skip(1) {
            q = f.step(q, v.class);
        }
        if let Some(c) = cy {
            q = f.step(q, c);
        }
        if let Some(c) = cz {
            q = f.step(q, c);
        }
        for v in cam.iter().skip(1).rev() {
            q = f.step(q, v.class);
        }
        f.is_accepting(f.step(q, Symbol::E))
    }

    fn visible(&self, a: &Vertex, b: &Vertex) -> bool {
        let d = b.p - a.p;
        let oa = if a.on_surface() {
            offset_ray_origin(a.p, if a.ng.dot(d) > 0.0 { a.ng } else { -a.ng })
        } else {
            a.p
        };
        let ob = if b.on_surface() {
            offset_ray_origin(b.p, if b.ng.dot(-d) > 0.0 { b.ng } else { -b.ng })
        } else {
            b.p
        };
        !self.pt.bvh.occluded(oa, ob - oa, 1.0)
    }

    /// One bidirectional sample for pixel (x, y); camera-side contributions are returned,
    /// light-tracing splats go to `splat(px, py, value)`.
    pub fn sample(
        &self,
        x: u32,
        y: u32,
        sampler: &mut Sampler,
        splat: &mut dyn FnMut(u32, u32, Vec3),
    ) -> Vec3 {
        let max_depth = self.pt.max_depth.max(1) as usize;
        let mut cam: Vec<Vertex> = Vec::with_capacity(MAX_VERTS);
        let mut light: Vec<Vertex> = Vec::with_capacity(MAX_VERTS);
        let mut l = Color::ZERO;
        let j = sampler.next_2d();
        // Hero wavelengths shared by both subpaths (scenes with dispersion only).
        let sp = &Spectral {
            lambdas: if self.pt.spectral {
                Some(crate::math::spectrum::sample_hero_wavelengths(
                    sampler.next_1d(),
                ))
            } else {
                None
            },
        };
        let to_rgb = |c: Color| -> Vec3 {
            match sp.lambdas {
                Some(lambdas) => crate::math::spectrum::spectrum_sample_to_rgb(lambdas, c),
                None => c.truncate(),
            }
        };
        let dir = self.pt.scene.camera.ray_dir(
            (x as f32 + j.x) / self.cam.width as f32,
            (y as f32 + j.y) / self.cam.height as f32,
            self.cam.aspect,
        );
        cam.push(Vertex {
            kind: Kind::Camera,
            p: self.cam.pos,
            ng: Vec3::ZERO,
            ns: Vec3::ZERO,
            material: 0,
            bsdf: None,
            beta: Color::ONE,
            pdf_fwd: 1.0,
            pdf_rev: 0.0,
            delta: false,
            class: Symbol::E,
            w_prev: Vec3::ZERO,
            tri: 0,
            collapsed: false,
        });
        let pdf_cam = self.cam.pdf_dir(dir);
        // Camera subpath: at most max_depth + 1 vertices (max_depth segments).
        let cam_max = (max_depth + 1).min(MAX_VERTS);
        let escaped = self.walk(
            &mut cam,
            self.cam.pos,
            dir,
            Color::ONE,
            pdf_cam,
            cam_max,
            TransportMode::Radiance,
            sampler,
            sp,
        );
        // Environment: reached only by camera subpaths (no strategy samples it), weight 1.
        if let Some((b, collapsed)) = escaped {
            let env = self.pt.scene.environment;
            if self.mode == BdptMode::Full
                && env.max_element() > 0.0
                && cam.len() <= max_depth
                && self.accepted(&[], None, None, &cam)
            {
                l += Self::finish(b * sp.c(env), collapsed);
            }
        }
        let light_max = max_depth.min(MAX_VERTS);
        let mut ls = sampler.with_dim(1 << 16);
        self.light_path(&mut light, light_max, &mut ls, sp);

        for t in 1..=cam.len() {
            for s in 0..=light.len() {
                if s + t < 2 || s + t - 1 > max_depth {
                    continue;
                }
                if self.mode == BdptMode::LightTracing && t != 1 {
                    continue;
                }
                if t == 1 {
                    // (1,1) would see emitters directly a second time; (0,2) does that in the
                    // full estimator (as in Veach's and pbrt's BDPT). Pure light tracing keeps it.
                    // A delta-position light is never seen directly through a pinhole.
                    let delta_light = matches!(
                        light.first().map(|v| v.kind),
                        Some(Kind::Light {
                            delta_pos: true,
                            ..
                        })
                    );
                    if s == 0 || (s == 1 && (self.mode == BdptMode::Full || delta_light)) {
                        continue;
                    }
                    if let Some((px, py, v)) = self.connect_camera(&light[..s], &cam, sp) {
                        splat(px, py, to_rgb(v));
                    }
                    continue;
                }
                l += self.connect(&light[..s], &cam[..t], sp);
            }
        }
        to_rgb(l)
    }

    /// t = 1: connect light vertex y = light[s-1] to the camera.
    fn connect_camera(
        &self,
        light: &[Vertex],
        cam: &[Vertex],
        sp: &Spectral,
    ) -> Option<(u32, u32, Color)> {
        let s = light.len();
        let yv = light[s - 1];
        if !yv.connectible() || self.is_directional(&yv) {
            return None;
        }
        let c0 = cam[0];
        let to_cam = c0.p - yv.p;
        let d2 = to_cam.length_squared();
        if d2 <= 0.0 {
            return None;
        }
        let w = to_cam / d2.sqrt();
        let (px, py, cos_c) = self.cam.raster(-w)?;
        // f at y (or emission for s = 1), per class
        let mut contrib = Color::ZERO;
        let classes: [(Option<Symbol>, Color); 2] = if s == 1 {
            [(None, self.light_emit(&yv, w, sp)), (None, Color::ZERO)]
        } else {
            let f = self.f(&yv, yv.w_prev, w, TransportMode::Importance);
            [(Some(f[0].0), f[0].1), (Some(f[1].0), f[1].1)]
        };
        for (cy, fv) in classes {
            if fv.max_element() <= 0.0 || !self.accepted(&light[..s - 1], cy, None, &cam[..1]) {
                continue;
            }
            contrib += fv;
        }
        if contrib.max_element() <= 0.0 {
            return None;
        }
        let cos_y = if yv.on_surface() {
            yv.ns.dot(w).abs()
        } else {
            1.0
        };
        // We·G with a pinhole: |cos_y| / (d² A_plane cos³θ) (see module docs / `render` notes).
        let we_g = cos_y / (d2 * self.cam.a_plane * cos_c * cos_c * cos_c);
        let mut v = yv.beta * contrib * we_g;
        if v.max_element() <= 0.0 || !self.visible(&yv, &c0) {
            return None;
        }
        if self.mode == BdptMode::Full {
            // Camera density of generating y (area), for the MIS ratio.
            let pdf_cam_y = to_area(self.cam.pdf_dir(-w), &c0, &yv);
            v *= self.mis_weight(light, cam, 1, Some(pdf_cam_y));
        }
        let collapse = yv.collapsed || (s >= 2 && self.dispersive(&yv));
        Some((px, py, Self::finish(v, collapse)))
    }

    fn is_directional(&self, v: &Vertex) -> bool {
        matches!(v.kind, Kind::Light { light: LightRef::Punctual(i), .. }
            if matches!(self.pt.scene.punctual_lights[i as usize], PunctualLight::Directional { .. }))
    }

    /// Strategy (s, t ≥ 2).
    fn connect(&self, light: &[Vertex], cam: &[Vertex], sp: &Spectral) -> Color {
        let s = light.len();
        let t = cam.len();
        let z = cam[t - 1];
        if s == 0 {
            // Camera subpath hit an emitter.
            if z.kind != Kind::Surface {
                return Color::ZERO;
            }
            let m = self.material(&z);
            if !m.is_emissive() {
                return Color::ZERO;
            }
            let le = self.le(&z, z.w_prev, z.ng, sp);
            // The emitter vertex itself is the L: feed the camera classes before it.
            if le.max_element() <= 0.0 || !self.accepted(&[], None, None, &cam[..t - 1]) {
                return Color::ZERO;
            }
            let v = z.beta * le;
            let w = if self.mode == BdptMode::Full {
                self.mis_weight(light, cam, t, None)
            } else {
                1.0
            };
            return Self::finish(v * w, z.collapsed);
        }
        if z.kind != Kind::Surface || !z.connectible() || z.bsdf.is_none() {
            return Color::ZERO;
        }
        let y = light[s - 1];
        if !y.connectible() {
            return Color::ZERO;
        }
        let directional = self.is_directional(&y);
        let (w_zy, d2) = if directional {
            let PunctualLight::Directional { direction, .. } =
                self.pt.scene.punctual_lights[match y.kind {
                    Kind::Light {
                        light: LightRef::Punctual(i),
                        ..
                    } => i as usize,
                    _ => 0,
                }]
            else {
                return Color::ZERO;
            };
            (-direction, 1.0)
        } else {
            let d = y.p - z.p;
            let d2 = d.length_squared();
            if d2 <= 0.0 {
                return Color::ZERO;
            }
            (d / d2.sqrt(), d2)
        };
        let fz = self.f(&z, z.w_prev, w_zy, TransportMode::Radiance);
        let fy: [(Option<Symbol>, Color); 2] = if s == 1 {
            [(None, self.light_emit(&y, -w_zy, sp)), (None, Color::ZERO)]
        } else {
            let f = self.f(&y, y.w_prev, -w_zy, TransportMode::Importance);
            [(Some(f[0].0), f[0].1), (Some(f[1].0), f[1].1)]
        };
        let mut sum = Color::ZERO;
        for (cy, fyv) in fy {
            if fyv.max_element() <= 0.0 {
                continue;
            }
            for (cz, fzv) in fz {
                if fzv.max_element() <= 0.0 {
                    continue;
                }
                if !self.accepted(&light[..s - 1], cy, Some(cz), &cam[..t - 1]) {
                    continue;
                }
                sum += fyv * fzv;
            }
        }
        if sum.max_element() <= 0.0 {
            return Color::ZERO;
        }
        let cos_z = z.ns.dot(w_zy).abs();
        let cos_y = if y.on_surface() {
            y.ns.dot(w_zy).abs()
        } else {
            1.0
        };
        let g = cos_z * cos_y / d2;
        let v = y.beta * sum * z.beta * g;
        if v.max_element() <= 0.0 {
            return Color::ZERO;
        }
        let vis = if directional {
            let o = offset_ray_origin(z.p, if z.ng.dot(w_zy) > 0.0 { z.ng } else { -z.ng });
            !self.pt.bvh.occluded(o, w_zy, f32::INFINITY)
        } else {
            self.visible(&z, &y)
        };
        if !vis {
            return Color::ZERO;
        }
        let collapse = y.collapsed || z.collapsed || self.dispersive(&y) || self.dispersive(&z);
        if directional || self.mode != BdptMode::Full {
            return Self::finish(v, collapse);
        }
        Self::finish(v * self.mis_weight(light, cam, t, None), collapse)
    }

    /// Power-heuristic MIS weight of strategy (s = light.len(), t) for the path light + cam
    /// (Veach 1997, §10.2 ratio recurrence). `pdf_cam_y` is the camera density of the light
    /// end vertex for t = 1.
    fn mis_weight(
        &self,
        light: &[Vertex],
        cam: &[Vertex],
        t: usize,
        pdf_cam_y: Option<f32>,
    ) -> f32 {
        let s = light.len();
        if s + t == 2 {
            return 1.0; // only (0,2) exists for paths of one segment (see `sample`)
        }
        // Local copies of the few vertices whose reverse densities change for this strategy.
        let mut lv: [Vertex; 2] = [light.last().copied().unwrap_or(cam[0]); 2];
        let mut cv: [Vertex; 2] = [cam[t - 1]; 2];
        // indices: lv[0] = y_{s-1}, lv[1] = y_{s-2}; cv[0] = z_{t-1}, cv[1] = z_{t-2}
        if s >= 2 {
            lv[1] = light[s - 2];
        }
        if t >= 2 {
            cv[1] = cam[t - 2];
        }
        let y = if s >= 1 { Some(light[s - 1]) } else { None };
        let z = cam[t - 1];
        // z.pdf_rev: density of z generated from the light side
        if t >= 1 {
            cv[0].pdf_rev = match y {
                Some(yv) => {
                    if s == 1 {
                        to_area(
                            self.light_pdf_dir(&yv, (z.p - yv.p).normalize_or_zero()),
                            &yv,
                            &z,
                        )
                    } else {
                        self.bsdf_pdf_area(&yv, yv.w_prev, &z)
                    }
                }
                // z is on an emitter: density of choosing it as a light point.
                None => self.light_point_pdf(&z),
            };
        }
        // z_{t-2}.pdf_rev: density of z_{t-2} generated from z
        if t >= 2 {
            cv[1].pdf_rev = match y {
                Some(yv) => self.bsdf_pdf_area(&z, (yv.p - z.p).normalize_or_zero(), &cam[t - 2]),
                None => {
                    // emission from z towards z_{t-2}
                    let w = (cam[t - 2].p - z.p).normalize_or_zero();
                    let m = self.material(&z);
                    let c = z.ng.dot(w);
                    let pdf_w = if m.double_sided {
                        0.5 * c.abs() * FRAC_1_PI
                    } else {
                        c.max(0.0) * FRAC_1_PI
                    };
                    to_area(pdf_w, &z, &cam[t - 2])
                }
            };
        }
        // y.pdf_rev: density of y generated from the camera side
        if let Some(yv) = y {
            lv[0].pdf_rev = if t == 1 {
                pdf_cam_y.unwrap_or(0.0)
            } else {
                self.bsdf_pdf_area(&z, z.w_prev, &yv)
            };
            if s >= 2 {
                lv[1].pdf_rev =
                    self.bsdf_pdf_area(&yv, (z.p - yv.p).normalize_or_zero(), &light[s - 2]);
            }
        }
        let cam_at = |i: usize| -> Vertex {
            if i == t - 1 {
                cv[0]
            } else if t >= 2 && i == t - 2 {
                cv[1]
            } else {
                cam[i]
            }
        };
        let light_at = |i: usize| -> Vertex {
            if i == s - 1 {
                lv[0]
            } else if s >= 2 && i == s - 2 {
                lv[1]
            } else {
                light[i]
            }
        };
        let mut sum = 0.0f32;
        let mut ri = 1.0f32;
        // Strategies with fewer camera vertices.
        let mut i = t - 1;
        while i > 0 {
            let v = cam_at(i);
            ri *= remap0(v.pdf_rev) / remap0(v.pdf_fwd);
            let prev_delta = cam_at(i - 1).delta;
            if !v.delta && !prev_delta {
                sum += ri * ri;
            }
            i -= 1;
        }
        // Strategies with fewer light vertices.
        ri = 1.0;
        for i in (0..s).rev() {
            let v = light_at(i);
            ri *= remap0(v.pdf_rev) / remap0(v.pdf_fwd);
            let prev_delta = if i > 0 {
                light_at(i - 1).delta
            } else {
                matches!(
                    light_at(0).kind,
                    Kind::Light {
                        delta_pos: true,
                        ..
                    }
                )
            };
            if !v.delta && !prev_delta {
                sum += ri * ri;
            }
        }
        1.0 / (1.0 + sum)
    }

    /// Area density at `to` of sampling the BSDF at `v` given the other direction `w_other`.
    fn bsdf_pdf_area(&self, v: &Vertex, w_other: Vec3, to: &Vertex) -> f32 {
        let Some(b) = v.bsdf else {
            return 0.0;
        };
        if b.is_delta() {
            return 0.0;
        }
        let frame = Frame::from_normal(v.ns);
        let w = (to.p - v.p).normalize_or_zero();
        let pdf = b.pdf(frame.to_local(w_other), frame.to_local(w));
        to_area(pdf, v, to)
    }

    /// Density (area) of choosing surface vertex `z` as a light-subpath origin.
    fn light_point_pdf(&self, z: &Vertex) -> f32 {
        let area = self.pt.scene.mesh.area(z.tri as usize);
        let pick = self
            .pt
            .lights
            .tri_pick_prob
            .get(z.tri as usize)
            .copied()
            .unwrap_or(0.0);
        if area > 0.0 { pick / area } else { 0.0 }
    }
}

/// Adjoint shading-normal correction for importance transport (Veach 1997, eq. 5.19):
/// |ωo·ns||ωi·ng| / (|ωo·ng||ωi·ns|), ωo towards the previous vertex, ωi the new direction.
#[inline]
fn shading_correction(wo: Vec3, wi: Vec3, ns: Vec3, ng: Vec3) -> f32 {
    let num = wo.dot(ns).abs() * wi.dot(ng).abs();
    let den = wo.dot(ng).abs() * wi.dot(ns).abs();
    if den <= 0.0 { 0.0 } else { num / den }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cpu::Renderer;
    use crate::render::RenderOptions;
    use crate::scene::{MaterialKind, Scene};

    /// MIS check (Veach 1997, §9.2): for a fixed full path x0 (on the light) … xk (camera) of
    /// non-delta vertices, the power-heuristic weights of all strategies (s, t = k + 1 − s)
    /// that can produce it sum to 1. The subpaths are built with the densities the random
    /// walks would store; `mis_weight` recomputes the connection vertices itself.
    #[test]
    fn strategy_weights_sum_to_one() {
        let scene = Scene::load("builtin:cornell-glass").expect("builtin");
        let r = Renderer::new(scene).expect("valid");
        let mut o = RenderOptions::from_scene(&r.scene);
        o.width = 64;
        o.height = 64;
        let integ = r.integrator(&o);
        let bd = Bdpt::new(&integ, BdptMode::Full, None, 64, 64);
        let sc = &r.scene;
        let diffuse: Vec<u32> = (0..sc.mesh.triangle_count() as u32)
            .filter(|&t| {
                sc.materials[sc.mesh.tri_material[t as usize] as usize].kind
                    == MaterialKind::Diffuse
                    && !sc.materials[sc.mesh.tri_material[t as usize] as usize].is_emissive()
            })
            .collect();
        let light_tris = sc.emissive_triangles();
        let mut rng = Sampler::new(7, 0, 1);
        let surface = |t: u32, u: glam::Vec2, prev: Vec3| -> Vertex {
            let (p, n, _) = sample_triangle(sc, t, u);
            let m = sc.mesh.tri_material[t as usize];
            let mat = &sc.materials[m as usize];
            Vertex {
                kind: Kind::Surface,
                p,
                ng: n,
                ns: n,
                material: m,
                bsdf: Some(mat.bsdf(&sc.textures, glam::Vec2::ZERO, mat.ior)),
                beta: Color::ONE,
                pdf_fwd: 0.0,
                pdf_rev: 0.0,
                delta: false,
                class: Symbol::D,
                w_prev: (prev - p).normalize(),
                tri: t,
                collapsed: false,
            }
        };
        let mut checked = 0;
        for _ in 0..400 {
            let k = 2 + (rng.next_1d() * 4.0) as usize; // path of k segments, k + 1 vertices
            // x0 on the light, x1..x(k-1) on diffuse walls (different planes), xk = camera.
            let lt =
                light_tris[(rng.next_1d() * light_tris.len() as f32) as usize % light_tris.len()];
            let (p0, n0, _) = sample_triangle(sc, lt, rng.next_2d());
            let mut xs: Vec<(Vec3, Vec3, u32)> = vec![(p0, n0, lt)];
            while xs.len() < k {
                let t = diffuse[(rng.next_1d() * diffuse.len() as f32) as usize % diffuse.len()];
                let (p, n, _) = sample_triangle(sc, t, rng.next_2d());
                let (pp, pn, _) = *xs.last().unwrap();
                let d = (p - pp).normalize();
                if n.dot(-d) > 0.05 && pn.dot(d) > 0.05 {
                    xs.push((p, n, t));
                }
            }
            // the last surface vertex must be on the film
            let cam_p = bd.cam.pos;
            let (pl, _, _) = *xs.last().unwrap();
            if bd.cam.raster((pl - cam_p).normalize()).is_none() {
                continue;
            }
            // full path as vertices, both directions' densities
            let mut full: Vec<Vertex> = Vec::new();
            for (i, &(p, _, t)) in xs.iter().enumerate() {
                let prev = if i == 0 { p + n0 } else { xs[i - 1].0 };
                let mut v = surface(t, glam::Vec2::ZERO, prev);
                v.p = p;
                full.push(v);
            }
            full[0].kind = Kind::Light {
                light: LightRef::Triangle(lt),
                delta_pos: false,
            };
            full[0].bsdf = None;
            let mut cam_v = full[0];
            cam_v.kind = Kind::Camera;
            cam_v.p = cam_p;
            cam_v.ng = Vec3::ZERO;
            cam_v.ns = Vec3::ZERO;
            cam_v.bsdf = None;
            full.push(cam_v);
            let n = full.len(); // k + 1
            // light-direction densities
            let mut pl_fwd = vec![0.0f32; n];
            pl_fwd[0] = bd.light_point_pdf(&Vertex {
                kind: Kind::Surface,
                ..full[0]
            });
            for i in 1..n {
                let w = (full[i].p - full[i - 1].p).normalize();
                let pdf_w = if i == 1 {
                    bd.light_pdf_dir(&full[0], w)
                } else {
                    let v = &full[i - 1];
                    let f = Frame::from_normal(v.ns);
                    let wo = (full[i - 2].p - v.p).normalize();
                    v.bsdf.unwrap().pdf(f.to_local(wo), f.to_local(w))
                };
                pl_fwd[i] = to_area(pdf_w, &full[i - 1], &full[i]);
            }
            // camera-direction densities
            let mut pc_fwd = vec![0.0f32; n];
            pc_fwd[n - 1] = 1.0;
            for i in (0..n - 1).rev() {
                let w = (full[i].p - full[i + 1].p).normalize();
                let pdf_w = if i == n - 2 {
                    bd.cam.pdf_dir(w)
                } else {
                    let v = &full[i + 1];
                    let f = Frame::from_normal(v.ns);
                    let wo = (full[i + 2].p - v.p).normalize();
                    v.bsdf.unwrap().pdf(f.to_local(wo), f.to_local(w))
                };
                pc_fwd[i] = to_area(pdf_w, &full[i + 1], &full[i]);
            }
            let mut sum = 0.0f32;
            for s in 0..n {
                let t = n - s;
                if t < 1 || (s == 1 && t == 1) {
                    continue;
                }
                let light: Vec<Vertex> = (0..s)
                    .map(|i| Vertex {
                        pdf_fwd: pl_fwd[i],
                        pdf_rev: pc_fwd[i],
                        w_prev: if i == 0 {
                            full[0].w_prev
                        } else {
                            (full[i - 1].p - full[i].p).normalize()
                        },
                        ..full[i]
                    })
                    .collect();
                let cam: Vec<Vertex> = (0..t)
                    .map(|j| {
                        let i = n - 1 - j;
                        let w_prev = if j == 0 {
                            Vec3::ZERO
                        } else {
                            (full[i + 1].p - full[i].p).normalize()
                        };
                        Vertex {
                            pdf_fwd: pc_fwd[i],
                            pdf_rev: pl_fwd[i],
                            w_prev,
                            ..full[i]
                        }
                    })
                    .collect();
                let w = if t == 1 {
                    let y = light[s - 1];
                    let pdf_cam_y = to_area(bd.cam.pdf_dir((y.p - cam_p).normalize()), &cam[0], &y);
                    bd.mis_weight(&light, &cam, 1, Some(pdf_cam_y))
                } else if s == 0 {
                    // the camera path ends on the emitter x0
                    let mut cam = cam;
                    let last = cam.len() - 1;
                    cam[last].kind = Kind::Surface;
                    bd.mis_weight(&[], &cam, t, None)
                } else {
                    bd.mis_weight(&light, &cam, t, None)
                };
                sum += w;
            }
            assert!((sum - 1.0).abs() < 1e-3, "k = {k}: weights sum to {sum}");
            checked += 1;
        }
        assert!(checked > 100, "only {checked} paths checked");
    }
}
