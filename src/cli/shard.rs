//! `render --shard I/N` (issue 37): one of N disjoint slices of the render's samples
//! (`render::shard`), written as an EXR whose header records which samples of which render it
//! holds (`render::shard_exr`), for `refract merge` (`cli::merge`).

use super::RenderArgs;
use super::job::Job;
use anyhow::{Context, Result};
use glam::Vec3;
use refract::math::fnv::Fnv1a64;
use refract::render::Estimator;
use refract::render::shard_exr::{self, RenderRecord, ShardOf};
use refract::scene::Scene;

/// Write the rendered image: the shard's EXR with its record when `job` is a shard, else
/// `film::save_image` as usual. `estimator` and `device` are what rendered it.
pub(crate) fn save(
    args: &RenderArgs,
    scene: &Scene,
    job: &Job,
    (w, h): (u32, u32),
    img: &[Vec3],
    (estimator, device): (Estimator, &str),
) -> Result<()> {
    let Some(plan) = &job.shard else {
        return refract::film::save_image(&args.out, w, h, img, job.exposure, job.tone);
    };
    let settings = settings_json(args, scene, job, device);
    let record = RenderRecord {
        spp: u64::from(plan.samples.end - plan.samples.start),
        spp_total: plan.spp_total,
        seed: job.seed,
        shard: ShardOf::One(plan.shard),
        samples: vec![plan.samples.clone()],
        scene_hash: scene_hash(args, scene, job, &settings)?,
        scene: job.spec.clone(),
        estimator: estimator.to_string(),
        settings,
    };
    shard_exr::write_exr(&args.out, (w, h), img, &record)?;
    eprintln!(
        "shard {}: samples {}..{} of {} spp (merge the shards with `refract merge`)",
        plan.shard, plan.samples.start, plan.samples.end, plan.spp_total
    );
    Ok(())
}

/// What the merge compares besides scene, seed and estimator: everything else that changes
/// the samples (size, depths, path filter, light line, environment flags, device, version).
fn settings_json(args: &RenderArgs, scene: &Scene, job: &Job, device: &str) -> String {
    let s = &scene.settings;
    serde_json::json!({
        "version": env!("CARGO_PKG_VERSION"),
        "device": device,
        "width": s.width,
        "height": s.height,
        "max_depth": s.max_depth,
        "rr_depth": s.rr_depth,
        "paths": job.filter.source(),
        "light_line_nm": s.light_line_nm,
        "env_strength": args.env.env_strength,
        "env_rotation": args.env.env_rotation,
    })
    .to_string()
}

/// FNV-1a 64 (stable across builds, unlike std's hasher) of the scene as given — a file's
/// bytes or a built-in's name —, the settings sidecar's and environment image's bytes, the
/// loaded triangles and `settings`.
fn scene_hash(args: &RenderArgs, scene: &Scene, job: &Job, settings: &str) -> Result<u64> {
    let read = |p: &std::path::Path, flag: &str| {
        std::fs::read(p).with_context(|| format!("{flag} '{}': cannot read it", p.display()))
    };
    let mut h = Fnv1a64::default();
    h.write_field(b"refract scene hash 1");
    if job.spec.starts_with("builtin:") {
        h.write_field(job.spec.as_bytes());
    } else {
        h.write_field(&read(std::path::Path::new(&job.spec), "scene")?);
    }
    for (file, flag) in [(&args.settings, "--settings"), (&args.env.env, "--env")] {
        match file {
            Some(p) => h.write_field(&read(p, flag)?),
            None => h.write_field(b""),
        }
    }
    let m = &scene.mesh;
    h.write(&(m.positions.len() as u64).to_le_bytes());
    for p in &m.positions {
        for v in p.to_array() {
            h.write(&v.to_le_bytes());
        }
    }
    for (t, mat) in m.indices.iter().zip(&m.tri_material) {
        for v in [t[0], t[1], t[2], *mat] {
            h.write(&v.to_le_bytes());
        }
    }
    h.write_field(settings.as_bytes());
    Ok(h.finish())
}
