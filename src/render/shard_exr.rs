//! EXR files that say which samples of which render they hold (issue 37, renders split across
//! machines): linear float RGB, plus text attributes `refract.*` in the header — this file's
//! spp, the whole render's spp, the seed, the shard "I/N" (or "merged k/N"), the sample index
//! ranges, a hash of the scene, the estimator and the render settings as JSON. `refract merge`
//! reads them back to refuse files that do not belong together (`render::shard_merge`).
//!
//! Values are UTF-8 text (OpenEXR's text attributes are byte strings).

use crate::render::Shard;
use anyhow::{Context, Result, bail};
use glam::Vec3;
use std::collections::HashMap;
use std::ops::Range;
use std::path::Path;

/// Prefix of every attribute this module writes.
const PREFIX: &str = "refract.";

/// Which shards a file holds: one, or a merge of several.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShardOf {
    /// Shard I of N, as rendered.
    One(Shard),
    /// `have` of `count` shards merged.
    Merged { have: u32, count: u32 },
}

impl ShardOf {
    /// N: the shards the render was split into.
    pub fn count(&self) -> u32 {
        match *self {
            ShardOf::One(s) => s.count,
            ShardOf::Merged { count, .. } => count,
        }
    }

    fn parse(s: &str) -> Result<ShardOf, String> {
        match s.strip_prefix("merged ") {
            Some(rest) => {
                let one = Shard::parse(rest)?;
                Ok(ShardOf::Merged {
                    have: one.index,
                    count: one.count,
                })
            }
            None => Shard::parse(s).map(ShardOf::One),
        }
    }
}

impl std::fmt::Display for ShardOf {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ShardOf::One(s) => write!(f, "{s}"),
            ShardOf::Merged { have, count } => write!(f, "merged {have}/{count}"),
        }
    }
}

/// What a shard's (or a merge's) EXR says about the samples it holds.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderRecord {
    /// Samples per pixel in this file.
    pub spp: u64,
    /// Samples per pixel of the whole (one-machine) render.
    pub spp_total: u32,
    pub seed: u32,
    pub shard: ShardOf,
    /// Sample indices in this file: sorted, disjoint ranges within `0 .. spp_total`.
    pub samples: Vec<Range<u32>>,
    /// FNV-1a 64 of the scene's bytes and settings (`render::shard` callers decide what).
    pub scene_hash: u64,
    /// The scene as given on the command line (informational: paths differ between machines).
    pub scene: String,
    /// The estimator that rendered it (never `auto`).
    pub estimator: String,
    /// The render settings as a JSON object (size, depths, device, …).
    pub settings: String,
}

impl RenderRecord {
    /// The header attributes, name without the prefix → value.
    fn fields(&self) -> Vec<(&'static str, String)> {
        vec![
            ("spp", self.spp.to_string()),
            ("spp_total", self.spp_total.to_string()),
            ("seed", self.seed.to_string()),
            ("shard", self.shard.to_string()),
            ("samples", ranges_text(&self.samples)),
            ("scene_hash", format!("fnv1a64:{:016x}", self.scene_hash)),
            ("scene", self.scene.clone()),
            ("estimator", self.estimator.clone()),
            ("settings", self.settings.clone()),
        ]
    }

    /// The record in `attrs` (name → text); None when there is no `refract.` attribute at all,
    /// an error naming the attribute when one is missing or malformed.
    fn from_attributes(attrs: &HashMap<String, String>) -> Result<Option<RenderRecord>> {
        if !attrs.keys().any(|k| k.starts_with(PREFIX)) {
            return Ok(None);
        }
        let get = |k: &str| {
            attrs
                .get(&format!("{PREFIX}{k}"))
                .map(String::as_str)
                .with_context(|| format!("attribute {PREFIX}{k} is missing"))
        };
        let num = |k: &str| -> Result<u64> {
            let v = get(k)?;
            v.trim()
                .parse::<u64>()
                .map_err(|_| anyhow::anyhow!("attribute {PREFIX}{k} '{v}' is not a whole number"))
        };
        let small = |k: &str| -> Result<u32> {
            u32::try_from(num(k)?).with_context(|| format!("attribute {PREFIX}{k} is too large"))
        };
        let shard = ShardOf::parse(get("shard")?)
            .map_err(|e| anyhow::anyhow!("attribute {PREFIX}shard: {e}"))?;
        let samples = parse_ranges(get("samples")?)
            .map_err(|e| anyhow::anyhow!("attribute {PREFIX}samples: {e}"))?;
        let hash = get("scene_hash")?;
        let scene_hash = hash
            .strip_prefix("fnv1a64:")
            .and_then(|h| u64::from_str_radix(h, 16).ok())
            .with_context(|| {
                format!("attribute {PREFIX}scene_hash '{hash}' is not fnv1a64:<16 hex digits>")
            })?;
        Ok(Some(RenderRecord {
            spp: num("spp")?,
            spp_total: small("spp_total")?,
            seed: small("seed")?,
            shard,
            samples,
            scene_hash,
            scene: get("scene")?.to_owned(),
            estimator: get("estimator")?.to_owned(),
            settings: get("settings")?.to_owned(),
        }))
    }
}

/// "0..4,8..12".
pub fn ranges_text(ranges: &[Range<u32>]) -> String {
    let parts: Vec<String> = ranges
        .iter()
        .map(|r| format!("{}..{}", r.start, r.end))
        .collect();
    parts.join(",")
}

