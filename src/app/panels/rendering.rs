//! Rendering group: depth, Heckbert path filter, the path inspector's toggle, exposure, tone map, pause, spp target,
//! render scale, screenshot and reset.

use crate::app::denoise_view::FilterDevice;
use crate::app::{Edit, ViewerApp};
use crate::film::ToneMap;
use crate::render::Estimator;
use crate::render::settings::RenderEdit;
use crate::scene::Scene;
use eframe::egui::{self, Color32, Slider, SliderClamping};

/// Path filter presets (read light → eye) with what they show.
pub const PATH_PRESETS: &[(&str, &str, &str)] = &[
    ("all", "", "Every path: the full image."),
    (
        "LDE",
        "LDE",
        "Direct diffuse lighting only: light hits a diffuse surface, then the eye.",
    ),
    (
        "L(D|S)*E",
        "L(D|S)*E",
        "Any mix of diffuse and specular bounces (no glossy ones).",
    ),
    (
        "LS+DE",
        "LS+DE",
        "Caustics: light focused by mirrors or glass onto a diffuse surface.",
    ),
    (
        "LDS+E",
        "LDS+E",
        "Diffusely lit surfaces seen through or in specular objects (reflections, refractions).",
    ),
    (
        "L(S|G)+E",
        "L(S|G)+E",
        "The light seen only through specular or glossy surfaces.",
    ),
];

pub fn show(app: &mut ViewerApp, ui: &mut egui::Ui) {
    let mut render = app.settings.render.clone();
    let auto = (render.estimator == Estimator::Auto).then(|| app.auto_choice());
    depth_and_estimator(ui, &mut render, &app.scene, auto);
    path_filter(app, ui);
    ui.separator();
    layer_views(app, ui);
    ui.separator();
    super::inspect::controls(app, ui);
    ui.separator();
    display(app, ui);
    ui.separator();
    accumulation(app, ui, &mut render);
    if render != app.settings.render {
        app.push(Edit::Render(render));
    }
    ui.separator();
    ui.horizontal(|ui| {
        if ui
            .button("Screenshot")
            .on_hover_text("Save PNG (as shown), linear EXR and a JSON of every setting to screenshots/ (F12, Ctrl+S).")
            .clicked()
        {
            let _ = app.save_screenshot();
        }
        if ui
            .button("Reset to defaults")
            .on_hover_text("Forget every edit and setting: the scene as loaded, default render options.")
            .clicked()
        {
            app.push(Edit::ResetAll);
        }
    });
}

