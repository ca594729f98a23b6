//! Emissive textures (glTF `emissiveTexture`, sRGB, with `KHR_texture_transform`): a
//! checkerboard emitter seen directly shows its texture pixel for pixel; a diffuse floor lit by
//! it renders the same with NEE + MIS (path), BDPT and light tracing, and the same as the
//! checkerboard built from untextured tiles; the GPU agrees with the CPU. Block Z-tests use the
//! helpers of tests/common_scenes.rs (≥ 90% of 8×8 blocks within 3σ, image means within 4σ,
//! fixed seeds).

mod common_scenes;
use common_scenes::*;
use glam::{Vec2, Vec3};
use refract::cpu::Renderer;
use refract::film::Film;
use refract::gltf_io::load::load_slice;
use refract::gpu::GpuRenderer;
use refract::math::color::srgb_to_linear;
use refract::render::{Estimator, RenderOptions};
use refract::scene::{Camera, Features, Material, Mesh, Scene};
use serde_json::{Value, json};

/// The checkerboard's two texels (sRGB bytes): bright and dim, on a 2 × 2 image.
const BRIGHT: u8 = 255;
const DIM: u8 = 128;
/// emissiveFactor × KHR_materials_emissive_strength.
const STRENGTH: f32 = 3.0;
/// KHR_texture_transform scale: the 2 × 2 image repeats twice each way (4 × 4 cells).
const REPEAT: f32 = 2.0;

/// Linear radiance of a cell (the factor × the sRGB-decoded texel).
fn cell_radiance(bright: bool) -> f32 {
    STRENGTH * srgb_to_linear(if bright { BRIGHT } else { DIM } as f32 / 255.0)
}

/// Whether the wall point with glTF uv (before the transform) is on a bright cell.
fn bright_at(uv: Vec2) -> bool {
    let t = uv * REPEAT * 2.0; // texel coordinates of the transformed, 2-texel-wide image
    (t.x.floor() as i64 + t.y.floor() as i64).rem_euclid(2) == 0
}

/// The 2 × 2 checkerboard as a PNG (texel (x, y) bright when x + y is even).
fn checker_png() -> Vec<u8> {
    let mut px = Vec::new();
    for y in 0..2 {
        for x in 0..2 {
            let c = if (x + y) % 2 == 0 { BRIGHT } else { DIM };
            px.extend([c, c, c]);
        }
    }
    let img = image::RgbImage::from_raw(2, 2, px).unwrap();
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).unwrap();
    out.into_inner()
}

/// The wall: x ∈ [−1, 1], y ∈ [0, 2] at z = −1 facing +Z; uv (0, 0) at its top left.
const WALL: [[f32; 3]; 4] = [
    [-1.0, 0.0, -1.0],
    [1.0, 0.0, -1.0],
    [1.0, 2.0, -1.0],
    [-1.0, 2.0, -1.0],
];
const WALL_UV: [[f32; 2]; 4] = [[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]];

/// glTF uv of a point on the wall.
fn wall_uv(p: Vec3) -> Vec2 {
    Vec2::new((p.x + 1.0) / 2.0, 1.0 - p.y / 2.0)
}

