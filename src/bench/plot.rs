//! `bench.png`: relMSE against run time on log-log axes, one panel per scene and path class,
//! one colour per estimator, one line style per device (solid CPU, dashed GPU), the legend in
//! its own column right of the panels.

use super::BenchPoint;
use anyhow::{Context, Result};
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use std::path::Path;

/// Colours of the estimators in order of first appearance (Tableau 10; distinct in print and
/// for the common colour-vision deficiencies).
const COLOURS: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(140, 86, 75),
    RGBColor(23, 190, 207),
    RGBColor(127, 127, 127),
];
const PANEL: (u32, u32) = (520, 380);
const LEGEND_W: u32 = 260;
const TITLE_H: u32 = 40;

fn err(e: impl std::fmt::Display) -> anyhow::Error {
    anyhow::anyhow!("plot: {e}")
}

/// Keys in order of first appearance, without repeats.
fn unique<T: PartialEq + Clone>(items: impl Iterator<Item = T>) -> Vec<T> {
    let mut out: Vec<T> = Vec::new();
    for x in items {
        if !out.contains(&x) {
            out.push(x);
        }
    }
    out
}

fn is_gpu(device: &str) -> bool {
    !device.starts_with("cpu")
}

/// A device's legend label: the GPU adapter without its driver details, e.g. "gpu
/// (llvmpipe)" for "gpu (llvmpipe (LLVM 15.0.6, 256 bits))".
fn device_label(device: &str) -> String {
    match device.strip_prefix("gpu (") {
        Some(adapter) => {
            let name = adapter.split(" (").next().unwrap_or(adapter);
            format!("gpu ({})", name.trim_end_matches(')'))
        }
        None => device.to_string(),
    }
}

/// The estimators and devices the plot shows, fixing each one's colour and line style.
struct Styles {
    estimators: Vec<String>,
    devices: Vec<String>,
}

impl Styles {
    fn colour(&self, estimator: &str) -> RGBColor {
        let i = self.estimators.iter().position(|e| e == estimator);
        COLOURS[i.unwrap_or(0) % COLOURS.len()]
    }
}

impl Styles {
    /// The estimators in order of first appearance; the devices CPU first, then GPUs in
    /// order of appearance.
    fn of(points: &[&BenchPoint]) -> Styles {
        Styles {
            estimators: unique(points.iter().map(|p| p.estimator.clone())),
            devices: {
                let mut d = unique(points.iter().map(|p| p.device.clone()));
                d.sort_by_key(|d| is_gpu(d)); // CPU first, then GPUs in order of appearance
                d
            },
        }
    }
}

/// The figure's grid of panels and its size in pixels (panels, legend column, title row).
struct Layout {
    rows: usize,
    cols: usize,
    w: u32,
    h: u32,
}

impl Layout {
    /// One column for one panel, two for up to four, three beyond.
    fn for_panels(panels: usize) -> Layout {
        let cols = match panels {
            1 => 1,
            2..=4 => 2,
            _ => 3,
        };
        let rows = panels.div_ceil(cols);
        Layout {
            rows,
            cols,
            w: cols as u32 * PANEL.0 + LEGEND_W,
            h: rows as u32 * PANEL.1 + TITLE_H,
        }
    }
}

/// Log-log plot of relMSE against time: a grid of panels, one per (scene, path class).
pub fn plot(path: &Path, points: &[BenchPoint]) -> Result<()> {
    use plotters::style::{FontStyle, register_font};
    // Register the font egui ships (no system fonts needed).
    let _ = register_font(
        "sans-serif",
        FontStyle::Normal,
        epaint_default_fonts::UBUNTU_LIGHT,
    );
    let finite: Vec<&BenchPoint> = points
        .iter()
        .filter(|p| p.rel_mse > 0.0 && p.seconds > 0.0)
        .collect();
    anyhow::ensure!(!finite.is_empty(), "nothing to plot");
    let panels = unique(finite.iter().map(|p| (p.scene.clone(), p.paths.clone())));
    let styles = Styles::of(&finite);
    let layout = Layout::for_panels(panels.len());
    let (w, h) = (layout.w, layout.h);
    let mut buf = vec![255u8; (w * h * 3) as usize];
    draw_figure(&mut buf, &layout, &panels, &finite, &styles)?;
    let img = image::RgbImage::from_raw(w, h, buf).context("plot buffer size")?;
    img.save(path)
        .with_context(|| format!("cannot write '{}'", path.display()))
}

/// Draw the whole figure into the RGB buffer `buf`: the title, one panel per (scene, path
/// class) of `panels` with its points from `finite`, and the legend.
fn draw_figure(
    buf: &mut [u8],
    layout: &Layout,
    panels: &[(String, String)],
    finite: &[&BenchPoint],
    styles: &Styles,
) -> Result<()> {
    let root = BitMapBackend::with_buffer(buf, (layout.w, layout.h)).into_drawing_area();
    root.fill(&WHITE).map_err(err)?;
    let (title, body) = root.split_vertically(TITLE_H);
    title
        .titled(
            "refract bench: relative MSE against run time (log-log)",
            ("sans-serif", 22),
        )
        .map_err(err)?;
    let (grid, legend) = body.split_horizontally(layout.cols as u32 * PANEL.0);
    let areas = grid.split_evenly((layout.rows, layout.cols));
    for (area, (scene, class)) in areas.iter().zip(panels) {
        let curve: Vec<&BenchPoint> = finite
            .iter()
            .copied()
            .filter(|p| (&p.scene, &p.paths) == (scene, class))
            .collect();
        draw_panel(area, &panel_caption(scene, class), &curve, styles)?;
    }
    draw_legend(&legend, styles)?;
    root.present().map_err(err)?;
    Ok(())
}

