//! Normal maps (glTF `normalTexture`, tangent space): the shading normal the CPU builds
//! equals the analytic n' = normalize(T·x + B·y + N·z), generated (MikkTSpace) tangents equal
//! the TANGENT attribute on a quad, a Lambert plane under a directional light dims by
//! n'·l (CPU and GPU), the GPU image of the mapped quad under an environment and an oblique
//! sun agrees with the CPU's (block Z-test), and broken references are warnings naming the
//! material, never panics.

use glam::Vec3;
use refract::bvh::Hit;
use refract::cpu::Renderer;
use refract::cpu::interaction::surface;
use refract::gltf_io::load::load_slice;
use refract::render::RenderOptions;
use refract::scene::{Camera, Features, PunctualLight, Scene};
use serde_json::{Value, json};

mod common_scenes;

/// The normal texture's one texel: a tilt of 30° towards the tangent (+X), (191, 128, 238).
const TEXEL: [u8; 3] = [191, 128, 238];

fn png(px: [u8; 3]) -> Vec<u8> {
    let img = image::RgbImage::from_raw(1, 1, px.to_vec()).unwrap();
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).unwrap();
    out.into_inner()
}

/// How the test quad describes its normal map.
#[derive(Clone, Copy, PartialEq)]
enum Variant {
    /// TANGENT = (1, 0, 0, 1) given.
    Tangent,
    /// No TANGENT: MikkTSpace generates it.
    Generated,
    /// No normal texture at all.
    Plain,
    /// No TEXCOORD_0 (the normal map cannot be applied).
    NoUv,
    /// normalTexture.index out of range.
    BadIndex,
    /// Plus the textures the renderer ignores (occlusion, transmission, thickness) and an
    /// emissive texture without an emissive factor (it emits nothing).
    Ignored,
}

