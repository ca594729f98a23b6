//! Soak test of the viewer's GPU renderer (issue 37, item 5): the backend the viewer draws
//! from (`app::backend::GpuBackend`, headless on lavapipe) driven through random edits —
//! scenes (the built-ins without dispersion or nested media: `common_scenes::soak_scene`),
//! materials (IOR, roughness, roughness type, colour, emission), the
//! camera, the estimator, path filters, depth and image size — with a few frames of rendering
//! between them. After every edit batch the accumulation is read back: no pixel may be NaN or
//! infinite, and nothing may panic. The same edits run three times: the first pass waits
//! after each edit until its kernel has compiled and rendered, then the mean resident memory
//! over the third pass must be at most 5 % above that over the second — a leak per edit grows
//! the third by a pass's worth. The backend runs the general kernels only, so passes 2 and 3
//! compile nothing (asserted) and memory does not depend on which pipelines a cache holds.
//!
//! `REFRACT_SOAK_EDITS` sets the edits per pass (CI: 100; docs/testing.md has a longer run).

mod common_scenes;
use common_scenes::{Rng, assert_passes_flat, gpu_context, rss_bytes, soak_scenes};

use eframe::egui::mutex::RwLock;
use eframe::{egui_wgpu, wgpu};
use glam::Vec3;
use refract::app::backend::{Backend, GpuBackend};
use refract::paths::PathFilter;
use refract::render::{Estimator, RenderOptions};
use refract::scene::{Camera, Checked, Scene, builtin};
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

/// Specialisations the soak keeps compiled: more than the kernel families its edits reach
/// (3 estimators × filter, and the tree layouts of the scenes; 31 when every built-in and
/// dispersion were in the edits).
const FAMILIES_KEPT: usize = 48;

/// Step until no kernel compiles and the current one has rendered (at most 60 s): its
/// pipelines exist and lavapipe has compiled their machine code, which it does at the first
/// dispatch.
fn settle(b: &mut GpuBackend) {
    let start = std::time::Instant::now();
    b.step(Duration::from_millis(8));
    while (b.is_compiling() || b.spp() == 0) && start.elapsed() < Duration::from_secs(60) {
        std::thread::sleep(Duration::from_millis(5));
        b.step(Duration::from_millis(8));
    }
}

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
            let names = soak_scenes();
            let name = names[rng.below(names.len())];
            *st = load(b, name, (st.opts.width, st.opts.height));
        }
        0 | 1 => {
            let k = rng.below(st.scene.materials.len());
            let m = &mut st.scene.materials[k];
            m.ior = 1.0 + 1.42 * rng.unit();
            m.roughness = rng.unit();
            m.base_color = Vec3::new(rng.unit(), rng.unit(), rng.unit());
            if m.emission.max_element() > 0.0 {
                m.emission *= 0.5 + rng.unit();
            }
            b.update_material(
                k,
                &Checked::new(st.scene.materials[k].clone()).expect("valid"),
            );
        }
        2 => {
            let c = &st.scene.camera;
            let eye =
                c.position + Vec3::new(rng.unit() - 0.5, rng.unit() - 0.5, rng.unit() - 0.5) * 0.2;
            let target = eye - c.rotation.z_axis;
            let yfov = (c.yfov * (0.9 + 0.2 * rng.unit())).clamp(0.2, 2.0);
            st.scene.camera = Camera::look_at(eye, target, Vec3::Y, yfov);
            b.update_camera(&Checked::new(st.scene.camera).expect("valid"));
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

/// One pass of `edits` random edits from `NAMES[0]` with the seed every pass uses: the
/// resident memory after each, and the accumulations read back. With `settle`, each edit
/// waits until its kernel has compiled and rendered.
fn pass(b: &mut GpuBackend, edits: usize, settle_each: bool) -> (Vec<u64>, usize) {
    let mut rng = Rng(0x5eed_50a6);
    let mut st = load(b, builtin::NAMES[0], (48, 32));
    let (mut rss, mut checked) = (Vec::with_capacity(edits), 0);
    for i in 0..edits {
        edit(b, &mut st, &mut rng, i);
        b.step(Duration::from_millis(4));
        b.step(Duration::from_millis(4));
        if settle_each {
            let t = std::time::Instant::now();
            settle(b);
            if t.elapsed() > Duration::from_secs(1) {
                eprintln!(
                    "edit {i}: its kernel compiled and rendered in {:.1} s, (pipelines \
                     compiled, specialisations cached) {:?}",
                    t.elapsed().as_secs_f64(),
                    b.pipeline_stats()
                );
            }
        }
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
    (rss, checked)
}

#[test]
fn thousands_of_random_edits_neither_poison_nor_leak() {
    let Some(ctx) = gpu_context("thousands_of_random_edits_neither_poison_nor_leak") else {
        return;
    };
    let edits: usize = std::env::var("REFRACT_SOAK_EDITS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(100);
    let renderer = egui_wgpu::Renderer::new(
        &ctx.device,
        wgpu::TextureFormat::Rgba8Unorm,
        egui_wgpu::RendererOptions::default(),
    );
    let mut b = GpuBackend::new(ctx, Arc::new(RwLock::new(renderer)), None).expect("backend");
    // The general kernels only, all kept: after the first pass the edits compile nothing, so
    // resident memory measures the buffers, trees and textures the edits allocate, not which
    // of lavapipe's pipelines (50–250 MB each once executed) the cache happens to hold. With
    // the specialised kernels the edits kept compiling and evicting and the mean moved by
    // ±5–15 % with the cache's contents; the cache's bound is tested on its own
    // (`gpu_general_kernel::the_pipeline_cache_keeps_at_most_its_capacity`).
    b.set_general_kernel(true);
    b.set_pipeline_capacity(FAMILIES_KEPT);
    // Pass 1 compiles and runs every kernel the edits reach (waiting after each edit); passes
    // 2 and 3 repeat the same edits at full speed. A leak grows pass 3 over pass 2.
    let start = std::time::Instant::now();
    let (_, mut checked) = pass(&mut b, edits, true);
    let warm = b.pipeline_stats();
    eprintln!(
        "pass 1: {:.0} s, (pipelines compiled, specialisations cached) {warm:?}",
        start.elapsed().as_secs_f64()
    );
    let (second, c2) = pass(&mut b, edits, false);
    let (third, c3) = pass(&mut b, edits, false);
    checked += c2 + c3;
    let after = b.pipeline_stats();
    eprintln!(
        "passes 2 and 3: {:.0} s in all, {after:?}",
        start.elapsed().as_secs_f64()
    );
    assert!(
        checked > 3 * edits / 20,
        "only {checked} accumulations read back"
    );
    assert_passes_flat(warm, after, &second, &third, edits);
}
