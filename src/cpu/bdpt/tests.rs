//! MIS check (Veach 1997, §9.2): for a fixed full path x0 (on the light) … xk (camera) of
//! non-delta vertices, the power-heuristic weights of all strategies (s, t = k + 1 − s) that
//! can produce it sum to 1. The subpaths are built with the densities the random walks would
//! store; `mis_weight` recomputes the connection vertices itself.

use super::vertex::to_area;
use super::*;
use crate::bsdf::BxDF;
use crate::cpu::Renderer;
use crate::math::Frame;
use crate::render::RenderOptions;
use crate::scene::light::TriangleLight;
use crate::scene::{MaterialKind, Scene};

/// A uniform point on scene triangle `t`: (position, unit geometric normal).
fn sample_triangle(sc: &Scene, t: u32, u: glam::Vec2) -> (Vec3, Vec3) {
    let l = TriangleLight::new(t, 0, sc.mesh.tri(t as usize), Vec3::ONE, false);
    (l.sample_point(u), l.n)
}

/// A diffuse surface vertex on triangle `t` at `p`, arrived at from `prev`.
fn surface_vertex(sc: &Scene, t: u32, p: Vec3, prev: Vec3) -> Vertex<'static> {
    let (_, n) = sample_triangle(sc, t, glam::Vec2::ZERO);
    let m = sc.mesh.tri_material[t as usize];
    let mat = &sc.materials[m as usize];
    Vertex {
        ng: n,
        ns: n,
        bsdf: Some(mat.bsdf(&sc.textures, glam::Vec2::ZERO, mat.ior)),
        w_prev: (prev - p).normalize(),
        tri: t,
        ..Vertex::new(Kind::Surface, p, Color::ONE, 0.0, Symbol::D)
    }
}

/// A random full path of `k` segments: x0 on the light, x1…x(k−1) on diffuse walls facing each
/// other, then the camera; `None` when the last surface vertex is off the film.
fn random_path<'r>(
    bd: &Bdpt,
    r: &'r Renderer,
    rng: &mut Sampler,
    k: usize,
) -> Option<Vec<Vertex<'r>>> {
    let sc = &r.scene;
    let mat_of = |t: u32| &sc.materials[sc.mesh.tri_material[t as usize] as usize];
    let diffuse: Vec<u32> = (0..sc.mesh.triangle_count() as u32)
        .filter(|&t| mat_of(t).kind == MaterialKind::Diffuse && !mat_of(t).is_emissive())
        .collect();
    let light_tris = sc.emissive_triangles();
    let pick = |u: f32, v: &[u32]| v[(u * v.len() as f32) as usize % v.len()];
    let lt = pick(rng.next_1d(), &light_tris);
    let (p0, n0) = sample_triangle(sc, lt, rng.next_2d());
    let mut xs: Vec<(Vec3, Vec3, u32)> = vec![(p0, n0, lt)];
    while xs.len() < k {
        let t = pick(rng.next_1d(), &diffuse);
        let (p, n) = sample_triangle(sc, t, rng.next_2d());
        let (pp, pn, _) = *xs.last().expect("non-empty");
        let d = (p - pp).normalize();
        if n.dot(-d) > 0.05 && pn.dot(d) > 0.05 {
            xs.push((p, n, t));
        }
    }
    let cam_p = bd.cam.pos;
    let (pl, _, _) = *xs.last().expect("non-empty");
    bd.cam.raster((pl - cam_p).normalize())?;
    let mut full: Vec<Vertex> = xs
        .iter()
        .enumerate()
        .map(|(i, &(p, _, t))| {
            let prev = if i == 0 { p + n0 } else { xs[i - 1].0 };
            surface_vertex(sc, t, p, prev)
        })
        .collect();
    let (light0, pick0) = r.lights.area_light(lt).expect("emissive triangle");
    full[0].kind = Kind::Light {
        light: light0,
        pick: pick0,
    };
    full[0].bsdf = None;
    full.push(Vertex::new(Kind::Camera, cam_p, Color::ONE, 0.0, Symbol::E));
    Some(full)
}

