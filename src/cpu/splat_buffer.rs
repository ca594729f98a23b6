//! The light-tracing splats of one BDPT pass (`Renderer::render_pass_bdpt`): every row's
//! camera-side work runs in parallel and a light subpath may land on any pixel, so the splats
//! go to a shared image of f64 sums added atomically (a compare-and-swap loop on the bits),
//! folded into the film once the pass is done.

use crate::film::Film;
use glam::Vec3;
use std::sync::atomic::{AtomicU64, Ordering};

/// A `width × height` RGB image of atomically added f64 sums.
pub struct SplatBuffer {
    width: usize,
    sums: Vec<AtomicU64>,
}

impl SplatBuffer {
    /// All zeros.
    pub fn new(width: u32, height: u32) -> SplatBuffer {
        let n = width as usize * height as usize * 3;
        SplatBuffer {
            width: width as usize,
            sums: (0..n).map(|_| AtomicU64::new(0f64.to_bits())).collect(),
        }
    }

    /// Add `v` to channel slot `i`.
    fn add(&self, i: usize, v: f64) {
        let a = &self.sums[i];
        let mut cur = a.load(Ordering::Relaxed);
        loop {
            let new = (f64::from_bits(cur) + v).to_bits();
            match a.compare_exchange_weak(cur, new, Ordering::Relaxed, Ordering::Relaxed) {
                Ok(_) => break,
                Err(x) => cur = x,
            }
        }
    }

    /// Add the RGB value `v` to pixel (x, y).
    pub fn add_rgb(&self, x: u32, y: u32, v: Vec3) {
        let i = 3 * (y as usize * self.width + x as usize);
        self.add(i, v.x as f64);
        self.add(i + 1, v.y as f64);
        self.add(i + 2, v.z as f64);
    }

    /// Add every pixel's sums to the film's (same size).
    pub fn fold_into(&self, film: &mut Film) {
        for (i, px) in film.sums_mut().iter_mut().enumerate() {
            for (k, c) in px.iter_mut().enumerate() {
                *c += f64::from_bits(self.sums[3 * i + k].load(Ordering::Relaxed));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splats_from_many_threads_all_arrive() {
        let buf = SplatBuffer::new(3, 2);
        std::thread::scope(|s| {
            for _ in 0..4 {
                s.spawn(|| {
                    for _ in 0..1000 {
                        buf.add_rgb(2, 1, Vec3::new(1.0, 0.5, 0.25));
                        buf.add_rgb(0, 0, Vec3::ONE);
                    }
                });
            }
        });
        let mut film = Film::new(3, 2);
        buf.fold_into(&mut film);
        let sums = film.sums_mut();
        assert_eq!(sums[5], [4000.0, 2000.0, 1000.0]);
        assert_eq!(sums[0], [4000.0, 4000.0, 4000.0]);
        assert_eq!(sums[1], [0.0; 3]);
    }
}
