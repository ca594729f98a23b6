//! Development tool: dump a scene (after loading) as OBJ meshes per material plus a JSON
//! description, so `tools/mitsuba_ref.py` can render the same scene in Mitsuba 3.
//! Usage: cargo run --release --example dump_scene -- builtin:cornell-glass /tmp/dump [env.hdr]
//! (the optional environment image replaces the scene's, as `render --env` does).

use glam::Vec3;
use refract::scene::{MaterialKind, Scene};
use std::fmt::Write as _;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    anyhow::ensure!(
        args.len() == 3 || args.len() == 4,
        "usage: dump_scene <scene> <out-dir> [env.hdr]"
    );
    let mut scene = Scene::load(&args[1])?;
    if let Some(env) = args.get(3) {
        refract::scene::env_map::override_environment(
            &mut scene,
            Some(std::path::Path::new(env)),
            None,
            None,
        )?;
    }
    let dir = std::path::Path::new(&args[2]);
    std::fs::create_dir_all(dir)?;
    let mut mats = Vec::new();
    for (mi, m) in scene.materials.iter().enumerate() {
        let tris: Vec<usize> = (0..scene.mesh.triangle_count())
            .filter(|&t| scene.mesh.tri_material[t] as usize == mi)
            .collect();
        if tris.is_empty() {
            continue;
        }
        let mut obj = String::new();
        for &t in &tris {
            for &v in &scene.mesh.indices[t] {
                let p = scene.mesh.positions[v as usize];
                let n = scene.mesh.normals[v as usize];
                writeln!(obj, "v {} {} {}", p.x, p.y, p.z)?;
                writeln!(obj, "vn {} {} {}", n.x, n.y, n.z)?;
            }
        }
        for (k, _) in tris.iter().enumerate() {
            let b = 3 * k + 1;
            writeln!(
                obj,
                "f {}//{} {}//{} {}//{}",
                b,
                b,
                b + 1,
                b + 1,
                b + 2,
                b + 2
            )?;
        }
        let file = format!("mat{mi}.obj");
        std::fs::write(dir.join(&file), obj)?;
        let kind = match m.kind {
            MaterialKind::Diffuse | MaterialKind::MetalRough => "diffuse",
            MaterialKind::Mirror => "mirror",
            MaterialKind::GlossyMetal => "glossy",
            MaterialKind::Glass => "glass",
            MaterialKind::ThinGlass => "thin",
        };
        mats.push(serde_json::json!({
            "file": file, "kind": kind, "name": m.name,
            "base_color": m.base_color.to_array(), "ior": m.ior, "roughness": m.roughness,
            "ext_ior": ext_ior(&scene, mi),
            "distribution": m.distribution, "emission": m.emission.to_array(),
            "double_sided": m.double_sided, "conductor": m.conductor,
        }));
    }
    // The environment image as linear EXR next to the meshes (Mitsuba's `envmap`).
    let env_map = match &scene.env_map {
        Some(e) => {
            let m = &e.map;
            let px: Vec<f32> = m.texels.iter().flat_map(|t| t.to_array()).collect();
            let img = image::Rgb32FImage::from_raw(m.width, m.height, px)
                .ok_or_else(|| anyhow::anyhow!("environment image size"))?;
            img.save(dir.join("env.exr"))?;
            serde_json::json!({ "file": "env.exr", "strength": e.strength, "rotation": e.rotation })
        }
        None => serde_json::Value::Null,
    };
    let c = scene.camera;
    let json = serde_json::json!({
        "env_map": env_map,
        "materials": mats,
        "camera": { "position": c.position.to_array(), "forward": c.forward().to_array(),
                    "up": c.rotation.y_axis.to_array(), "yfov": c.yfov },
        "environment": scene.environment.to_array(),
        "settings": scene.settings,
    });
    std::fs::write(dir.join("scene.json"), serde_json::to_string_pretty(&json)?)?;
    eprintln!("wrote {}", dir.display());
    Ok(())
}

/// Bounds of the triangles of material `mi`.
fn bounds(scene: &Scene, mi: usize) -> Option<(Vec3, Vec3)> {
    let mut b: Option<(Vec3, Vec3)> = None;
    for t in 0..scene.mesh.triangle_count() {
        if scene.mesh.tri_material[t] as usize != mi {
            continue;
        }
        for &v in &scene.mesh.indices[t] {
            let p = scene.mesh.positions[v as usize];
            let e = b.get_or_insert((p, p));
            *e = (e.0.min(p), e.1.max(p));
        }
    }
    b
}

/// The IOR outside solid material `mi` for renderers that set both IORs per interface
/// (Mitsuba's `ext_ior`): that of the innermost other solid whose bounds contain it, else 1.
/// Right for disjoint nested volumes (glass in water); overlapping ones (false hits) would need
/// their interfaces cut apart and are not handled.
fn ext_ior(scene: &Scene, mi: usize) -> f32 {
    let solid = |m: usize| scene.materials[m].kind == MaterialKind::Glass;
    let Some((lo, hi)) = bounds(scene, mi).filter(|_| solid(mi)) else {
        return 1.0;
    };
    let mut best: Option<(f32, f32)> = None;
    for m in (0..scene.materials.len()).filter(|&m| m != mi && solid(m)) {
        let Some((l, h)) = bounds(scene, m) else {
            continue;
        };
        if l.cmple(lo).all() && hi.cmple(h).all() {
            let vol = (h - l).element_product();
            if best.is_none_or(|(v, _)| vol < v) {
                best = Some((vol, scene.materials[m].ior));
            }
        }
    }
    best.map_or(1.0, |(_, n)| n)
}