/// An emissive wall with the checkerboard texture (nearest filtering) and a Lambert floor
/// (albedo 0.5, x ∈ [−2, 2], z ∈ [−1, 3]), loaded from glTF; no other light.
fn textured_scene() -> Scene {
    let floor: [[f32; 3]; 4] = [
        [-2.0, 0.0, -1.0],
        [-2.0, 0.0, 3.0],
        [2.0, 0.0, 3.0],
        [2.0, 0.0, -1.0],
    ];
    let idx: [u32; 6] = [0, 1, 2, 0, 2, 3];
    let image = checker_png();
    let mut bytes: Vec<u8> = Vec::new();
    let mut views = vec![];
    let mut view = |raw: &[u8], bytes: &mut Vec<u8>| {
        while !bytes.len().is_multiple_of(4) {
            bytes.push(0);
        }
        views.push(json!({"buffer": 0, "byteOffset": bytes.len(), "byteLength": raw.len()}));
        bytes.extend_from_slice(raw);
        views.len() - 1
    };
    let v_wall = view(bytemuck::cast_slice(&WALL), &mut bytes);
    let v_uv = view(bytemuck::cast_slice(&WALL_UV), &mut bytes);
    let v_floor = view(bytemuck::cast_slice(&floor), &mut bytes);
    let v_idx = view(bytemuck::cast_slice(&idx), &mut bytes);
    let v_img = view(&image, &mut bytes);
    let acc = |view: usize, count: usize, ty: &str, ct: u32| -> Value {
        json!({"bufferView": view, "componentType": ct, "count": count, "type": ty})
    };
    let doc = json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_texture_transform", "KHR_materials_emissive_strength"],
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0}, {"mesh": 1}],
        "meshes": [
            {"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 3, "material": 0}]},
            {"primitives": [{"attributes": {"POSITION": 2}, "indices": 3, "material": 1}]}
        ],
        "materials": [
            {"name": "screen", "emissiveFactor": [1.0, 1.0, 1.0],
             "emissiveTexture": {"index": 0, "extensions": {"KHR_texture_transform": {"scale": [REPEAT, REPEAT]}}},
             "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": STRENGTH}}},
            {"name": "floor", "pbrMetallicRoughness": {
                "baseColorFactor": [0.5, 0.5, 0.5, 1.0], "metallicFactor": 0.0, "roughnessFactor": 1.0}}
        ],
        "samplers": [{"magFilter": 9728, "minFilter": 9728}],
        "images": [{"bufferView": v_img, "mimeType": "image/png"}],
        "textures": [{"source": 0, "sampler": 0}],
        "buffers": [{"byteLength": bytes.len(),
            "uri": format!("data:application/octet-stream;base64,{}", base64(&bytes))}],
        "bufferViews": views,
        "accessors": [acc(v_wall, 4, "VEC3", 5126), acc(v_uv, 4, "VEC2", 5126),
            acc(v_floor, 4, "VEC3", 5126), acc(v_idx, 6, "SCALAR", 5125)],
    });
    let mut s = load_slice(doc.to_string().as_bytes(), None, "checker").expect("the scene loads");
    s.environment = Vec3::ZERO;
    s.env_map = None;
    s.camera = floor_camera();
    s.settings.width = 48;
    s.settings.height = 48;
    s.settings.max_depth = 4;
    s
}

/// The same wall as 4 × 4 untextured quads of the cells' radiance, and the same floor.
fn tiled_scene() -> Scene {
    let mut mesh = Mesh::default();
    let n = (2.0 * REPEAT) as usize;
    let side = 2.0 / n as f32;
    for j in 0..n {
        for i in 0..n {
            let p = Vec3::new(-1.0 + i as f32 * side, j as f32 * side, -1.0);
            let centre = p + Vec3::new(0.5 * side, 0.5 * side, 0.0);
            let m = if bright_at(wall_uv(centre)) { 0 } else { 1 };
            quad(&mut mesh, p, Vec3::X * side, Vec3::Y * side, m);
        }
    }
    quad(
        &mut mesh,
        Vec3::new(-2.0, 0.0, -1.0),
        Vec3::Z * 4.0,
        Vec3::X * 4.0,
        2,
    );
    let materials = vec![
        Material::emitter("bright", Vec3::splat(cell_radiance(true))),
        Material::emitter("dim", Vec3::splat(cell_radiance(false))),
        Material::diffuse("floor", Vec3::splat(0.5)),
    ];
    let mut s = scene("tiles", mesh, materials, floor_camera(), 0.0);
    s.settings.width = 48;
    s.settings.height = 48;
    s.settings.max_depth = 4;
    s
}

/// Looking down at the floor in front of the wall (the wall at the top of the image).
fn floor_camera() -> Camera {
    Camera::look_at(
        Vec3::new(0.0, 2.2, 2.6),
        Vec3::new(0.0, 0.4, 0.0),
        Vec3::Y,
        0.9,
    )
}

/// Looking straight at the wall from z = 1 (only the wall in view).
fn wall_camera() -> Camera {
    Camera::look_at(
        Vec3::new(0.0, 1.0, 1.0),
        Vec3::new(0.0, 1.0, -1.0),
        Vec3::Y,
        0.7,
    )
}

