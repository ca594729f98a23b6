//! The screenshot sidecar records the environment image (file, strength, rotation), so
//! `refract render --settings SIDE.json` re-renders a screenshot of an image-lit scene: the
//! viewer (no window, egui_kittest) loads `assets/studio.hdr` into env-spheres, turns and
//! brightens it and takes a screenshot; the headless re-render matches the viewer's EXR
//! within 4σ, while the scene's own lighting (the sidecar without its environment) differs
//! per pixel by more than 3× the seed-to-seed noise.

use eframe::egui;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use refract::app::ViewerApp;
use refract::app::edit::{Edit, EnvEdit};
use refract::render::settings::ViewerSettings;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

const STRENGTH: f32 = 2.5;
const ROTATION: f32 = 120.0;

fn scratch_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!(
        "refract-screenshot-env-{name}-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn studio() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/studio.hdr")
}

fn pixels(path: &Path) -> Vec<f64> {
    let (_, _, px) = refract::film::load_exr(path).unwrap();
    px.iter().map(|p| (p.x + p.y + p.z) as f64 / 3.0).collect()
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len() as f64
}

/// `refract render --settings json --out out` (plus `extra`).
fn render(json: &Path, out: &Path, extra: &[&str]) {
    let st = Command::new(env!("CARGO_BIN_EXE_refract"))
        .args(["render", "--quiet", "--settings"])
        .arg(json)
        .arg("--out")
        .arg(out)
        .args(extra)
        .status()
        .unwrap();
    assert!(st.success(), "render --settings {}", json.display());
}

#[test]
fn sidecar_records_the_environment_and_rerenders_it() {
    let dir = scratch_dir("shot");
    let mut app = ViewerApp::open("builtin:env-spheres").expect("env-spheres opens");
    app.settings.render.render_scale = 0.125;
    app.settings.render.fit_viewport = false;
    app.settings.render.spp_target = 16;
    app.screenshot_dir = dir.clone();
    app.apply(Edit::Environment(EnvEdit::Load(
        studio().display().to_string(),
    )));
    app.apply(Edit::Environment(EnvEdit::Adjust {
        strength: STRENGTH,
        rotation: ROTATION,
    }));
    assert!(app.messages.error.is_none(), "{:?}", app.messages.error);
    app.options_changed();
    let mut h = Harness::builder()
        .with_size(egui::vec2(1280.0, 2400.0))
        .build_ui_state(|ui, app: &mut ViewerApp| app.show(ui), app);
    h.step();
    let start = Instant::now();
    while h.state().backend().spp() < 16 {
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "timed out rendering"
        );
        std::thread::sleep(Duration::from_millis(20));
        h.step();
    }
    h.get_by_label("Screenshot").click();
    h.step();
    h.step();
    let json = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|e| e == "json"))
        .expect("a sidecar");
    let sidecar = ViewerSettings::load(&json).unwrap();
    let env = sidecar
        .environment
        .clone()
        .expect("the sidecar records the environment");
    assert_eq!((env.strength, env.rotation), (STRENGTH, ROTATION));
    let uri = PathBuf::from(env.uri.as_deref().expect("the image's file"));
    assert_eq!(
        std::fs::canonicalize(&uri).unwrap(),
        std::fs::canonicalize(studio()).unwrap()
    );

    // Headless with the same seed, with another seed (the noise), and without the recorded
    // environment (the scene's own generated sun and sky at strength 1).
    let again = dir.join("again.exr");
    let other = dir.join("other-seed.exr");
    render(&json, &again, &[]);
    render(&json, &other, &["--seed", "7"]);
    let mut bare = sidecar.clone();
    bare.environment = None;
    let bare_json = dir.join("bare.json");
    bare.save(&bare_json).unwrap();
    let own = dir.join("own-sky.exr");
    render(&bare_json, &own, &[]);

    let a = pixels(&json.with_extension("exr"));
    let b = pixels(&other);
    // σ of one image's mean from two independent renders: Var(mean_a − mean_b) = 2σ².
    let n = a.len() as f64;
    let d: Vec<f64> = a.iter().zip(&b).map(|(x, y)| x - y).collect();
    let dm = mean(&d);
    let var = d.iter().map(|x| (x - dm).powi(2)).sum::<f64>() / (n - 1.0);
    let sigma = (var / n / 2.0).sqrt();
    assert!(sigma > 0.0);
    let (m_view, m_again, m_other, m_own) = (
        mean(&a),
        mean(&pixels(&again)),
        mean(&b),
        mean(&pixels(&own)),
    );
    eprintln!(
        "viewer {m_view:.5}, headless {m_again:.5}, other seed {m_other:.5}, scene's own sky {m_own:.5}, σ {sigma:.2e}"
    );
    assert!(
        (m_view - m_again).abs() < 4.0 * sigma,
        "viewer {m_view} vs headless {m_again}, σ {sigma}"
    );
    assert!(
        (m_view - m_other).abs() < 4.0 * sigma * 2f64.sqrt(),
        "viewer {m_view} vs other seed {m_other}, σ {sigma}"
    );
    // The lighting, not only the noise, differs without the recorded environment: per pixel
    // the scene's own sky is further from the screenshot than another seed is.
    let rms = |x: &[f64], y: &[f64]| {
        (x.iter().zip(y).map(|(p, q)| (p - q).powi(2)).sum::<f64>() / x.len() as f64).sqrt()
    };
    let (noise, lighting) = (rms(&a, &b), rms(&a, &pixels(&own)));
    let same = rms(&a, &pixels(&again));
    eprintln!(
        "per-pixel rms: same seed {same:.4}, other seed {noise:.4}, scene's own sky {lighting:.4}"
    );
    // Same seed: the same paths (counter-based RNG), so far closer than another seed.
    assert!(same < 0.25 * noise, "same seed rms {same} vs noise {noise}");
    assert!(
        lighting > 3.0 * noise,
        "the sidecar without its environment renders alike: rms {lighting} vs noise {noise}"
    );
}

/// The environment round-trips through the sidecar's JSON; a sidecar naming a missing image
/// is an error naming the settings file and the image, not a silently different render.
#[test]
fn environment_round_trips_and_a_missing_image_is_an_error() {
    let dir = scratch_dir("json");
    let mut s = ViewerSettings::for_scene("builtin:env-spheres");
    s.environment = Some(refract::render::settings::EnvironmentSetting {
        uri: Some("no-such-sky.hdr".into()),
        strength: 0.5,
        rotation: -30.0,
    });
    let json = dir.join("side.json");
    s.save(&json).unwrap();
    assert_eq!(ViewerSettings::load(&json).unwrap(), s);
    let out = Command::new(env!("CARGO_BIN_EXE_refract"))
        .args(["render", "--quiet", "--spp", "1", "--settings"])
        .arg(&json)
        .arg("--out")
        .arg(dir.join("x.png"))
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("side.json") && err.contains("no-such-sky.hdr"),
        "{err}"
    );
}
