//! The light interface's own consistency (each light type, one place): `pdf_li` and
//! `pdf_le` return the densities `sample_li` and `sample_le` report, the emission estimator
//! E[L·|cos|/(p_pos·p_dir)] recovers the analytic power, and emitted rays of lights at
//! infinity cross the scene's bounding sphere. The WGSL twin (`light.wgsl`) is compared with
//! these functions case by case in tests/light_twin.rs, and through the GPU renders in
//! tests/gpu.rs and tests/gpu_lt.rs.

use super::*;
use crate::math::rng::Sampler;
use crate::scene::env_map::{EnvImage, EnvMap};
use std::f32::consts::PI;
use std::sync::Arc;

/// A 24 × 12 environment image of varied (seeded) texels with one bright "sun" texel,
/// rotated by `rotation` degrees.
/// (Without importance sampling the bright texel is left out: uniform directions would hit
/// it too rarely for the power estimate's 1% tolerance.)
pub(crate) fn image_light(rotation: f32, importance: bool) -> ImageEnvironment {
    let (w, h) = (24u32, 12u32);
    let mut rng = Sampler::new(77, 0, 1);
    let mut t: Vec<Vec3> = (0..w * h)
        .map(|_| Vec3::new(rng.next_1d(), rng.next_1d(), rng.next_1d()) * 2.0)
        .collect();
    if importance {
        t[(3 * w + 7) as usize] = Vec3::new(300.0, 280.0, 250.0);
    }
    t[5] = Vec3::ZERO;
    let (map, _) = EnvMap::from_texels(w, h, t, "test");
    let mut img = EnvImage::new(Arc::new(map), 1.5, rotation);
    img.importance = importance;
    ImageEnvironment::new(img, Vec3::new(0.0, 1.0, 0.0), 1.5)
}

/// A 4 × 3 bilinear texture whose red and green ramp across it (blue constant): smooth, so
/// the 8 × 8-point mean behind `power` is within the power test's 1%.
pub(crate) fn ramp_texture() -> Arc<crate::scene::Texture> {
    let (w, h) = (4u32, 3u32);
    let texels = (0..w * h)
        .map(|i| {
            let (x, y) = ((i % w) as f32, (i / w) as f32);
            glam::Vec4::new(0.2 + 0.25 * x, 1.0 - 0.3 * y, 0.5, 1.0)
        })
        .collect();
    Arc::new(crate::scene::Texture {
        width: w,
        height: h,
        texels,
        wrap_s: crate::scene::Wrap::ClampToEdge,
        wrap_t: crate::scene::Wrap::ClampToEdge,
        linear: true,
    })
}

/// A triangle light with the ramp texture over uv (0, 0), (1, 0), (0, 1).
pub(crate) fn textured_triangle(v: [Vec3; 3], two_sided: bool) -> TriangleLight {
    TriangleLight::new(2, 0, v, Vec3::new(2.0, 3.0, 4.0), two_sided).with_texture(EmissiveTexture {
        texture: ramp_texture(),
        transform: glam::Affine2::IDENTITY,
        uv: [glam::Vec2::ZERO, glam::Vec2::X, glam::Vec2::Y],
    })
}

fn lights() -> Vec<Light> {
    let v = [
        Vec3::new(-0.5, 2.0, -0.4),
        Vec3::new(0.6, 2.1, -0.3),
        Vec3::new(0.1, 1.9, 0.7),
    ];
    vec![
        Light::Triangle(TriangleLight::new(0, 0, v, Vec3::new(3.0, 2.0, 1.0), false)),
        Light::Triangle(TriangleLight::new(1, 0, v, Vec3::new(1.0, 2.0, 3.0), true)),
        Light::Triangle(textured_triangle(v, false)),
        Light::Triangle(textured_triangle(v, true)),
        Light::Point(PointLight {
            position: Vec3::new(0.2, 1.5, 0.1),
            intensity: Vec3::new(5.0, 4.0, 3.0),
        }),
        Light::Spot(SpotLight {
            position: Vec3::new(0.0, 2.0, 0.0),
            direction: Vec3::new(0.1, -1.0, 0.2).normalize(),
            intensity: Vec3::splat(7.0),
            cos_inner: 0.95,
            cos_outer: 0.8,
        }),
        Light::Directional(DirectionalLight {
            direction: Vec3::new(0.3, -1.0, 0.1).normalize(),
            irradiance: Vec3::splat(2.0),
            center: Vec3::new(0.0, 1.0, 0.0),
            radius: 1.5,
        }),
        Light::Environment(UniformEnvironment {
            radiance: Vec3::new(0.5, 0.6, 0.7),
            center: Vec3::new(0.0, 1.0, 0.0),
            radius: 1.5,
        }),
        Light::Image(image_light(30.0, true)),
        Light::Image(image_light(-75.0, false)),
    ]
}

