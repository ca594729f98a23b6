//! What each compiled instance of the camera walk (`cpu::walk_spec`) costs on one scene: the
//! same camera samples through the lean, the textured and the general instance, one thread,
//! the instances alternated round by round; prints ns per sample (the median round) and
//! checks that every instance that fits returns bit-identical radiance.
//!
//! `cargo run --release --example walk_instances -- [builtin:NAME | file.glb] [--texture]`
//! (`--texture`: give every diffuse material a 64×64 checker base-colour texture first, the
//! way most glTF assets come).

use glam::{Affine2, Vec3, Vec4};
use refract::cpu::Renderer;
use refract::cpu::camera_ray::camera_ray;
use refract::cpu::walk_spec::{General, Lean, Spec, WalkSpec};
use refract::math::rng::Sampler;
use refract::render::RenderOptions;
use refract::scene::Scene;
use refract::scene::camera::CameraRays;
use refract::scene::material::{MaterialKind, Texture, TextureRef, Wrap};
use std::time::Instant;

const W: u32 = 64;
const H: u32 = 64;
const SPP: u32 = 8;
const ROUNDS: usize = 7;

fn checker(scene: &mut Scene) {
    let n = 64;
    let texels = (0..n * n)
        .map(|i| {
            let (x, y) = (i % n, i / n);
            let v = if (x / 8 + y / 8) % 2 == 0 { 0.9 } else { 0.4 };
            Vec4::new(v, v, v, 1.0)
        })
        .collect();
    scene.textures.push(Texture {
        width: n as u32,
        height: n as u32,
        texels,
        wrap_s: Wrap::Repeat,
        wrap_t: Wrap::Repeat,
        linear: true,
    });
    let texture = scene.textures.len() as u32 - 1;
    for m in &mut scene.materials {
        if m.kind == MaterialKind::Diffuse {
            m.base_color_texture = Some(TextureRef {
                texture,
                tex_coord: 0,
                transform: Affine2::IDENTITY,
            });
        }
    }
}

/// Every sample through instance `S`: (seconds, radiance bits).
fn run<S: WalkSpec>(r: &Renderer, opts: &RenderOptions) -> (f64, Vec<[u32; 3]>) {
    let integ = r.integrator(opts);
    let cam = &CameraRays::new(&r.scene.camera);
    let mut out = Vec::with_capacity((W * H * SPP) as usize);
    let t = Instant::now();
    for pixel in 0..W * H {
        for s in 0..SPP {
            let mut a = Sampler::new(pixel, s, 7);
            let dir = camera_ray(cam, (pixel % W, pixel / W), (W, H), &mut a);
            let sp = integ.lanes(|| a.next_1d());
            let v: Vec3 = integ.li_spec::<S, (), ()>((cam.position, dir), &mut a, sp, &mut (), &());
            out.push(v.to_array().map(f32::to_bits));
        }
    }
    (t.elapsed().as_secs_f64(), out)
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let name = args
        .iter()
        .find(|a| !a.starts_with("--"))
        .map_or("builtin:cornell-glass", |s| s.as_str());
    let mut scene = Scene::load(name)?;
    if args.iter().any(|a| a == "--texture") {
        checker(&mut scene);
    }
    scene.settings.width = W;
    scene.settings.height = H;
    let r = Renderer::new(scene)?;
    let mut opts = RenderOptions::from_scene(&r.scene);
    opts.max_depth = 64;
    let features = r
        .integrator(&opts)
        .walk_features(&refract::cpu::spectral::Spectral::RGB);
    println!("{name}: {features:?}, {W}x{H}, {SPP} spp, one thread");
    type Textured = Spec<false, false, false, true>;
    let (mut lean, mut tex, mut general) = (vec![], vec![], vec![]);
    let mut images = None;
    for _ in 0..ROUNDS {
        let (tl, il) = run::<Lean>(&r, &opts);
        let (tt, it) = run::<Textured>(&r, &opts);
        let (tg, ig) = run::<General>(&r, &opts);
        lean.push(tl);
        tex.push(tt);
        general.push(tg);
        images = Some((il, it, ig));
    }
    let (il, it, ig) = images.expect("rounds");
    let n = (W * H * SPP) as f64;
    let ns = |v: Vec<f64>| median(v) / n * 1e9;
    let (nl, nt, ng) = (ns(lean), ns(tex), ns(general));
    println!(
        "lean     {nl:8.1} ns/sample  identical to general: {}",
        il == ig
    );
    println!(
        "textured {nt:8.1} ns/sample  identical to general: {}",
        it == ig
    );
    println!("general  {ng:8.1} ns/sample");
    println!(
        "general / textured = {:.3}, general / lean = {:.3}",
        ng / nt,
        ng / nl
    );
    Ok(())
}