/// A panel's caption: the scene, followed by the path class unless that is "all" or empty.
fn panel_caption(scene: &str, class: &str) -> String {
    if class == "all" || class.is_empty() {
        scene.to_string()
    } else {
        format!("{scene}, {class}")
    }
}

/// A panel's chart: seconds against relMSE, both on log axes.
type LogChart<'a, DB> = ChartContext<'a, DB, Cartesian2d<LogCoord<f64>, LogCoord<f64>>>;

/// The smallest and largest `value` over `points` ((MAX, MIN) for none).
fn extent(points: &[&BenchPoint], value: impl Fn(&BenchPoint) -> f64) -> (f64, f64) {
    points.iter().fold((f64::MAX, f64::MIN), |(a, b), p| {
        (a.min(value(p)), b.max(value(p)))
    })
}

/// One panel: every (device, estimator) curve of one scene and path class.
fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    caption: &str,
    points: &[&BenchPoint],
    styles: &Styles,
) -> Result<()> {
    let (t0, t1) = extent(points, |p| p.seconds);
    let (e0, e1) = extent(points, |p| p.rel_mse);
    let mut chart = ChartBuilder::on(area)
        .caption(caption, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(
            (t0 * 0.8..t1 * 1.25).log_scale(),
            (e0 * 0.5..e1 * 2.0).log_scale(),
        )
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("seconds")
        .y_desc("relMSE")
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .draw()
        .map_err(err)?;
    let curves = unique(
        points
            .iter()
            .map(|p| (p.device.clone(), p.estimator.clone())),
    );
    for (device, estimator) in &curves {
        draw_curve(&mut chart, (device, estimator), points, styles)?;
    }
    Ok(())
}

/// The curve of one (device, estimator) pair through its `points`: in the estimator's colour,
/// a solid line with filled markers on the CPU, dashed with hollow markers on a GPU.
fn draw_curve<DB: DrawingBackend>(
    chart: &mut LogChart<'_, DB>,
    (device, estimator): (&String, &String),
    points: &[&BenchPoint],
    styles: &Styles,
) -> Result<()> {
    let colour = styles.colour(estimator);
    let series: Vec<(f64, f64)> = points
        .iter()
        .filter(|p| (&p.device, &p.estimator) == (device, estimator))
        .map(|p| (p.seconds, p.rel_mse))
        .collect();
    let line = colour.stroke_width(2);
    if is_gpu(device) {
        chart
            .draw_series(DashedLineSeries::new(series.clone(), 8, 5, line))
            .map_err(err)?;
    } else {
        chart
            .draw_series(LineSeries::new(series.clone(), line))
            .map_err(err)?;
    }
    // Filled markers on the CPU, hollow ones on the GPU: the device reads without colour.
    let marker = if is_gpu(device) {
        colour.stroke_width(2)
    } else {
        colour.filled()
    };
    chart
        .draw_series(series.iter().map(|&(x, y)| Circle::new((x, y), 3, marker)))
        .map_err(err)?;
    Ok(())
}

/// The legend column: a colour swatch per estimator, a line style per device.
fn draw_legend<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, styles: &Styles) -> Result<()> {
    let font = ("sans-serif", 16).into_font();
    let (x, mut y) = (16i32, 30i32);
    let text = |s: &str, y: i32| Text::new(s.to_string(), (x + 44, y - 8), font.clone());
    area.draw(&Text::new("estimator", (x, y - 8), font.clone()))
        .map_err(err)?;
    for e in &styles.estimators {
        y += 24;
        let style = styles.colour(e).stroke_width(3);
        area.draw(&PathElement::new(vec![(x, y), (x + 34, y)], style))
            .map_err(err)?;
        area.draw(&text(e, y)).map_err(err)?;
    }
    y += 40;
    area.draw(&Text::new("device", (x, y - 8), font.clone()))
        .map_err(err)?;
    for d in &styles.devices {
        y += 24;
        let style = BLACK.stroke_width(2);
        let pts = vec![(x, y), (x + 34, y)];
        if is_gpu(d) {
            area.draw(&DashedPathElement::new(pts, 8, 5, style))
                .map_err(err)?;
        } else {
            area.draw(&PathElement::new(pts, style)).map_err(err)?;
        }
        let name: String = device_label(d).chars().take(24).collect();
        area.draw(&text(&name, y)).map_err(err)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn device_labels_drop_driver_details() {
        assert_eq!(
            device_label("gpu (llvmpipe (LLVM 15.0.6, 256 bits))"),
            "gpu (llvmpipe)"
        );
        assert_eq!(device_label("gpu (NVIDIA H200)"), "gpu (NVIDIA H200)");
        assert_eq!(device_label("cpu"), "cpu");
        assert!(is_gpu("gpu (x)") && !is_gpu("cpu"));
    }

    #[test]
    fn unique_keeps_first_appearance_order() {
        assert_eq!(unique([3, 1, 3, 2, 1].into_iter()), vec![3, 1, 2]);
    }
}
