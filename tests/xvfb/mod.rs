//! `refract view` in a real window under a fresh Xvfb server, screenshots taken while it runs
//! (shared by `viewer.rs` and `window_fallback.rs`).

use std::path::{Path, PathBuf};
use std::process::{Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

/// Find an executable on PATH.
pub fn which(name: &str) -> Option<PathBuf> {
    std::env::var_os("PATH").and_then(|p| {
        std::env::split_paths(&p)
            .map(|d| d.join(name))
            .find(|f| f.is_file())
    })
}

/// Mean brightness (0–255) of a PNG.
pub fn png_mean(path: &Path) -> Option<f64> {
    let img = image::open(path).ok()?.into_rgb8();
    let n = (img.width() * img.height()) as f64;
    Some(
        img.pixels()
            .map(|p| (p[0] as f64 + p[1] as f64 + p[2] as f64) / 3.0)
            .sum::<f64>()
            / n,
    )
}

/// What one run of the real window under Xvfb produced.
pub struct WindowRun {
    pub status: ExitStatus,
    /// Its standard error.
    pub log: String,
    /// Best mean brightness over the screenshots taken while it ran.
    pub best: f64,
    pub shots: usize,
}

/// How to run it: extra arguments of the X server, and environment variables of the viewer.
#[derive(Default)]
pub struct Setup<'a> {
    pub server_args: &'a [&'a str],
    pub env: &'a [(&'a str, &'a str)],
}

/// A fresh scratch folder for `test`.
pub fn scratch_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("refract-xvfb-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("scratch dir");
    d
}

/// Run `refract ARGS` in a fresh Xvfb server set up by `setup`, taking screenshots until it
/// exits. None (with a SKIP message) where Xvfb or ImageMagick's `import` is missing; CI
/// installs both.
pub fn run_under_xvfb(test: &str, args: &[&str], setup: &Setup<'_>) -> Option<WindowRun> {
    let (Some(xvfb), Some(import)) = (which("Xvfb"), which("import")) else {
        assert!(
            std::env::var_os("REFRACT_REQUIRE_GPU").is_none(),
            "CI must run the window test: Xvfb and ImageMagick are required"
        );
        eprintln!("SKIPPED {test}: Xvfb or ImageMagick `import` is not installed");
        return None;
    };
    let dir = scratch_dir(test);
    // A display number per test and process (tests run in parallel).
    let offset = test.bytes().map(u32::from).sum::<u32>() % 7;
    let display = format!(":{}", 90 + (std::process::id() % 50) * 7 + offset);
    let mut server = Command::new(xvfb)
        .args([display.as_str(), "-screen", "0", "1280x860x24", "-br"])
        .args(["-nolisten", "tcp"])
        .args(setup.server_args)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("start Xvfb");
    std::thread::sleep(Duration::from_millis(1500));
    let runtime = dir.join("runtime");
    std::fs::create_dir_all(&runtime).expect("runtime dir");
    let mut viewer = Command::new(env!("CARGO_BIN_EXE_refract"))
        .args(args)
        .env("DISPLAY", &display)
        .env("XDG_RUNTIME_DIR", &runtime)
        .env("HOME", &dir) // keep the persisted settings out of the user's home
        .env_remove("WAYLAND_DISPLAY")
        .envs(setup.env.iter().copied())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start refract view");
    let mut stderr = viewer.stderr.take().expect("piped stderr");
    let reader = std::thread::spawn(move || {
        let mut log = String::new();
        let _ = std::io::Read::read_to_string(&mut stderr, &mut log);
        log
    });
    let start = Instant::now();
    let mut best = 0.0f64;
    let mut shots = 0;
    let status = loop {
        if let Some(st) = viewer.try_wait().expect("wait for refract") {
            break st;
        }
        if start.elapsed() > Duration::from_secs(150) {
            let _ = viewer.kill();
            let _ = server.kill();
            panic!("refract {args:?} did not exit within 150 s");
        }
        std::thread::sleep(Duration::from_millis(700));
        let shot = dir.join(format!("shot-{shots}.png"));
        let ok = Command::new(&import)
            .args(["-display", display.as_str(), "-window", "root"])
            .arg(&shot)
            .stderr(Stdio::null())
            .status()
            .is_ok_and(|s| s.success());
        if ok {
            shots += 1;
            best = best.max(png_mean(&shot).unwrap_or(0.0));
        }
    };
    let log = reader.join().unwrap_or_default();
    let _ = server.kill();
    let _ = server.wait();
    Some(WindowRun {
        status,
        log,
        best,
        shots,
    })
}
