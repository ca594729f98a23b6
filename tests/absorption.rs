//! Beer–Lambert absorption works in every estimator: the Cornell box whose glass sphere has
//! `KHR_materials_volume` attenuation (colour 0.25/0.55/0.9 after 0.25 m) renders alike with
//! CPU path tracing, CPU BDPT, CPU light tracing (on the paths light tracing can sample:
//! `L(D|G|S)*DE`, the last bounce diffuse) and GPU path tracing and lt+pt (block Z-tests over
//! 8 independent runs per side; a block passes within 3σ, and ≥ 90% must pass — with 7
//! degrees of freedom per side a block exceeds |t| = 3 about 2% of the time). A control
//! asserts that the absorption is visible (the test would catch an estimator that ignores it:
//! before the shared per-vertex step BDPT rendered the sphere 2.1× too bright in red).

mod common_scenes;
use common_scenes::*;
use glam::Vec3;
use refract::cpu::Renderer;
use refract::gpu::GpuRenderer;
use refract::render::{Estimator, RenderOptions};
use refract::scene::{MaterialKind, Scene};

const RUNS: u32 = 8;

/// cornell-glass at 48² with absorbing glass (or the plain scene when `absorb` is false).
fn absorbing_cornell(absorb: bool) -> Scene {
    let mut s = Scene::load("builtin:cornell-glass").expect("builtin");
    s.settings.width = 48;
    s.settings.height = 48;
    let mut n = 0;
    for m in s
        .materials
        .iter_mut()
        .filter(|m| m.kind == MaterialKind::Glass)
    {
        if absorb {
            m.attenuation_color = Vec3::new(0.25, 0.55, 0.9);
            m.attenuation_distance = 0.25;
        }
        n += 1;
    }
    assert!(n > 0, "cornell-glass has a solid glass material");
    s
}

/// Block means of `RUNS` independent CPU renders (seeds `seed0`…) of `spp` each.
fn cpu_runs(
    scene: &Scene,
    est: Estimator,
    spp: u32,
    filter: Option<&str>,
    seed0: u32,
) -> Vec<Vec<f64>> {
    let r = Renderer::new(scene.clone()).expect("valid scene");
    cpu_block_runs(&r, est, spp, filter, seed0, RUNS)
}

fn assert_agree(name: &str, a: &[Vec<f64>], b: &[Vec<f64>]) {
    assert_blocks_agree(name, a, b);
}

#[test]
fn bdpt_and_light_tracing_absorb_like_path_tracing() {
    let scene = absorbing_cornell(true);
    let path = cpu_runs(&scene, Estimator::Path, 64, None, 0);
    let bdpt = cpu_runs(&scene, Estimator::Bdpt, 16, None, 100);
    assert_agree("absorbing glass: bdpt vs path", &bdpt, &path);
    // Light tracing reaches the camera only from non-specular vertices.
    let f = Some("L(D|G|S)*DE");
    let path_d = cpu_runs(&scene, Estimator::Path, 64, f, 200);
    let lt_d = cpu_runs(&scene, Estimator::Lt, 32, f, 300);
    assert_agree("absorbing glass, L(D|G|S)*DE: lt vs path", &lt_d, &path_d);
    // Control: without absorption the image is measurably brighter, so an estimator that
    // ignored the medium would fail the comparisons above.
    let clear = cpu_runs(&absorbing_cornell(false), Estimator::Bdpt, 16, None, 400);
    let t = block_z_test(&clear, &bdpt);
    eprintln!(
        "control: clear vs absorbing glass (bdpt): whole-image z = {:.2}",
        t.z_image
    );
    assert!(
        t.z_image > 8.0,
        "absorption is not visible: z = {:.2}",
        t.z_image
    );
}

#[test]
fn gpu_estimators_absorb_like_cpu_path_tracing() {
    let Some(ctx) = gpu_context("absorbing glass (GPU)") else {
        return;
    };
    let scene = absorbing_cornell(true);
    let cpu = cpu_runs(&scene, Estimator::Path, 64, None, 0);
    let mut g = GpuRenderer::with_context(ctx, scene.clone(), RenderOptions::from_scene(&scene))
        .expect("GPU renderer");
    for est in [Estimator::Path, Estimator::LtPt] {
        g.set_estimator(est).expect("estimator");
        let runs: Vec<Vec<f64>> = (0..RUNS)
            .map(|i| {
                let mut opts = RenderOptions::from_scene(&scene);
                opts.seed = 1000 + i;
                g.set_options(opts).expect("options");
                let img = g.render(16).expect("render");
                assert_eq!(img.dropped, 0, "GPU {est}: the firewall dropped samples");
                block_means(&img.mean, 48, 48)
            })
            .collect();
        assert_agree(
            &format!("absorbing glass: GPU {est} vs CPU path"),
            &runs,
            &cpu,
        );
    }
}
