//! Whole-renderer checks with analytic answers: slab transmittance, white furnace,
//! single-bounce albedo, determinism across thread counts.

mod common_scenes;
use common_scenes::*;
use glam::Vec3;
use refract::cpu::Renderer;
use refract::render::RenderOptions;
use refract::scene::{Camera, Material, Mesh, Scene};

fn render(scene: Scene, spp: u32) -> (Vec<Vec3>, u64) {
    let r = Renderer::new(scene).expect("valid scene");
    let opts = RenderOptions::from_scene(&r.scene);
    let (film, stats) = r.render(&opts, spp, None, |_| {});
    (film.image(), stats.dropped)
}

/// Mean and standard error of the mean of one channel over pixels (pixels independent).
fn mean_sem(img: &[Vec3], ch: usize) -> (f64, f64) {
    let n = img.len() as f64;
    let m = img.iter().map(|p| p[ch] as f64).sum::<f64>() / n;
    let var = img.iter().map(|p| (p[ch] as f64 - m).powi(2)).sum::<f64>() / (n - 1.0);
    (m, (var / n).sqrt())
}

/// A glass slab (n = 1.5) in front of a uniform emitter, seen at normal incidence, transmits
/// (1 − R)/(1 + R) of the radiance (all internal reflections summed), R = ((n−1)/(n+1))².
#[test]
fn slab_transmittance_normal_incidence() {
    let mut m = Mesh::default();
    let mats = vec![
        Material::glass("glass", 1.5),
        Material::emitter("e", Vec3::ONE),
    ];
    cuboid(
        &mut m,
        Vec3::new(-20.0, -20.0, -1.0),
        Vec3::new(20.0, 20.0, 1.0),
        0,
    );
    quad(
        &mut m,
        Vec3::new(-50.0, -50.0, -5.0),
        Vec3::X * 100.0,
        Vec3::Y * 100.0,
        1,
    );
    let cam = Camera::look_at(Vec3::new(0.0, 0.0, 10.0), Vec3::ZERO, Vec3::Y, 1e-3);
    let mut s = scene("slab", m, mats, cam, 0.0);
    s.settings.max_depth = 1000;
    let (img, dropped) = render(s, 256);
    assert_eq!(dropped, 0);
    let r = (0.5f64 / 2.5).powi(2);
    let expect = (1.0 - r) / (1.0 + r);
    let (mean, sem) = mean_sem(&img, 1);
    assert!(
        (mean - expect).abs() < 3.0 * sem + 1e-6,
        "slab transmits {mean:.5} ± {sem:.5}, expected {expect:.5} (3σ)"
    );
    assert!((expect - 0.9231).abs() < 1e-4);
}

/// Furnace with a flat-shaded sphere (shading normal = geometric normal, so no energy is lost
/// to shading-normal inconsistencies; `coarse_smooth_normals` in the stress suite covers those).
fn furnace_check(mat: Material, expect: f64, spp: u32) {
    let mut m = Mesh::default();
    sphere(&mut m, Vec3::ZERO, 1.0, 48, 96, 0);
    let m = flatten(&m);
    let cam = Camera::look_at(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, Vec3::Y, 0.5);
    let mut s = scene("furnace", m, vec![mat], cam, 1.0);
    s.settings.max_depth = 1000;
    let name = s.materials[0].name.clone();
    let (img, dropped) = render(s, spp);
    assert_eq!(dropped, 0);
    for ch in 0..3 {
        let (mean, sem) = mean_sem(&img, ch);
        assert!(
            (mean - expect).abs() <= 3.0 * sem + 1e-6,
            "{name}: furnace channel {ch} = {mean:.5} ± {sem:.5}, expected {expect} (3σ)"
        );
    }
}

/// White furnace: closed non-absorbing objects in a uniform environment of 1 render 1.
#[test]
fn furnace_diffuse_albedo_one() {
    furnace_check(Material::diffuse("diffuse", Vec3::ONE), 1.0, 64);
}

#[test]
fn furnace_mirror() {
    let (img, _) = {
        let mut m = Mesh::default();
        sphere(&mut m, Vec3::ZERO, 1.0, 48, 96, 0);
        let cam = Camera::look_at(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, Vec3::Y, 0.5);
        let s = scene(
            "furnace",
            m,
            vec![Material::mirror("m", Vec3::ONE)],
            cam,
            1.0,
        );
        render(s, 4)
    };
    // Deterministic: every path is exactly 1 (mirror weight 1, then escapes).
    let worst = img
        .iter()
        .map(|p| (p.x - 1.0).abs().max((p.y - 1.0).abs()))
        .fold(0.0, f32::max);
    assert!(worst < 1e-6, "mirror furnace deviates by {worst}");
}

#[test]
fn furnace_smooth_glass() {
    furnace_check(Material::glass("glass", 1.5), 1.0, 64);
}

/// A diffuse albedo-0.8 convex object under a uniform environment renders 0.8 exactly
/// (single bounce: every cosine-sampled ray escapes; weight = albedo).
#[test]
fn convex_diffuse_single_bounce_exact() {
    let mut m = Mesh::default();
    cuboid(&mut m, Vec3::splat(-1.0), Vec3::splat(1.0), 0);
    let cam = Camera::look_at(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, Vec3::Y, 0.3);
    let s = scene(
        "cube",
        m,
        vec![Material::diffuse("d", Vec3::splat(0.8))],
        cam,
        1.0,
    );
    let (img, _) = render(s, 8);
    let worst = img.iter().map(|p| (p.y - 0.8).abs()).fold(0.0, f32::max);
    assert!(worst < 1e-6, "worst deviation from 0.8: {worst}");
}

/// The same seed gives the same image bit for bit on 1 and 2 threads.
#[test]
fn deterministic_across_thread_counts() {
    let s = refract::scene::Scene::load("builtin:cornell-glass").expect("builtin");
    let r = Renderer::new(s).expect("valid");
    let mut opts = RenderOptions::from_scene(&r.scene);
    opts.width = 48;
    opts.height = 48;
    opts.seed = 7;
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| r.render(&opts, 4, None, |_| {}).0.image())
    };
    let a = run(1);
    let b = run(2);
    let differ = a
        .iter()
        .zip(&b)
        .filter(|(x, y)| x.to_array().map(f32::to_bits) != y.to_array().map(f32::to_bits))
        .count();
    assert_eq!(differ, 0, "{differ} pixels differ between 1 and 2 threads");
    let mut opts2 = opts;
    opts2.seed = 8;
    let c = pool_render(&r, &opts2);
    assert!(
        a.iter().zip(&c).any(|(x, y)| x != y),
        "a different seed must change the image"
    );
}

fn pool_render(r: &Renderer, opts: &RenderOptions) -> Vec<Vec3> {
    r.render(opts, 4, None, |_| {}).0.image()
}
