//! Bidirectional path tracing (Veach 1997, ch. 10; Veach & Guibas 1995, "Bidirectional
//! Estimators for Light Transport") with multiple importance sampling over every connection
//! strategy (s light vertices, t camera vertices), including light-tracing splats (t = 1) to
//! the film, and pure light tracing as a restriction of the same machinery.
//!
//! Files: `vertex` (subpath vertices, density conversions), `camera` (pinhole importance),
//! `walk` (both subpaths' random walks on the shared per-vertex step), `connect` (the
//! strategies), `mis` (power-heuristic weights by Veach's ratio recurrence, §10.2).
//! Importance transport uses the adjoint BSDF: no 1/η² on refraction and the shading-normal
//! correction |ωo·ns||ωi·ng| / (|ωo·ng||ωi·ns|) (Veach 1997, §5.3, eq. 5.19). Absorbing
//! media attenuate every walk segment and every connection (Beer–Lambert).
//!
//! Scope: lights at infinity (directional) are connected only by the s = 1 strategy (they
//! start no light subpath here), so their weight is 1; the environment is reached only by
//! camera subpaths (weight 1).

mod camera;
mod connect;
mod mis;
mod vertex;
mod walk;

use super::integrator::Integrator;
use super::path_state::PathState;
use super::spectral::Spectral;
use crate::bsdf::TransportMode;
use crate::math::{Color, rng::Sampler};
use crate::paths::{DfaTable, Symbol};
use camera::CameraModel;
use glam::Vec3;
use vertex::{Kind, Vertex};

/// Which strategies contribute.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BdptMode {
    /// All strategies, MIS-weighted.
    Full,
    /// Only t = 1 (light tracing: every light-subpath vertex connected to the camera), weight 1.
    LightTracing,
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
        Bdpt {
            pt,
            mode,
            filter,
            cam: CameraModel::new(&pt.scene.camera, width, height),
        }
    }

    /// The camera subpath through pixel (x, y) with jitter `j`; adds the environment seen by
    /// an escaping camera subpath to `l` (no strategy samples it: weight 1).
    fn camera_path(
        &self,
        cam: &mut Vec<Vertex>,
        (x, y, j): (u32, u32, glam::Vec2),
        max_depth: usize,
        sampler: &mut Sampler,
        sp: &Spectral,
    ) -> Color {
        let dir = self.pt.scene.camera.ray_dir(
            (x as f32 + j.x) / self.cam.width as f32,
            (y as f32 + j.y) / self.cam.height as f32,
            self.cam.aspect,
        );
        cam.push(Vertex::new(
            Kind::Camera,
            self.cam.pos,
            Color::ONE,
            1.0,
            Symbol::E,
        ));
        // Camera subpath: at most max_depth + 1 vertices (max_depth segments).
        let cam_max = (max_depth + 1).min(MAX_VERTS);
        let escaped = self.walk(
            cam,
            (self.cam.pos, dir),
            PathState::new(Color::ONE, false),
            self.cam.pdf_dir(dir),
            cam_max,
            TransportMode::Radiance,
            sampler,
            sp,
        );
        let Some((b, collapsed, d)) = escaped else {
            return Color::ZERO;
        };
        let env = self.pt.lights.environment.le(Vec3::ZERO, -d);
        if self.mode == BdptMode::Full
            && env.max_element() > 0.0
            && cam.len() <= max_depth
            && self.accepted(&[], None, None, cam)
        {
            Self::finish(b * sp.c(env), collapsed)
        } else {
            Color::ZERO
        }
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
        let j = sampler.next_2d();
        // Hero wavelengths shared by both subpaths (scenes with dispersion only).
        let sp = &Spectral::new(self.pt.spectral, || sampler.next_1d());
        let mut l = self.camera_path(&mut cam, (x, y, j), max_depth, sampler, sp);
        let mut ls = sampler.with_dim(1 << 16);
        self.light_path(&mut light, max_depth.min(MAX_VERTS), &mut ls, sp);
        // A delta-position light is never seen directly through a pinhole.
        let delta_light = light.first().is_some_and(|v| v.is_delta_light());
        for t in 1..=cam.len() {
            for s in 0..=light.len() {
                if s + t < 2 || s + t - 1 > max_depth {
                    continue;
                }
                if t == 1 {
                    // (1,1) would see emitters directly a second time; (0,2) does that in the
                    // full estimator (as in Veach's and pbrt's BDPT). Pure light tracing keeps it.
                    if s == 0 || (s == 1 && (self.mode == BdptMode::Full || delta_light)) {
                        continue;
                    }
                    if let Some((px, py, v)) = self.connect_camera(&light[..s], &cam, sp) {
                        splat(px, py, sp.to_rgb(v));
                    }
                } else if self.mode == BdptMode::Full {
                    l += self.connect(&light[..s], &cam[..t], sp);
                }
            }
        }
        sp.to_rgb(l)
    }
}

#[cfg(test)]
mod tests {
    use super::vertex::to_area;
    use super::*;
    use crate::bsdf::BxDF;
    use crate::cpu::Renderer;
    use crate::math::Frame;
    use crate::render::RenderOptions;
    use crate::scene::light::TriangleLight;
    use crate::scene::{MaterialKind, Scene};

    /// A uniform point on scene triangle `t`: (position, unit geometric normal).
    fn sample_triangle(sc: &Scene, t: u32, u: glam::Vec2) -> (Vec3, Vec3, f32) {
        let l = TriangleLight::new(t, 0, sc.mesh.tri(t as usize), Vec3::ONE, false);
        (l.sample_point(u), l.n, l.area)
    }

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
                medium: None,
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
            let (light0, pick0) = r.lights.area_light(lt).expect("emissive triangle");
            full[0].kind = Kind::Light {
                light: *light0,
                pick: pick0,
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