#[test]
fn pdf_li_matches_sample_li() {
    let p = Vec3::new(0.05, 0.0, 0.02);
    let pick = 0.3;
    let mut rng = Sampler::new(1, 0, 3);
    for l in lights() {
        let mut n = 0;
        for _ in 0..256 {
            let Some(s) = l.sample_li(p, rng.next_2d(), pick) else {
                continue;
            };
            n += 1;
            assert!(s.pdf > 0.0 && s.pdf.is_finite(), "{l:?}: pdf {}", s.pdf);
            assert!((s.wi.length() - 1.0).abs() < 1e-5, "{l:?}: wi not unit");
            if s.is_delta {
                assert_eq!(
                    s.pdf, pick,
                    "{l:?}: a delta light's pdf is its selection probability"
                );
                assert_eq!(
                    l.pdf_li(pick, s.wi, 1.0, 1.0),
                    0.0,
                    "{l:?}: pdf_li of a delta light"
                );
                continue;
            }
            let dist = (s.p_light - p).length();
            let cos = s.n_light.dot(s.wi).abs();
            let q = l.pdf_li(pick, s.wi, dist, cos);
            // An image's density has a 1/sinθ factor: pdf_li recomputes θ from the sampled
            // direction through acos, whose f32 error (≈ 6e-8/sinθ) grows near the poles, and
            // moves 1/sinθ by ≈ 6e-8/sin²θ relative (×4 margin).
            let sin2 = (1.0 - s.wi.y * s.wi.y).max(1e-12);
            let tol = if matches!(l, Light::Image(_)) {
                1e-4 + 2.4e-7 / sin2
            } else {
                1e-4
            };
            assert!(
                (q - s.pdf).abs() <= tol * s.pdf,
                "{l:?}: pdf_li {q} vs sample_li {}",
                s.pdf
            );
        }
        assert!(n > 100, "{l:?}: only {n} samples");
    }
}

#[test]
fn pdf_le_matches_sample_le() {
    let pick = 0.25;
    let mut rng = Sampler::new(2, 0, 5);
    for l in lights() {
        for _ in 0..256 {
            let Some(s) = l.sample_le(rng.next_2d(), rng.next_2d(), rng.next_1d(), pick) else {
                continue;
            };
            if s.pdf_dir == 0.0 {
                continue;
            }
            let (pp, pd) = l.pdf_le(pick, s.n, s.dir);
            assert!(
                (pp - s.pdf_pos).abs() <= 1e-5 * s.pdf_pos,
                "{l:?}: pdf_pos {pp} vs {}",
                s.pdf_pos
            );
            if let Light::Directional(_) = l {
                assert_eq!(pd, 0.0, "a delta direction reports 0");
            } else {
                assert!(
                    (pd - s.pdf_dir).abs() <= 1e-4 * s.pdf_dir,
                    "{l:?}: pdf_dir {pd} vs {}",
                    s.pdf_dir
                );
            }
            // (The spot's falloff ramp is steep: allow for cosθ rounded differently.)
            let le = l.le(s.p, s.n, s.dir);
            assert!(
                le.abs_diff_eq(s.l, 1e-4 * s.l.max_element().max(1.0)),
                "{l:?}: le {le} vs sampled {}",
                s.l
            );
        }
    }
}

