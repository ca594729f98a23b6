//! Event heatmaps (`render --aov tir,refraction,depth`): per pixel, the fraction of camera
//! paths with at least one total internal reflection, the fraction with at least one
//! refraction, and the mean number of surface vertices a path reached (the camera not
//! counted). Events are classified by the path inspector's rule (`inspect::sample_event`):
//! TIR is a reflection at a smooth dielectric chosen with F = 1; a refraction is a
//! transmission through a smooth or thin dielectric (the inspector's `refract`) or through
//! a rough dielectric. Every camera sample counts, also one the film's firewall drops.

use super::inspect::{VertexEvent, sample_event};
use super::interaction::{Interaction, SurfaceHit};
use super::layers::LayerObserver;
use super::observer::PathObserver;
use super::path_state::PathState;
use super::spectral::Spectral;
use crate::bsdf::{BsdfSample, Event, Lobe};
use crate::scene::Scene;
use glam::Vec3;

/// One heatmap.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Aov {
    /// Fraction of paths with ≥ 1 total internal reflection.
    Tir,
    /// Fraction of paths with ≥ 1 refraction.
    Refraction,
    /// Mean surface vertices per path.
    Depth,
}

impl Aov {
    pub const ALL: [Aov; 3] = [Aov::Tir, Aov::Refraction, Aov::Depth];

    /// The name `--aov` takes and the file suffix (`OUT.tir.exr`).
    pub fn name(self) -> &'static str {
        match self {
            Aov::Tir => "tir",
            Aov::Refraction => "refraction",
            Aov::Depth => "depth",
        }
    }

    /// The channel of the event layer that holds it.
    pub fn channel(self) -> usize {
        match self {
            Aov::Tir => 0,
            Aov::Refraction => 1,
            Aov::Depth => 2,
        }
    }

    /// Parse `tir,refraction,depth` (any subset, any order; `all` = all three).
    pub fn parse_list(spec: &str) -> anyhow::Result<Vec<Aov>> {
        let mut out: Vec<Aov> = Vec::new();
        for item in spec.split(',').map(str::trim) {
            let found: Vec<Aov> = match item.to_ascii_lowercase().as_str() {
                "all" => Aov::ALL.to_vec(),
                s => match Aov::ALL.iter().find(|a| a.name() == s) {
                    Some(&a) => vec![a],
                    None => anyhow::bail!(
                        "unknown AOV '{item}' (use tir, refraction, depth or all, \
                         comma-separated)"
                    ),
                },
            };
            for a in found {
                if !out.contains(&a) {
                    out.push(a);
                }
            }
        }
        Ok(out)
    }
}

/// Counts one camera path's events into a single layer: (TIR?, refraction?, vertices).
#[derive(Clone, Copy, Default)]
pub struct EventCounter {
    tir: bool,
    refraction: bool,
    vertices: u32,
}

impl PathObserver for EventCounter {
    fn start(&mut self, _origin: Vec3, _dir: Vec3, _sp: &Spectral) {
        *self = EventCounter::default();
    }

    fn surface(&mut self, _scene: &Scene, _hit: &SurfaceHit, _st: &PathState) {
        self.vertices += 1;
    }

    fn bounce(&mut self, _: &Scene, it: &Interaction, _: &PathState, s: &BsdfSample, _: Vec3) {
        match sample_event(it, s).0 {
            VertexEvent::Tir => self.tir = true,
            VertexEvent::Refract => self.refraction = true,
            VertexEvent::Glossy if s.lobe == Lobe::G && s.event == Event::Transmit => {
                self.refraction = true
            }
            _ => {}
        }
    }
}

impl LayerObserver for EventCounter {
    fn layers(&self) -> usize {
        1
    }

    fn commit(&mut self, _accepted: bool, px: &mut [[f64; 3]]) {
        px[0][0] += self.tir as u32 as f64;
        px[0][1] += self.refraction as u32 as f64;
        px[0][2] += self.vertices as f64;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parse_list() {
        assert_eq!(
            Aov::parse_list("depth, TIR").unwrap(),
            [Aov::Depth, Aov::Tir]
        );
        assert_eq!(Aov::parse_list("all,tir").unwrap(), Aov::ALL);
        let e = Aov::parse_list("tir,bounces").unwrap_err().to_string();
        assert!(e.contains("'bounces'"), "{e}");
    }
}
