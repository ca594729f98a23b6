//! Bidirectional path tracing (Veach 1997, ch. 10; Veach & Guibas 1995, "Bidirectional
//! Estimators for Light Transport") with multiple importance sampling over every connection
//! strategy (s light vertices, t camera vertices), including light-tracing splats (t = 1) to
//! the film, and pure light tracing as a restriction of the same machinery.
//!
//! Files: `vertex` (subpath vertices, density conversions), `camera` (pinhole importance),
//! `walk` (both subpaths' random walks on the shared per-vertex step), `connect` (the
//! strategies), `end` (a connection end evaluated once), `mis` (power-heuristic weights by
//! Veach's ratio recurrence, §10.2, O(1) per connection from per-vertex partial sums;
//! `mis_oracle` keeps the direct form for tests), `filter` (the Heckbert filter from
//! per-vertex prefix states).
//! Importance transport uses the adjoint BSDF: no 1/η² on refraction and the shading-normal
//! correction |ωo·ns||ωi·ng| / (|ωo·ng||ωi·ns|) (Veach 1997, §5.3, eq. 5.19). Absorbing
//! media attenuate every walk segment and every connection (Beer–Lambert).
//!
//! Scope: lights at infinity start no light subpath in the full estimator: a directional light
//! is connected only by the s = 1 strategy (weight 1); an image environment by s = 1 and by
//! camera subpaths escaping to it (s = 0), the two MIS-weighted against each other as in the
//! path tracer; a uniform environment only by escaping camera subpaths (weight 1). Pure light
//! tracing walks from every light, those at infinity included (from their bounding disk).

mod camera;
mod connect;
mod end;
mod filter;
mod mis;
#[cfg(test)]
mod mis_oracle;
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
use walk::WalkStart;

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
    /// The scene has nested or absorbing volumes: the walks keep a medium stack and
    /// connections attenuate (without, every segment is in air, as in the path tracer's
    /// lean walk, `cpu::walk_spec`).
    media: bool,
    /// The scene has textures: surface hits interpolate uv.
    with_uv: bool,
}

const MAX_VERTS: usize = 66;

/// The two subpaths' vertex buffers, reused from sample to sample (no allocation per sample).
#[derive(Default)]
pub struct Scratch<'a> {
    cam: Vec<Vertex<'a>>,
    light: Vec<Vertex<'a>>,
}

impl Scratch<'_> {
    pub fn new() -> Self {
        Scratch {
            cam: Vec::with_capacity(MAX_VERTS),
            light: Vec::with_capacity(MAX_VERTS),
        }
    }
}

impl<'a> Bdpt<'a> {
    pub fn new(
        pt: &'a Integrator<'a>,
        mode: BdptMode,
        filter: Option<&'a DfaTable>,
        width: u32,
        height: u32,
    ) -> Self {
        let features = pt.walk_features(&Spectral::RGB);
        Bdpt {
            pt,
            mode,
            filter,
            cam: CameraModel::new(&pt.scene.camera, width, height),
            media: features.media,
            with_uv: features.textures,
        }
    }

    /// The camera subpath through pixel (x, y) with jitter `j`; adds the environment seen by
    /// an escaping camera subpath to `l` (no strategy samples it: weight 1).
    fn camera_path(
        &self,
        cam: &mut Vec<Vertex<'a>>,
        (x, y, j): (u32, u32, glam::Vec2),
        max_depth: usize,
        sampler: &mut Sampler,
        sp: &Spectral,
    ) -> Color {
        let dir = self.cam.rays.dir(
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
        if self.mode == BdptMode::LightTracing {
            // Pure light tracing connects only to the camera vertex (t = 1).
            self.camera_suffix_masks(cam);
            return Color::ZERO;
        }
        // Camera subpath: at most max_depth + 1 vertices (max_depth segments).
        let cam_max = (max_depth + 1).min(MAX_VERTS);
        let start = WalkStart {
            ray: (self.cam.pos, dir),
            st: PathState::new(Color::ONE, false, self.pt.nested),
            // A primary ray lands on the film by construction.
            pdf_w: self.cam.pdf_at_cos(self.cam.cos_to_axis(dir)),
            mode: TransportMode::Radiance,
        };
        let escaped = self.walk(cam, start, cam_max, sampler, sp);
        self.camera_suffix_masks(cam);
        let Some((b, collapsed, d)) = escaped else {
            return Color::ZERO;
        };
        let env = self.pt.lights.environment.le(Vec3::ZERO, Vec3::ZERO, -d);
        if self.mode == BdptMode::Full
            && env.max_element() > 0.0
            && cam.len() <= max_depth
            && self.accepted(&[], None, None, cam)
        {
            Self::finish(b * sp.c(env) * self.env_escape_weight(cam, d), collapsed)
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
        scratch: &mut Scratch<'a>,
    ) -> Vec3 {
        let max_depth = self.pt.max_depth.max(1) as usize;
        let Scratch { cam, light } = scratch;
        cam.clear();
        light.clear();
        let j = sampler.next_2d();
        // Hero wavelengths shared by both subpaths (scenes with dispersion only).
        let sp = &self.pt.lanes(|| sampler.next_1d());
        let mut l = self.camera_path(cam, (x, y, j), max_depth, sampler, sp);
        let mut ls = sampler.with_dim(1 << 16);
        self.light_path(light, max_depth.min(MAX_VERTS), &mut ls, sp);
        self.light_prefix_states(light);
        if self.mode == BdptMode::Full {
            mis::prefix_sums(cam);
            mis::prefix_sums(light);
        }
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
                    if let Some((px, py, v)) = self.connect_camera(&light[..s], cam, sp) {
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
mod prefix_tests;
#[cfg(test)]
mod tests;