/// E[L·|cos|/(p_pos·p_dir)] over `sample_le` = the emitted power (luminance).
#[test]
fn emission_estimator_recovers_power() {
    let mut rng = Sampler::new(3, 0, 7);
    for l in lights() {
        let expect = match &l {
            Light::Triangle(t) => t.power() as f64,
            Light::Point(p) => p.power() as f64,
            Light::Directional(d) => d.power() as f64,
            // Spot: ∫ I·falloff dω has no closed form here; environment: its disk power
            // E[L/(p_pos p_dir)] = 4π·πr²·L = `power`.
            Light::Spot(_) => continue,
            Light::Environment(e) => e.power() as f64,
            Light::Image(e) => e.power() as f64,
        };
        let n = 200_000;
        let mut sum = 0.0f64;
        for _ in 0..n {
            let Some(s) = l.sample_le(rng.next_2d(), rng.next_2d(), rng.next_1d(), 1.0) else {
                continue;
            };
            if s.pdf_dir == 0.0 {
                continue;
            }
            let cos = if s.delta_pos || s.infinite {
                1.0
            } else {
                s.n.dot(s.dir).abs()
            };
            sum += (luminance(s.l) * cos / (s.pdf_pos * s.pdf_dir)) as f64;
        }
        let got = sum / n as f64;
        assert!(
            (got - expect).abs() <= 0.01 * expect,
            "{l:?}: estimated power {got}, expected {expect}"
        );
    }
}

#[test]
fn infinite_lights_emit_through_the_bounding_sphere() {
    let mut rng = Sampler::new(4, 0, 9);
    for l in lights().into_iter().filter(|l| l.is_infinite()) {
        let l = l.clone();
        let (c, r) = match &l {
            Light::Directional(d) => (d.center, d.radius),
            Light::Environment(e) => (e.center, e.radius),
            Light::Image(e) => (e.center, e.radius),
            _ => unreachable!(),
        };
        for _ in 0..256 {
            let s = l
                .sample_le(rng.next_2d(), rng.next_2d(), 0.5, 1.0)
                .expect("sample");
            let to_c = c - s.p;
            assert!(
                to_c.dot(s.dir) > 0.0,
                "{l:?}: the ray starts in front of the scene"
            );
            let miss = (to_c - to_c.dot(s.dir) * s.dir).length();
            assert!(
                miss <= r * (1.0 + 1e-4),
                "{l:?}: ray passes {miss} from the centre (r = {r})"
            );
        }
        let expect = match &l {
            Light::Directional(d) => PI * r * r * luminance(d.irradiance),
            Light::Environment(e) => 4.0 * PI * PI * r * r * luminance(e.radiance),
            // πr² ∫L dω with ∫ over the texels' solid angles of their mean radiance.
            Light::Image(e) => {
                let m = &e.image.map;
                let (w, h) = (m.width as usize, m.height as usize);
                let mut sum = 0.0f64;
                // The image is interpolated bilinearly: each texel's mean over its footprint
                // is [1, 6, 1]/8 of its row and column neighbours (periodic in u, clamped rows).
                let lum = |x: usize, y: usize| luminance(m.texels[y * w + x]) as f64;
                let row_mean = |x: usize, y: usize| {
                    (lum((x + w - 1) % w, y) + 6.0 * lum(x, y) + lum((x + 1) % w, y)) / 8.0
                };
                for i in 0..w * h {
                    let (x, row) = (i % w, i / w);
                    let mean = (row_mean(x, row.saturating_sub(1))
                        + 6.0 * row_mean(x, row)
                        + row_mean(x, (row + 1).min(h - 1)))
                        / 8.0;
                    let (t0, t1) = (row as f64 / h as f64, (row + 1) as f64 / h as f64);
                    let omega = 2.0 * std::f64::consts::PI / w as f64
                        * ((t0 * std::f64::consts::PI).cos() - (t1 * std::f64::consts::PI).cos());
                    sum += mean * omega;
                }
                (PI * r * r) as f64 as f32 * e.image.strength * sum as f32
            }
            _ => 0.0,
        };
        assert!(
            (l.power() - expect).abs() <= 1e-3 * expect.max(1.0),
            "{l:?}: power {} vs {expect}",
            l.power()
        );
    }
}

