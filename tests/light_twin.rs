//! Light twin test: the WGSL lights (src/scene/light/light.wgsl, run through
//! src/gpu/light_probe.wgsl) against the Rust `scene::light::Light` methods, on one scene
//! with every light type — a one-sided area light with an emissive texture (a bilinear ramp
//! under a `KHR_texture_transform` scale) and a two-sided one, a point light, a spot light
//! (reference points and directions inside the inner cone, in the falloff ramp and outside
//! the outer cone), a directional light and the uniform environment.
//!
//! Per case (light, reference point, random numbers) both sides compute `sample_li`
//! (l, wi, pdf, p_light, n_light, is_delta, infinite), `pdf_li` of the sampled point, `le`
//! and `pdf_le` for a given normal and direction, `sample_le` (p, n, dir, l, pdf_pos,
//! pdf_dir, delta_pos), the light-selection pick and an area light's hit probability.
//!
//! Tolerance: relative 1e-5 (vectors by the length of the difference over the longer
//! length, scalars by |a − b| / max(|a|, |b|)); 1e-4 for spot-light radiance, where a
//! cosine enters the falloff ramp with slope 1/(cos θ_inner − cos θ_outer) ≈ 9. The pick is
//! exact (the same f32 CDF entries and subtraction on both sides).
//!
//! Documented differences of the twins (asserted as such below, not compared):
//! - `light_sample_le` draws a two-sided emitter's side from the sampler it is given; the
//!   Rust `sample_le` takes it as `u_side`. The probe reports the sampler's first draw and
//!   the Rust side is given that, so both take the same side.
//! - `light_sample_le` of a triangle reports the emitting side as `n` (the Rust `n` is the
//!   front normal) and the cosine `cos_n`; it returns `valid = false` where the Rust
//!   `sample_le` returns a direction with `pdf_dir` 0 (a tangent direction; not probed).
//!
//! The environment image (a seeded 24 × 12 map with one bright texel, rotated 37°, with and
//! without importance sampling, next to an area light) is compared the same way in
//! `image_environment_twin_parity`.
//!
//! Lights at infinity (directional, uniform environment, environment image) emit from the
//! disk covering the scene's bounding sphere on both sides (`sample_le` / `pdf_le`, the GPU
//! `Light` carries the sphere): compared like the others, the image's with `IMAGE_REL`.

mod common_scenes;
use common_scenes::*;
use glam::{Vec2, Vec3};
use refract::gpu::layout::{LightProbeCase, LightProbeOut, LightProbeParams, check_layout};
use refract::gpu::light_probe::run_light_probe;
use refract::gpu::pipeline::light_probe_source;
use refract::scene::light::{Light, LightSet};
use refract::scene::material::{Texture, TextureRef, Wrap};
use refract::scene::{Camera, Material, Mesh, PunctualLight, Scene};

/// Relative tolerance of every compared value.
const REL: f32 = 1e-5;
/// Relative tolerance of spot-light radiance (a cosine through the steep falloff ramp).
const SPOT_REL: f32 = 1e-4;
/// Relative tolerance of the environment image's densities and directions: they go through
/// atan2, acos and sin, which Vulkan lets a GPU compute to 2⁻¹¹ absolute error (Vulkan spec,
/// "Precision and Operation of SPIR-V Instructions"); lavapipe's differ from Rust's by ≤ 7e-5.
const IMAGE_REL: f32 = 1e-3;

/// Absolute error of the image coordinates (u, t) the GPU may make through atan2 and acos
/// (lavapipe's differ from Rust's by ≤ 7e-5; see [`IMAGE_REL`]).
const IMAGE_UV_ABS: f32 = 1e-4;

