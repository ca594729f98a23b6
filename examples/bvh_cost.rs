//! Traversal cost per ray on the GPU adapter, BVH2 against CWBVH (and obvhs' build presets of
//! the CWBVH with `--presets`): node records visited, child boxes tested and triangles
//! tested, counted by the traversal probe (`gpu::bvh_probe`) on each built-in's camera,
//! bounce and shadow rays (`gpu::probe_rays`), and each tree's build time.
//!
//! `cargo run --release --example bvh_cost [-- --presets] [builtin names…]`

use anyhow::Result;
use obvhs::BvhBuildParams;
use refract::gpu::GpuContext;
use refract::gpu::bvh_probe::run_bvh_probe;
use refract::gpu::layout::BvhProbeRay;
use refract::gpu::probe_rays::workload;
use refract::gpu::upload::{self, GpuBvh};
use refract::scene::Scene;

/// Mean (nodes, boxes, triangles) per ray of `rays` over `bvh`.
fn cost(ctx: &GpuContext, scene: &Scene, bvh: &GpuBvh, rays: &[BvhProbeRay]) -> Result<[f64; 3]> {
    if rays.is_empty() {
        return Ok([0.0; 3]);
    }
    let out = run_bvh_probe(ctx, scene, bvh, rays, ctx.is_software())?;
    let sum = out.iter().fold([0u64; 3], |a, o| {
        [
            a[0] + u64::from(o.nodes),
            a[1] + u64::from(o.boxes),
            a[2] + u64::from(o.tris),
        ]
    });
    Ok(sum.map(|s| s as f64 / rays.len() as f64))
}

fn presets() -> Vec<(&'static str, BvhBuildParams)> {
    vec![
        ("very_fast", BvhBuildParams::very_fast_build()),
        ("fast", BvhBuildParams::fast_build()),
        ("medium", BvhBuildParams::medium_build()),
        (
            "slow (no splits)",
            BvhBuildParams {
                pre_split: false,
                ..BvhBuildParams::slow_build()
            },
        ),
        (
            "medium, 1 per leaf",
            BvhBuildParams {
                max_prims_per_leaf: 1,
                ..BvhBuildParams::medium_build()
            },
        ),
        (
            "medium, 2 per leaf",
            BvhBuildParams {
                max_prims_per_leaf: 2,
                ..BvhBuildParams::medium_build()
            },
        ),
    ]
}

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let all_presets = args.iter().any(|a| a == "--presets");
    let names: Vec<String> = args.into_iter().filter(|a| !a.starts_with("--")).collect();
    let names = if names.is_empty() {
        refract::scene::builtin::NAMES
            .iter()
            .map(|s| s.to_string())
            .collect()
    } else {
        names
    };
    let ctx = GpuContext::new()?;
    // Per tree label: the sum of ln(nodes + triangles per ray) and the scene count.
    let mut logs: Vec<(String, f64, u32)> = Vec::new();
    println!("adapter: {}", ctx.describe());
    println!(
        "scene | tris | tree | nodes | depth | build ms | per ray: camera n+t | bounce n+t | shadow n+t | all: nodes | boxes | tris | nodes+tris"
    );
    for name in &names {
        let scene = Scene::load(&format!("builtin:{name}"))?;
        let w = workload(&scene, 64, 48, 1);
        let mut trees = vec![("BVH2".to_string(), upload::build_bvh(&scene)?)];
        let cw: Vec<_> = if all_presets {
            presets()
        } else {
            vec![("medium, 2 per leaf", upload::cwbvh_params())]
        };
        for (p, params) in cw {
            trees.push((
                format!("CWBVH {p}"),
                upload::build_wide_bvh(&scene, params)?,
            ));
        }
        let mut base = None;
        for (label, bvh) in &trees {
            let kinds = [&w.camera, &w.bounce, &w.shadow].map(|r| cost(&ctx, &scene, bvh, r));
            let [c, b, s] = kinds;
            let (c, b, s) = (c?, b?, s?);
            let n = (w.camera.len() + w.bounce.len() + w.shadow.len()) as f64;
            let weighted = |k: usize| {
                (c[k] * w.camera.len() as f64
                    + b[k] * w.bounce.len() as f64
                    + s[k] * w.shadow.len() as f64)
                    / n
            };
            let all = [weighted(0), weighted(1), weighted(2)];
            let nt = all[0] + all[2];
            match logs.iter_mut().find(|l| &l.0 == label) {
                Some(l) => (l.1, l.2) = (l.1 + nt.ln(), l.2 + 1),
                None => logs.push((label.clone(), nt.ln(), 1)),
            }
            let ratio = match base {
                None => {
                    base = Some(nt);
                    String::new()
                }
                Some(b0) => format!(" ({:.2}× fewer)", b0 / nt),
            };
            println!(
                "{name} | {} | {label} | {} | {} | {:.2} | {:.1} | {:.1} | {:.1} | {:.1} | {:.1} | {:.1} | {:.1}{ratio}",
                scene.mesh.triangle_count(),
                bvh.node_count(),
                bvh.depth,
                bvh.build_time.as_secs_f64() * 1e3,
                c[0] + c[2],
                b[0] + b[2],
                s[0] + s[2],
                all[0],
                all[1],
                all[2],
                nt,
            );
        }
    }
    for (label, sum, n) in &logs {
        println!(
            "geometric mean over {n} scenes, {label}: {:.2} nodes + triangles per ray",
            (sum / f64::from(*n)).exp()
        );
    }
    Ok(())
}
