//! `refract merge`: the shards of a render split across machines (`render --shard I/N`) back
//! into one image. Files that do not belong together are refused, each error naming the file:
//! another scene, seed, estimator, size or settings, sample ranges that overlap (a shard given
//! twice), or no `refract.*` attributes at all. The image is the mean weighted by spp,
//! Σ sppᵢ·imgᵢ / Σ sppᵢ in f64: each shard's image is its samples' sum over its spp, so this
//! is the sum of all the samples over their number, the one-machine estimate.

use super::shard_exr::{RecordedExr, RenderRecord, ShardOf, ranges_text, read_exr};
use crate::render::Shard;
use anyhow::{Result, bail};
use glam::Vec3;
use std::ops::Range;
use std::path::{Path, PathBuf};

/// The merged image, its record, and the shards (1-based) none of the files held.
pub struct Merged {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<Vec3>,
    pub record: RenderRecord,
    pub missing: Vec<u32>,
}

/// One input: its path, pixels and (checked) record.
struct Input {
    path: PathBuf,
    exr: RecordedExr,
    record: RenderRecord,
    settings: serde_json::Value,
}

/// Merge the shard EXRs `paths` (at least one).
pub fn merge(paths: &[PathBuf]) -> Result<Merged> {
    let inputs = paths
        .iter()
        .map(|p| read_input(p))
        .collect::<Result<Vec<_>>>()?;
    let Some(first) = inputs.first() else {
        bail!("no files to merge");
    };
    for b in &inputs[1..] {
        check_same(first, b)?;
    }
    let samples = check_disjoint(&inputs)?;
    let pixels = weighted_mean(&inputs);
    let count = first.record.shard.count();
    let total = first.record.spp_total;
    let missing = missing_shards(&samples, total, count);
    let record = RenderRecord {
        spp: inputs.iter().map(|i| i.record.spp).sum(),
        shard: ShardOf::Merged {
            have: count - missing.len() as u32,
            count,
        },
        samples,
        ..first.record.clone()
    };
    Ok(Merged {
        width: first.exr.width,
        height: first.exr.height,
        pixels,
        record,
        missing,
    })
}

/// Read `path` and check its record on its own: present, its ranges sorted, disjoint and
/// within the render's samples, its spp their count.
fn read_input(path: &Path) -> Result<Input> {
    let name = path.display();
    let mut exr = read_exr(path)?;
    let Some(record) = exr.record.take() else {
        bail!(
            "'{name}' has no refract.* attributes: it is not a shard written by \
             `refract render --shard`"
        );
    };
    let r = &record;
    let in_order = r.samples.windows(2).all(|w| w[0].end <= w[1].start);
    let inside = r.samples.last().is_some_and(|l| l.end <= r.spp_total);
    let count: u64 = r.samples.iter().map(|s| u64::from(s.end - s.start)).sum();
    if !in_order || !inside || count != r.spp {
        bail!(
            "'{name}': refract.samples {} does not fit refract.spp {} of refract.spp_total {}",
            ranges_text(&r.samples),
            r.spp,
            r.spp_total
        );
    }
    let settings = serde_json::from_str(&r.settings)
        .map_err(|e| anyhow::anyhow!("'{name}': refract.settings is not JSON ({e})"))?;
    let pixels = exr.width as usize * exr.height as usize;
    anyhow::ensure!(exr.pixels.len() == pixels, "'{name}': pixel count mismatch");
    Ok(Input {
        path: path.to_owned(),
        exr,
        record,
        settings,
    })
}

/// `b` is of the same render as `a`: size, seed, estimator, split, settings, then the scene
/// (its hash covers the settings too, so a settings difference is named as such first).
fn check_same(a: &Input, b: &Input) -> Result<()> {
    let differs = |what: &str, va: String, vb: String| -> Result<()> {
        if va != vb {
            bail!(
                "'{}' does not belong with '{}': {what} {vb} ≠ {va}",
                b.path.display(),
                a.path.display()
            );
        }
        Ok(())
    };
    let size = |i: &Input| format!("{}x{}", i.exr.width, i.exr.height);
    let (ra, rb) = (&a.record, &b.record);
    differs("image size", size(a), size(b))?;
    differs("seed", ra.seed.to_string(), rb.seed.to_string())?;
    differs("estimator", ra.estimator.clone(), rb.estimator.clone())?;
    differs(
        "total spp",
        ra.spp_total.to_string(),
        rb.spp_total.to_string(),
    )?;
    differs(
        "shard count",
        ra.shard.count().to_string(),
        rb.shard.count().to_string(),
    )?;
    if let Some((key, va, vb)) = first_difference(&a.settings, &b.settings) {
        differs(&format!("settings.{key}"), va, vb)?;
    }
    differs(
        "scene hash",
        format!("{:016x}", ra.scene_hash),
        format!("{:016x}", rb.scene_hash),
    )
}

