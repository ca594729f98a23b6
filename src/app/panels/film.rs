//! The thin-film controls of the Material group (glTF `KHR_materials_iridescence`): a film on
//! glass or metal, its thickness — the slider of the interference lecture — index and factor.

use crate::scene::{Iridescence, Material, MaterialKind};
use eframe::egui::{self, Slider, SliderClamping};

/// The thickness slider's range (nm): from no film through the first interference orders;
/// beyond ≈ 1.5 µm the orders overlap within every colour band and the colours wash out.
pub const FILM_THICKNESS_RANGE: std::ops::RangeInclusive<f32> = 0.0..=1500.0;

/// The film-index slider's range (water 1.33, oil ≈ 1.47, TiO₂ ≈ 2.4).
pub const FILM_IOR_RANGE: std::ops::RangeInclusive<f32> = 1.0..=2.5;

/// The kinds a film lies on (`bsdf::Iridescent::over`).
pub fn takes_a_film(kind: MaterialKind) -> bool {
    matches!(
        kind,
        MaterialKind::Glass
            | MaterialKind::ThinGlass
            | MaterialKind::Mirror
            | MaterialKind::GlossyMetal
    )
}

/// The film checkbox and, with a film, its sliders; edits `m` in place with checked values
/// (only what the user changed is written back).
pub fn film_controls(ui: &mut egui::Ui, m: &mut Material) {
    if !takes_a_film(m.kind) {
        return;
    }
    let mut on = m.iridescence.is_some();
    if ui
        .checkbox(&mut on, "Thin film (iridescence)")
        .on_hover_text(
            "A transparent film a few hundred nm thick: light reflected at its top and at its \
             bottom interferes, so some wavelengths add up and others cancel — soap bubbles, \
             oil on water, anodised titanium.",
        )
        .changed()
    {
        m.iridescence = on.then(Iridescence::default);
    }
    if let Some(film) = &mut m.iridescence {
        thickness_slider(ui, film);
        film_sliders(ui, film);
    }
}

/// The thickness (the maximum; with a thickness texture the range keeps its width).
fn thickness_slider(ui: &mut egui::Ui, film: &mut Iridescence) {
    let mut d = film.thickness_max;
    let r = ui
        .add(
            Slider::new(&mut d, FILM_THICKNESS_RANGE)
                .text("Film thickness (nm)")
                .clamping(SliderClamping::Edits),
        )
        .on_hover_text(
            "The round trip through the film is 2·n·d·cos θ longer: wavelengths fitting a whole \
             number of times into it are reflected strongly, those with half a wavelength over \
             cancel. Thin films look blue-purple, thicker ones cycle through the orders.",
        );
    if r.changed() && d.is_finite() && d >= 0.0 {
        if film.thickness_texture.is_some() {
            film.thickness_min = (film.thickness_min + d - film.thickness_max).max(0.0);
        }
        film.thickness_max = d;
    }
}

/// The film's index and the factor blending it in.
fn film_sliders(ui: &mut egui::Ui, film: &mut Iridescence) {
    let mut n = film.ior;
    let r = ui
        .add(
            Slider::new(&mut n, FILM_IOR_RANGE)
                .text("Film IOR")
                .clamping(SliderClamping::Edits)
                .max_decimals(3),
        )
        .on_hover_text(
            "The film's index n: the optical path 2·n·d·cos θ and the reflectance of its two \
             faces. Equal to the outside's (1) the film vanishes.",
        );
    if r.changed() && n.is_finite() && n >= 1.0 {
        film.ior = n;
    }
    let mut f = film.factor;
    let r = ui
        .add(Slider::new(&mut f, 0.0..=1.0).text("Film factor"))
        .on_hover_text("How much of the surface the film covers (glTF iridescenceFactor).");
    if r.changed() && (0.0..=1.0).contains(&f) {
        film.factor = f;
    }
}