/// Relative tolerance of the environment image's radiance towards `wi` (unit, towards the
/// environment): the image is interpolated bilinearly, so an error δ ≤ [`IMAGE_UV_ABS`] in
/// (u, t) moves the radiance by up to δ·(W + H) × the spread of the four texels read (a bright
/// texel next to a dark one is the steepest); [`REL`] for every other light. Sampled
/// directions read the radiance where they were sampled, on both sides.
fn radiance_tol(light: &Light, wi: Vec3, l: Vec3) -> f32 {
    use refract::scene::env_map::{bilinear, dir_to_uv, rotate_y};
    let Light::Image(e) = light else {
        return if matches!(light, Light::Spot(_)) {
            SPOT_REL
        } else {
            REL
        };
    };
    let m = &e.image.map;
    let uv = dir_to_uv(rotate_y(wi, e.cos_rot, -e.sin_rot));
    let ((x0, x1, _), (y0, y1, _)) = bilinear(uv, m.width, m.height);
    let w = m.width as usize;
    let four = [y0 * w + x0, y0 * w + x1, y1 * w + x0, y1 * w + x1].map(|i| m.texels[i]);
    let hi = four.iter().fold(Vec3::ZERO, |a, t| a.max(*t));
    let lo = four
        .iter()
        .fold(Vec3::splat(f32::INFINITY), |a, t| a.min(*t));
    let spread = e.image.strength * (hi - lo).length();
    REL + spread * (m.width + m.height) as f32 * IMAGE_UV_ABS / l.length().max(1e-6)
}

const SPOT_INNER_DEG: f32 = 20.0;
const SPOT_OUTER_DEG: f32 = 30.0;

/// A floor, a one-sided area light facing down, a two-sided vertical area light, a point,
/// a spot pointing down (cone 20°–30°), a directional light and a uniform environment.
fn all_lights_scene() -> Scene {
    let mut m = Mesh::default();
    quad(
        &mut m,
        Vec3::new(-5.0, 0.0, 5.0),
        Vec3::X * 10.0,
        Vec3::Z * -10.0,
        0,
    );
    // Normal X × Z = −Y (facing the floor); an emissive texture over uv (0, 0)–(1, 1).
    quad(&mut m, Vec3::new(-1.5, 3.0, -0.5), Vec3::X, Vec3::Z, 1);
    let n = m.uvs.len();
    m.uvs[n - 4..].copy_from_slice(&[Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y]);
    // Normal Y × Z = +X; emits on both faces.
    quad(&mut m, Vec3::new(2.0, 1.0, -0.5), Vec3::Y, Vec3::Z, 2);
    let one_sided = Material {
        emissive_texture: Some(TextureRef {
            texture: 0,
            tex_coord: 0,
            transform: glam::Affine2::from_scale(Vec2::new(1.5, 1.0)),
        }),
        ..Material::emitter("one-sided", Vec3::new(4.0, 3.0, 2.0))
    };
    let two_sided = Material {
        double_sided: true,
        ..Material::emitter("two-sided", Vec3::new(1.0, 2.0, 3.0))
    };
    let cam = Camera::look_at(Vec3::new(0.0, 2.0, 6.0), Vec3::ZERO, Vec3::Y, 0.8);
    let floor = Material::diffuse("floor", Vec3::splat(0.5));
    let mut s = scene("all lights", m, vec![floor, one_sided, two_sided], cam, 0.0);
    s.environment = Vec3::new(0.2, 0.3, 0.4);
    // A bilinear ramp (repeating, so the transform wraps it once across the quad).
    s.textures = vec![Texture {
        width: 4,
        height: 3,
        texels: (0..12)
            .map(|i| {
                glam::Vec4::new(
                    0.1 + 0.3 * (i % 4) as f32,
                    1.0 - 0.4 * (i / 4) as f32,
                    0.6,
                    1.0,
                )
            })
            .collect(),
        wrap_s: Wrap::Repeat,
        wrap_t: Wrap::Repeat,
        linear: true,
    }];
    s.punctual_lights = vec![
        PunctualLight::Point {
            position: Vec3::new(0.0, 2.5, 1.0),
            intensity: Vec3::new(5.0, 4.0, 3.0),
        },
        PunctualLight::Spot {
            position: Vec3::new(0.0, 3.0, 0.0),
            direction: -Vec3::Y,
            intensity: Vec3::new(10.0, 20.0, 30.0),
            cos_inner: SPOT_INNER_DEG.to_radians().cos(),
            cos_outer: SPOT_OUTER_DEG.to_radians().cos(),
        },
        PunctualLight::Directional {
            direction: Vec3::new(0.3, -1.0, 0.2).normalize(),
            irradiance: Vec3::new(1.5, 1.0, 0.5),
        },
    ];
    s
}

