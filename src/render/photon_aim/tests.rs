use super::*;
use crate::math::rng::{pcg_hash, u32_to_unit_f32};

struct Rng(u32);

impl Rng {
    fn next(&mut self) -> f32 {
        self.0 = pcg_hash(self.0);
        u32_to_unit_f32(self.0)
    }
    fn next_2d(&mut self) -> Vec2 {
        Vec2::new(self.next(), self.next())
    }
}

/// Does the ray from `p` along `w` meet sphere `s`?
fn hits(s: &Sphere, p: Vec3, w: Vec3) -> bool {
    let oc = p - s.center;
    let b = oc.dot(w);
    let c = oc.length_squared() - s.radius * s.radius;
    c <= 0.0 || (b < 0.0 && b * b - c >= 0.0)
}

/// Mean and standard error of `n` draws of `f`.
fn estimate(n: usize, mut f: impl FnMut() -> f64) -> (f64, f64) {
    let (mut s1, mut s2) = (0.0, 0.0);
    for _ in 0..n {
        let x = f();
        s1 += x;
        s2 += x * x;
    }
    let m = s1 / n as f64;
    (m, ((s2 / n as f64 - m * m).max(0.0) / n as f64).sqrt())
}

/// ∫ g(ω) dω over the directions that meet a target, by aimed sampling (g/p) and by uniform
/// sampling of the sphere (4π g), for overlapping, disjoint and enclosing targets and a
/// non-constant g: the aimed estimator is unbiased where the integrand lives.
#[test]
fn aimed_directions_integrate_like_uniform_ones() {
    let g = |w: Vec3| 1.0 + 0.8 * w.x - 0.3 * w.y * w.z;
    let cases = [
        // Two overlapping cones, one small and far.
        (
            Vec3::ZERO,
            vec![
                Sphere {
                    center: Vec3::new(2.0, 0.0, 0.0),
                    radius: 0.7,
                },
                Sphere {
                    center: Vec3::new(2.5, 0.4, 0.0),
                    radius: 0.6,
                },
                Sphere {
                    center: Vec3::new(0.0, -9.0, 3.0),
                    radius: 0.2,
                },
            ],
        ),
        // The point inside one sphere (all directions) and near another.
        (
            Vec3::new(0.1, 0.0, 0.0),
            vec![
                Sphere {
                    center: Vec3::ZERO,
                    radius: 0.5,
                },
                Sphere {
                    center: Vec3::new(0.0, 1.0, 0.0),
                    radius: 0.3,
                },
            ],
        ),
    ];
    for (p, spheres) in cases {
        let t = PhotonTargets {
            spheres: spheres.clone(),
        };
        let mut r = Rng(7);
        let (aimed, se_a) = estimate(200_000, || {
            let (w, pdf) = t.sample_dir(p, r.next(), r.next_2d()).expect("targets");
            assert!(pdf > 0.0 && pdf.is_finite());
            assert!((w.length() - 1.0).abs() < 1e-4);
            assert!(
                spheres.iter().any(|s| hits(s, p, w)),
                "{w} misses every target"
            );
            g(w) as f64 / pdf as f64
        });
        let (uniform, se_u) = estimate(2_000_000, || {
            let w = crate::math::sampling::uniform_sphere(r.next_2d());
            let inside = spheres.iter().any(|s| hits(s, p, w));
            if inside {
                4.0 * std::f64::consts::PI * g(w) as f64
            } else {
                0.0
            }
        });
        let z = (aimed - uniform) / (se_a * se_a + se_u * se_u).sqrt();
        assert!(
            z.abs() < 4.0,
            "aimed {aimed} ± {se_a}, uniform {uniform} ± {se_u}"
        );
    }
}

/// Disjoint small cones: the mean of 1/p is the sum of their solid angles 2π(1 − cos θ).
#[test]
fn disjoint_cones_sum_their_solid_angles() {
    let spheres = vec![
        Sphere {
            center: Vec3::new(0.0, 0.0, 100.0),
            radius: 0.01,
        },
        Sphere {
            center: Vec3::new(0.0, 50.0, 0.0),
            radius: 0.5,
        },
    ];
    let exact: f64 = spheres
        .iter()
        .map(|s| {
            let d = s.center.length() as f64;
            let sin2 = (s.radius as f64 / d).powi(2);
            2.0 * std::f64::consts::PI * (1.0 - (1.0 - sin2).sqrt())
        })
        .sum();
    let t = PhotonTargets { spheres };
    let mut r = Rng(3);
    for _ in 0..1000 {
        let (_, pdf) = t
            .sample_dir(Vec3::ZERO, r.next(), r.next_2d())
            .expect("targets");
        assert!(
            ((1.0 / pdf as f64) - exact).abs() < 1e-3 * exact,
            "1/p {} vs {exact}",
            1.0 / pdf
        );
    }
}

/// The targets of the built-ins: every vertex of caustic's glass is inside a sphere; the
/// ball (one piece: its triangles share vertices) is in a sphere of its own radius, the
/// slab's six faces (which share none) in one each; the same scene all diffuse has none.
#[test]
fn pieces_of_the_built_ins() {
    let scene = crate::scene::builtin::load("caustic").expect("built-in");
    let t = PhotonTargets::new(&scene);
    assert_eq!(t.spheres.len(), 7, "{:?}", t.spheres);
    let ball = Vec3::new(0.0, 0.3, 0.0);
    assert!(
        t.spheres
            .iter()
            .any(|s| s.center.distance(ball) < 1e-3 && (s.radius - 0.3).abs() < 1e-3),
        "{:?}",
        t.spheres
    );
    let mesh = &scene.mesh;
    let specular = specular_materials(&scene);
    for tri in 0..mesh.triangle_count() {
        if specular[mesh.tri_material[tri] as usize] {
            for p in mesh.tri(tri) {
                assert!(
                    t.spheres
                        .iter()
                        .any(|s| p.distance(s.center) <= s.radius * 1.0001),
                    "{p} outside every target"
                );
            }
        }
    }
    let mut plain = scene.clone();
    for m in &mut plain.materials {
        m.kind = MaterialKind::Diffuse;
    }
    assert!(PhotonTargets::new(&plain).spheres.is_empty());
}

/// Of the frosted panes only the smooth one can start a caustic path: the rough sheets
/// scatter photons off a glossy lobe, which stores nothing.
#[test]
fn rough_sheets_are_no_targets() {
    let scene = crate::scene::builtin::load("frosted-panes").expect("built-in");
    let specular = specular_materials(&scene);
    let names: Vec<&str> = scene
        .materials
        .iter()
        .zip(&specular)
        .filter(|(_, s)| **s)
        .map(|(m, _)| m.name.as_str())
        .collect();
    assert_eq!(names, ["pane-r0.00"]);
    assert_eq!(PhotonTargets::new(&scene).spheres.len(), 1);
}

/// More pieces than [`MAX_TARGETS`] are clustered into that many spheres that still cover
/// every piece.
#[test]
fn clusters_cover_every_piece() {
    let mut r = Rng(11);
    let pieces: Vec<Sphere> = (0..500)
        .map(|_| Sphere {
            center: Vec3::new(r.next(), r.next(), r.next()) * 20.0,
            radius: 0.1 + r.next(),
        })
        .collect();
    let spheres = cluster(pieces.clone(), MAX_TARGETS);
    assert_eq!(spheres.len(), MAX_TARGETS);
    for p in &pieces {
        assert!(
            spheres
                .iter()
                .any(|s| p.center.distance(s.center) + p.radius <= s.radius * 1.0001),
            "{p:?} not covered"
        );
    }
}
