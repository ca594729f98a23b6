//! Bidirectional estimators: they converge to the path tracer's image, pure light tracing
//! matches path tracing where it can see everything, importance transport through glass is
//! consistent with radiance transport, and Heckbert classes still partition the image.

mod common_scenes;
use common_scenes::*;
use glam::Vec3;
use refract::cpu::Renderer;
use refract::paths::PathFilter;
use refract::render::{Estimator, RenderOptions};
use refract::scene::{Camera, Material, Mesh, Scene};

fn render(r: &Renderer, est: Estimator, spp: u32, seed: u32, w: u32, h: u32) -> Vec<Vec3> {
    let mut o = RenderOptions::from_scene(&r.scene);
    o.width = w;
    o.height = h;
    o.seed = seed;
    o.estimator = est;
    r.render(&o, spp, None, |_| {}).0.image()
}

fn mean_sem(px: &[Vec3]) -> (f64, f64) {
    let n = px.len() as f64;
    let lum = |p: &Vec3| (p.x + p.y + p.z) as f64 / 3.0;
    let m = px.iter().map(lum).sum::<f64>() / n;
    let v = px.iter().map(|p| (lum(p) - m).powi(2)).sum::<f64>() / (n - 1.0).max(1.0);
    (m, (v / n).sqrt())
}

/// Fraction of b×b blocks whose mean luminance agrees within `z` combined standard errors.
fn block_pass(a: &[Vec3], b: &[Vec3], w: usize, h: usize, bs: usize, z: f64) -> f64 {
    let (mut pass, mut total) = (0, 0);
    for by in 0..h / bs {
        for bx in 0..w / bs {
            let pick = |img: &[Vec3]| -> Vec<Vec3> {
                (by * bs..(by + 1) * bs)
                    .flat_map(|y| (bx * bs..(bx + 1) * bs).map(move |x| (y, x)))
                    .map(|(y, x)| img[y * w + x])
                    .collect()
            };
            let (ma, sa) = mean_sem(&pick(a));
            let (mb, sb) = mean_sem(&pick(b));
            total += 1;
            let se = (sa * sa + sb * sb).sqrt() + 1e-3 * (ma + mb) + 1e-6;
            if (ma - mb).abs() <= z * se {
                pass += 1;
            }
        }
    }
    pass as f64 / total as f64
}

/// BDPT converges to the path tracer on the built-in scenes: ≥ 90% of 8×8 blocks agree
/// within 4σ (+0.1% relative for the reference's own bias-free noise floor) and the image
/// means within 4σ. Heavy-tailed caustic noise in the path-traced reference is why this is a
/// pass rate and not every block.
#[test]
fn bdpt_matches_path_tracing_on_builtins() {
    for name in [
        "cornell-glass",
        "caustic",
        "glass-slab",
        "rough-glass",
        "materials",
    ] {
        let s = Scene::load(&format!("builtin:{name}")).expect("builtin");
        let r = Renderer::new(s).expect("valid");
        let (w, h) = (32, 24);
        let pt = render(&r, Estimator::Path, 512, 1, w, h);
        let bd = render(&r, Estimator::Bdpt, 64, 2, w, h);
        let pass = block_pass(&pt, &bd, w as usize, h as usize, 8, 4.0);
        let (ma, sa) = mean_sem(&pt);
        let (mb, sb) = mean_sem(&bd);
        let z = (ma - mb).abs() / (sa * sa + sb * sb).sqrt();
        eprintln!(
            "{name}: block pass {:.0}%, means {ma:.4} vs {mb:.4} (z = {z:.2})",
            pass * 100.0
        );
        assert!(
            pass >= 0.9,
            "{name}: only {:.0}% of blocks agree",
            pass * 100.0
        );
        assert!(
            z < 4.0,
            "{name}: means {ma:.5} (PT) vs {mb:.5} (BDPT), z = {z:.2}"
        );
    }
}

fn diffuse_box(with_slab: bool) -> Scene {
    let mut m = Mesh::default();
    let mats = vec![
        Material::diffuse("white", Vec3::splat(0.7)),
        Material::diffuse("red", Vec3::new(0.7, 0.1, 0.1)),
        Material::emitter("light", Vec3::splat(8.0)),
        Material::glass("slab", 1.5),
    ];
    cuboid(
        &mut m,
        Vec3::new(-1.0, -0.1, -1.0),
        Vec3::new(1.0, 0.0, 1.0),
        0,
    );
    cuboid(
        &mut m,
        Vec3::new(-0.9, 0.0, -0.8),
        Vec3::new(-0.4, 0.5, -0.3),
        1,
    );
    quad(
        &mut m,
        Vec3::new(-0.25, 1.2, -0.25),
        Vec3::X * 0.5,
        Vec3::Z * 0.5,
        2,
    );
    if with_slab {
        cuboid(
            &mut m,
            Vec3::new(-0.6, 0.6, -0.6),
            Vec3::new(0.6, 0.8, 0.6),
            3,
        );
    }
    let cam = Camera::look_at(
        Vec3::new(0.0, 1.6, 2.2),
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::Y,
        0.9,
    );
    let mut s = scene("box", m, mats, cam, 0.0);
    s.settings.max_depth = 32;
    s
}