/// Reference points. Seen from the spot at (0, 3, 0) pointing down: the origin is on its
/// axis, (1.40, 0, 0) at 25° and (0, 0, −1.2) at 21.8° are in the ramp, (2.52, 0, 0.3) at
/// 40.2° and (−1, 4, 0) (above it) are outside. (−1, 4, 0) is behind the one-sided light,
/// (2.52, 0, 0.3) in front of the two-sided one and the others behind it.
fn points() -> [Vec3; 6] {
    let ramp = 3.0 * 25f32.to_radians().tan();
    let outside = 3.0 * 40f32.to_radians().tan();
    [
        Vec3::ZERO,
        Vec3::new(ramp, 0.0, 0.0),
        Vec3::new(0.0, 0.0, -1.2),
        Vec3::new(outside, 0.0, 0.3),
        Vec3::new(-1.0, 4.0, 0.0),
        Vec3::new(0.5, 0.5, -2.0),
    ]
}

/// Directions of `le` / `pdf_le`: relative to the spot axis −Y at 0°, ≈21.8°, ≈25.2°, ≈40°
/// (inside, ramp, ramp, outside), then upwards, sideways and along ±X (the two-sided light's
/// normal).
fn directions() -> [Vec3; 8] {
    [
        -Vec3::Y,
        Vec3::new(0.4, -1.0, 0.0).normalize(),
        Vec3::new(0.0, -1.0, -0.47).normalize(),
        Vec3::new(0.84, -1.0, 0.0).normalize(),
        Vec3::Y,
        Vec3::new(1.0, 0.2, -0.3).normalize(),
        Vec3::X,
        -Vec3::X,
    ]
}

/// Probes per light: every reference point with 5 sets of random numbers.
const PER_POINT: usize = 5;

/// The cases of light `light` (index into `set.lights`; `set.lights.len()`: environment).
fn cases_of(set: &LightSet, light: usize, out: &mut Vec<LightProbeCase>) {
    let n_lights = set.lights.len();
    let (pick, normal) = match set.lights.get(light) {
        Some(l) => {
            let prev = if light == 0 { 0.0 } else { set.cdf[light - 1] };
            let n = match l {
                Light::Triangle(t) => t.n,
                _ => Vec3::Y,
            };
            (set.cdf[light] - prev, n)
        }
        None => (0.5, Vec3::Y),
    };
    let frac = |x: f32| x - x.floor();
    let ws = directions();
    for (pi, p) in points().into_iter().enumerate() {
        for k in 0..PER_POINT {
            let idx = pi * PER_POINT + k;
            let f = idx as f32 + 0.5 * light as f32;
            let sign = if (idx / ws.len()).is_multiple_of(2) {
                1.0
            } else {
                -1.0
            };
            // Every third pick lands exactly on a CDF entry (first entry > u wins).
            let u_pick = if idx.is_multiple_of(3) {
                set.cdf[(idx / 3 + light) % n_lights]
            } else {
                (idx as f32 + 0.5) / (points().len() * PER_POINT) as f32
            };
            out.push(LightProbeCase {
                p: p.to_array(),
                light: light as u32,
                n: (sign * normal).to_array(),
                pick,
                w: ws[idx % ws.len()].to_array(),
                u_pick,
                u: [frac(f * 0.29 + 0.11), frac(f * 0.61 + 0.05)],
                u_pos: [frac(f * 0.37 + 0.23), frac(f * 0.17 + 0.71)],
                u_dir: [frac(f * 0.53 + 0.07), frac(f * 0.83 + 0.31)],
                pixel: (idx as u32).wrapping_mul(2_654_435_761) ^ light as u32,
                sample: idx as u32,
                seed: light as u32,
                ..Default::default()
            });
        }
    }
}