/// Ranges "a..b,c..d" (each a < b).
fn parse_ranges(s: &str) -> Result<Vec<Range<u32>>, String> {
    s.split(',')
        .map(|part| {
            let (a, b) = part
                .trim()
                .split_once("..")
                .ok_or_else(|| format!("'{part}' is not a range a..b"))?;
            let n = |t: &str| {
                t.trim()
                    .parse::<u32>()
                    .map_err(|_| format!("'{part}': '{t}' is not a sample index"))
            };
            let r = n(a)?..n(b)?;
            if r.is_empty() {
                return Err(format!("'{part}' is empty"));
            }
            Ok(r)
        })
        .collect()
}

/// Write `img` (`width` × `height`, linear RGB, row-major) to `path` as float EXR with
/// `record` in its header, whole or not at all (`film::atomic`).
pub fn write_exr(
    path: &Path,
    (width, height): (u32, u32),
    img: &[Vec3],
    record: &RenderRecord,
) -> Result<()> {
    use exr::prelude::*;
    let (w, h) = (width as usize, height as usize);
    anyhow::ensure!(
        img.len() == w * h,
        "image buffer size does not match its dimensions"
    );
    if let Some(dir) = path.parent()
        && !dir.as_os_str().is_empty()
    {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("cannot create folder '{}'", dir.display()))?;
    }
    let mut attrs = LayerAttributes {
        software_name: Some(Text::from("refract")),
        ..Default::default()
    };
    for (k, v) in record.fields() {
        let name = Text::from_slice_unchecked(format!("{PREFIX}{k}").as_bytes());
        let value = Text::from_slice_unchecked(v.as_bytes());
        attrs.other.insert(name, AttributeValue::Text(value));
    }
    let pixels = SpecificChannels::rgb(|p: Vec2<usize>| {
        let v = img[p.y() * w + p.x()];
        (v.x, v.y, v.z)
    });
    let image = Image::from_layer(Layer::new((w, h), attrs, Encoding::FAST_LOSSLESS, pixels));
    crate::film::write_atomically(path, |tmp| {
        image
            .write()
            .to_file(tmp)
            .with_context(|| format!("cannot write '{}'", path.display()))
    })
}

/// An EXR read back: its size, linear RGB pixels and the render record, if it has one.
pub struct RecordedExr {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<Vec3>,
    pub record: Option<RenderRecord>,
}

/// Read the first RGB layer of the EXR `path` and its `refract.*` attributes; errors name
/// the file.
pub fn read_exr(path: &Path) -> Result<RecordedExr> {
    use exr::prelude::*;
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .rgb_channels(
            |size, _| (size.width(), vec![Vec3::ZERO; size.area()]),
            |(w, px): &mut (usize, Vec<Vec3>), p, (r, g, b): (f32, f32, f32)| {
                px[p.y() * *w + p.x()] = Vec3::new(r, g, b);
            },
        )
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .with_context(|| format!("cannot read '{}' as an RGB EXR", path.display()))?;
    let layer = image.layer_data;
    let mut attrs = HashMap::new();
    for other in [&image.attributes.other, &layer.attributes.other] {
        for (k, v) in other {
            if let AttributeValue::Text(t) = v {
                let key = String::from_utf8_lossy(k.as_slice()).into_owned();
                attrs.insert(key, String::from_utf8_lossy(t.as_slice()).into_owned());
            }
        }
    }
    let record =
        RenderRecord::from_attributes(&attrs).with_context(|| format!("'{}'", path.display()))?;
    let size = (layer.size.width(), layer.size.height());
    Ok(RecordedExr {
        width: u32::try_from(size.0).context("EXR too wide")?,
        height: u32::try_from(size.1).context("EXR too tall")?,
        pixels: layer.channel_data.pixels.1,
        record,
    })
}

/// Refuse an output that is not `.exr` (`flag` names where it came from).
pub fn require_exr(path: &Path, flag: &str, why: &str) -> Result<()> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if ext.as_deref() != Some("exr") {
        bail!(
            "{flag} '{}' must be an .exr file {why}",
            crate::render::settings::abbreviate(&path.display().to_string())
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record() -> RenderRecord {
        RenderRecord {
            spp: 5,
            spp_total: 16,
            seed: 3,
            shard: ShardOf::One(Shard::parse("2/3").expect("shard")),
            samples: [5, 7, 10].windows(2).map(|w| w[0]..w[1]).collect(),
            scene_hash: 0x0123_4567_89ab_cdef,
            scene: "builtin:cornell-glass — ü".into(),
            estimator: "bdpt".into(),
            settings: r#"{"width":3,"height":2}"#.into(),
        }
    }

    #[test]
    fn an_exr_keeps_its_pixels_and_record() {
        let dir = std::env::temp_dir().join(format!("refract-exr-record-{}", std::process::id()));
        let path = dir.join("a.exr");
        let img: Vec<Vec3> = (0..6).map(|i| Vec3::new(i as f32, 0.5, 1e-3)).collect();
        write_exr(&path, (3, 2), &img, &record()).expect("write");
        let back = read_exr(&path).expect("read");
        assert_eq!((back.width, back.height), (3, 2));
        assert_eq!(back.pixels, img);
        assert_eq!(back.record, Some(record()));
        let _ = std::fs::remove_dir_all(dir);
    }

    #[test]
    fn ranges_round_trip_and_bad_ones_are_refused() {
        let r = vec![0..4, 8..12];
        assert_eq!(parse_ranges(&ranges_text(&r)), Ok(r));
        for bad in ["", "4..4", "a..b", "1-2", "0..4,"] {
            assert!(parse_ranges(bad).is_err(), "{bad} accepted");
        }
        assert_eq!(
            ShardOf::parse("merged 3/4"),
            Ok(ShardOf::Merged { have: 3, count: 4 })
        );
    }
}
