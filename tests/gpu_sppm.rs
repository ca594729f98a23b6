//! GPU photon mapping (`sppm`, src/shaders/photon.wgsl, src/gpu/photons.rs): the same radius
//! schedule as the CPU's, and images that agree with CPU sppm and CPU bdpt on the caustic
//! scenes (block Z-tests over independent runs), also for the caustic class LS+DE alone.
//! Tests print a SKIP line without an adapter (CI installs lavapipe and sets
//! REFRACT_REQUIRE_GPU, so there they run).

mod common_scenes;
use common_scenes::{assert_blocks_agree, block_means, cpu_block_runs, gpu_context};
use refract::cpu::Renderer;
use refract::cpu::sppm::SppmParams;
use refract::gpu::{GpuContext, GpuRenderer, photons};
use refract::paths::PathFilter;
use refract::render::{Estimator, RenderOptions};
use refract::scene::Scene;

const W: u32 = 32;
const H: u32 = 24;
const RUNS: u32 = 6;
const SPP: u32 = 32;

fn small(name: &str) -> Scene {
    let mut s = Scene::load(&format!("builtin:{name}")).expect("built-in");
    s.settings.width = W;
    s.settings.height = H;
    s
}

/// `RUNS` independent GPU sppm renders (seeds 1000…) as block means; none may drop a sample
/// or overflow the photon store.
fn gpu_sppm_runs(ctx: GpuContext, scene: &Scene, filter: Option<&str>) -> Vec<Vec<f64>> {
    let filter = filter.map(|f| PathFilter::parse(f).expect("valid regex"));
    let mut opts = RenderOptions::from_scene(scene);
    opts.estimator = Estimator::Sppm;
    let mut g = GpuRenderer::with_context(ctx, scene.clone(), opts).expect("GPU renderer");
    g.set_filter(filter.as_ref());
    assert_eq!(g.effective_estimator(), Estimator::Sppm);
    let t = std::time::Instant::now();
    let runs = (0..RUNS)
        .map(|i| {
            opts.seed = 1000 + i;
            g.set_options(opts).expect("options");
            let img = g.render(SPP).expect("render");
            assert_eq!(img.dropped, 0, "the firewall dropped samples");
            let (stored, overflow) = g.photon_counts().expect("photon counts");
            assert_eq!(overflow, 0, "the photon store overflowed");
            assert!(stored <= W * H, "{stored} photons from {} paths", W * H);
            block_means(&img.mean, W, H)
        })
        .collect();
    eprintln!(
        "GPU sppm: {RUNS} × {SPP} spp of {W}×{H} in {:.2} s",
        t.elapsed().as_secs_f64()
    );
    runs
}

/// GPU sppm against CPU sppm and CPU bdpt on `name` (class `filter`); returns the GPU mean.
fn agrees(name: &str, filter: Option<&str>) -> Option<f64> {
    let ctx = gpu_context(name)?;
    let scene = small(name);
    let gpu = gpu_sppm_runs(ctx, &scene, filter);
    let cpu = Renderer::new(scene).expect("valid");
    let sppm = cpu_block_runs(&cpu, Estimator::Sppm, SPP, filter, 200, RUNS);
    let bdpt = cpu_block_runs(&cpu, Estimator::Bdpt, SPP, filter, 100, RUNS);
    let what = filter.unwrap_or("all paths");
    let t = assert_blocks_agree(
        &format!("{name} ({what}): GPU sppm vs CPU sppm"),
        &gpu,
        &sppm,
    );
    assert_blocks_agree(
        &format!("{name} ({what}): GPU sppm vs CPU bdpt"),
        &gpu,
        &bdpt,
    );
    Some(t.mean_a)
}

/// r₁ and r_s are the CPU's (`SppmParams`), so both estimators blur caustics alike.
#[test]
fn gpu_radius_schedule_is_the_cpus() {
    for name in ["caustic", "caustic-mirror", "cornell-glass"] {
        let s = small(name);
        let cpu = SppmParams::new(&s.camera, s.bounds(), W, H);
        let r0 = photons::radius0(&s.camera, s.bounds(), H);
        assert_eq!(r0, cpu.radius0, "{name}");
        assert_eq!(
            cpu.photons_per_iteration,
            W * H,
            "one photon path per pixel"
        );
        for it in [0, 1, 7, 100, 4095] {
            assert_eq!(
                photons::radius(r0, it),
                cpu.radius(it),
                "{name} iteration {it}"
            );
        }
    }
    assert_eq!(photons::buckets(768), 2048);
    assert_eq!(photons::buckets(1), 16);
}

#[test]
fn gpu_sppm_agrees_with_cpu_on_caustic() {
    agrees("caustic", None);
}

#[test]
fn gpu_sppm_agrees_with_cpu_on_caustic_mirror() {
    agrees("caustic-mirror", None);
}

/// The photons' own class: the caustic on the floor, seen directly (LS+DE), is not empty and
/// agrees with the CPU's photons and with bdpt.
#[test]
fn gpu_sppm_caustic_class_agrees() {
    if let Some(mean) = agrees("caustic", Some("LS+DE")) {
        assert!(mean > 0.0, "GPU sppm rendered no LS+DE caustic");
    }
}

/// The caustic seen in the mirror (LS+DS+E), which no connection strategy samples: GPU and
/// CPU photons render it alike, and it is not empty.
#[test]
fn gpu_sppm_mirrored_caustic_agrees_with_cpu_sppm() {
    let name = "caustic-mirror";
    let Some(ctx) = gpu_context(name) else {
        return;
    };
    let filter = Some("LS+DS+E");
    let scene = small(name);
    let gpu = gpu_sppm_runs(ctx, &scene, filter);
    let cpu = Renderer::new(scene).expect("valid");
    let sppm = cpu_block_runs(&cpu, Estimator::Sppm, SPP, filter, 200, RUNS);
    let t = assert_blocks_agree(
        "caustic-mirror (LS+DS+E): GPU sppm vs CPU sppm",
        &gpu,
        &sppm,
    );
    assert!(t.mean_a > 0.0, "GPU sppm rendered no mirrored caustic");
}

/// Dispersive glass (hero wavelengths shared by an iteration's photons and camera paths, the
/// hero lane alone after the first dispersive vertex): GPU and CPU sppm agree.
#[test]
fn gpu_sppm_with_dispersion_agrees_with_cpu_sppm() {
    let name = "caustic, dispersive";
    let Some(ctx) = gpu_context(name) else {
        return;
    };
    let mut scene = small("caustic");
    for m in scene.materials.iter_mut().filter(|m| m.is_transmissive()) {
        m.abbe = Some(30.0);
    }
    let gpu = gpu_sppm_runs(ctx, &scene, None);
    let cpu = Renderer::new(scene).expect("valid");
    let sppm = cpu_block_runs(&cpu, Estimator::Sppm, SPP, None, 200, RUNS);
    assert_blocks_agree("caustic, dispersive: GPU sppm vs CPU sppm", &gpu, &sppm);
}