/// Worst errors and the first mismatches.
#[derive(Default)]
struct Track {
    /// Worst relative error under [`REL`] and under [`SPOT_REL`].
    worst: f32,
    worst_spot: f32,
    failures: Vec<String>,
    n_fail: usize,
    compared: usize,
}

impl Track {
    fn err(&mut self, e: f32, what: &str, gpu: String, cpu: String, tol: f32, case: usize) {
        self.compared += 1;
        if tol == SPOT_REL || tol == IMAGE_REL {
            self.worst_spot = self.worst_spot.max(e);
        } else {
            self.worst = self.worst.max(e);
        }
        if e.is_nan() || e > tol {
            self.fail(format!(
                "case {case}: {what}: GPU {gpu} vs CPU {cpu} (rel {e:.2e})"
            ));
        }
    }
    /// Scalars: |a − b| / max(|a|, |b|).
    fn val(&mut self, gpu: f32, cpu: f32, what: &str, tol: f32, case: usize) {
        let e = if gpu == cpu {
            0.0
        } else {
            (gpu - cpu).abs() / gpu.abs().max(cpu.abs())
        };
        self.err(e, what, gpu.to_string(), cpu.to_string(), tol, case);
    }
    /// Vectors: |a − b| / max(|a|, |b|).
    fn vec(&mut self, gpu: [f32; 3], cpu: Vec3, what: &str, tol: f32, case: usize) {
        let g = Vec3::from_array(gpu);
        let e = if g == cpu {
            0.0
        } else {
            (g - cpu).length() / g.length().max(cpu.length())
        };
        self.err(e, what, format!("{g:?}"), format!("{cpu:?}"), tol, case);
    }
    fn check(&mut self, ok: bool, what: String) {
        if !ok {
            self.fail(what);
        }
    }
    fn fail(&mut self, msg: String) {
        self.n_fail += 1;
        if self.failures.len() < 30 {
            self.failures.push(msg);
        } else if self.failures.len() == 30 {
            self.failures.push("…".into());
        }
    }
}

/// `sample_li` and `pdf_li` of the sampled point.
fn compare_li(t: &mut Track, light: &Light, c: &LightProbeCase, o: &LightProbeOut, i: usize) {
    let p = Vec3::from_array(c.p);
    let cpu = light.sample_li(p, Vec2::from_array(c.u), c.pick);
    let valid = o.li_flags & 1 != 0;
    t.check(
        valid == cpu.is_some(),
        format!(
            "case {i}: sample_li valid: GPU {valid}, CPU {}",
            cpu.is_some()
        ),
    );
    let Some(s) = cpu.filter(|_| valid) else {
        return;
    };
    let l_tol = radiance_tol(light, s.wi, s.l);
    let tol = if matches!(light, Light::Image(_)) {
        IMAGE_REL
    } else {
        REL
    };
    t.vec(o.li_l, s.l, "sample_li l", l_tol, i);
    t.vec(o.li_wi, s.wi, "sample_li wi", tol, i);
    t.val(o.li_pdf, s.pdf, "sample_li pdf", tol, i);
    t.vec(o.li_p, s.p_light, "sample_li p_light", REL, i);
    t.vec(o.li_n, s.n_light, "sample_li n_light", REL, i);
    let flags = [(o.li_flags >> 1) & 1 != 0, (o.li_flags >> 2) & 1 != 0];
    t.check(
        flags == [s.is_delta, s.infinite],
        format!(
            "case {i}: sample_li (is_delta, infinite): GPU {flags:?}, CPU {:?}",
            [s.is_delta, s.infinite]
        ),
    );
    let dist = (s.p_light - p).length();
    let cos_light = s.n_light.dot(s.wi).abs();
    let back = light.pdf_li(c.pick, s.wi, dist, cos_light);
    t.val(o.li_pdf_back, back, "pdf_li", tol, i);
}

