//! The light interface's own consistency (each light type, one place): `pdf_li` and
//! `pdf_le` return the densities `sample_li` and `sample_le` report, the emission estimator
//! E[L·|cos|/(p_pos·p_dir)] recovers the analytic power, and emitted rays of lights at
//! infinity cross the scene's bounding sphere. The WGSL twin (`light.wgsl`) is compared with
//! these functions case by case in tests/light_twin.rs, and through the GPU renders in
//! tests/gpu.rs and tests/gpu_lt.rs.

use super::*;
use crate::math::rng::Sampler;
use std::f32::consts::PI;

fn lights() -> Vec<Light> {
    let v = [
        Vec3::new(-0.5, 2.0, -0.4),
        Vec3::new(0.6, 2.1, -0.3),
        Vec3::new(0.1, 1.9, 0.7),
    ];
    vec![
        Light::Triangle(TriangleLight::new(0, 0, v, Vec3::new(3.0, 2.0, 1.0), false)),
        Light::Triangle(TriangleLight::new(1, 0, v, Vec3::new(1.0, 2.0, 3.0), true)),
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
                    l.pdf_li(pick, 1.0, 1.0),
                    0.0,
                    "{l:?}: pdf_li of a delta light"
                );
                continue;
            }
            let dist = (s.p_light - p).length();
            let cos = s.n_light.dot(s.wi).abs();
            let q = l.pdf_li(pick, dist, cos);
            assert!(
                (q - s.pdf).abs() <= 1e-4 * s.pdf,
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
            let le = l.le(s.n, s.dir);
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
        let expect = match l {
            Light::Triangle(t) => t.power() as f64,
            Light::Point(p) => p.power() as f64,
            Light::Directional(d) => d.power() as f64,
            // Spot: ∫ I·falloff dω has no closed form here; environment: its disk power
            // E[L/(p_pos p_dir)] = 4π·πr²·L = `power`.
            Light::Spot(_) => continue,
            Light::Environment(e) => e.power() as f64,
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
        let (c, r) = match l {
            Light::Directional(d) => (d.center, d.radius),
            Light::Environment(e) => (e.center, e.radius),
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
        assert!(
            (l.power()
                - match l {
                    Light::Directional(d) => PI * r * r * luminance(d.irradiance),
                    Light::Environment(e) => 4.0 * PI * PI * r * r * luminance(e.radiance),
                    _ => 0.0,
                })
            .abs()
                < 1e-3
        );
    }
}