fn cpu_image(scene: &Scene, est: Estimator, seed: u32, spp: u32) -> Vec<Vec3> {
    let r = Renderer::new(scene.clone()).expect("valid scene");
    let mut opts = RenderOptions::from_scene(&r.scene);
    opts.seed = seed;
    opts.estimator = est;
    let mut film = Film::new(opts.width, opts.height);
    r.render_pass(&opts, &mut film, 0, spp);
    assert_eq!(film.dropped, 0);
    film.image()
}

/// The cell colour of every pixel whose whole footprint lies inside one cell of the wall
/// (None: straddles a boundary).
fn pure_pixels(cam: &Camera, w: u32, h: u32) -> Vec<Option<bool>> {
    let on_wall = |sx: f32, sy: f32| {
        let d = cam.ray_dir(sx, sy, w as f32 / h as f32);
        let t = (-1.0 - cam.position.z) / d.z;
        bright_at(wall_uv(cam.position + t * d))
    };
    let mut out = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let c = [(0, 0), (1, 0), (0, 1), (1, 1)]
                .map(|(i, j)| on_wall((x + i) as f32 / w as f32, (y + j) as f32 / h as f32));
            out.push(c.iter().all(|&b| b == c[0]).then_some(c[0]));
        }
    }
    out
}

/// Every pixel inside one cell shows that cell's radiance (the sRGB-decoded texel × the
/// strength, exactly: emission seen directly has no noise), bright and dim cells both appear,
/// and their ratio is the texels' linear ratio.
fn assert_shows_checker(img: &[Vec3], cam: &Camera, w: u32, h: u32, who: &str) {
    let (mut n_b, mut n_d) = (0, 0);
    for (i, (p, cell)) in img.iter().zip(pure_pixels(cam, w, h)).enumerate() {
        let Some(bright) = cell else { continue };
        let want = cell_radiance(bright);
        assert!(
            (p.x - want).abs() <= 1e-4 * want && (p.z - want).abs() <= 1e-4 * want,
            "{who}: pixel {i} ({}) is {p}, want {want}",
            if bright { "bright" } else { "dim" }
        );
        if bright { n_b += 1 } else { n_d += 1 }
    }
    assert!(
        n_b >= 50 && n_d >= 50,
        "{who}: {n_b} bright and {n_d} dim pixels"
    );
}

#[test]
fn the_loader_keeps_the_emissive_texture() {
    let s = textured_scene();
    let m = &s.materials[0];
    assert_eq!(m.emission, Vec3::splat(STRENGTH));
    let r = m.emissive_texture.expect("emissive texture");
    // sRGB-decoded like base colour.
    let t = &s.textures[r.texture as usize];
    assert!((t.texels[1].x - srgb_to_linear(DIM as f32 / 255.0)).abs() < 1e-6);
    assert!(!t.linear, "nearest filtering from the sampler");
    assert!(s.features().contains(Features::TEXTURES));
    assert!(
        !s.warnings.iter().any(|w| w.contains("emissive")),
        "{:?}",
        s.warnings
    );
}

#[test]
fn emitter_seen_directly_shows_the_texture() {
    let mut s = textured_scene();
    s.camera = wall_camera();
    let (w, h) = (s.settings.width, s.settings.height);
    let img = cpu_image(&s, Estimator::Path, 1, 4);
    assert_shows_checker(&img, &s.camera, w, h, "CPU path");
    write_png(&img, w, h, "direct", 1.0 / STRENGTH);
}

/// A look at the image (`REFRACT_TEST_PNG=dir`): linear × `scale`, sRGB-encoded.
fn write_png(img: &[Vec3], w: u32, h: u32, name: &str, scale: f32) {
    let Some(dir) = std::env::var_os("REFRACT_TEST_PNG") else {
        return;
    };
    let enc = |x: f32| {
        (refract::math::color::linear_to_srgb((x * scale).clamp(0.0, 1.0)) * 255.0).round() as u8
    };
    let px: Vec<u8> = img
        .iter()
        .flat_map(|p| [enc(p.x), enc(p.y), enc(p.z)])
        .collect();
    let out = std::path::Path::new(&dir).join(format!("emissive_texture_{name}.png"));
    image::RgbImage::from_raw(w, h, px)
        .unwrap()
        .save(out)
        .unwrap();
}