/// `sample_le`, with the side the GPU sampler drew.
fn compare_sample_le(
    t: &mut Track,
    light: &Light,
    c: &LightProbeCase,
    o: &LightProbeOut,
    i: usize,
) {
    let u_pos = Vec2::from_array(c.u_pos);
    let u_dir = Vec2::from_array(c.u_dir);
    let cpu = light.sample_le(u_pos, u_dir, o.u_side, c.pick);
    let valid = o.le_flags & 1 != 0;
    // The image may have no direction for u_dir (a cell of density 0) on both sides.
    let agree = valid == cpu.is_some() && (valid || light.is_infinite());
    t.check(
        agree,
        format!(
            "case {i}: sample_le valid: GPU {valid}, CPU {}",
            cpu.is_some()
        ),
    );
    let Some(s) = cpu.filter(|_| valid) else {
        return;
    };
    // The WGSL reports the emitting side and its cosine.
    let side = match light {
        Light::Triangle(tl) if tl.two_sided && o.u_side < 0.5 => -s.n,
        _ => s.n,
    };
    let l_tol = radiance_tol(light, -s.dir, s.l);
    // The image's direction (and the disk point in its frame) go through atan2, acos, sin.
    let tol = if matches!(light, Light::Image(_)) {
        IMAGE_REL
    } else {
        REL
    };
    t.vec(o.le_p, s.p, "sample_le p", tol, i);
    t.vec(o.le_n, side, "sample_le n (emitting side)", tol, i);
    t.vec(o.le_dir, s.dir, "sample_le dir", tol, i);
    t.vec(o.le_l, s.l, "sample_le l", l_tol, i);
    t.val(o.le_pdf_pos, s.pdf_pos, "sample_le pdf_pos", REL, i);
    t.val(o.le_pdf_dir, s.pdf_dir, "sample_le pdf_dir", tol, i);
    let cos_n = if light.is_delta_position() {
        1.0
    } else {
        side.dot(s.dir).abs()
    };
    t.val(o.le_cos_n, cos_n, "sample_le cos_n", REL, i);
    let delta = (o.le_flags >> 1) & 1 != 0;
    t.check(
        delta == s.delta_pos,
        format!(
            "case {i}: sample_le delta_pos: GPU {delta}, CPU {}",
            s.delta_pos
        ),
    );
}

/// `le` and `pdf_le` for the case's normal and direction.
fn compare_le(t: &mut Track, light: &Light, c: &LightProbeCase, o: &LightProbeOut, i: usize) {
    let n = Vec3::from_array(c.n);
    let w = Vec3::from_array(c.w);
    let l = light.le(Vec3::from_array(c.p), n, w);
    let l_tol = radiance_tol(light, -w, l);
    t.vec(o.emitted, l, "le", l_tol, i);
    let (pdf_pos, pdf_dir) = light.pdf_le(c.pick, n, w);
    let tol = if matches!(light, Light::Image(_)) {
        IMAGE_REL
    } else {
        REL
    };
    t.val(o.pdf_pos, pdf_pos, "pdf_le pdf_pos", REL, i);
    t.val(o.pdf_dir, pdf_dir, "pdf_le pdf_dir", tol, i);
}

/// `LightSet::pick` and `LightSet::area_light`: the same entry, exactly.
fn compare_pick(t: &mut Track, set: &LightSet, c: &LightProbeCase, o: &LightProbeOut, i: usize) {
    let (picked, prob) = set.pick(c.u_pick).expect("the scene has lights");
    let k = set
        .lights
        .iter()
        .position(|l| std::ptr::eq(l, picked))
        .unwrap();
    t.check(
        o.pick_cdf == set.cdf[k] && o.pick_prob == prob,
        format!(
            "case {i}: pick({}): GPU (cdf {}, prob {}), CPU light {k} (cdf {}, prob {prob})",
            c.u_pick, o.pick_cdf, o.pick_prob, set.cdf[k]
        ),
    );
    let area = match set.lights.get(c.light as usize) {
        Some(Light::Triangle(tl)) => set.area_light(tl.tri).map_or(0.0, |(_, p)| p),
        _ => 0.0,
    };
    t.check(
        o.area_prob == area,
        format!(
            "case {i}: area light probability: GPU {}, CPU {area}",
            o.area_prob
        ),
    );
}

