//! Unidirectional path tracing with next-event estimation on area and punctual lights and
//! MIS (power heuristic) between light and BSDF sampling. Veach 1997, ch. 9–10;
//! PBR 4th ed. §13.4 (`PathIntegrator`). Depth and Russian roulette follow Mitsuba 3's `path`
//! integrator: `max_depth` 1 = emitters seen directly, 2 = direct lighting, RR from `rr_depth`.

use crate::bsdf::{Bsdf, BxDF, Event, TransportMode};
use crate::bvh::{Bvh, offset_ray_origin};
use crate::math::sampling::power_heuristic;
use crate::math::{Color, Frame, rgb3, rng::Sampler};
use crate::paths::{DfaTable, Symbol};
use crate::scene::light::{LightRef, LightSet, sample_triangle, spot_falloff};
use crate::scene::{MaterialKind, PunctualLight, Scene};
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

/// The path tracer for one prepared scene.
pub struct Integrator<'a> {
    pub scene: &'a Scene,
    pub bvh: &'a Bvh,
    pub lights: &'a LightSet,
    pub max_depth: u32,
    pub rr_depth: u32,
    /// Heckbert path filter in eye→light order (`PathFilter::reversed`); None = all paths.
    pub filter: Option<&'a DfaTable>,
    /// Hero-wavelength spectral transport (only scenes with a dispersive material pay for it).
    pub spectral: bool,
}

/// Colour representation of one path: RGB, or four hero wavelengths (dispersive scenes).
#[derive(Clone, Copy, Debug)]
pub struct Spectral {
    pub lambdas: Option<[f32; 4]>,
}

impl Spectral {
    /// RGB parameter → the path's colour lanes (smooth uplift in spectral mode).
    #[inline]
    pub fn c(&self, rgb: Vec3) -> Color {
        match self.lambdas {
            Some(l) => crate::math::spectrum::rgb_to_spectrum4(rgb, l),
            None => rgb3(rgb),
        }
    }
}

/// Which Heckbert classes a next-event connection may use at a vertex (D, G).
#[derive(Clone, Copy)]
struct ClassMask {
    d: bool,
    g: bool,
}