/// The first key (in sorted order) whose value differs between two settings objects, and
/// the two values as JSON (`null` where one lacks it); a non-object compares whole.
fn first_difference(
    a: &serde_json::Value,
    b: &serde_json::Value,
) -> Option<(String, String, String)> {
    let (Some(oa), Some(ob)) = (a.as_object(), b.as_object()) else {
        return (a != b).then(|| (String::new(), a.to_string(), b.to_string()));
    };
    let mut keys: Vec<&String> = oa.keys().chain(ob.keys()).collect();
    keys.sort();
    keys.dedup();
    let null = serde_json::Value::Null;
    keys.into_iter().find_map(|k| {
        let (va, vb) = (oa.get(k).unwrap_or(&null), ob.get(k).unwrap_or(&null));
        (va != vb).then(|| (k.clone(), va.to_string(), vb.to_string()))
    })
}

/// No sample index in two files (a shard given twice, or shards of two splits); returns the
/// union of the files' ranges, sorted and joined where they touch.
fn check_disjoint(inputs: &[Input]) -> Result<Vec<Range<u32>>> {
    let mut all: Vec<(Range<u32>, usize)> = inputs
        .iter()
        .enumerate()
        .flat_map(|(k, i)| i.record.samples.iter().map(move |r| (r.clone(), k)))
        .collect();
    all.sort_by_key(|(r, _)| (r.start, r.end));
    for w in all.windows(2) {
        let ((ra, ka), (rb, kb)) = (&w[0], &w[1]);
        if rb.start < ra.end {
            let (pa, pb) = (&inputs[*ka].path, &inputs[*kb].path);
            let what = if ra == rb && inputs[*ka].record.shard == inputs[*kb].record.shard {
                "the same shard twice"
            } else {
                "overlapping sample ranges"
            };
            bail!(
                "'{}' (samples {}..{}) and '{}' (samples {}..{}): {what}",
                pb.display(),
                rb.start,
                rb.end,
                pa.display(),
                ra.start,
                ra.end
            );
        }
    }
    let mut union: Vec<Range<u32>> = Vec::new();
    for (r, _) in all {
        match union.last_mut() {
            Some(last) if last.end == r.start => last.end = r.end,
            _ => union.push(r),
        }
    }
    Ok(union)
}

/// Σ sppᵢ·imgᵢ / Σ sppᵢ per pixel, in f64.
fn weighted_mean(inputs: &[Input]) -> Vec<Vec3> {
    let n = inputs[0].exr.pixels.len();
    let mut sum = vec![[0.0f64; 3]; n];
    let mut weight = 0.0f64;
    for i in inputs {
        let s = i.record.spp as f64;
        weight += s;
        for (acc, p) in sum.iter_mut().zip(&i.exr.pixels) {
            for (a, v) in acc.iter_mut().zip(p.to_array()) {
                *a += s * f64::from(v);
            }
        }
    }
    sum.iter()
        .map(|a| {
            let m = a.map(|v| (v / weight) as f32);
            Vec3::from_array(m)
        })
        .collect()
}

/// The shards of a `spp`-sample render in `count` shards whose samples `have` lacks.
fn missing_shards(have: &[Range<u32>], spp: u32, count: u32) -> Vec<u32> {
    (1..=count)
        .filter(|&index| {
            let want = Shard { index, count }.samples(spp);
            !want.is_empty()
                && !have
                    .iter()
                    .any(|r| r.start <= want.start && want.end <= r.end)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::missing_shards;

    #[test]
    fn missing_shards_are_those_not_covered() {
        // 16 spp in 4 shards: 0..4, 4..8, 8..12, 12..16.
        assert_eq!(missing_shards(&[0..8, 12..16], 16, 4), vec![3]);
        let (all, second) = (0..16, 4..8);
        assert_eq!(missing_shards(&[all], 16, 4), Vec::<u32>::new());
        assert_eq!(missing_shards(&[second], 16, 4), vec![1, 3, 4]);
    }
}