/// Solid-angle density of leaving `full[from]` towards `full[to]`, having arrived from
/// `full[back]` (BSDF), or emitted by the light `full[0]` (`back` = None).
fn pdf_dir(bd: &Bdpt, full: &[Vertex], from: usize, to: usize, back: Option<usize>) -> f32 {
    let w = (full[to].p - full[from].p).normalize();
    match back {
        None => bd.light_pdf_dir(&full[from], w),
        Some(b) => {
            let v = &full[from];
            let f = Frame::from_normal(v.ns);
            let wo = (full[b].p - v.p).normalize();
            v.bsdf.expect("surface").pdf(f.to_local(wo), f.to_local(w))
        }
    }
}

/// Area densities of every vertex generated from the light side and from the camera side.
fn densities(bd: &Bdpt, full: &[Vertex]) -> (Vec<f32>, Vec<f32>) {
    let n = full.len();
    let mut pl_fwd = vec![0.0f32; n];
    pl_fwd[0] = bd.light_point_pdf(&Vertex {
        kind: Kind::Surface,
        ..full[0]
    });
    for i in 1..n {
        let back = if i == 1 { None } else { Some(i - 2) };
        pl_fwd[i] = to_area(pdf_dir(bd, full, i - 1, i, back), &full[i - 1], &full[i]);
    }
    let mut pc_fwd = vec![0.0f32; n];
    pc_fwd[n - 1] = 1.0;
    for i in (0..n - 1).rev() {
        let pdf_w = if i == n - 2 {
            bd.cam.pdf_dir((full[i].p - full[i + 1].p).normalize())
        } else {
            pdf_dir(bd, full, i + 1, i, Some(i + 2))
        };
        pc_fwd[i] = to_area(pdf_w, &full[i + 1], &full[i]);
    }
    (pl_fwd, pc_fwd)
}

/// MIS weight of strategy (s, n − s) for the full path with its densities.
fn strategy_weight(
    bd: &Bdpt,
    full: &[Vertex],
    (pl_fwd, pc_fwd): (&[f32], &[f32]),
    s: usize,
) -> f32 {
    let n = full.len();
    let t = n - s;
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
    let mut cam: Vec<Vertex> = (0..t)
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
    if t == 1 {
        let y = light[s - 1];
        let pdf_cam_y = to_area(bd.cam.pdf_dir((y.p - bd.cam.pos).normalize()), &cam[0], &y);
        bd.mis_weight(&light, &cam, 1, Some(pdf_cam_y))
    } else if s == 0 {
        // The camera path ends on the emitter x0.
        let last = cam.len() - 1;
        cam[last].kind = Kind::Surface;
        bd.mis_weight(&[], &cam, t, None)
    } else {
        bd.mis_weight(&light, &cam, t, None)
    }
}

#[test]
fn strategy_weights_sum_to_one() {
    let scene = Scene::load("builtin:cornell-glass").expect("builtin");
    let r = Renderer::new(scene).expect("valid");
    let mut o = RenderOptions::from_scene(&r.scene);
    o.width = 64;
    o.height = 64;
    let integ = r.integrator(&o);
    let bd = Bdpt::new(&integ, BdptMode::Full, None, 64, 64);
    let mut rng = Sampler::new(7, 0, 1);
    let mut checked = 0;
    for _ in 0..400 {
        let k = 2 + (rng.next_1d() * 4.0) as usize; // path of k segments, k + 1 vertices
        let Some(full) = random_path(&bd, &r, &mut rng, k) else {
            continue;
        };
        let (pl, pc) = densities(&bd, &full);
        let n = full.len();
        let sum: f32 = (0..n)
            .filter(|&s| !(s == 1 && n - s == 1))
            .map(|s| strategy_weight(&bd, &full, (&pl, &pc), s))
            .sum();
        assert!((sum - 1.0).abs() < 1e-3, "k = {k}: weights sum to {sum}");
        checked += 1;
    }
    assert!(checked > 100, "only {checked} paths checked");
}