impl<'a> Integrator<'a> {
    /// Reconstruct the surface record of a BVH hit.
    #[inline]
    pub fn surface(&self, hit: &crate::bvh::Hit) -> SurfaceHit {
        let mesh = &self.scene.mesh;
        let t = hit.tri as usize;
        let [i0, i1, i2] = mesh.indices[t];
        let (i0, i1, i2) = (i0 as usize, i1 as usize, i2 as usize);
        let (p0, p1, p2) = (mesh.positions[i0], mesh.positions[i1], mesh.positions[i2]);
        let b0 = 1.0 - hit.b1 - hit.b2;
        // Barycentric hit point (more accurate than o + t·d; PBR 4th ed. §6.8.4).
        let p = p0 * b0 + p1 * hit.b1 + p2 * hit.b2;
        let ng = (p1 - p0).cross(p2 - p0).normalize_or_zero();
        let mut ns =
            (mesh.normals[i0] * b0 + mesh.normals[i1] * hit.b1 + mesh.normals[i2] * hit.b2)
                .normalize_or_zero();
        if ns == Vec3::ZERO || !ns.is_finite() {
            ns = ng;
        } else if ns.dot(ng) < 0.0 {
            ns = -ns;
        }
        let uv = mesh.uvs[i0] * b0 + mesh.uvs[i1] * hit.b1 + mesh.uvs[i2] * hit.b2;
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

    /// Solid-angle pdf with which next-event estimation would have chosen the point `hit`
    /// seen from direction `dir` at distance `hit.t`.
    #[inline]
    fn light_pdf(&self, hit: &SurfaceHit, dir: Vec3) -> f32 {
        let p_pick = self.lights.tri_pick_prob[hit.tri as usize];
        if p_pick <= 0.0 {
            return 0.0;
        }
        let area = self.scene.mesh.area(hit.tri as usize);
        let cos_l = hit.ng.dot(dir).abs();
        if cos_l <= 0.0 || area <= 0.0 {
            return 0.0;
        }
        p_pick / area * hit.t * hit.t / cos_l
    }

    /// DFA state after `sym` (0 when unfiltered).
    #[inline]
    fn step(&self, q: u32, sym: Symbol) -> u32 {
        match self.filter {
            Some(f) => f.step(q, sym),
            None => 0,
        }
    }

    /// Does a path in state `q` that now reaches a light count?
    #[inline]
    fn accepts_light(&self, q: u32) -> bool {
        match self.filter {
            Some(f) => f.is_accepting(f.step(q, Symbol::L)),
            None => true,
        }
    }

    /// Radiance along the camera ray (origin, dir) — one path sample, RGB.
    pub fn li(&self, origin: Vec3, dir: Vec3, sampler: &mut Sampler) -> Vec3 {
        let scene = self.scene;
        // Hero wavelength sampling, Wilkie et al. 2014, "Hero Wavelength Spectral Sampling".
        let sp = Spectral {
            lambdas: if self.spectral {
                Some(crate::math::spectrum::sample_hero_wavelengths(
                    sampler.next_1d(),
                ))
            } else {
                None
            },
        };
        let mut collapsed = false;
        let mut l = Color::ZERO;
        let mut beta = Color::ONE;
        let mut o = origin;
        let mut d = dir;
        let mut prev_pdf = 0.0f32;
        let mut prev_delta = true;
        let mut eta_scale = 1.0f32;
        // Absorbing medium the ray travels in (material index), if any.
        let mut medium: Option<u32> = None;
        let mut depth: u32 = 0;
        // Path-filter state: the camera vertex is E (reversed DFA reads eye→light).
        let mut q = self.step(self.filter.map_or(0, |f| f.start()), Symbol::E);
        loop {
            let Some(h) = self.bvh.intersect(o, d, f32::INFINITY) else {
                // Escaped: uniform environment (not light-sampled, so MIS weight 1).
                if self.accepts_light(q) {
                    l += beta * sp.c(scene.environment);
                }
                break;
            };
            let hit = self.surface(&h);
            if let Some(m) = medium {
                let mm = &scene.materials[m as usize];
                if mm.has_absorption() {
                    // Beer–Lambert: T = exp(−σ_a t), σ_a = −ln(c)/d (glTF KHR_materials_volume).
                    let sa = match sp.lambdas {
                        Some(_) => {
                            let c = sp.c(mm.attenuation_color).max(Color::splat(1e-6));
                            -Color::new(c.x.ln(), c.y.ln(), c.z.ln(), c.w.ln())
                                / mm.attenuation_distance
                        }
                        None => rgb3(mm.sigma_a()),
                    };
                    let tr = -sa * hit.t;
                    beta *= Color::new(tr.x.exp(), tr.y.exp(), tr.z.exp(), tr.w.exp());
                }
            }
            let mat = &scene.materials[hit.material as usize];
            let front = d.dot(hit.ng) < 0.0;

            // Emission (one-sided unless doubleSided).
            if mat.is_emissive() && (front || mat.double_sided) && self.accepts_light(q) {
                let w = if prev_delta {
                    1.0
                } else {
                    power_heuristic(prev_pdf, self.light_pdf(&hit, d))
                };
                l += beta * sp.c(mat.emission) * w;
            }
            if depth + 1 >= self.max_depth {
                break;
            }

            // Orient normals: opaque double-sided materials shade both sides alike; one-sided
            // opaque back faces are black; dielectrics keep the outward normal (eta convention).
            let transmissive = mat.is_transmissive();
            let (ng, ns) = if transmissive || front {
                (hit.ng, hit.ns)
            } else if mat.double_sided {
                (-hit.ng, -hit.ns)
            } else {
                break;
            };
            if mat.is_emissive() && mat.base_color == Vec3::ZERO {
                break; // emitters are black surfaces otherwise
            }
            let dispersive = sp.lambdas.is_some() && mat.abbe.is_some() && transmissive;
            let eta = match sp.lambdas {
                Some(l) if dispersive => mat.ior_at(l[0]),
                _ => mat.ior,
            };
            if dispersive && !collapsed {
                // Wavelength-dependent refraction: only the hero wavelength can follow this
                // direction. Keep lane 0 (×4: it now carries the whole estimate), drop the rest.
                beta = Color::new(4.0 * beta.x, 0.0, 0.0, 0.0);
                collapsed = true;
            }
            let mut bsdf = mat.bsdf(&scene.textures, hit.uv, eta);
            if sp.lambdas.is_some() {
                bsdf = bsdf.map_colors(|c| sp.c(c.truncate()));
            }
            let frame = Frame::from_normal(ns);
            let wo_w = -d;
            let wo = frame.to_local(wo_w);
            let uc = sampler.next_1d();
            let u2 = sampler.next_2d();
            let ul = sampler.next_1d();
            let ul2 = sampler.next_2d();

            // Next-event estimation.
            if !bsdf.is_delta() && !self.lights.is_empty() {
                let mask = ClassMask {
                    d: self.accepts_light(self.step(q, Symbol::D)),
                    g: self.accepts_light(self.step(q, Symbol::G)),
                };
                if mask.d || mask.g {
                    l += beta
                        * self.sample_light(&hit, ng, &frame, wo, wo_w, &bsdf, ul, ul2, mask, &sp);
                }
            }

            // BSDF sampling.
            let Some(s) = bsdf.sample(wo, uc, u2, TransportMode::Radiance) else {
                break;
            };
            let wi_w = frame.to_world(s.wi);
            let side_o = wo_w.dot(ng);
            let side_i = wi_w.dot(ng);
            let consistent = match s.event {
                Event::Reflect => side_o * side_i > 0.0,
                Event::Transmit => side_o * side_i < 0.0,
            };
            if !s.weight.is_finite() {
                // A broken BSDF value: poison the sample so the film's firewall drops and
                // counts it instead of silently biasing the image.
                return Vec3::NAN;
            }
            if !consistent {
                break;
            }
            if let Some(f) = self.filter {
                q = f.step(q, Symbol::from(s.lobe));
                if !f.can_reach_accept(q) {
                    break; // nothing this path can still reach counts
                }
            }
            beta *= s.weight;
            if s.event == Event::Transmit {
                eta_scale *= s.eta_rel * s.eta_rel;
                if mat.kind == MaterialKind::Glass {
                    // Entering when the new direction points against the outward normal.
                    medium = if wi_w.dot(hit.ng) < 0.0 {
                        Some(hit.material)
                    } else {
                        None
                    };
                }
            }
            prev_pdf = s.pdf;
            prev_delta = s.is_delta;
            o = offset_ray_origin(hit.p, if side_i > 0.0 { ng } else { -ng });
            d = wi_w;
            depth += 1;

            // Russian roulette (Mitsuba 3 `path`: q = min(max(β)·η², 0.95) from rr_depth).
            if depth >= self.rr_depth {
                let q = (beta.max_element() * eta_scale).min(0.95);
                if q <= 0.0 || sampler.next_1d() >= q {
                    break;
                }
                beta /= q;
            } else if beta.max_element() <= 0.0 {
                break;
            }
        }
        match sp.lambdas {
            Some(lambdas) => crate::math::spectrum::spectrum_sample_to_rgb(lambdas, l),
            None => l.truncate(),
        }
    }

    /// One next-event estimate at `hit` (without the path throughput), MIS-weighted.
    #[allow(clippy::too_many_arguments)]
    fn sample_light(
        &self,
        hit: &SurfaceHit,
        ng: Vec3,
        frame: &Frame,
        wo: Vec3,
        wo_w: Vec3,
        bsdf: &Bsdf,
        ul: f32,
        ul2: Vec2,
        mask: ClassMask,
        sp: &Spectral,
    ) -> Color {
        let scene = self.scene;
        let Some((light, p_pick)) = self.lights.pick(ul) else {
            return Color::ZERO;
        };
        let side_o = wo_w.dot(ng);
        // Returns (wi_world, Le or intensity term, pdf, is_delta, shadow dir, shadow tmax).
        let (wi_w, li, pdf, delta, shadow_dir, tmax, target_n) = match light {
            LightRef::Triangle(t) => {
                let (pl, nl, area) = sample_triangle(scene, t, ul2);
                let m = &scene.materials[scene.mesh.tri_material[t as usize] as usize];
                let to = pl - hit.p;
                let dist2 = to.length_squared();
                if dist2 <= 0.0 {
                    return Color::ZERO;
                }
                let dist = dist2.sqrt();
                let wi = to / dist;
                let cos_l = -wi.dot(nl);
                if cos_l <= 0.0 && !m.double_sided {
                    return Color::ZERO;
                }
                let cos_l = cos_l.abs();
                if cos_l <= 0.0 {
                    return Color::ZERO;
                }
                let pdf = p_pick / area * dist2 / cos_l;
                (wi, sp.c(m.emission), pdf, false, to, 1.0, Some(nl))
            }
            LightRef::Punctual(i) => match scene.punctual_lights[i as usize] {
                PunctualLight::Point {
                    position,
                    intensity,
                } => {
                    let to = position - hit.p;
                    let d2 = to.length_squared();
                    if d2 <= 0.0 {
                        return Color::ZERO;
                    }
                    let wi = to / d2.sqrt();
                    (wi, sp.c(intensity / d2), p_pick, true, to, 1.0, None)
                }
                PunctualLight::Spot {
                    position,
                    direction,
                    intensity,
                    cos_inner,
                    cos_outer,
                } => {
                    let to = position - hit.p;
                    let d2 = to.length_squared();
                    if d2 <= 0.0 {
                        return Color::ZERO;
                    }
                    let wi = to / d2.sqrt();
                    let fall = spot_falloff((-wi).dot(direction), cos_inner, cos_outer);
                    if fall <= 0.0 {
                        return Color::ZERO;
                    }
                    (wi, sp.c(intensity * fall / d2), p_pick, true, to, 1.0, None)
                }
                PunctualLight::Directional {
                    direction,
                    irradiance,
                } => {
                    let wi = -direction;
                    (wi, sp.c(irradiance), p_pick, true, wi, f32::INFINITY, None)
                }
            },
        };
        let side_i = wi_w.dot(ng);
        let wi = frame.to_local(wi_w);
        let f = if mask.d && mask.g {
            bsdf.eval(wo, wi, TransportMode::Radiance)
        } else {
            let lv = bsdf.eval_lobes(wo, wi, TransportMode::Radiance);
            (if mask.d { lv.d } else { Color::ZERO }) + (if mask.g { lv.g } else { Color::ZERO })
        };
        // Reflection must stay on the geometric side of wo; transmission must cross it.
        if side_i == 0.0 || f.max_element() <= 0.0 {
            return Color::ZERO;
        }
        let geometric_ok = if side_i * side_o > 0.0 {
            true
        } else {
            bsdf.can_transmit()
        };
        if !geometric_ok {
            return Color::ZERO;
        }
        let origin = offset_ray_origin(hit.p, if side_i > 0.0 { ng } else { -ng });
        let (sdir, stmax) = match target_n {
            Some(nl) => {
                let pl = hit.p + shadow_dir;
                let target = offset_ray_origin(pl, if nl.dot(-wi_w) > 0.0 { nl } else { -nl });
                (target - origin, tmax)
            }
            None => {
                if tmax.is_finite() {
                    (hit.p + shadow_dir - origin, tmax)
                } else {
                    (shadow_dir, tmax)
                }
            }
        };
        if self.bvh.occluded(origin, sdir, stmax) {
            return Color::ZERO;
        }
        let w = if delta {
            1.0
        } else {
            power_heuristic(pdf, bsdf.pdf(wo, wi))
        };
        f * wi.z.abs() * li * (w / pdf)
    }
}