/// The probe structs match their WGSL twins (no adapter needed).
#[test]
fn light_probe_layout_matches_wgsl() {
    let src = light_probe_source();
    check_layout::<LightProbeParams>(&src).unwrap();
    check_layout::<LightProbeCase>(&src).unwrap();
    check_layout::<LightProbeOut>(&src).unwrap();
}

/// Every light type through WGSL and Rust on the same cases (module docs).
#[test]
fn light_twin_parity() {
    let Some(ctx) = gpu_context("light_twin_parity") else {
        return;
    };
    let scene = all_lights_scene();
    let set = LightSet::build(&scene);
    let kinds: Vec<&str> = set
        .lights
        .iter()
        .map(|l| match l {
            Light::Triangle(t) if t.two_sided => "triangle (two-sided)",
            Light::Triangle(_) => "triangle (one-sided)",
            Light::Point(_) => "point",
            Light::Spot(_) => "spot",
            Light::Directional(_) => "directional",
            Light::Environment(_) => "environment",
            Light::Image(_) => "image",
        })
        .collect();
    for k in [
        "triangle (one-sided)",
        "triangle (two-sided)",
        "point",
        "spot",
        "directional",
    ] {
        assert!(kinds.contains(&k), "the scene has no {k} light: {kinds:?}");
    }
    let mut cases = Vec::new();
    for light in 0..=set.lights.len() {
        cases_of(&set, light, &mut cases);
    }
    let outs = run_light_probe(&ctx, &scene, &cases).unwrap();
    assert_eq!(outs.len(), cases.len());
    let mut t = Track::default();
    let (mut li_valid, mut li_none, mut sides) = (0, 0, [0, 0]);
    // Emitted rays of the directional light and the uniform environment (always valid).
    let mut le_infinite = 0;
    let mut spot_li = [0usize; 3];
    for (i, (c, o)) in cases.iter().zip(&outs).enumerate() {
        let light = set.lights.get(c.light as usize).unwrap_or(&set.environment);
        compare_li(&mut t, light, c, o, i);
        compare_sample_le(&mut t, light, c, o, i);
        compare_le(&mut t, light, c, o, i);
        compare_pick(&mut t, &set, c, o, i);
        if o.li_flags & 1 != 0 {
            li_valid += 1;
        } else {
            li_none += 1;
        }
        if light.is_infinite() && o.le_flags & 1 != 0 {
            le_infinite += 1;
        }
        if let Light::Triangle(tl) = light
            && tl.two_sided
        {
            sides[usize::from(o.u_side < 0.5)] += 1;
        }
        if let Light::Spot(s) = light {
            let to = Vec3::from_array(c.p) - s.position;
            let cos = to.normalize().dot(s.direction);
            let zone = if cos >= s.cos_inner {
                0
            } else if cos > s.cos_outer {
                1
            } else {
                2
            };
            spot_li[zone] += 1;
        }
    }
    eprintln!(
        "light twin: {} cases, {} comparisons, worst relative error {:.2e} (spot radiance {:.2e}); sample_li valid \
         {li_valid}, none {li_none}; two-sided sides (front, back) {sides:?}; spot points \
         (inside, ramp, outside) {spot_li:?}",
        cases.len(),
        t.compared,
        t.worst,
        t.worst_spot
    );
    assert!(
        t.failures.is_empty(),
        "{} light twin mismatches:\n{}",
        t.n_fail,
        t.failures.join("\n")
    );
    // The cases reach what they are meant to reach.
    assert!(
        li_none > 0 && li_valid > 0,
        "sample_li: {li_valid} valid, {li_none} none"
    );
    assert!(
        sides[0] > 0 && sides[1] > 0,
        "two-sided light: sides {sides:?}"
    );
    assert!(spot_li.iter().all(|&n| n > 0), "spot zones {spot_li:?}");
    assert_eq!(
        le_infinite,
        2 * points().len() * PER_POINT,
        "emitted rays of the directional light and the environment"
    );
}