/// Pure light tracing sees every path of a diffuse scene (the camera never looks at a delta
/// surface), so it must match path tracing: ≥ 90% of blocks within 4σ, means within 4σ.
#[test]
fn light_tracing_matches_path_tracing_on_diffuse_scene() {
    let r = Renderer::new(diffuse_box(false)).expect("valid");
    let (w, h) = (32, 24);
    let pt = render(&r, Estimator::Path, 256, 3, w, h);
    let lt = render(&r, Estimator::Lt, 256, 4, w, h);
    let pass = block_pass(&pt, &lt, w as usize, h as usize, 8, 4.0);
    let (ma, sa) = mean_sem(&pt);
    let (mb, sb) = mean_sem(&lt);
    let z = (ma - mb).abs() / (sa * sa + sb * sb).sqrt();
    assert!(pass >= 0.9, "only {:.0}% of blocks agree", pass * 100.0);
    assert!(z < 4.0, "means {ma:.5} (PT) vs {mb:.5} (LT), z = {z:.2}");
}

/// Light under a glass slab: light tracing carries importance through the slab without the
/// 1/η² factor, the path tracer carries radiance with it (and η² on exit). Both must give the
/// same floor illumination (means within 4σ, blocks ≥ 90% within 4σ); a wrong η² rule on
/// either side changes the transmitted light by a factor 2.25.
#[test]
fn importance_and_radiance_agree_through_glass() {
    let r = Renderer::new(diffuse_box(true)).expect("valid");
    let (w, h) = (32, 24);
    let pt = render(&r, Estimator::Path, 512, 5, w, h);
    let lt = render(&r, Estimator::Lt, 256, 6, w, h);
    let bd = render(&r, Estimator::Bdpt, 128, 7, w, h);
    for (name, img) in [("light tracing", &lt), ("bdpt", &bd)] {
        let (ma, sa) = mean_sem(&pt);
        let (mb, sb) = mean_sem(img);
        let z = (ma - mb).abs() / (sa * sa + sb * sb).sqrt();
        let pass = block_pass(&pt, img, w as usize, h as usize, 8, 4.0);
        assert!(
            z < 4.0,
            "{name}: mean {mb:.5} vs path tracing {ma:.5} (z = {z:.2})"
        );
        assert!(
            pass >= 0.9,
            "{name}: only {:.0}% of blocks agree",
            pass * 100.0
        );
    }
}

/// The Heckbert filter applies to every BDPT strategy: disjoint classes add up to the
/// unfiltered image (same seed ⇒ same subpaths; exact up to float rounding).
#[test]
fn bdpt_filter_classes_partition_the_image() {
    let s = Scene::load("builtin:cornell-glass").expect("builtin");
    let r = Renderer::new(s).expect("valid");
    let run = |re: &str| {
        let mut o = RenderOptions::from_scene(&r.scene);
        o.width = 24;
        o.height = 24;
        o.seed = 9;
        o.estimator = Estimator::Bdpt;
        let f = PathFilter::parse(re).expect("regex");
        o.set_filter(Some(&f));
        r.render(&o, 8, None, |_| {}).0.image()
    };
    let all = run("");
    let parts = [run("LE"), run("L(D|G|S)*DE"), run("L(D|G|S)*(G|S)E")];
    let worst = worst_part_sum_error(&parts, &all);
    assert!(
        worst < 1e-4,
        "classes do not add up: worst relative error {worst}"
    );
    let caustic: f32 = run("LS+DE").iter().map(|p| p.y).sum();
    assert!(caustic > 0.0, "BDPT found no LS+DE paths");
}

/// Spectral (dispersive) scenes: BDPT with hero wavelengths (collapse once per full path)
/// converges to the spectral path tracer on the Cornell box with a dispersive sphere.
#[test]
fn bdpt_matches_path_tracing_with_dispersion() {
    let mut s = Scene::load("builtin:cornell-glass").expect("builtin");
    for m in s.materials.iter_mut().filter(|m| m.is_transmissive()) {
        m.abbe = Some(20.0);
    }
    let r = Renderer::new(s).expect("valid");
    assert!(r.spectral);
    let (w, h) = (32, 24);
    let pt = render(&r, Estimator::Path, 512, 11, w, h);
    let bd = render(&r, Estimator::Bdpt, 64, 12, w, h);
    let pass = block_pass(&pt, &bd, w as usize, h as usize, 8, 4.0);
    let (ma, sa) = mean_sem(&pt);
    let (mb, sb) = mean_sem(&bd);
    let z = (ma - mb).abs() / (sa * sa + sb * sb).sqrt();
    assert!(pass >= 0.9, "only {:.0}% of blocks agree", pass * 100.0);
    assert!(z < 4.0, "means {ma:.5} (PT) vs {mb:.5} (BDPT), z = {z:.2}");
}
