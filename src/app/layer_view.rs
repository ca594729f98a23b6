//! The viewer's layer views (CPU backend): the dominant path class of each pixel in false
//! colour, the event heatmaps (`cpu::decompose`, `cpu::aov`), and the degree and angle of
//! polarisation (`cpu::polarized::view`, from the polarised walk's Stokes layers). The backend accumulates
//! the layers only while such a view is on; the views path-trace every path (the estimator
//! and the path filter are set aside while one is shown).

use crate::cpu::aov::EventCounter;
use crate::cpu::decompose::{ClassRouter, Decomposition};
use crate::cpu::layers::LayerFilm;
use glam::Vec3;
use std::sync::LazyLock;

/// What the viewport shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum ViewMode {
    /// The rendered image.
    #[default]
    Beauty,
    /// The path class that brings each pixel the most light, in false colour.
    Classes,
    /// Fraction of paths with a total internal reflection.
    Tir,
    /// Fraction of paths with a refraction.
    Refraction,
    /// Mean surface vertices per path (scaled to the image's maximum).
    Depth,
    /// Degree of polarisation in false colour (the polarised walk, `cpu::polarized::view`).
    Dop,
    /// Angle of polarisation as hue, brightness by degree (the polarised walk).
    Aop,
}

impl ViewMode {
    pub const ALL: [ViewMode; 7] = [
        ViewMode::Beauty,
        ViewMode::Classes,
        ViewMode::Tir,
        ViewMode::Refraction,
        ViewMode::Depth,
        ViewMode::Dop,
        ViewMode::Aop,
    ];

    /// Whether the view comes from the path-class and event layers ([`proto`]).
    pub fn uses_layers(self) -> bool {
        matches!(
            self,
            ViewMode::Classes | ViewMode::Tir | ViewMode::Refraction | ViewMode::Depth
        )
    }

    /// Whether the view comes from the polarised walk's Stokes layers ([`polarized_image`]).
    pub fn is_polarized(self) -> bool {
        matches!(self, ViewMode::Dop | ViewMode::Aop)
    }

    /// The selector's label.
    pub fn label(self) -> &'static str {
        match self {
            ViewMode::Beauty => "beauty",
            ViewMode::Classes => "path classes",
            ViewMode::Tir => "TIR heat",
            ViewMode::Refraction => "refraction heat",
            ViewMode::Depth => "depth heat",
            ViewMode::Dop => "polarisation degree",
            ViewMode::Aop => "polarisation angle",
        }
    }

    pub fn hover(self) -> &'static str {
        match self {
            ViewMode::Beauty => "The rendered image.",
            ViewMode::Classes => {
                "Each pixel in the colour of the path class that brings it the most light \
                 (first match wins; legend below). CPU only; path-traces every path."
            }
            ViewMode::Tir => {
                "Fraction of the pixel's paths with at least one total internal reflection \
                 (black 0, white 1). CPU only; path-traces every path."
            }
            ViewMode::Refraction => {
                "Fraction of the pixel's paths with at least one refraction (black 0, white \
                 1). CPU only; path-traces every path."
            }
            ViewMode::Depth => {
                "Mean number of surfaces a path from this pixel meets, scaled to the image's \
                 largest (white). CPU only; path-traces every path."
            }
            ViewMode::Dop => {
                "Degree of polarisation of the light reaching each pixel, before any filter: \
                 black unpolarised, through purple and orange to pale yellow fully polarised \
                 (legend below). CPU only; traces polarised light (Stokes vectors)."
            }
            ViewMode::Aop => {
                "Angle of polarisation from the image's horizontal as hue (red 0°, green 60°, \
                 blue 120°, red again at 180°), brighter the more polarised (legend below). \
                 CPU only; traces polarised light (Stokes vectors)."
            }
        }
    }
}

/// The classes of the "path classes" view, in priority order (docs/viewer.md's example).
pub const VIEW_CLASSES: &str = "LE,LDE,LS+DE,LDS+E";

