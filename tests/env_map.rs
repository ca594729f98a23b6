//! Environment images: the three.js equirectangular mapping (a map bright in one known texel
//! lights from the expected direction, read from a real `.hdr` file, with and without
//! rotation), the analytic irradiance of that texel on a Lambert floor, a white furnace under
//! a constant image, CPU path tracing vs BDPT vs light tracing on a sun-and-sky scene (block
//! Z-tests, 8 runs per side), the shipped HDRIs against their generator, and glTF / CLI input
//! (`extras.environment` objects, safe-file rules, budgets, bad texels, the lightless
//! fallback).

mod common_scenes;
use common_scenes::*;
use glam::Vec3;
use refract::cpu::Renderer;
use refract::render::{Estimator, RenderOptions};
use refract::scene::env_map::{EnvImage, EnvMap};
use refract::scene::light::LightSet;
use refract::scene::{Camera, Material, Mesh, Scene, hdri};
use std::f32::consts::PI;
use std::path::{Path, PathBuf};
use std::sync::Arc;

fn tmp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("refract-env-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

/// A `w × h` map, black but for texel (col, row) of radiance `l`.
fn one_texel(w: u32, h: u32, col: u32, row: u32, l: f32) -> Vec<Vec3> {
    let mut t = vec![Vec3::ZERO; (w * h) as usize];
    t[(row * w + col) as usize] = Vec3::splat(l);
    t
}

/// The direction of image coordinates (u, v) by three.js's definition, v = 1 at the top:
/// atan2(d.z, d.x) = 2π(u − ½), asin(d.y) = π(v − ½).
fn threejs_dir(u: f32, v: f32) -> Vec3 {
    let (phi, elev) = (2.0 * PI * (u - 0.5), PI * (v - 0.5));
    Vec3::new(elev.cos() * phi.cos(), elev.sin(), elev.cos() * phi.sin())
}

/// A 2 × 2 m Lambert floor (albedo 0.5) seen from 3 m above; 8 × 8 pixels, direct light.
fn floor_with(env: EnvImage) -> Scene {
    let mut m = Mesh::default();
    quad(
        &mut m,
        Vec3::new(-1.0, 0.0, 1.0),
        Vec3::X * 2.0,
        Vec3::Z * -2.0,
        0,
    );
    let cam = Camera::look_at(Vec3::new(0.0, 3.0, 0.0), Vec3::ZERO, Vec3::Z, 0.3);
    let mut s = scene(
        "floor",
        m,
        vec![Material::diffuse("floor", Vec3::splat(0.5))],
        cam,
        0.0,
    );
    s.env_map = Some(env);
    s.settings.width = 8;
    s.settings.height = 8;
    s.settings.max_depth = 2;
    s
}

fn mean(img: &[Vec3]) -> f64 {
    img.iter().map(|p| p.y as f64).sum::<f64>() / img.len() as f64
}

#[test]
fn one_bright_texel_lights_from_the_threejs_direction() {
    let (w, h, col, row) = (64u32, 32u32, 48u32, 7u32);
    let dir = tmp_dir("texel");
    let file = dir.join("one.hdr");
    let (map, _) = EnvMap::from_texels(w, h, one_texel(w, h, col, row, 1000.0), "one");
    map.write_hdr(&file).expect("write hdr");
    let (map, warnings) = EnvMap::load_file(&file).expect("load hdr");
    assert!(warnings.is_empty(), "{warnings:?}");
    let map = Arc::new(map);
    // Texel centre: u = (col + ½)/W, v = 1 − (row + ½)/H (row 0 is the top of the file).
    let (u, v) = (
        (col as f32 + 0.5) / w as f32,
        1.0 - (row as f32 + 0.5) / h as f32,
    );
    // The image is interpolated bilinearly, so the bright texel's radiance reaches into its
    // 3 × 3 neighbourhood and so may the samples: at most 1.5 texels from its centre along
    // each axis (both axes' texels span π/h = 2π/w here).
    let texel = (PI / h as f32).max(2.0 * PI / w as f32);
    let reach = 1.5 * std::f32::consts::SQRT_2 * texel;
    for (rotation, expect) in [
        (0.0f32, threejs_dir(u, v)),
        // +90° about +Y: x' = z, z' = −x (right-handed).
        (90.0, {
            let d = threejs_dir(u, v);
            Vec3::new(d.z, d.y, -d.x)
        }),
    ] {
        let s = floor_with(EnvImage::new(map.clone(), 1.0, rotation));
        let lights = LightSet::build(&s);
        let env = &lights.environment;
        let mut rng = refract::math::rng::Sampler::new(5, 0, 1);
        for _ in 0..64 {
            let ls = env
                .sample_li(Vec3::ZERO, rng.next_2d(), 1.0)
                .expect("sample");
            let angle = ls.wi.dot(expect).clamp(-1.0, 1.0).acos();
            assert!(
                angle <= reach,
                "rotation {rotation}: sampled {} is {angle} rad from {expect}",
                ls.wi
            );
        }
        // Wherever the interpolated image is bright the density is positive (else NEE with
        // MIS would miss that light): directions jittered around the texel.
        for i in 0..4096 {
            let (du, dv) = rng.next_2d().into();
            let d = threejs_dir(
                u + (du - 0.5) * 3.0 / w as f32,
                v + (dv - 0.5) * 3.0 / h as f32 + 1e-3 * (i % 3) as f32,
            );
            if env.le(Vec3::ZERO, Vec3::ZERO, -d).x > 0.0 {
                assert!(
                    env.pdf_li(1.0, d, f32::INFINITY, 1.0) > 0.0,
                    "rotation {rotation}: radiance but no density towards {d}"
                );
            }
        }
        // `le` takes the direction light travels: from the texel towards the scene.
        assert!(
            env.le(Vec3::ZERO, Vec3::ZERO, -expect).x > 500.0,
            "rotation {rotation}"
        );
        assert_eq!(
            env.le(Vec3::ZERO, Vec3::ZERO, expect).x,
            0.0,
            "rotation {rotation}"
        );
    }
}

#[test]
fn one_texel_irradiance_on_a_floor_is_analytic() {
    let (w, h, col, l) = (64u32, 32u32, 20u32, 50.0f32);
    for (row, lit) in [(7u32, true), (h - 1 - 7, false)] {
        let (map, _) = EnvMap::from_texels(w, h, one_texel(w, h, col, row, l), "one");
        let r = Renderer::new(floor_with(EnvImage::new(Arc::new(map), 2.0, 33.0))).expect("ok");
        let o = RenderOptions::from_scene(&r.scene);
        let img = r.render(&o, 256, None, |_| {}).0.image();
        // The interpolated image is L × tent(u) × tent(θ), each tent one texel wide either
        // side of the texel's centre; ∫ tent(u) du = 1/W, so
        // E = 2L (2π/W) ∫ tent(θ) cosθ sinθ dθ (θ from +Y; midpoint rule, 20,000 steps).
        let (c, dt) = (
            PI as f64 * (row as f64 + 0.5) / h as f64,
            PI as f64 / h as f64,
        );
        let n = 20_000;
        let step = 2.0 * dt / n as f64;
        let band: f64 = (0..n)
            .map(|i| {
                let th = c - dt + (i as f64 + 0.5) * step;
                (1.0 - (th - c).abs() / dt) * th.cos() * th.sin() * step
            })
            .sum();
        let e = 2.0 * l as f64 * (2.0 * PI as f64 / w as f64) * band;
        let expect = if lit { 0.5 / PI as f64 * e } else { 0.0 };
        // The sampling density is piecewise constant while the image is now a tent, so the
        // estimate has variance: the pixels are independent estimates of the same radiance
        // (a flat floor under light at infinity); 4 standard errors.
        let m = mean(&img);
        let n = img.len() as f64;
        let sd = (img.iter().map(|p| (p.y as f64 - m).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
        assert!(
            (m - expect).abs() <= 4.0 * sd / n.sqrt() + 1e-4 * expect.max(1e-3),
            "row {row}: floor radiance {m:.6} ± {:.6}, expected {expect:.6}",
            sd / n.sqrt()
        );
    }
}

/// The image's radiance in direction `d` by the definition (three.js's mapping, bilinear
/// between texel centres at ((i + ½)/W, (j + ½)/H), periodic in u, clamped rows).
fn bilinear_by_definition(t: &[Vec3], w: u32, h: u32, d: Vec3) -> Vec3 {
    let u = d.z.atan2(d.x) / (2.0 * PI) + 0.5;
    let v = d.y.clamp(-1.0, 1.0).acos() / PI;
    let (x, y) = (u * w as f32 - 0.5, v * h as f32 - 0.5);
    let (i, j) = (x.floor() as i32, y.floor() as i32);
    let (fx, fy) = (x - i as f32, y - j as f32);
    let at = |i: i32, j: i32| {
        let i = i.rem_euclid(w as i32) as u32;
        let j = j.clamp(0, h as i32 - 1) as u32;
        t[(j * w + i) as usize]
    };
    let top = at(i, j) * (1.0 - fx) + at(i + 1, j) * fx;
    let bottom = at(i, j + 1) * (1.0 - fx) + at(i + 1, j + 1) * fx;
    top * (1.0 - fy) + bottom * fy
}

/// The directly seen background is the bilinear interpolation of the image at each pixel's
/// direction: a 30° view across the image's seam (−X) and the horizon of a seeded 32 × 16 map
/// (texels 11.25° wide, so the view spans several texel boundaries, where a nearest-texel
/// lookup would be off by the texels' difference). Each pixel's mean is compared with the
/// definition averaged over the pixel's area, within 5 standard errors of its 64 samples.
#[test]
fn the_background_is_the_bilinear_interpolation_of_the_image() {
    let (w, h) = (32u32, 16u32);
    let texels = seeded_texels(w * h);
    let (map, _) = EnvMap::from_texels(w, h, texels.clone(), "seeded");
    let mut m = Mesh::default();
    quad(
        &mut m,
        Vec3::new(10.0, -1.0, -1.0),
        Vec3::Z * 2.0,
        Vec3::Y * 2.0,
        0,
    );
    let cam = Camera::look_at(
        Vec3::ZERO,
        Vec3::new(-1.0, 0.1, 0.0),
        Vec3::Y,
        30f32.to_radians(),
    );
    let mut s = scene(
        "sky",
        m,
        vec![Material::diffuse("d", Vec3::splat(0.5))],
        cam,
        0.0,
    );
    s.env_map = Some(EnvImage::new(Arc::new(map), 1.0, 0.0));
    let (pw, ph) = (32u32, 32u32);
    s.settings.width = pw;
    s.settings.height = ph;
    let r = Renderer::new(s.clone()).expect("valid");
    let spp = 64;
    let img = r
        .render(&RenderOptions::from_scene(&r.scene), spp, None, |_| {})
        .0
        .image();
    let (mut worst, mut nearest_worst) = (0.0f32, 0.0f32);
    for y in 0..ph {
        for x in 0..pw {
            // The pixel's expected value and spread: the definition averaged over a 16 × 16
            // grid of the pixel's area (the box filter of the renderer's jittered samples).
            let (mut sum, mut sum_sq) = (Vec3::ZERO, Vec3::ZERO);
            for k in 0..256 {
                let (sx, sy) = ((k % 16) as f32 + 0.5, (k / 16) as f32 + 0.5);
                let d = s.camera.ray_dir(
                    (x as f32 + sx / 16.0) / pw as f32,
                    (y as f32 + sy / 16.0) / ph as f32,
                    1.0,
                );
                let l = bilinear_by_definition(&texels, w, h, d);
                sum += l;
                sum_sq += l * l;
            }
            let expect = sum / 256.0;
            let sigma = ((sum_sq / 256.0 - expect * expect).max(Vec3::ZERO) / spp as f32)
                .powf(0.5)
                .max_element();
            let got = img[(y * pw + x) as usize];
            worst = worst.max((got - expect).abs().max_element() / (5.0 * sigma + 2e-4));
            let d = s.camera.ray_dir(
                (x as f32 + 0.5) / pw as f32,
                (y as f32 + 0.5) / ph as f32,
                1.0,
            );
            let (u, v) = (d.z.atan2(d.x) / (2.0 * PI) + 0.5, d.y.acos() / PI);
            let (i, j) = (
                ((u * w as f32) as u32).min(w - 1),
                ((v * h as f32) as u32).min(h - 1),
            );
            nearest_worst =
                nearest_worst.max((texels[(j * w + i) as usize] - expect).abs().max_element());
        }
    }
    assert!(
        worst <= 1.0,
        "background off the bilinear image by {worst} × (5σ + 2e-4)"
    );
    // The view does cross texel boundaries: nearest lookup would be far off.
    assert!(
        nearest_worst > 0.1,
        "nearest lookup would differ by only {nearest_worst}"
    );
}

/// White furnace: a closed Lambert sphere of albedo 1 under a constant image of radiance 1
/// renders 1 everywhere with path tracing and BDPT (importance sampling, MIS and the light
/// selection of the image all have to be right).
#[test]
fn image_furnace_renders_one() {
    let mut m = Mesh::default();
    sphere(&mut m, Vec3::ZERO, 0.5, 24, 48, 0);
    let cam = Camera::look_at(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, Vec3::Y, 0.5);
    let mut s = scene(
        "furnace",
        m,
        vec![Material::diffuse("white", Vec3::ONE)],
        cam,
        0.0,
    );
    let (map, _) = EnvMap::from_texels(16, 8, vec![Vec3::ONE; 128], "const");
    s.env_map = Some(EnvImage::new(Arc::new(map), 1.0, 10.0));
    s.settings.width = 16;
    s.settings.height = 16;
    let r = Renderer::new(s).expect("valid");
    for est in [Estimator::Path, Estimator::Bdpt] {
        let mut o = RenderOptions::from_scene(&r.scene);
        o.estimator = est;
        let img = r.render(&o, 128, None, |_| {}).0.image();
        let n = img.len() as f64;
        let m = mean(&img);
        let sd = (img.iter().map(|p| (p.y as f64 - m).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
        assert!(
            (m - 1.0).abs() <= (4.0 * sd / n.sqrt()).max(2e-3),
            "{est}: furnace mean {m:.5} ± {:.5}",
            sd / n.sqrt()
        );
    }
}

const RUNS: u32 = 8;

/// A Lambert floor, a diffuse and a glossy-metal sphere under the shipped sun-and-sky, and a
/// small area light (so the image shares the light distribution, and light tracing has a
/// light to start from).
fn sun_sky_scene() -> Scene {
    sun_sky_with(refract::scene::builtin::glossy_metal(
        "gold",
        Vec3::new(0.95, 0.78, 0.42),
        0.3,
    ))
}

/// [`sun_sky_scene`] with a glass sphere (IOR 1.5) in place of the glossy one: the sky seen
/// through it, refracted, samples the image between texels, and its sun caustic on the floor.
fn sun_sky_glass_scene() -> Scene {
    sun_sky_with(Material::glass("glass", 1.5))
}

fn sun_sky_with(right_sphere: Material) -> Scene {
    let mut m = Mesh::default();
    quad(
        &mut m,
        Vec3::new(-2.0, 0.0, 2.0),
        Vec3::X * 4.0,
        Vec3::Z * -4.0,
        0,
    );
    sphere(&mut m, Vec3::new(-0.45, 0.4, 0.0), 0.4, 24, 48, 1);
    sphere(&mut m, Vec3::new(0.45, 0.4, 0.0), 0.4, 24, 48, 2);
    // Normal X × Z = −Y: facing the floor.
    quad(
        &mut m,
        Vec3::new(-0.2, 1.6, -0.6),
        Vec3::X * 0.4,
        Vec3::Z * 0.4,
        3,
    );
    let cam = Camera::look_at(
        Vec3::new(0.0, 1.2, 2.6),
        Vec3::new(0.0, 0.3, 0.0),
        Vec3::Y,
        0.7,
    );
    let materials = vec![
        Material::diffuse("floor", Vec3::splat(0.5)),
        Material::diffuse("white", Vec3::splat(0.8)),
        right_sphere,
        Material::emitter("lamp", Vec3::splat(20.0)),
    ];
    let mut s = scene("sun-sky", m, materials, cam, 0.0);
    s.env_map = Some(hdri::sun_sky_env());
    s.settings.width = 64;
    s.settings.height = 64;
    s.settings.max_depth = 5;
    s
}

fn cpu_runs(r: &Renderer, est: Estimator, spp: u32, filter: Option<&str>) -> Vec<Vec<f64>> {
    cpu_block_runs(r, est, spp, filter, 100, RUNS)
}

/// [`assert_blocks_agree`], and the image must not be dark (an unlit render agrees trivially).
fn assert_agree(name: &str, a: &[Vec<f64>], b: &[Vec<f64>]) {
    let t = assert_blocks_agree(name, a, b);
    assert!(t.mean_a > 0.05, "{name}: the image is dark ({})", t.mean_a);
}

#[test]
fn path_bdpt_and_light_tracing_agree_under_sun_and_sky() {
    let r = Renderer::new(sun_sky_scene()).expect("valid");
    let pt = cpu_runs(&r, Estimator::Path, 64, None);
    let bd = cpu_runs(&r, Estimator::Bdpt, 32, None);
    assert_agree("path vs bdpt", &pt, &bd);
    // Light tracing cannot see the environment directly: compare the paths it samples.
    let f = "L(D|G|S)*DE";
    let pt = cpu_runs(&r, Estimator::Path, 64, Some(f));
    let lt = cpu_runs(&r, Estimator::Lt, 64, Some(f));
    assert_agree("path vs lt on L(D|G|S)*DE", &pt, &lt);
}

/// [`RUNS`] independent GPU renders of `scene` (seeds `seed0`…), as block means.
fn gpu_runs(
    g: &mut refract::gpu::GpuRenderer,
    scene: &Scene,
    seed0: u32,
    spp: u32,
) -> Vec<Vec<f64>> {
    (0..RUNS)
        .map(|i| {
            let mut opts = RenderOptions::from_scene(scene);
            opts.seed = seed0 + i;
            g.set_options(opts).expect("options");
            let img = g.render(spp).expect("render");
            assert_eq!(img.dropped, 0, "GPU: the firewall dropped samples");
            block_means(&img.mean, scene.settings.width, scene.settings.height)
        })
        .collect()
}

/// The HDRI-lit glass scene: CPU path tracing against BDPT (which reaches the sun caustic
/// through its light subpaths), and the GPU path tracer against the CPU one.
#[test]
fn glass_under_sun_and_sky_agrees_across_estimators_and_devices() {
    let scene = sun_sky_glass_scene();
    let r = Renderer::new(scene.clone()).expect("valid");
    let pt = cpu_runs(&r, Estimator::Path, 128, None);
    let bd = cpu_runs(&r, Estimator::Bdpt, 64, None);
    assert_agree("glass: path vs bdpt", &pt, &bd);
    let Some(ctx) = gpu_context("env image glass (GPU)") else {
        return;
    };
    let mut g = refract::gpu::GpuRenderer::with_context(
        ctx,
        scene.clone(),
        RenderOptions::from_scene(&scene),
    )
    .expect("GPU renderer");
    let runs = gpu_runs(&mut g, &scene, 2000, 128);
    assert_agree("glass: GPU path vs CPU path", &runs, &pt);
}

/// GPU path tracing and lt+pt against the CPU path tracer on the sun-and-sky scene (the
/// WGSL twin of the image environment, its NEE and its MIS-weighted escape).
#[test]
fn gpu_path_and_lt_pt_agree_with_the_cpu_under_sun_and_sky() {
    let Some(ctx) = gpu_context("env image (GPU)") else {
        return;
    };
    let scene = sun_sky_scene();
    let r = Renderer::new(scene.clone()).expect("valid");
    let cpu = cpu_runs(&r, Estimator::Path, 128, None);
    let mut g = refract::gpu::GpuRenderer::with_context(
        ctx,
        scene.clone(),
        RenderOptions::from_scene(&scene),
    )
    .expect("GPU renderer");
    for est in [Estimator::Path, Estimator::LtPt] {
        g.set_estimator(est).expect("estimator");
        let runs = gpu_runs(&mut g, &scene, 1000, 64);
        assert_agree(&format!("GPU {est} vs CPU path"), &runs, &cpu);
    }
}

/// RGBE keeps 8 mantissa bits of the largest component: |error| < max component / 128.
#[test]
fn shipped_hdris_are_the_generators_output() {
    let assets = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets");
    for (file, gen_map) in [
        ("studio.hdr", hdri::studio(hdri::HDRI_WIDTH)),
        ("sun-sky.hdr", hdri::sun_sky(hdri::HDRI_WIDTH)),
    ] {
        let (shipped, w) = EnvMap::load_file(&assets.join(file)).expect(file);
        assert!(w.is_empty(), "{file}: {w:?}");
        assert_eq!(
            (shipped.width, shipped.height),
            (gen_map.width, gen_map.height)
        );
        for (i, (a, b)) in shipped.texels.iter().zip(&gen_map.texels).enumerate() {
            let tol = b.max_element() / 128.0 + 1e-6;
            assert!(
                (*a - *b).abs().max_element() <= tol,
                "{file}: texel {i} is {a}, the generator says {b}"
            );
        }
        let bytes = std::fs::metadata(assets.join(file)).expect("size").len();
        assert!(bytes < 1 << 20, "{file}: {bytes} bytes");
    }
    // The sun: the brightest texels lie around the documented direction.
    let sky = hdri::sun_sky(hdri::HDRI_WIDTH);
    let (i, _) = sky
        .texels
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.x.total_cmp(&b.1.x))
        .expect("texels");
    let (x, y) = (i as u32 % sky.width, i as u32 / sky.width);
    let d = threejs_dir(
        (x as f32 + 0.5) / sky.width as f32,
        1.0 - (y as f32 + 0.5) / sky.height as f32,
    );
    let sun = hdri::direction(hdri::SUN_ELEVATION_DEG, hdri::SUN_AZIMUTH_DEG);
    assert!(
        d.dot(sun) > 2f32.to_radians().cos(),
        "sun texel at {d}, expected {sun}"
    );
    // The studio: its key soft box is the brightest thing, the floor dark.
    let st = hdri::studio(hdri::HDRI_WIDTH);
    let max = st.texels.iter().map(|t| t.x).fold(0.0, f32::max);
    assert!((max - 6.0).abs() < 1e-4, "studio maximum {max}");
    assert!(st.texels.last().expect("texel").x < 0.05);
}

/// A one-triangle glTF in `dir` with `extras` on its scene.
fn gltf_with(dir: &Path, extras: &str) -> PathBuf {
    let pos: [f32; 9] = [0.0, 0.0, -1.0, 1.0, 0.0, -1.0, 0.0, 1.0, -1.0];
    let bytes: Vec<u8> = pos.iter().flat_map(|v| v.to_le_bytes()).collect();
    std::fs::write(dir.join("tri.bin"), &bytes).expect("write bin");
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0],"extras":{extras}}}],
"nodes":[{{"mesh":0}}],"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],
"accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3",
"min":[0,0,-1],"max":[1,1,-1]}}],
"bufferViews":[{{"buffer":0,"byteLength":36}}],"buffers":[{{"uri":"tri.bin","byteLength":36}}]}}"#
    );
    let p = dir.join("tri.gltf");
    std::fs::write(&p, json).expect("write gltf");
    p
}