/// Max depth and the estimator (edits `r`); `auto` is what auto picks, when it is selected.
fn depth_and_estimator(
    ui: &mut egui::Ui,
    r: &mut RenderEdit,
    scene: &Scene,
    auto: Option<(Estimator, &'static str)>,
) {
    let scene_depth = scene.settings.max_depth;
    {
        let mut depth = r.max_depth.unwrap_or(scene_depth).clamp(1, 64);
        if ui
            .add(Slider::new(&mut depth, 1..=64).text("Max depth").clamping(SliderClamping::Always))
            .on_hover_text("Longest path in segments (Mitsuba's convention): 1 = only emitters, 2 = direct light, more = interreflections.")
            .changed()
        {
            r.max_depth = Some(depth);
        }
    }

    {
        egui::ComboBox::from_label("Estimator")
            .selected_text(match auto {
                Some((resolved, _)) => format!("auto ({resolved})"),
                None => r.estimator.to_string(),
            })
            .show_ui(ui, |ui| {
                ui.selectable_value(&mut r.estimator, Estimator::Auto, "auto")
                    .on_hover_text("Photon-mapped caustics (or light + path tracing for rough or dispersive glass) when the lights look small from the scene's glass and mirrors, else path tracing.");
                ui.selectable_value(&mut r.estimator, Estimator::Path, "path")
                    .on_hover_text("Paths start at the eye; light is found by aiming at lights (NEE) and by chance: caustics from small lights converge slowly.");
                ui.selectable_value(&mut r.estimator, Estimator::Bdpt, "bdpt")
                    .on_hover_text("Paths from the eye and from the light, joined in every possible way and weighted by MIS: caustics on diffuse surfaces converge fast.");
                ui.selectable_value(&mut r.estimator, Estimator::Lt, "light tracing")
                    .on_hover_text("Paths start at the light and are connected to the camera: sees caustics at once, but cannot see mirrors or glass directly.");
                ui.selectable_value(&mut r.estimator, Estimator::LtPt, "lt+pt")
                    .on_hover_text("Eye paths and light paths, each path weighted by how likely each side was to find it (MIS): caustics and glass both converge. The GPU's caustic estimator; the CPU runs bdpt for it.");
                ui.selectable_value(&mut r.estimator, Estimator::Sppm, "photons (sppm)")
                    .on_hover_text("Path tracing, with the caustics (light through glass or off a mirror onto a diffuse surface) gathered from photons shot from the lights: the caustic converges seen directly, through glass and in mirrors. Slightly blurred at first; the blur shrinks as samples add up. CPU only (the GPU runs lt+pt for it).");
            })
            .response
            .on_hover_text(match auto {
                Some((resolved, why)) => format!(
                    "How light paths are sampled; all estimators converge to the same image. \
                     Auto picks {resolved} here: {why}."
                ),
                None => {
                    "How light paths are sampled; all estimators converge to the same image."
                        .to_string()
                }
            });
    }
}

/// The view selector (image, dominant path class, event heatmaps) and the class legend.
fn layer_views(app: &mut ViewerApp, ui: &mut egui::Ui) {
    use crate::app::layer_view::{CLASS_COLOURS, DECOMPOSITION, ViewMode};
    ui.label("View");
    let mut view = app.view;
    ui.horizontal_wrapped(|ui| {
        for mode in ViewMode::ALL {
            ui.selectable_value(&mut view, mode, mode.label())
                .on_hover_text(mode.hover());
        }
    });
    if view != app.view {
        app.set_view(view);
    }
    polarizer(app, ui);
    if app.view == ViewMode::Classes {
        let names = DECOMPOSITION
            .classes
            .iter()
            .map(|c| c.filter.source().trim());
        for (name, c) in names.chain(["rest"]).zip(CLASS_COLOURS) {
            let [r, g, b] = c.map(|v| (crate::math::color::linear_to_srgb(v) * 255.0) as u8);
            ui.horizontal(|ui| {
                let (swatch, _) =
                    ui.allocate_exact_size(egui::vec2(12.0, 12.0), egui::Sense::hover());
                ui.painter()
                    .rect_filled(swatch, 2.0, Color32::from_rgb(r, g, b));
                ui.label(format!("class {name}"));
            });
        }
    }
    if app.view.is_polarized() {
        polarization_legend(ui, app.view);
    }
    if app.view != ViewMode::Beauty {
        ui.small("Layer views path-trace every path (estimator and path filter set aside).");
    }
}

/// The colour scale of a polarisation view: degree 0 → 1 through the sequential map, or the
/// angle's hue 0° → 180° (at full brightness), labelled at both ends and the middle.
fn polarization_legend(ui: &mut egui::Ui, view: crate::app::layer_view::ViewMode) {
    use crate::cpu::polarized::view::{aop_colour, dop_colour};
    use std::f32::consts::PI;
    let dop = view == crate::app::layer_view::ViewMode::Dop;
    let colour = |t: f32| {
        let c = if dop {
            dop_colour(t)
        } else {
            aop_colour(t * PI, 1.0)
        };
        let [r, g, b] = c.to_array().map(|v| (v.clamp(0.0, 1.0) * 255.0) as u8);
        Color32::from_rgb(r, g, b)
    };
    let (bar, _) = ui.allocate_exact_size(egui::vec2(180.0, 12.0), egui::Sense::hover());
    const STEPS: usize = 36;
    for i in 0..STEPS {
        let x0 = bar.left() + bar.width() * i as f32 / STEPS as f32;
        let x1 = bar.left() + bar.width() * (i + 1) as f32 / STEPS as f32;
        let cell = egui::Rect::from_x_y_ranges(x0..=x1, bar.y_range());
        ui.painter()
            .rect_filled(cell, 0.0, colour((i as f32 + 0.5) / STEPS as f32));
    }
    let ends = if dop {
        ["0 unpolarised", "0.5", "1 polarised"]
    } else {
        ["0° (horizontal)", "90°", "180°"]
    };
    ui.horizontal(|ui| {
        for e in ends {
            ui.small(e);
        }
    })
    .response
    .on_hover_text(if dop {
        "Degree of polarisation sqrt(Q² + U² + V²) / I of the light reaching the pixel."
    } else {
        "Angle of polarisation ½ atan2(U, Q), counter-clockwise from the image's horizontal; \
         darker where the light is less polarised (full brightness from degree 0.5)."
    });
}

/// The Heckbert path filter: an invalid expression is highlighted and the last valid one keeps
/// rendering.
fn path_filter(app: &mut ViewerApp, ui: &mut egui::Ui) {
    // Path filter: an invalid expression is highlighted and the last valid one keeps rendering.
    let label = ui.label("Path filter (Heckbert, light to eye)");
    let mut text = app.filter_text.clone();
    let bad = app.filter_error.is_some();
    let edit = egui::TextEdit::singleline(&mut text)
        .hint_text("all paths")
        .desired_width(200.0)
        .text_color_opt(bad.then_some(Color32::from_rgb(255, 110, 110)));
    let resp = ui
        .add(edit)
        .labelled_by(label.id)
        .on_hover_text("A regular expression over events L (light), D (diffuse), G (glossy), S (specular), E (eye); only matching paths are drawn.");
    if resp.changed() {
        app.push(Edit::PathFilter(text));
    }
    if let Some(e) = &app.filter_error {
        ui.colored_label(Color32::from_rgb(255, 110, 110), format!("invalid: {e}"));
        let shown = if app.settings.render.paths.is_empty() {
            "all paths"
        } else {
            app.settings.render.paths.as_str()
        };
        ui.label(egui::RichText::new(format!("still rendering '{shown}'")).weak());
    }
    ui.horizontal_wrapped(|ui| {
        for (label, expr, tip) in PATH_PRESETS {
            if ui.small_button(*label).on_hover_text(*tip).clicked() {
                app.push(Edit::PathFilter(expr.to_string()));
            }
        }
    });
}

/// Exposure and tone map (the samples stay).
fn display(app: &mut ViewerApp, ui: &mut egui::Ui) {
    let mut display = app.settings.display;
    let d = &mut display;
    ui.add(
        Slider::new(&mut d.exposure, -10.0..=10.0)
            .text("Exposure (stops)")
            .clamping(SliderClamping::Always),
    )
    .on_hover_text("Multiplies the radiance by 2^stops before display, like a camera's shutter time; does not restart rendering.");
    if !d.exposure.is_finite() {
        d.exposure = 0.0;
    }
    egui::ComboBox::from_label("Tone map")
        .selected_text(match d.tone_map {
            ToneMap::Clamp => "clamp",
            ToneMap::Reinhard => "Reinhard",
            ToneMap::Aces => "ACES",
        })
        .show_ui(ui, |ui| {
            ui.selectable_value(&mut d.tone_map, ToneMap::Clamp, "clamp")
                .on_hover_text("Radiance above 1 is clipped: faithful in range, burns out highlights.");
            ui.selectable_value(&mut d.tone_map, ToneMap::Reinhard, "Reinhard")
                .on_hover_text("x/(1+x): compresses highlights smoothly, never clips.");
            ui.selectable_value(&mut d.tone_map, ToneMap::Aces, "ACES")
                .on_hover_text("Filmic curve (Narkowicz's ACES fit): film-like contrast and highlight roll-off.");
        })
        .response
        .on_hover_text("How radiance, which has no upper bound, is squeezed into the displayable range.");
    if display != app.settings.display {
        app.push(Edit::Display(display));
    }
    denoise(app, ui);
}

/// The live view's denoiser: the toggle and the split between raw (left) and denoised.
fn denoise(app: &mut ViewerApp, ui: &mut egui::Ui) {
    ui.checkbox(&mut app.denoise.on, "Denoise").on_hover_text(
        "Show the image filtered by an edge-avoiding à-trous wavelet filter (guided by first-hit \
         albedo, normal and depth) right of the split line, raw left of it. Display only: the \
         accumulation and screenshots' EXR stay unbiased. It blurs caustics seen through glass.",
    );
    if app.denoise.on {
        ui.add(
            Slider::new(&mut app.denoise.split, 0.0..=1.0)
                .text("Split (raw | denoised)")
                .clamping(SliderClamping::Always),
        );
        if !app.denoise.split.is_finite() {
            app.denoise.split = 0.5;
        }
        if let Some((_, _, device)) = app.denoise.shown() {
            ui.weak(match device {
                FilterDevice::Gpu => "Filtered on the GPU (WGSL)",
                FilterDevice::Cpu => "Filtered on the CPU",
            });
        }
    }
}

/// Pause, restart, spp target, render scale and seed (edits `r`).
fn accumulation(app: &mut ViewerApp, ui: &mut egui::Ui, r: &mut RenderEdit) {
    ui.horizontal(|ui| {
        let label = if app.paused { "Resume" } else { "Pause" };
        if ui
            .button(label)
            .on_hover_text("Stop or continue adding samples (Space); the image keeps its samples.")
            .clicked()
        {
            let p = !app.paused;
            app.push(Edit::Pause(p));
        }
        if ui
            .button("Restart")
            .on_hover_text("Drop all samples and start accumulating again.")
            .clicked()
        {
            app.push(Edit::Restart);
        }
    });
    {
        ui.add(
            egui::DragValue::new(&mut r.spp_target)
                .range(0..=1_000_000)
                .speed(4.0)
                .prefix("spp target ")
                .custom_formatter(|v, _| {
                    if v == 0.0 {
                        "∞".into()
                    } else {
                        format!("{v:.0}")
                    }
                }),
        )
        .on_hover_text(
            "Stop at this many samples per pixel (0 = never); Monte Carlo noise falls as 1/√spp.",
        );
        ui.add(
            Slider::new(&mut r.render_scale, 0.1..=1.0)
                .text("Render scale")
                .clamping(SliderClamping::Always),
        )
        .on_hover_text("Fraction of the viewport's pixels (or of the scene's resolution) rendered: fewer pixels give more samples per second each.");
        ui.checkbox(&mut r.fit_viewport, "Fit viewport")
            .on_hover_text("Render the viewport's size in physical pixels (HiDPI aware; a resize restarts accumulation). Off: the scene's own resolution, letterboxed.");
        if !r.render_scale.is_finite() {
            r.render_scale = 0.5;
        }
        ui.add(egui::DragValue::new(&mut r.seed).prefix("seed "))
            .on_hover_text("Seed of the random numbers: another seed gives independent noise with the same mean.");
    }
}

/// The polarising filter in front of the sensor (the beauty view, CPU or GPU): on/off and its
/// angle from the image's horizontal (docs/polarization.md).
fn polarizer(app: &mut ViewerApp, ui: &mut egui::Ui) {
    let mut on = app.polarizer.is_some();
    let mut deg = app.polarizer.unwrap_or(90.0);
    ui.horizontal(|ui| {
        ui.checkbox(&mut on, "Polarizer").on_hover_text(
            "Trace polarised light and look through a linear polarising filter (image view; \
             the path tracer over every path, on the CPU or the GPU). 0° passes horizontally \
             polarised light, 90° vertically: at Brewster's angle (builtin:brewster) 90° \
             removes the reflection off glass.",
        );
        if on {
            ui.add(egui::Slider::new(&mut deg, 0.0..=180.0).suffix("°"));
        }
    });
    let want = on.then_some(deg);
    if want != app.polarizer {
        app.set_polarizer(want);
    }
}
