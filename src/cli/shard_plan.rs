//! `render --shard I/N`: which samples this shard renders, and the flags it needs and
//! refuses — decided from the arguments before the job (`job`) is prepared; the shard's file
//! is written by `shard`.

use super::RenderArgs;
use anyhow::{Result, bail};
use refract::render::shard_exr;
use refract::render::{Device, Shard};
use std::ops::Range;

/// The slice of the samples a shard renders.
#[derive(Clone, Debug)]
pub(crate) struct ShardPlan {
    pub(crate) shard: Shard,
    /// Samples per pixel of the whole render (`--spp`).
    pub(crate) spp_total: u32,
    /// This shard's sample indices.
    pub(crate) samples: Range<u32>,
}

/// `--shard` with the flags it needs and refuses, checked before any work: `--spp` given
/// (a time budget cannot split into disjoint slices), at most `--spp` shards, an `.exr`
/// output, and none of the choices that differ between machines or files (`--measure-auto`
/// times trials; `--decompose`/`--aov` write more files).
pub(crate) fn plan(args: &RenderArgs) -> Result<Option<ShardPlan>> {
    let Some(shard) = args.shard else {
        return Ok(None);
    };
    if args.time_budget.is_some() {
        bail!("--shard {shard} needs a fixed --spp, not --time-budget (shards split the samples)");
    }
    let Some(spp_total) = args.spp else {
        bail!("--shard {shard} needs --spp (the whole render's samples per pixel, split N ways)");
    };
    if shard.count > spp_total {
        bail!(
            "--shard {shard}: {} shards of --spp {spp_total} leave some without samples \
             (at most {spp_total} shards)",
            shard.count
        );
    }
    shard_exr::require_exr(
        &args.out,
        "--out",
        "with --shard (the header records the samples)",
    )?;
    if args.measure_auto {
        bail!("--shard and --measure-auto: the estimator timed on each machine may differ");
    }
    if args.decompose.is_some() || args.aov.is_some() {
        bail!("--shard does not split --decompose or --aov renders");
    }
    if args.device == Device::Auto {
        eprintln!(
            "note: --shard with --device auto: the CPU and the GPU draw different samples, so \
             give every shard the same --device cpu or gpu (merge refuses a mix)"
        );
    }
    Ok(Some(ShardPlan {
        shard,
        spp_total,
        samples: shard.samples(spp_total),
    }))
}
