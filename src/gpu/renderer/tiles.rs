//! Images larger than one storage binding (issue 15, part 4): the accumulation film holds a
//! tile of whole rows, and [`GpuRenderer::render_tiled`] renders the image tile after tile —
//! each tile's running mean uploaded from the CPU copy, the same counter-based samples added
//! (bands of rows bounded in time as usual), and read back. Every pixel gets exactly the
//! samples, in the same order, that a whole-image film would give it, so the image equals the
//! untiled one to float rounding of nothing at all: the fold is per pixel. Path tracing,
//! sppm and lt+pt (issue 37): sppm's photons live in world space, so each tile traces every
//! iteration's photons again (the same counter-based photon paths: the tile gathers exactly
//! the photons the whole image would) and gathers them for its rows only; lt+pt's light
//! subpaths splat anywhere in the image, so each tile traces every light subpath again (a
//! whole-image submission before the tile's camera pass) and its splat film, which holds the
//! tile's rows only, keeps the splats that land on them. The photon pass or the light pass
//! costs once per tile.

use super::{GpuImage, GpuRenderer};
use anyhow::Result;
use std::time::{Duration, Instant};

impl GpuRenderer {
    /// Rows the film holds (the image's height unless tiled).
    pub fn film_rows(&self) -> u32 {
        let row = u64::from(self.opts.width) * 16;
        (self.buffers.accum.size() / row.max(1)) as u32
    }

    /// Whether an image larger than one binding may render in tiles: for headless renders
    /// (`with_context`), not for the viewer's progressive renderer
    /// (`with_context_in_background`, `with_context_untiled`), whose display reads the whole
    /// film and which falls back to the CPU instead.
    pub(super) fn tiles_allowed(&self) -> bool {
        self.tiles
    }

    /// Start or stop tiling after the film was (re)allocated: a CPU copy of the whole image
    /// when the film holds fewer rows than it.
    pub(super) fn fit_tiles(&mut self) {
        let (w, h) = (self.opts.width as usize, self.opts.height);
        self.film_y0 = 0;
        self.tiled = (self.film_rows() < h).then(|| vec![[0.0; 4]; w * h as usize]);
    }

    /// The viewer's progressive dispatches need the whole image in the film: record an error
    /// (the viewer falls back to the CPU renderer) and report true when tiled.
    pub(super) fn refuse_tiled(&self) -> bool {
        if self.tiled.is_some() {
            super::super::context::record(
                &self.ctx.errors,
                format!(
                    "image {}x{} is larger than one GPU binding: it renders in tiles, headless only",
                    self.opts.width, self.opts.height
                ),
            );
        }
        self.tiled.is_some()
    }

    /// [`GpuRenderer::render_with`] for a tiled image: every tile gets the same samples per
    /// pixel; with a budget, the first tile decides how many (it may spend its share of the
    /// budget, the image's tiles times that share in all).
    pub(super) fn render_tiled(
        &mut self,
        spp: u32,
        budget: Option<Duration>,
        mut progress: impl FnMut(u64),
    ) -> Result<GpuImage> {
        self.pipelines.compile(self.spec)?;
        let start = Instant::now();
        let h = self.opts.height;
        let rows = self.film_rows();
        let tiles = h.div_ceil(rows);
        let share = budget.map(|b| b / tiles);
        let mut spp = spp;
        for y0 in (0..h).step_by(rows as usize) {
            let tile_rows = rows.min(h - y0);
            self.load_tile(y0, tile_rows);
            let done = self.render_tile(spp, share.filter(|_| y0 == 0), y0, tile_rows)?;
            spp = done;
            self.store_tile(y0, tile_rows)?;
        }
        self.film_y0 = 0;
        self.spp += u64::from(spp);
        self.elapsed += start.elapsed();
        progress(self.spp);
        self.image()
    }

    /// Up to `spp` samples per pixel for image rows `y0 .. y0 + rows` (whose running mean the
    /// film holds), stopping once `budget` is spent; returns the samples added.
    fn render_tile(
        &mut self,
        spp: u32,
        budget: Option<Duration>,
        y0: u32,
        rows: u32,
    ) -> Result<u32> {
        let start = Instant::now();
        let w = self.opts.width;
        let mut done = 0u32;
        while done < spp && !budget.is_some_and(|b| done > 0 && start.elapsed() >= b) {
            // sppm: one band (its photons are traced once per submission), at most the
            // iterations its store holds; lt+pt: one band (each submission's light pass
            // splats on every row of the tile, and one camera pass must take them all).
            let whole = self.spec.sppm || self.spec.light_tracing;
            let (mut k, band) = self.submissions.plan(w, rows, spp - done, whole);
            if self.spec.sppm {
                k = k.min(self.buffers.photon_store.iterations.max(1));
            }
            for by in (y0..y0 + rows).step_by(band as usize) {
                let n = band.min(y0 + rows - by);
                let submitted = Instant::now();
                let first = self.spp + u64::from(done);
                let Some(index) = self.submit_pass(first, k, by, n) else {
                    return Err(self
                        .ctx
                        .check_errors()
                        .err()
                        .unwrap_or_else(|| anyhow::anyhow!("the GPU kernels are not compiled")));
                };
                self.ctx.wait_for(index)?;
                self.submissions.observe(
                    submitted.elapsed(),
                    u64::from(w) * u64::from(n) * u64::from(k),
                );
            }
            done += k;
        }
        Ok(done)
    }

    /// Put rows `y0 .. y0 + rows` of the CPU copy into the film.
    fn load_tile(&mut self, y0: u32, rows: u32) {
        let w = self.opts.width as usize;
        let Some(mean) = &self.tiled else { return };
        let tile = &mean[y0 as usize * w..(y0 + rows) as usize * w];
        self.ctx
            .queue
            .write_buffer(&self.buffers.accum, 0, bytemuck::cast_slice(tile));
        self.clear_pending = false;
        self.film_y0 = y0;
    }

    /// Read the film back into rows `y0 .. y0 + rows` of the CPU copy.
    fn store_tile(&mut self, y0: u32, rows: u32) -> Result<()> {
        let w = self.opts.width as usize;
        let bytes = self
            .ctx
            .read_buffer(&self.buffers.accum, (w * rows as usize * 16) as u64)?;
        let px: Vec<[f32; 4]> = bytemuck::pod_collect_to_vec(&bytes);
        if let Some(mean) = &mut self.tiled {
            mean[y0 as usize * w..(y0 + rows) as usize * w].copy_from_slice(&px);
        }
        Ok(())
    }
}
