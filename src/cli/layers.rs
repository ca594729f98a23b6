//! `render --decompose` and `render --aov`: the extra images one CPU path-tracing render can
//! write next to `--out` (`cpu::decompose`, `cpu::aov`). `--out dir/out.exr` (or `.png`)
//! gives `dir/out.<layer>.exr`, linear float RGB whatever the beauty's format.

use anyhow::{Result, bail};
use refract::cpu::aov::{Aov, EventCounter};
use refract::cpu::decompose::{ClassRouter, Decomposition};
use refract::cpu::layers::{LayerFilm, LayerObserver};
use refract::film::{self, ToneMap};
use refract::render::{Device, Estimator};
use std::path::{Path, PathBuf};

/// What the layers of one render are.
pub struct Layers {
    pub decomposition: Option<Decomposition>,
    pub aovs: Vec<Aov>,
}

/// The observer of a layered render: the class router's layers first, then the one event
/// layer.
pub type LayerProto<'a> = (Option<ClassRouter<'a>>, Option<EventCounter>);

impl Layers {
    /// `--decompose` and `--aov` parsed (None when neither is given). Errors name the flag.
    pub fn parse(decompose: Option<&str>, aov: Option<&str>) -> Result<Option<Layers>> {
        if decompose.is_none() && aov.is_none() {
            return Ok(None);
        }
        let decomposition = decompose
            .map(|d| Decomposition::parse(d).map_err(|e| anyhow::anyhow!("--decompose: {e}")))
            .transpose()?;
        let aovs = aov
            .map(|a| Aov::parse_list(a).map_err(|e| anyhow::anyhow!("--aov: {e}")))
            .transpose()?
            .unwrap_or_default();
        Ok(Some(Layers {
            decomposition,
            aovs,
        }))
    }

    /// The flags in use, for error lines (`--decompose`, `--aov` or both).
    fn flags(&self) -> &'static str {
        match (self.decomposition.is_some(), self.aovs.is_empty()) {
            (true, false) => "--decompose and --aov",
            (true, true) => "--decompose",
            _ => "--aov",
        }
    }

    /// The render these layers need: the CPU path tracer over all paths. `--device auto`
    /// renders on the CPU, `--estimator auto` (or a sidecar's) path-traces; anything else
    /// that was asked for explicitly is an error.
    pub fn check(&self, device: Device, choice: Estimator, paths: &str) -> Result<()> {
        let flags = self.flags();
        let (is, needs) = if flags.contains(" and ") {
            ("are", "need")
        } else {
            ("is", "needs")
        };
        if device == Device::Gpu {
            bail!("{flags} {is} CPU only: use --device cpu (or auto, which renders on the CPU)");
        }
        if !matches!(choice, Estimator::Auto | Estimator::Path) {
            bail!(
                "{flags} {needs} --estimator path (or auto, which path-traces then), not \
                 {choice}: the layers come from the path tracer's camera walk"
            );
        }
        if !paths.trim().is_empty() {
            bail!("{flags} renders every path: drop --paths (or a sidecar's render.paths)");
        }
        Ok(())
    }

    /// The beauty film and the layers fit in `--max-film-gib` (`budget` bytes).
    pub fn check_memory(&self, (width, height): (u32, u32), budget: u64) -> Result<()> {
        let layers = self.proto().layers();
        let bytes =
            film::Film::bytes_for(width, height) + LayerFilm::bytes_for(width, height, layers);
        let gib = |b: u64| b as f64 / (1u64 << 30) as f64;
        if bytes > budget {
            bail!(
                "{}: a {width}x{height} image with {layers} layers needs {:.1} GiB of films, \
                 more than the {:.1} GiB budget (raise it with --max-film-gib)",
                self.flags(),
                gib(bytes),
                gib(budget)
            );
        }
        Ok(())
    }

    /// The observer prototype.
    pub fn proto(&self) -> LayerProto<'_> {
        let router = self.decomposition.as_ref().map(Decomposition::router);
        let events = (!self.aovs.is_empty()).then(EventCounter::default);
        (router, events)
    }

    /// Every file the layers write for `--out out`, with its (layer, channel) in the layer
    /// film (channel None: the layer's RGB).
    pub fn outputs(&self, out: &Path) -> Vec<(PathBuf, usize, Option<usize>)> {
        let mut v = Vec::new();
        let mut layer = 0;
        if let Some(d) = &self.decomposition {
            for name in d.layer_names() {
                v.push((layer_path(out, &name), layer, None));
                layer += 1;
            }
        }
        for a in &self.aovs {
            v.push((layer_path(out, a.name()), layer, Some(a.channel())));
        }
        v
    }

    /// Refuse before rendering when a layer file could not be written.
    pub fn check_outputs(&self, out: &Path) -> Result<()> {
        for (p, _, _) in self.outputs(out) {
            film::check_output_path(&p).map_err(|e| anyhow::anyhow!("{}: {e:#}", self.flags()))?;
        }
        Ok(())
    }

    /// Write every layer file (means over `spp`), one line each.
    pub fn save(&self, out: &Path, layers: &LayerFilm, spp: u64) -> Result<()> {
        for (path, layer, channel) in self.outputs(out) {
            let img = match channel {
                Some(c) => layers.channel_image(layer, c, spp),
                None => layers.image(layer, spp),
            };
            film::save_image(
                &path,
                layers.width,
                layers.height,
                &img,
                0.0,
                ToneMap::Clamp,
            )?;
            eprintln!("wrote {}", path.display());
        }
        Ok(())
    }
}

/// `dir/stem.<name>.exr` for `--out dir/stem.ext`.
pub fn layer_path(out: &Path, name: &str) -> PathBuf {
    let stem = out
        .file_stem()
        .map_or_else(|| "out".into(), |s| s.to_string_lossy().into_owned());
    out.with_file_name(format!("{stem}.{name}.exr"))
}