/// The floor under the textured wall: NEE + MIS against BDPT, light tracing and the tiled wall.
#[test]
fn lit_floor_agrees_across_estimators_and_with_tiles() {
    let textured = Renderer::new(textured_scene()).unwrap();
    let tiled = Renderer::new(tiled_scene()).unwrap();
    let (spp, runs) = (32, 8);
    let path = cpu_block_runs(&textured, Estimator::Path, spp, None, 100, runs);
    let bdpt = cpu_block_runs(&textured, Estimator::Bdpt, spp, None, 200, runs);
    let lt = cpu_block_runs(&textured, Estimator::Lt, 4 * spp, None, 300, runs);
    let tiles = cpu_block_runs(&tiled, Estimator::Path, spp, None, 400, runs);
    let (w, h) = (
        textured.scene.settings.width,
        textured.scene.settings.height,
    );
    write_png(
        &cpu_image(&textured.scene, Estimator::Path, 9, 256),
        w,
        h,
        "floor",
        1.0,
    );
    write_png(
        &cpu_image(&tiled.scene, Estimator::Path, 9, 256),
        w,
        h,
        "tiles",
        1.0,
    );
    assert_blocks_agree("path vs bdpt", &path, &bdpt);
    assert_blocks_agree("path vs lt", &path, &lt);
    assert_blocks_agree("textured vs tiles", &path, &tiles);
}

/// The texture changes the picture: the textured floor differs from a wall of the cells'
/// mean radiance (so the agreement above is not a coincidence of means).
#[test]
fn the_texture_is_not_its_mean() {
    let mut s = textured_scene();
    let img = cpu_image(&s, Estimator::Path, 5, 64);
    s.materials[0].emissive_texture = None;
    s.materials[0].emission = Vec3::splat(0.5 * (cell_radiance(true) + cell_radiance(false)));
    let flat = cpu_image(&s, Estimator::Path, 5, 64);
    let (w, h) = (s.settings.width, s.settings.height);
    let a = block_means(&img, w, h);
    let b = block_means(&flat, w, h);
    let worst = a
        .iter()
        .zip(&b)
        .map(|(x, y)| (x - y).abs() / y.max(1e-6))
        .fold(0.0, f64::max);
    assert!(worst > 0.2, "largest block difference {worst}");
}

#[test]
fn gpu_agrees_with_cpu() {
    let Some(ctx) = gpu_context("gpu_agrees_with_cpu") else {
        return;
    };
    // Direct view: exact texels.
    let mut direct = textured_scene();
    direct.camera = wall_camera();
    let (w, h) = (direct.settings.width, direct.settings.height);
    let opts = RenderOptions::from_scene(&direct);
    let mut g = GpuRenderer::with_context(ctx.clone(), direct.clone(), opts).unwrap();
    let img = g.render(4).unwrap();
    assert_shows_checker(&img.mean, &direct.camera, w, h, "GPU path");
    // The lit floor: GPU path and lt+pt against the CPU path tracer.
    let s = textured_scene();
    let (spp, runs) = (32, 8);
    let cpu = cpu_block_runs(
        &Renderer::new(s.clone()).unwrap(),
        Estimator::Path,
        spp,
        None,
        700,
        runs,
    );
    for est in [Estimator::Path, Estimator::LtPt] {
        let mut opts = RenderOptions::from_scene(&s);
        let mut g = GpuRenderer::with_context(ctx.clone(), s.clone(), opts).unwrap();
        g.set_estimator(est).unwrap();
        let gpu: Vec<Vec<f64>> = (0..runs)
            .map(|i| {
                opts.seed = 900 + i;
                g.set_options(opts).unwrap();
                let img = g.render(spp).unwrap();
                assert_eq!(img.dropped, 0);
                block_means(&img.mean, w, h)
            })
            .collect();
        assert_blocks_agree(&format!("GPU {est} vs CPU path"), &gpu, &cpu);
    }
}