/// The view's decomposition, parsed once.
pub static DECOMPOSITION: LazyLock<Decomposition> = LazyLock::new(|| {
    Decomposition::parse(VIEW_CLASSES).unwrap_or_else(|e| panic!("built-in classes: {e}"))
});

/// False colours of the classes in [`VIEW_CLASSES`] order, then `rest` (linear RGB).
pub const CLASS_COLOURS: [[f32; 3]; 5] = [
    [1.0, 1.0, 1.0],  // LE: white
    [0.1, 0.35, 1.0], // LDE: blue
    [1.0, 0.75, 0.0], // LS+DE: gold (caustics)
    [0.0, 0.9, 0.3],  // LDS+E: green
    [0.8, 0.1, 0.6],  // rest: magenta
];

/// The observer the backend walks with while a layer view is on: the classes' layers, then
/// the event layer.
pub fn proto() -> (Option<ClassRouter<'static>>, Option<EventCounter>) {
    (Some(DECOMPOSITION.router()), Some(EventCounter::default()))
}

/// Layers [`proto`] writes per pixel.
pub fn layer_count() -> usize {
    DECOMPOSITION.classes.len() + 2
}

/// Heat ramp for t in [0, 1]: black → red → yellow → white.
fn heat(t: f32) -> Vec3 {
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    Vec3::new(
        (3.0 * t).min(1.0),
        (3.0 * t - 1.0).clamp(0.0, 1.0),
        (3.0 * t - 2.0).clamp(0.0, 1.0),
    )
}

/// The image a polarised `mode` shows from the Stokes layers (`cpu::polarized`) over `spp`
/// samples (None: not a polarised view).
pub fn polarized_image(mode: ViewMode, stokes: &LayerFilm, spp: u64) -> Option<Vec<Vec3>> {
    use crate::cpu::polarized::view::{aop_image, dop_image, stokes_pixels};
    if !mode.is_polarized() {
        return None;
    }
    let px = stokes_pixels(stokes, spp);
    Some(if mode == ViewMode::Dop {
        dop_image(&px)
    } else {
        aop_image(&px)
    })
}

/// The image `mode` shows from the layers of [`proto`] over `spp` samples (None: a view that
/// does not use them).
pub fn view_image(mode: ViewMode, layers: &LayerFilm, spp: u64) -> Option<Vec<Vec3>> {
    let event_layer = layer_count() - 1;
    let events = |ch| layers.channel_image(event_layer, ch, spp);
    Some(match mode {
        ViewMode::Beauty | ViewMode::Dop | ViewMode::Aop => return None,
        ViewMode::Tir => events(0).iter().map(|v| heat(v.x)).collect(),
        ViewMode::Refraction => events(1).iter().map(|v| heat(v.x)).collect(),
        ViewMode::Depth => {
            let d = events(2);
            let max = d.iter().map(|v| v.x).fold(0.0, f32::max).max(1e-6);
            d.iter().map(|v| heat(v.x / max)).collect()
        }
        ViewMode::Classes => {
            let k = event_layer;
            let classes: Vec<Vec<Vec3>> = (0..k).map(|l| layers.image(l, spp)).collect();
            (0..classes[0].len())
                .map(|i| {
                    let lum = |l: usize| classes[l][i].dot(Vec3::new(0.2126, 0.7152, 0.0722));
                    let best = (0..k).max_by(|&a, &b| lum(a).total_cmp(&lum(b)));
                    match best {
                        Some(b) if lum(b) > 0.0 => Vec3::from(CLASS_COLOURS[b]),
                        _ => Vec3::ZERO,
                    }
                })
                .collect()
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colours_cover_the_classes_and_heat_is_monotone() {
        assert_eq!(CLASS_COLOURS.len(), DECOMPOSITION.layer_names().len());
        assert_eq!(heat(0.0), Vec3::ZERO);
        assert_eq!(heat(1.0), Vec3::ONE);
        assert!(heat(0.5).element_sum() > heat(0.25).element_sum());
    }
}