/// A floor, an area light and an environment image (seeded texels, one bright texel,
/// rotated 37°; `importance` false: uniform directions).
fn image_scene(importance: bool) -> Scene {
    use refract::scene::env_map::{EnvImage, EnvMap};
    let mut m = Mesh::default();
    quad(
        &mut m,
        Vec3::new(-5.0, 0.0, 5.0),
        Vec3::X * 10.0,
        Vec3::Z * -10.0,
        0,
    );
    quad(&mut m, Vec3::new(-1.5, 3.0, -0.5), Vec3::X, Vec3::Z, 1);
    let cam = Camera::look_at(Vec3::new(0.0, 2.0, 6.0), Vec3::ZERO, Vec3::Y, 0.8);
    let mats = vec![
        Material::diffuse("floor", Vec3::splat(0.5)),
        Material::emitter("light", Vec3::new(4.0, 3.0, 2.0)),
    ];
    let mut s = scene("image", m, mats, cam, 0.0);
    let (w, h) = (24u32, 12u32);
    let mut texels: Vec<Vec3> = seeded_texels(w * h).into_iter().map(|t| t * 2.0).collect();
    texels[(3 * w + 7) as usize] = Vec3::new(300.0, 280.0, 250.0);
    texels[5] = Vec3::ZERO;
    let (map, _) = EnvMap::from_texels(w, h, texels, "twin");
    let mut img = EnvImage::new(std::sync::Arc::new(map), 1.5, 37.0);
    img.importance = importance;
    s.env_map = Some(img);
    s
}

/// The environment image through WGSL and Rust (module docs), with and without importance
/// sampling.
#[test]
fn image_environment_twin_parity() {
    let Some(ctx) = gpu_context("image_environment_twin_parity") else {
        return;
    };
    for importance in [true, false] {
        let scene = image_scene(importance);
        let set = LightSet::build(&scene);
        let env = set.lights.len() - 1;
        assert!(
            matches!(set.lights[env], Light::Image(_)),
            "the image is the last light"
        );
        let mut cases = Vec::new();
        for light in 0..set.lights.len() {
            cases_of(&set, light, &mut cases);
        }
        let outs = run_light_probe(&ctx, &scene, &cases).unwrap();
        let mut t = Track::default();
        let (mut image_valid, mut image_le) = (0, 0);
        for (i, (c, o)) in cases.iter().zip(&outs).enumerate() {
            let light = &set.lights[c.light as usize];
            compare_li(&mut t, light, c, o, i);
            compare_sample_le(&mut t, light, c, o, i);
            compare_le(&mut t, light, c, o, i);
            compare_pick(&mut t, &set, c, o, i);
            if c.light as usize == env && o.li_flags & 1 != 0 {
                image_valid += 1;
            }
            if c.light as usize == env && o.le_flags & 1 != 0 {
                image_le += 1;
            }
        }
        eprintln!(
            "image twin (importance {importance}): {} cases, {} comparisons, worst relative \
             error {:.2e} (image densities and directions {:.2e}), {image_valid} image samples, \
             {image_le} emitted rays",
            cases.len(),
            t.compared,
            t.worst,
            t.worst_spot
        );
        assert!(
            t.failures.is_empty(),
            "{} image twin mismatches:\n{}",
            t.n_fail,
            t.failures.join("\n")
        );
        assert!(image_valid >= 25, "only {image_valid} valid image samples");
        assert!(
            image_le >= 25,
            "only {image_le} emitted rays from the image"
        );
    }
}
