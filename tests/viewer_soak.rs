//! Soak test of the viewer's GPU renderer (issue 37, item 5): the backend the viewer draws
//! from (`app::backend::GpuBackend`, headless on lavapipe) driven through random edits —
//! scenes, materials (IOR, roughness, roughness type, dispersion, colour, emission), the
//! camera, the estimator, path filters, depth and image size — with a few frames of rendering
//! between them. After every edit batch the accumulation is read back: no pixel may be NaN or
//! infinite, and nothing may panic. Resident memory must stay flat once every scene and
//! estimator has been seen: the mean over the last fifth of the edits at most 5 % above the
//! mean over the first fifth after warm-up.
//!
//! `REFRACT_SOAK_EDITS` sets the number of edits (CI: 300; docs/testing.md has a longer run).

mod common_scenes;
use common_scenes::{Rng, gpu_context, rss_bytes};

use eframe::egui::mutex::RwLock;
use eframe::{egui_wgpu, wgpu};
use glam::Vec3;
use refract::app::backend::{Backend, GpuBackend};
use refract::paths::PathFilter;
use refract::render::{Estimator, RenderOptions};
use refract::scene::{Camera, Scene, builtin};
use std::sync::Arc;
use std::time::Duration;

const ESTIMATORS: [Estimator; 4] = [
    Estimator::Auto,
    Estimator::Path,
    Estimator::LtPt,
    Estimator::Sppm,
];
const FILTERS: [Option<&str>; 5] = [
    None,
    Some("LS+DE"),
    Some("LDE"),
    Some("L(D|G|S)*(G|S)E"),
    None,
];

/// The viewer's state the edits change.
struct State {
    scene: Scene,
    opts: RenderOptions,
}

fn load(b: &mut GpuBackend, name: &str, size: (u32, u32)) -> State {
    let scene = builtin::load(name).expect("built-in");
    let mut opts = RenderOptions::from_scene(&scene);
    (opts.width, opts.height) = size;
    b.set_scene(&scene);
    b.set_options(&opts);
    State { scene, opts }
}

/// One random edit of the kinds the viewer's panels make.
fn edit(b: &mut GpuBackend, st: &mut State, rng: &mut Rng, i: usize) {
    match rng.below(6) {
        0 if i.is_multiple_of(4) => {
            let name = builtin::NAMES[rng.below(builtin::NAMES.len())];
            *st = load(b, name, (st.opts.width, st.opts.height));
        }
        0 | 1 => {
            let k = rng.below(st.scene.materials.len());
            let m = &mut st.scene.materials[k];
            m.ior = 1.0 + 1.42 * rng.unit();
            m.roughness = rng.unit();
            m.abbe = (rng.below(2) == 0).then(|| 20.0 + 60.0 * rng.unit());
            m.base_color = Vec3::new(rng.unit(), rng.unit(), rng.unit());
            if m.emission.max_element() > 0.0 {
                m.emission *= 0.5 + rng.unit();
            }
            b.update_material(k, &st.scene.materials[k]);
        }
        2 => {
            let c = &st.scene.camera;
            let eye =
                c.position + Vec3::new(rng.unit() - 0.5, rng.unit() - 0.5, rng.unit() - 0.5) * 0.2;
            let target = eye - c.rotation.z_axis;
            let yfov = (c.yfov * (0.9 + 0.2 * rng.unit())).clamp(0.2, 2.0);
            st.scene.camera = Camera::look_at(eye, target, Vec3::Y, yfov);
            b.update_camera(&st.scene.camera);
        }
        3 => {
            st.opts.estimator = ESTIMATORS[rng.below(ESTIMATORS.len())];
            st.opts.max_depth = 1 + rng.below(12) as u32;
            b.set_options(&st.opts);
        }
        4 => {
            let f = FILTERS[rng.below(FILTERS.len())].map(|s| PathFilter::parse(s).expect("regex"));
            st.opts.set_filter(f.as_ref());
            b.set_options(&st.opts);
        }
        _ => {
            let sizes = [(48, 32), (40, 40), (64, 36)];
            (st.opts.width, st.opts.height) = sizes[rng.below(sizes.len())];
            b.set_options(&st.opts);
        }
    }
}

#[test]
fn thousands_of_random_edits_neither_poison_nor_leak() {
    let Some(ctx) = gpu_context("thousands_of_random_edits_neither_poison_nor_leak") else {
        return;
    };
    let edits: usize = std::env::var("REFRACT_SOAK_EDITS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(300);
    let renderer = egui_wgpu::Renderer::new(
        &ctx.device,
        wgpu::TextureFormat::Rgba8Unorm,
        egui_wgpu::RendererOptions::default(),
    );
    let mut b = GpuBackend::new(ctx, Arc::new(RwLock::new(renderer)), None).expect("backend");
    let mut rng = Rng(0x5eed_50a6);
    // Warm-up: every scene once with every estimator, so caches (pipelines, BVHs) are full.
    // Each waits for its kernels: background compiles run one at a time on lavapipe, and a
    // request made while one runs supersedes the one waiting before it, so a burst without
    // waits compiles only its first and last specialisations, and the cache would fill during
    // the measured edits instead (1.2 → 2.0 GiB over 300 edits when tried). Waiting on only
    // the first eight scenes was not enough either (1.79 → 2.0 GiB: the edits' material kinds
    // bring specialisations of their own). About 9 min on 2 cores.
    let mut st = load(&mut b, builtin::NAMES[0], (48, 32));
    for name in builtin::NAMES {
        st = load(&mut b, name, (48, 32));
        for est in ESTIMATORS {
            st.opts.estimator = est;
            b.set_options(&st.opts);
            let start = std::time::Instant::now();
            b.step(Duration::from_millis(8));
            while b.is_compiling() && start.elapsed() < Duration::from_secs(60) {
                std::thread::sleep(Duration::from_millis(20));
                b.step(Duration::from_millis(8));
            }
        }
    }
    let mut rss = Vec::with_capacity(edits);
    let mut checked = 0;
    for i in 0..edits {
        edit(&mut b, &mut st, &mut rng, i);
        b.step(Duration::from_millis(4));
        b.step(Duration::from_millis(4));
        while b.take_message().is_some() {}
        if i % 10 == 9 {
            // Let the edit's first samples land (a new kernel may be compiling) before reading.
            let start = std::time::Instant::now();
            while b.spp() == 0 && start.elapsed() < Duration::from_secs(30) {
                b.step(Duration::from_millis(8));
                std::thread::sleep(Duration::from_millis(2));
            }
            if let Some(img) = b.read_image() {
                let bad = img.pixels.iter().filter(|p| !p.is_finite()).count();
                assert_eq!(
                    bad, 0,
                    "edit {i}: {bad} non-finite pixels after {} spp",
                    img.spp
                );
                checked += 1;
            }
        }
        rss.extend(rss_bytes());
    }
    assert!(
        checked > edits / 20,
        "only {checked} accumulations read back"
    );
    if rss.len() >= 10 {
        let fifth = rss.len() / 5;
        let mean = |s: &[u64]| s.iter().sum::<u64>() as f64 / s.len() as f64;
        let (first, last) = (mean(&rss[..fifth]), mean(&rss[rss.len() - fifth..]));
        eprintln!(
            "{edits} edits: resident {:.1} MiB in the first fifth, {:.1} MiB in the last",
            first / 1048576.0,
            last / 1048576.0
        );
        assert!(
            last <= first * 1.05,
            "resident memory grew {:.1} % over {edits} edits",
            (last / first - 1.0) * 100.0
        );
    }
}
