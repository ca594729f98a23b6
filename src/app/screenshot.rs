//! Screenshots: `<dir>/<scene>-<local timestamp>.png` (tone-mapped, as shown), `.exr` (linear
//! accumulated radiance) and `.json` (every setting, see [`crate::render::settings`]), so the image can
//! be re-rendered headless with `refract render --settings <file>.json`.

use super::ViewerApp;
use crate::film;
use crate::render::settings::{CaptureInfo, EnvironmentSetting};
use anyhow::Context;
use std::path::{Path, PathBuf};
use std::time::SystemTime;

/// The files one screenshot wrote.
#[derive(Clone, Debug)]
pub struct Saved {
    pub png: PathBuf,
    pub exr: PathBuf,
    pub json: PathBuf,
}

/// `YYYYMMDD-HHMMSS` in the user's time zone (the system's, as file managers show file
/// times; UTC where none is configured).
pub fn timestamp(t: SystemTime) -> String {
    timestamp_in(t, &jiff::tz::TimeZone::system())
}

/// `YYYYMMDD-HHMMSS` of `t` in time zone `tz` (the Unix epoch for a time before it).
pub fn timestamp_in(t: SystemTime, tz: &jiff::tz::TimeZone) -> String {
    let ts = jiff::Timestamp::try_from(t).unwrap_or(jiff::Timestamp::UNIX_EPOCH);
    ts.to_zoned(tz.clone())
        .strftime("%Y%m%d-%H%M%S")
        .to_string()
}

/// A file-name-safe version of a scene name.
fn file_stem(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    if s.is_empty() { "scene".into() } else { s }
}

/// A stem in `dir` that no existing screenshot uses.
fn unique_stem(dir: &Path, base: &str) -> String {
    let taken = |s: &str| {
        ["png", "exr", "json"]
            .iter()
            .any(|e| dir.join(format!("{s}.{e}")).exists())
    };
    if !taken(base) {
        return base.to_owned();
    }
    (1..)
        .map(|i| format!("{base}-{i}"))
        .find(|s| !taken(s))
        .unwrap_or_else(|| base.to_owned())
}

/// Write the three files for what `app` shows now.
pub fn save(app: &ViewerApp) -> anyhow::Result<Saved> {
    let acc = app
        .backend()
        .read_image()
        .context("nothing rendered yet: wait for the first pass")?;
    let dir = &app.screenshot_dir;
    std::fs::create_dir_all(dir)
        .with_context(|| format!("cannot create folder '{}'", dir.display()))?;
    let name = if app.scene.name.is_empty() {
        app.settings.scene.as_str()
    } else {
        app.scene.name.as_str()
    };
    let stem = unique_stem(
        dir,
        &format!("{}-{}", file_stem(name), timestamp(SystemTime::now())),
    );
    let png = dir.join(format!("{stem}.png"));
    let exr = dir.join(format!("{stem}.exr"));
    let json = dir.join(format!("{stem}.json"));
    let d = app.settings.display;
    if app.denoise.on {
        save_denoised(app, &acc, &png, &dir.join(format!("{stem}.denoised.exr")))?;
    } else {
        film::save_image(
            &png,
            acc.width,
            acc.height,
            &acc.pixels,
            d.exposure,
            d.tone_map,
        )?;
    }
    film::save_image(&exr, acc.width, acc.height, &acc.pixels, 0.0, d.tone_map)?;
    let mut sidecar = app.settings.clone();
    sidecar.environment = EnvironmentSetting::of(&app.base);
    sidecar.render.polarizer = app.polarizer;
    sidecar.capture = Some(CaptureInfo {
        width: acc.width,
        height: acc.height,
        spp: acc.spp,
        dropped: acc.dropped,
        device: app.backend().device_name(),
        elapsed_s: acc.elapsed.as_secs_f64(),
        png: format!("{stem}.png"),
        exr: format!("{stem}.exr"),
    });
    sidecar.save(&json)?;
    Ok(Saved { png, exr, json })
}

/// With the denoiser on: the PNG as the viewport shows it (raw left of the split, denoised
/// right, the split line and the badge) and the denoised image as `denoised_exr`; the
/// screenshot's EXR stays the raw accumulation.
fn save_denoised(
    app: &ViewerApp,
    acc: &crate::app::backend::Accumulated,
    png: &Path,
    denoised_exr: &Path,
) -> anyhow::Result<()> {
    let d = app.settings.display;
    let den = super::denoise_view::denoise_now(&app.scene, acc)?;
    film::save_image(denoised_exr, acc.width, acc.height, &den, 0.0, d.tone_map)?;
    let raw8 = film::to_srgb8(&acc.pixels, d.exposure, d.tone_map);
    let den8 = film::to_srgb8(&den, d.exposure, d.tone_map);
    let shown = crate::denoise::badge::compose(&raw8, Some(&den8), acc.width, app.denoise.split);
    let img = image::RgbaImage::from_raw(acc.width, acc.height, shown)
        .context("screenshot: image size does not match its pixels")?;
    film::write_atomically(png, |tmp| {
        img.save_with_format(tmp, image::ImageFormat::Png)
            .with_context(|| format!("cannot write '{}'", png.display()))
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::{Duration, UNIX_EPOCH};

    #[test]
    fn timestamps_are_civil_dates_in_the_time_zone() {
        let utc = jiff::tz::TimeZone::UTC;
        assert_eq!(timestamp_in(UNIX_EPOCH, &utc), "19700101-000000");
        // 2024-02-29 12:34:56 UTC, a leap day; 13:34:56 in Berlin (CET, UTC+1).
        let t = UNIX_EPOCH + Duration::from_secs(1_709_210_096);
        assert_eq!(timestamp_in(t, &utc), "20240229-123456");
        let cet = jiff::tz::TimeZone::fixed(jiff::tz::offset(1));
        assert_eq!(timestamp_in(t, &cet), "20240229-133456");
        assert_eq!(timestamp(t).len(), "20240229-123456".len());
    }

    #[test]
    fn stems_are_file_name_safe() {
        assert_eq!(file_stem("cornell-glass"), "cornell-glass");
        assert_eq!(file_stem("a/b c"), "a_b_c");
        assert_eq!(file_stem(""), "scene");
    }
}
