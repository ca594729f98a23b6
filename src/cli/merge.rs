//! `refract merge a.exr b.exr … --out full.exr`: the shards of `render --shard I/N` into one
//! image (`render::shard_merge`), written atomically with the union's record ("merged k/N"); an
//! incomplete set still merges, with a warning naming the missing shards.

use anyhow::{Context, Result};
use refract::film;
use refract::render::{shard_exr, shard_merge};
use std::path::PathBuf;

#[derive(clap::Args, Clone)]
pub(crate) struct MergeArgs {
    /// The shards' EXRs (`render --shard I/N --out …`), in any order.
    #[arg(required = true, num_args = 1..)]
    files: Vec<PathBuf>,
    /// The merged image (.exr).
    #[arg(long)]
    out: PathBuf,
}

/// Check the output, merge the files, warn about missing shards, write the image.
pub(crate) fn run(args: &MergeArgs) -> Result<()> {
    shard_exr::require_exr(&args.out, "--out", "(the merge is linear float RGB)")?;
    film::probe_writable(&args.out).context("--out")?;
    let m = shard_merge::merge(&args.files)?;
    let r = &m.record;
    if !m.missing.is_empty() {
        let list: Vec<String> = m
            .missing
            .iter()
            .map(|i| format!("{i}/{}", r.shard.count()))
            .collect();
        let (noun, verb) = if list.len() == 1 {
            ("shard", "is")
        } else {
            ("shards", "are")
        };
        eprintln!(
            "warning: {noun} {} {verb} missing: the image has {} of the {} spp",
            list.join(", "),
            r.spp,
            r.spp_total
        );
    }
    shard_exr::write_exr(&args.out, (m.width, m.height), &m.pixels, r)?;
    eprintln!(
        "wrote {} — {} from {} files, samples {} ({} spp), seed {}, estimator {}",
        args.out.display(),
        r.shard,
        args.files.len(),
        shard_exr::ranges_text(&r.samples),
        r.spp,
        r.seed,
        r.estimator
    );
    Ok(())
}
