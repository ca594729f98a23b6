//! Screenshots: `<dir>/<scene>-<UTC timestamp>.png` (tone-mapped, as shown), `.exr` (linear
//! accumulated radiance) and `.json` (every setting, see [`crate::render::settings`]), so the image can
//! be re-rendered headless with `refract render --settings <file>.json`.

use super::ViewerApp;
use crate::film;
use crate::render::settings::{CaptureInfo, EnvironmentSetting};
use anyhow::Context;
use std::path::{Path, PathBuf};
use std::time::{SystemTime, UNIX_EPOCH};

/// The files one screenshot wrote.
#[derive(Clone, Debug)]
pub struct Saved {
    pub png: PathBuf,
    pub exr: PathBuf,
    pub json: PathBuf,
}

/// `YYYYMMDD-HHMMSS` in UTC (civil-from-days: Hinnant, "chrono-Compatible Low-Level Date
/// Algorithms", 2013).
pub fn timestamp(t: SystemTime) -> String {
    let secs = t.duration_since(UNIX_EPOCH).map_or(0, |d| d.as_secs()) as i64;
    let (days, rem) = (secs.div_euclid(86_400), secs.rem_euclid(86_400));
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!(
        "{y:04}{m:02}{d:02}-{:02}{:02}{:02}",
        rem / 3600,
        rem / 60 % 60,
        rem % 60
    )
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
    film::save_image(
        &png,
        acc.width,
        acc.height,
        &acc.pixels,
        d.exposure,
        d.tone_map,
    )?;
    film::save_image(&exr, acc.width, acc.height, &acc.pixels, 0.0, d.tone_map)?;
    let mut sidecar = app.settings.clone();
    sidecar.environment = EnvironmentSetting::of(&app.base);
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

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    #[test]
    fn timestamps_are_utc_civil_dates() {
        assert_eq!(timestamp(UNIX_EPOCH), "19700101-000000");
        // 2024-02-29 12:34:56 UTC
        let t = UNIX_EPOCH + Duration::from_secs(1_709_210_096);
        assert_eq!(timestamp(t), "20240229-123456");
    }

    #[test]
    fn stems_are_file_name_safe() {
        assert_eq!(file_stem("cornell-glass"), "cornell-glass");
        assert_eq!(file_stem("a/b c"), "a_b_c");
        assert_eq!(file_stem(""), "scene");
    }
}