/// χ² goodness of fit of the image environment's `sample_li` against `pdf_li`, binned by
/// texel of the (rotated) map: a texel's probability is ∫ pdf_li dω = pdf_li(centre) ·
/// 2π² sinθ_c / (W·H) exactly (the density is p(u,t)/(2π² sinθ), piecewise constant in
/// (u, t)). 500k samples; the statistic must stay below dof + 5·√(2·dof) (about 5σ).
#[test]
fn image_environment_samples_follow_pdf_li() {
    use crate::scene::env_map::{dir_to_uv, rotate_y, uv_to_dir};
    let l = image_light(37.0, true);
    let light = Light::Image(l.clone());
    let (w, h) = (l.image.map.width as usize, l.image.map.height as usize);
    let (c, s) = (l.cos_rot, l.sin_rot);
    let n = 500_000usize;
    let mut counts = vec![0usize; w * h];
    let mut rng = Sampler::new(11, 0, 2);
    for _ in 0..n {
        let ls = light
            .sample_li(Vec3::ZERO, rng.next_2d(), 1.0)
            .expect("sample");
        let uv = dir_to_uv(rotate_y(ls.wi, c, -s));
        let x = ((uv.x * w as f32) as usize).min(w - 1);
        let y = ((uv.y * h as f32) as usize).min(h - 1);
        counts[y * w + x] += 1;
    }
    let (mut chi2, mut dof, mut total_p) = (0.0f64, 0usize, 0.0f64);
    for y in 0..h {
        for x in 0..w {
            let uv = glam::Vec2::new((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
            let wi = rotate_y(uv_to_dir(uv), c, s);
            let sin_t = (uv.y * PI).sin() as f64;
            let p = light.pdf_li(1.0, wi, 1.0, 1.0) as f64 * 2.0 * (PI as f64).powi(2) * sin_t
                / (w * h) as f64;
            total_p += p;
            let k = counts[y * w + x] as f64;
            if p == 0.0 {
                assert_eq!(k, 0.0, "texel ({x}, {y}) has pdf 0 but was sampled");
                continue;
            }
            let e = p * n as f64;
            chi2 += (k - e).powi(2) / e;
            dof += 1;
        }
    }
    assert!((total_p - 1.0).abs() < 1e-4, "∫ pdf_li dω = {total_p}");
    let dof = (dof - 1) as f64;
    let limit = dof + 5.0 * (2.0 * dof).sqrt();
    assert!(
        chi2 < limit,
        "χ² = {chi2:.1} over {dof} dof (limit {limit:.1})"
    );
    // The black texel's footprint holds its bright neighbours' interpolation: it has density
    // (so NEE reaches the light there) and was sampled, in proportion (the χ² above).
    assert!(
        counts[5] > 0,
        "the black texel between bright ones is sampled too"
    );
}

/// An emissive texture is read at the point: `sample_li`, `sample_le` and `le` agree on the
/// radiance of the sampled point, and it equals emission × the texel the point's uv falls on
/// (computed here from the barycentrics by hand).
#[test]
fn textured_triangle_reads_the_texture_at_the_point() {
    use crate::scene::material::sample_one;
    let v = [
        Vec3::new(-0.5, 2.0, -0.4),
        Vec3::new(0.6, 2.1, -0.3),
        Vec3::new(0.1, 1.9, 0.7),
    ];
    let t = textured_triangle(v, false);
    let light = Light::Triangle(t.clone());
    let tex = ramp_texture();
    let mut rng = Sampler::new(5, 0, 1);
    let mut spread = (f32::MAX, 0.0f32);
    for _ in 0..256 {
        let s = light
            .sample_li(Vec3::ZERO, rng.next_2d(), 1.0)
            .expect("the front face is visible from the origin");
        // uv = (b1, b2): solve p = a + b1 (b − a) + b2 (c − a) in the triangle's plane.
        let (e1, e2, d) = (v[1] - v[0], v[2] - v[0], s.p_light - v[0]);
        let m = glam::Mat3::from_cols(e1, e2, t.n);
        let bc = m.inverse() * d;
        let want = t.emission * sample_one(&tex, glam::Affine2::IDENTITY, bc.truncate()).truncate();
        assert!(s.l.abs_diff_eq(want, 1e-4), "sample_li {} vs {want}", s.l);
        let le = light.le(s.p_light, s.n_light, -s.wi);
        assert!(le.abs_diff_eq(s.l, 1e-4), "le {le} vs sample_li {}", s.l);
        spread = (spread.0.min(s.l.x), spread.1.max(s.l.x));
        let e = light
            .sample_le(rng.next_2d(), rng.next_2d(), 0.7, 1.0)
            .expect("sample_le");
        let le = light.le(e.p, e.n, e.dir);
        assert!(le.abs_diff_eq(e.l, 1e-4), "le {le} vs sample_le {}", e.l);
    }
    // The radiance varies over the triangle (red ramps 0.2 … 0.95 across u).
    assert!(spread.1 > 1.5 * spread.0, "red spans {spread:?}");
    // The power uses the mean over the triangle, not the factor.
    assert!(t.mean_emission.x < t.emission.x && t.mean_emission.x > 0.2 * t.emission.x);
}