/// A 2 m quad in the plane y = 0 facing +Y, u along +X, v along +Z, material "bumpy" with
/// the one-texel normal map at `scale`.
fn quad(v: Variant, scale: f32) -> Scene {
    let pos: [[f32; 3]; 4] = [
        [-1.0, 0.0, -1.0],
        [-1.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [1.0, 0.0, -1.0],
    ];
    let nrm = [[0.0f32, 1.0, 0.0]; 4];
    let uv: [[f32; 2]; 4] = [[0.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, 0.0]];
    let tan = [[1.0f32, 0.0, 0.0, 1.0]; 4];
    let idx: [u32; 6] = [0, 1, 2, 0, 2, 3];
    let image = png(TEXEL);
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
    let vp = view(bytemuck::cast_slice(&pos), &mut bytes);
    let vn = view(bytemuck::cast_slice(&nrm), &mut bytes);
    let vt = view(bytemuck::cast_slice(&uv), &mut bytes);
    let vg = view(bytemuck::cast_slice(&tan), &mut bytes);
    let vi = view(bytemuck::cast_slice(&idx), &mut bytes);
    let vimg = view(&image, &mut bytes);
    let acc = |view: usize, count: usize, ty: &str, ct: u32| -> Value {
        json!({"bufferView": view, "componentType": ct, "count": count, "type": ty})
    };
    let mut attributes = json!({"POSITION": 0, "NORMAL": 1});
    if v != Variant::NoUv {
        attributes["TEXCOORD_0"] = json!(2);
    }
    if v == Variant::Tangent {
        attributes["TANGENT"] = json!(3);
    }
    let mut material = json!({"name": "bumpy", "pbrMetallicRoughness": {
        "baseColorFactor": [0.5, 0.5, 0.5, 1.0], "metallicFactor": 0.0, "roughnessFactor": 1.0}});
    if v != Variant::Plain {
        let index = if v == Variant::BadIndex { 5 } else { 0 };
        material["normalTexture"] = json!({"index": index, "scale": scale});
    }
    if v == Variant::Ignored {
        material["occlusionTexture"] = json!({"index": 0});
        material["emissiveTexture"] = json!({"index": 0});
        material["extensions"] = json!({
            "KHR_materials_transmission": {"transmissionFactor": 1.0, "transmissionTexture": {"index": 0}},
            "KHR_materials_volume": {"thicknessFactor": 0.1, "thicknessTexture": {"index": 0}}
        });
    }
    let doc = json!({
        "asset": {"version": "2.0"},
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": attributes, "indices": 4, "material": 0}]}],
        "materials": [material],
        "images": [{"bufferView": vimg, "mimeType": "image/png"}],
        "textures": [{"source": 0}],
        "buffers": [{"byteLength": bytes.len(),
            "uri": format!("data:application/octet-stream;base64,{}", common_scenes::base64(&bytes))}],
        "bufferViews": views,
        "accessors": [acc(vp, 4, "VEC3", 5126), acc(vn, 4, "VEC3", 5126),
            acc(vt, 4, "VEC2", 5126), acc(vg, 4, "VEC4", 5126), acc(vi, 6, "SCALAR", 5125)],
    });
    load_slice(doc.to_string().as_bytes(), None, "quad").expect("the quad loads")
}

/// The analytic shading normal: T = +X, N = +Y, B = w · N × T = −Z, texel → (2c − 1)·(s, s, 1).
fn expected_normal(scale: f32) -> Vec3 {
    let c = Vec3::from(TEXEL.map(|b| b as f32 / 255.0));
    let m = (c * 2.0 - Vec3::ONE) * Vec3::new(scale, scale, 1.0);
    (Vec3::X * m.x + Vec3::NEG_Z * m.y + Vec3::Y * m.z).normalize()
}

fn shading_normal(s: &Scene, tri: u32) -> Vec3 {
    surface(
        s,
        &Hit {
            t: 1.0,
            tri,
            b1: 0.3,
            b2: 0.2,
        },
    )
    .ns
}

#[test]
fn shading_normal_matches_the_analytic_tilt() {
    for scale in [1.0, 0.5] {
        let s = quad(Variant::Tangent, scale);
        let want = expected_normal(scale);
        for tri in 0..2 {
            let got = shading_normal(&s, tri);
            assert!(
                (got - want).length() < 1e-5,
                "scale {scale}: {got} vs {want}"
            );
        }
        // The normal texture is linear: 191/255 exactly, not sRGB-decoded.
        let t = &s.textures[s.materials[0].normal_texture.unwrap().texture as usize];
        assert!((t.texels[0].x - 191.0 / 255.0).abs() < 1e-6);
    }
    // A 30° tilt (to the 8-bit precision of the texel).
    let tilt = expected_normal(1.0).dot(Vec3::Y).acos().to_degrees();
    assert!((tilt - 30.0).abs() < 0.3, "{tilt}°");
    assert!(
        quad(Variant::Tangent, 1.0)
            .features()
            .contains(Features::NORMAL_MAP)
    );
}

#[test]
fn generated_tangents_equal_the_tangent_attribute() {
    let given = quad(Variant::Tangent, 1.0);
    let generated = quad(Variant::Generated, 1.0);
    assert_eq!(
        generated.mesh.tangents.len(),
        generated.mesh.positions.len()
    );
    for t in &generated.mesh.tangents {
        assert!(
            (*t - glam::Vec4::new(1.0, 0.0, 0.0, 1.0)).length() < 1e-5,
            "{t}"
        );
    }
    for tri in 0..2 {
        let (a, b) = (shading_normal(&given, tri), shading_normal(&generated, tri));
        assert!((a - b).length() < 1e-5, "{a} vs {b}");
    }
    // Without a normal map the mesh carries no tangents (no cost).
    let plain = quad(Variant::Plain, 1.0);
    assert!(plain.mesh.tangents.is_empty());
    assert!(!plain.features().contains(Features::NORMAL_MAP));
}

/// The quad seen from above, lit straight down by a directional light.
fn lit(mut s: Scene) -> Scene {
    s.punctual_lights = vec![PunctualLight::Directional {
        direction: -Vec3::Y,
        irradiance: Vec3::splat(2.0),
    }];
    s.environment = Vec3::ZERO;
    s.env_map = None;
    s.camera = Camera::look_at(Vec3::new(0.0, 3.0, 0.0), Vec3::ZERO, Vec3::Z, 0.3);
    s
}

/// Mean luminance of the `lit` quad.
fn lit_mean(s: Scene) -> f64 {
    let r = Renderer::new(lit(s)).expect("valid scene");
    let mut o = RenderOptions::from_scene(&r.scene);
    o.width = 16;
    o.height = 16;
    let img = r.render(&o, 4, None, |_| {}).0.image();
    img.iter().map(|p| p.y as f64).sum::<f64>() / img.len() as f64
}

#[test]
fn lambert_plane_dims_as_the_tilted_cosine() {
    let flat = lit_mean(quad(Variant::Plain, 1.0));
    let bumped = lit_mean(quad(Variant::Tangent, 1.0));
    // L = ρ/π · E · (n'·l) with l = +Y; the flat plane has n·l = 1.
    let want = expected_normal(1.0).dot(Vec3::Y) as f64;
    let expect_flat = 0.5 / std::f64::consts::PI * 2.0;
    assert!(
        (flat - expect_flat).abs() < 1e-4 * expect_flat,
        "{flat} vs {expect_flat}"
    );
    assert!(
        (bumped / flat - want).abs() < 1e-4,
        "ratio {} vs cos(tilt) {want}",
        bumped / flat
    );
}

#[test]
fn broken_normal_maps_are_warnings_naming_the_material() {
    let s = quad(Variant::NoUv, 1.0);
    assert!(
        s.warnings
            .iter()
            .any(|w| w.contains("'bumpy'") && w.contains("TEXCOORD_0")),
        "{:?}",
        s.warnings
    );
    // No frame: the shading normal stays the interpolated one.
    assert!((shading_normal(&s, 0) - Vec3::Y).length() < 1e-6);
    let s = quad(Variant::BadIndex, 1.0);
    assert!(s.materials[0].normal_texture.is_none());
    assert!(
        s.warnings
            .iter()
            .any(|w| w.contains("'bumpy'") && w.contains("texture 5 cannot be used")),
        "{:?}",
        s.warnings
    );
    assert!((shading_normal(&s, 0) - Vec3::Y).length() < 1e-6);
}

#[test]
fn ignored_textures_are_named_warnings() {
    let s = quad(Variant::Ignored, 1.0);
    for needle in [
        "occlusion textures are ignored: a path tracer computes occlusion itself",
        "material 'bumpy': emissiveTexture with emissiveFactor 0 emits nothing",
        // Used now (a per-texel glass mask); its one texel (0.75) is neither 0 nor 1.
        "material 'bumpy': transmissionTexture has texels between 0 and 1",
        "material 'bumpy': KHR_materials_volume.thicknessTexture is ignored",
    ] {
        assert!(
            s.warnings.iter().any(|w| w.contains(needle)),
            "no warning '{needle}' in {:?}",
            s.warnings
        );
    }
    // The plain quad has none of them.
    assert!(
        !quad(Variant::Plain, 1.0)
            .warnings
            .iter()
            .any(|w| w.contains("ignored"))
    );
}

/// Mean luminance of a GPU image of `s` (`spp` samples, seed `seed`).
fn gpu_image(ctx: &refract::gpu::GpuContext, s: &Scene, spp: u32, seed: u32) -> Vec<Vec3> {
    let mut o = RenderOptions::from_scene(s);
    o.seed = seed;
    let mut g = refract::gpu::GpuRenderer::with_context(ctx.clone(), s.clone(), o).unwrap();
    let img = g.render(spp).unwrap();
    assert_eq!(img.dropped, 0);
    img.mean
}

fn mean_luminance(img: &[Vec3]) -> f64 {
    img.iter().map(|p| p.y as f64).sum::<f64>() / img.len() as f64
}

/// The GPU twin of `lambert_plane_dims_as_the_tilted_cosine` (given and generated tangents).
#[test]
fn gpu_lambert_plane_dims_as_the_tilted_cosine() {
    let Some(ctx) = common_scenes::gpu_context("gpu_lambert_plane_dims_as_the_tilted_cosine")
    else {
        return;
    };
    let small = |s: Scene| {
        let mut s = lit(s);
        s.settings.width = 16;
        s.settings.height = 16;
        s
    };
    let bumped = small(quad(Variant::Tangent, 1.0));
    assert!(bumped.features().contains(Features::NORMAL_MAP));
    let flat = mean_luminance(&gpu_image(&ctx, &small(quad(Variant::Plain, 1.0)), 4, 1));
    let want = expected_normal(1.0).dot(Vec3::Y) as f64;
    for (name, s) in [
        ("tangent", bumped),
        ("generated", small(quad(Variant::Generated, 1.0))),
    ] {
        let b = mean_luminance(&gpu_image(&ctx, &s, 4, 1));
        assert!(
            (b / flat - want).abs() < 1e-4,
            "GPU {name}: ratio {} vs cos(tilt) {want}",
            b / flat
        );
    }
}

/// The mapped quad under a uniform environment and an oblique sun (every shading term reads
/// n'): 8 GPU runs against 8 CPU runs, block Z-test.
#[test]
fn gpu_agrees_with_cpu_on_the_mapped_quad() {
    let Some(ctx) = common_scenes::gpu_context("gpu_agrees_with_cpu_on_the_mapped_quad") else {
        return;
    };
    let mut s = quad(Variant::Generated, 0.7);
    s.punctual_lights = vec![PunctualLight::Directional {
        direction: Vec3::new(0.6, -1.0, 0.3).normalize(),
        irradiance: Vec3::splat(2.0),
    }];
    s.environment = Vec3::splat(0.4);
    s.env_map = None;
    // Only the quad in view (background blocks are noise-free and would have to match to
    // the last bit).
    s.camera = Camera::look_at(Vec3::new(0.4, 2.5, 1.5), Vec3::ZERO, Vec3::Y, 0.45);
    s.settings.width = 48;
    s.settings.height = 48;
    let (spp, runs) = (16, 8);
    let r = Renderer::new(s.clone()).unwrap();
    let cpu =
        common_scenes::cpu_block_runs(&r, refract::render::Estimator::Path, spp, None, 10, runs);
    let gpu: Vec<Vec<f64>> = (0..runs)
        .map(|i| common_scenes::block_means(&gpu_image(&ctx, &s, spp, 50 + i), 48, 48))
        .collect();
    common_scenes::assert_blocks_agree("GPU vs CPU, normal-mapped quad", &gpu, &cpu);
    // Without the map the image differs (the test sees the normal map).
    let plain = quad(Variant::Plain, 1.0);
    let mut p = s.clone();
    p.mesh = plain.mesh;
    p.materials = plain.materials;
    let flat = common_scenes::cpu_block_runs(
        &Renderer::new(p).unwrap(),
        refract::render::Estimator::Path,
        spp,
        None,
        30,
        runs,
    );
    let t = common_scenes::block_z_test(&gpu, &flat);
    assert!(
        t.z_image.abs() > 10.0,
        "mapped vs flat: z = {:.2}",
        t.z_image
    );
}
