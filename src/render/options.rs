//! Per-render options of both renderers.

use super::Estimator;
use crate::paths::{DfaTable, PathFilter};
use crate::scene::{MAX_IMAGE_SIDE, Scene};

/// Per-render options (overrides of the scene's settings are applied by the caller).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderOptions {
    pub width: u32,
    pub height: u32,
    pub max_depth: u32,
    pub rr_depth: u32,
    pub seed: u32,
    /// Index of the first sample `render` draws (0; shard I of N of a split render starts at
    /// its slice, `render::shard`): samples `first_sample ..` are those a one-machine render
    /// draws at these indices.
    pub first_sample: u32,
    /// Heckbert path filter (eye→light table); None = all paths.
    pub filter: Option<DfaTable>,
    /// The same filter in light→eye order (bidirectional estimators).
    pub filter_forward: Option<DfaTable>,
    pub estimator: Estimator,
    /// GPU: samples per pixel per dispatch (None: about 2²⁰ samples per dispatch, 1..=16
    /// spp). The CPU renderer sizes its passes the same way and ignores it.
    pub batch_spp: Option<u32>,
    /// The most bytes the film may take (`render --max-film-gib`; default
    /// [`crate::film::MAX_FILM_BYTES`]).
    pub max_film_bytes: u64,
}

impl RenderOptions {
    /// The scene's size and depth limits, seed 0, no filter, path tracing.
    pub fn from_scene(scene: &Scene) -> RenderOptions {
        let s = scene.settings;
        RenderOptions {
            width: s.width,
            height: s.height,
            max_depth: s.max_depth,
            rr_depth: s.rr_depth,
            seed: 0,
            first_sample: 0,
            filter: None,
            filter_forward: None,
            estimator: Estimator::Path,
            batch_spp: None,
            max_film_bytes: crate::film::MAX_FILM_BYTES,
        }
    }

    /// Set both directions of a Heckbert filter (None or an accept-all filter = no filter).
    pub fn set_filter(&mut self, f: Option<&PathFilter>) {
        match f {
            Some(f) if !f.is_accept_all() => {
                self.filter = Some(*f.reversed());
                self.filter_forward = Some(*f.forward());
            }
            _ => {
                self.filter = None;
                self.filter_forward = None;
            }
        }
    }

    /// Pixels of the image.
    pub fn pixels(&self) -> u64 {
        self.width as u64 * self.height as u64
    }

    /// Samples per pixel of one pass: about 2²⁰ samples, 1..=16 spp (unless `batch_spp`).
    pub fn pass_spp(&self) -> u32 {
        self.batch_spp
            .unwrap_or(((1u64 << 20) / self.pixels().max(1)).clamp(1, 16) as u32)
            .max(1)
    }

    /// Size and depth limits a renderer can honour.
    pub fn check(&self) -> anyhow::Result<()> {
        anyhow::ensure!(
            (1..=MAX_IMAGE_SIDE).contains(&self.width)
                && (1..=MAX_IMAGE_SIDE).contains(&self.height),
            "image size {}x{} is out of range (1..={MAX_IMAGE_SIDE} per side)",
            self.width,
            self.height
        );
        let bytes = crate::film::Film::bytes_for(self.width, self.height);
        anyhow::ensure!(
            bytes <= self.max_film_bytes,
            "a {}x{} image needs a {:.1} GiB film, more than the {:.1} GiB budget (raise it \
             with --max-film-gib)",
            self.width,
            self.height,
            bytes as f64 / (1u64 << 30) as f64,
            self.max_film_bytes as f64 / (1u64 << 30) as f64
        );
        anyhow::ensure!(self.max_depth >= 1, "max_depth must be at least 1");
        Ok(())
    }
}