fn load_err(p: &Path) -> String {
    match Scene::load(p.to_str().expect("utf-8")) {
        Ok(_) => panic!("{} loaded", p.display()),
        Err(e) => format!("{e:#}"),
    }
}

#[test]
fn gltf_environment_objects_follow_the_file_rules() {
    let d = tmp_dir("gltf");
    let (map, _) = EnvMap::from_texels(8, 4, vec![Vec3::splat(0.5); 32], "grey");
    map.write_hdr(&d.join("sky.hdr")).expect("write");
    let p = gltf_with(
        &d,
        r#"{"environment":{"uri":"sky.hdr","strength":2.5,"rotation":90}}"#,
    );
    let s = Scene::load(p.to_str().expect("utf-8")).expect("loads");
    let e = s.env_map.as_ref().expect("an environment image");
    assert_eq!((e.strength, e.rotation, e.map.width), (2.5, 90.0, 8));
    assert!(
        s.warnings.iter().all(|w| !w.contains("no light")),
        "{:?}",
        s.warnings
    );
    // The old [r, g, b] form stays.
    let p = gltf_with(&d, r#"{"environment":[0.1,0.2,0.3]}"#);
    let s = Scene::load(p.to_str().expect("utf-8")).expect("loads");
    assert_eq!(s.environment, Vec3::new(0.1, 0.2, 0.3));
    assert!(s.env_map.is_none());
    // Outside the folder, missing, a folder, bad numbers, a wrong format.
    let outside = tmp_dir("outside");
    map.write_hdr(&outside.join("o.hdr")).expect("write");
    for (extras, words) in [
        (
            r#"{"environment":{"uri":"../refract-env-X-outside/o.hdr"}}"#
                .replace("X", &std::process::id().to_string()),
            vec!["outside"],
        ),
        (
            r#"{"environment":{"uri":"missing.hdr"}}"#.to_string(),
            vec!["missing.hdr"],
        ),
        (
            r#"{"environment":{"uri":"."}}"#.to_string(),
            vec!["not a regular file"],
        ),
        (
            r#"{"environment":{"uri":"sky.hdr","strength":-1}}"#.to_string(),
            vec!["extras.environment.strength"],
        ),
        (
            r#"{"environment":{"uri":"sky.hdr","rotation":"x"}}"#.to_string(),
            vec!["extras.environment.rotation"],
        ),
        (
            r#"{"environment":{"uri":"tri.bin"}}"#.to_string(),
            vec![".hdr or .exr"],
        ),
        (r#"{"environment":{"strength":1}}"#.to_string(), vec!["uri"]),
        (
            r#"{"environment":{"uri":"http://x/y.hdr"}}"#.to_string(),
            vec!["relative"],
        ),
    ] {
        let p = gltf_with(&d, &extras);
        let e = load_err(&p);
        for w in words {
            assert!(e.contains(w), "{extras}: '{w}' not in '{e}'");
        }
    }
}

#[test]
fn huge_and_broken_images_are_refused_or_repaired() {
    let d = tmp_dir("huge");
    // A header claiming 100000 × 100000 texels: refused before decoding.
    let f = d.join("huge.hdr");
    std::fs::write(
        &f,
        b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 100000 +X 100000\n",
    )
    .expect("write");
    let e = format!("{:#}", EnvMap::load_file(&f).expect_err("refused"));
    assert!(e.contains("pixels") && e.contains("huge.hdr"), "{e}");
    // NaN, infinite and negative texels become 0, with one warning.
    let f = d.join("bad.exr");
    let mut img = image::Rgb32FImage::from_pixel(8, 4, image::Rgb([0.5, 0.5, 0.5]));
    img.put_pixel(1, 1, image::Rgb([f32::NAN, 1.0, 1.0]));
    img.put_pixel(2, 1, image::Rgb([f32::INFINITY, 1.0, 1.0]));
    img.put_pixel(3, 1, image::Rgb([-4.0, 1.0, 1.0]));
    img.save(&f).expect("write exr");
    let (map, w) = EnvMap::load_file(&f).expect("loads");
    assert!(w.len() == 1 && w[0].contains("3 texel(s)"), "{w:?}");
    assert!(
        map.texels
            .iter()
            .all(|t| t.is_finite() && t.min_element() >= 0.0)
    );
    assert_eq!(map.texels[8 + 1], Vec3::new(0.0, 1.0, 1.0));
}

fn refract_cli(args: &[&str]) -> (i32, String) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_refract"))
        .args(args)
        .output()
        .expect("run refract");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn cli_env_flags() {
    let d = tmp_dir("cli");
    let sky = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/sun-sky.hdr");
    let out = d.join("x.exr");
    let (code, err) = refract_cli(&[
        "render",
        "--scene",
        "builtin:furnace",
        "--env",
        sky.to_str().expect("utf-8"),
        "--env-strength",
        "0.5",
        "--env-rotation",
        "45",
        "--spp",
        "1",
        "--width",
        "8",
        "--height",
        "4",
        "--device",
        "cpu",
        "--quiet",
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.exists());
    // The GPU renders environment images too (or, without an adapter, says so).
    let (code, err) = refract_cli(&[
        "render",
        "--scene",
        "builtin:env-spheres",
        "--spp",
        "1",
        "--width",
        "8",
        "--height",
        "4",
        "--device",
        "gpu",
        "--quiet",
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    assert!(code == 0 || err.contains("adapter"), "{err}");
    for (args, word) in [
        (vec!["--env-strength", "2"], "--env-strength"),
        (vec!["--env", "/nonexistent/x.hdr"], "--env"),
        (
            vec![
                "--env",
                sky.to_str().expect("utf-8"),
                "--env-strength",
                "-1",
            ],
            "--env-strength",
        ),
        (
            vec![
                "--env",
                sky.to_str().expect("utf-8"),
                "--env-rotation",
                "NaN",
            ],
            "--env-rotation",
        ),
    ] {
        let mut a = vec![
            "render",
            "--scene",
            "builtin:furnace",
            "--spp",
            "1",
            "--device",
            "cpu",
        ];
        a.extend(args.iter().copied());
        a.extend(["--out", out.to_str().expect("utf-8")]);
        let (code, err) = refract_cli(&a);
        assert_ne!(code, 0, "{args:?} succeeded");
        let line = err.lines().find(|l| l.starts_with("error:")).unwrap_or("");
        assert!(line.contains(word), "{args:?}: '{word}' not in '{err}'");
    }
}
