//! Image files: linear EXR and tone-mapped sRGB PNG output, EXR input.

use super::tonemap::{ToneMap, to_srgb8};
use glam::Vec3;
use std::path::Path;

/// Check, before rendering, that `path` names a format we can write and that it can be
/// written: its folder is created as [`save_image`] would, then the file is opened for writing
/// (created and removed again when it did not exist), so an unwritable output is an error
/// before any work is done rather than after.
pub fn check_output_path(path: &Path) -> anyhow::Result<()> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
        .unwrap_or_default();
    anyhow::ensure!(
        ext == "exr" || ext == "png",
        "unsupported output format '{}': use .exr (linear) or .png (sRGB)",
        path.display()
    );
    probe_writable(path)
}

/// Open `path` for writing without truncating it (creating its folder first) and remove it
/// again if this created it: an error names the path and the reason.
pub fn probe_writable(path: &Path) -> anyhow::Result<()> {
    use anyhow::Context;
    if let Some(dir) = path.parent()
        && !dir.as_os_str().is_empty()
    {
        if let Some(file) = dir.ancestors().find(|a| a.is_file()) {
            anyhow::bail!(
                "cannot create folder '{}': '{}' is a file, not a folder",
                dir.display(),
                file.display()
            );
        }
        std::fs::create_dir_all(dir)
            .with_context(|| format!("cannot create folder '{}'", dir.display()))?;
    }
    // Opening a FIFO for writing would block until a reader comes; a folder cannot be written.
    if let Ok(meta) = std::fs::metadata(path) {
        anyhow::ensure!(
            meta.is_file(),
            "cannot write '{}': it exists and is not a regular file (a folder, FIFO or device)",
            path.display()
        );
    }
    let existed = std::fs::symlink_metadata(path).is_ok();
    std::fs::OpenOptions::new()
        .write(true)
        .create(true)
        .truncate(false)
        .open(path)
        .with_context(|| format!("cannot write '{}'", path.display()))?;
    if !existed {
        std::fs::remove_file(path)
            .with_context(|| format!("cannot remove the probe '{}'", path.display()))?;
    }
    Ok(())
}

/// Write `img` (linear radiance) to `path`: `.exr` = linear float RGB, `.png` = tone-mapped sRGB.
pub fn save_image(
    path: &Path,
    width: u32,
    height: u32,
    img: &[Vec3],
    exposure: f32,
    tone: ToneMap,
) -> anyhow::Result<()> {
    use anyhow::Context;
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
        .unwrap_or_default();
    if let Some(dir) = path.parent()
        && !dir.as_os_str().is_empty()
    {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("cannot create folder '{}'", dir.display()))?;
    }
    // Written whole or not at all (`atomic`): a killed process leaves no truncated image.
    match ext.as_str() {
        "exr" => {
            let data: Vec<f32> = img.iter().flat_map(|p| [p.x, p.y, p.z]).collect();
            let buf = image::Rgb32FImage::from_raw(width, height, data)
                .context("image buffer size does not match its dimensions")?;
            super::write_atomically(path, |tmp| {
                image::DynamicImage::ImageRgb32F(buf)
                    .save_with_format(tmp, image::ImageFormat::OpenExr)
                    .with_context(|| format!("cannot write '{}'", path.display()))
            })?;
        }
        "png" => {
            let data = to_srgb8(img, exposure, tone);
            let buf = image::RgbaImage::from_raw(width, height, data)
                .context("image buffer size does not match its dimensions")?;
            super::write_atomically(path, |tmp| {
                buf.save_with_format(tmp, image::ImageFormat::Png)
                    .with_context(|| format!("cannot write '{}'", path.display()))
            })?;
        }
        _ => anyhow::bail!(
            "unsupported output format '{}': use .exr (linear) or .png (sRGB)",
            path.display()
        ),
    }
    Ok(())
}

/// Read a linear RGB EXR back (used by tests and `bench`).
pub fn load_exr(path: &Path) -> anyhow::Result<(u32, u32, Vec<Vec3>)> {
    use anyhow::Context;
    let img = image::open(path)
        .with_context(|| format!("cannot read '{}'", path.display()))?
        .into_rgb32f();
    let (w, h) = img.dimensions();
    let px = img.pixels().map(|p| Vec3::new(p[0], p[1], p[2])).collect();
    Ok((w, h, px))
}
