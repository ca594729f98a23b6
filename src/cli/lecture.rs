//! `refract lecture list | export DIR`: the lecture's demos as a table, and as a handout —
//! every demo rendered headless to `DIR/KEY.png` (its scene, path filter; the teaching
//! switches off) and `DIR/index.html` listing them in lecture order with their captions.

use super::RenderArgs;
use anyhow::{Context, Result};
use clap::Parser;
use refract::app::lecture::{DEMOS, Demo};
use refract::render::Device;
use refract::scene::Scene;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

#[derive(clap::Subcommand, Clone)]
pub(crate) enum LectureCommand {
    /// Print KEY<TAB>concept<TAB>caption, one line per demo, in lecture order.
    List,
    /// Render every demo to DIR/KEY.png and write DIR/index.html (the handout).
    Export(ExportArgs),
}

#[derive(clap::Args, Clone)]
pub(crate) struct ExportArgs {
    /// Folder for the images and index.html (created if missing).
    dir: PathBuf,
    /// Samples per pixel of each image.
    #[arg(long, default_value_t = 64)]
    spp: u32,
    /// Image width (the height keeps each scene's aspect); default: each scene's own.
    #[arg(long)]
    width: Option<u32>,
    #[arg(long, value_enum, ignore_case = true, default_value_t = Device::Auto)]
    device: Device,
}

/// `render`'s arguments parsed from a command line, so a demo is rendered exactly as
/// `refract render …` would render it.
#[derive(Parser)]
struct RenderLine {
    #[command(flatten)]
    args: RenderArgs,
}

pub(crate) fn run(cmd: &LectureCommand) -> Result<()> {
    match cmd {
        LectureCommand::List => {
            print!("{}", list());
            Ok(())
        }
        LectureCommand::Export(args) => export(args),
    }
}

/// One line per demo: key, concept and caption separated by tabs.
fn list() -> String {
    DEMOS
        .iter()
        .map(|d| format!("{}\t{}\t{}\n", d.key, d.concept, one_line(d.caption)))
        .collect()
}

/// The caption with its line-continuation spacing collapsed.
fn one_line(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}

fn export(args: &ExportArgs) -> Result<()> {
    std::fs::create_dir_all(&args.dir)
        .with_context(|| format!("lecture export: cannot create {}", args.dir.display()))?;
    for (k, demo) in DEMOS.iter().enumerate() {
        eprintln!("[{}/{}] {} ({})", k + 1, DEMOS.len(), demo.key, demo.scene);
        let line = render_line(demo, args)?;
        super::render::render(&line.args)
            .with_context(|| format!("lecture demo '{}'", demo.key))?;
    }
    let index = args.dir.join("index.html");
    refract::film::write_atomically(&index, |tmp| {
        std::fs::write(tmp, index_html())
            .with_context(|| format!("cannot write '{}'", tmp.display()))
    })
    .with_context(|| format!("lecture export: writing {}", index.display()))?;
    eprintln!("wrote {}", index.display());
    Ok(())
}

/// The `render` command line of `demo` for the handout.
fn render_line(demo: &Demo, args: &ExportArgs) -> Result<RenderLine> {
    let out = image_path(&args.dir, demo);
    let mut line: Vec<String> = vec![
        "render".into(),
        "--scene".into(),
        demo.scene.into(),
        "--spp".into(),
        args.spp.to_string(),
        "--out".into(),
        out.display().to_string(),
        "--device".into(),
        args.device.to_string(),
        "--quiet".into(),
    ];
    if !demo.filter.is_empty() {
        line.extend(["--paths".into(), demo.filter.into()]);
    }
    if let Some(w) = args.width {
        let s = Scene::load(demo.scene)?;
        let h = (w as f64 * s.settings.height as f64 / s.settings.width as f64).round();
        line.extend([
            "--width".into(),
            w.to_string(),
            "--height".into(),
            (h as u32).max(1).to_string(),
        ]);
    }
    RenderLine::try_parse_from(&line)
        .map_err(|e| anyhow::anyhow!("lecture demo '{}': {e}", demo.key))
}

fn image_path(dir: &Path, demo: &Demo) -> PathBuf {
    dir.join(format!("{}.png", demo.key))
}

/// The handout page: every demo's image and caption in lecture order.
fn index_html() -> String {
    let mut h = String::from(
        "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <title>refract — Rendering: Materials, the demos</title>\n\
         <style>body{font-family:sans-serif;max-width:60em;margin:auto}\
         figure{margin:2em 0}img{max-width:100%}</style></head><body>\n\
         <h1>Rendering: Materials — the demos</h1>\n<ol>\n",
    );
    for d in &DEMOS {
        let _ = writeln!(
            h,
            "<li><figure id=\"{key}\"><h2>{concept}</h2><img src=\"{key}.png\" alt=\"{concept}\">\
             <figcaption>{caption} <code>refract view --lecture {key}</code></figcaption></figure></li>",
            key = escape(d.key),
            concept = escape(d.concept),
            caption = escape(&one_line(d.caption)),
        );
    }
    h.push_str("</ol>\n</body></html>\n");
    h
}

/// HTML text escaping (&, <, >, ").
fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_list_has_one_tab_separated_line_per_demo_in_order() {
        let l = list();
        let keys: Vec<&str> = l.lines().map(|x| x.split('\t').next().unwrap()).collect();
        let want: Vec<&str> = DEMOS.iter().map(|d| d.key).collect();
        assert_eq!(keys, want);
        assert!(l.lines().all(|x| x.split('\t').count() == 3));
    }

    #[test]
    fn the_handout_escapes_captions_and_lists_every_image() {
        let h = index_html();
        for d in &DEMOS {
            assert!(h.contains(&format!("src=\"{}.png\"", d.key)), "{}", d.key);
        }
        assert!(!h.contains("n₁ sin θ₁ < "), "unescaped");
        assert_eq!(escape("a<b & \"c\""), "a&lt;b &amp; &quot;c&quot;");
    }
}
