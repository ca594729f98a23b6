//! How the viewer's window presents (issue 39): which renderer eframe draws it with, the
//! order they are tried, and what each one said.
//!
//! eframe draws with wgpu (Vulkan, Metal, DX12 or its GL backend) or with glow (OpenGL through
//! glutin: GLX or EGL). Which of them can present to a window depends on the machine: an
//! NVIDIA GPU under Xvfb has no Vulkan surface for it and its EGL returns no X11 display (wgpu's
//! GL backend then panics inside `khronos-egl`); a remote desktop may have GLX and no Vulkan.
//! So the viewer tries [`Presenter`]s in the order of [`plan`]:
//!
//! 1. wgpu with its primary backends (or exactly the ones `WGPU_BACKEND` names), in this
//!    process. Its failure is a clean error, after which eframe's event loop can run again.
//! 2. wgpu's GL backend, then glow. Each is first *probed* in a child process (`refract
//!    __probe-window`, [`probe_window`]): a GL probe may panic or crash inside a driver, and
//!    winit keeps one event loop per process, which a panic inside it leaves unable to start
//!    again. Only a presenter whose probe opened a window runs in this process.
//!
//! A backend the user excluded with `WGPU_BACKEND` is not probed: `WGPU_BACKEND=vulkan`
//! excludes wgpu's GL and glow. `--window-renderer glow|wgpu` names one presenter. When
//! nothing presents, the error lists every presenter tried and what it said, what to set,
//! and that `refract render` still works. A panic that escapes a presenter in this process is
//! caught and becomes that presenter's error (its message is kept, not printed, until the
//! viewer is running); a crash by a signal is caught only where the presenter was probed in a
//! child, which is why the risky ones are.

use anyhow::{Result, anyhow};
use eframe::egui;
use eframe::wgpu::Backends;
use std::io::Read;
use std::panic::{self, AssertUnwindSafe, PanicHookInfo};
use std::process::{Command, ExitStatus, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// `--window-renderer`: what draws the viewer's window.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum WindowRenderer {
    /// wgpu's primary backends, then wgpu's GL backend, then glow: the first that presents.
    #[default]
    Auto,
    /// wgpu only (`WGPU_BACKEND` picks its backends).
    Wgpu,
    /// eframe's OpenGL renderer (glow, through GLX or EGL); the GPU renderer then runs
    /// headless and its image is copied through the CPU.
    Glow,
}

/// One way to present the window.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Presenter {
    /// eframe's wgpu renderer on these backends.
    Wgpu(Backends),
    /// eframe's glow renderer (OpenGL).
    Glow,
}

impl Presenter {
    /// Its name in messages and on the probe's command line: `wgpu:vulkan,gl`, `glow`.
    pub fn key(self) -> String {
        match self {
            Presenter::Glow => "glow".to_owned(),
            Presenter::Wgpu(b) => format!("wgpu:{}", backend_names(b)),
        }
    }

    /// The presenter a [`Presenter::key`] names.
    pub fn from_key(key: &str) -> Result<Presenter> {
        match key.split_once(':') {
            None if key == "glow" => Ok(Presenter::Glow),
            Some(("wgpu", list)) if !Backends::from_comma_list(list).is_empty() => {
                Ok(Presenter::Wgpu(Backends::from_comma_list(list)))
            }
            _ => Err(anyhow!(
                "unknown window presenter '{key}' (expected glow or wgpu:BACKENDS)"
            )),
        }
    }

    /// True where trying it may panic or crash inside a driver (GL: EGL and GLX probing), so
    /// it is probed in a child process first.
    fn risky(self) -> bool {
        match self {
            Presenter::Glow => true,
            Presenter::Wgpu(b) => b.contains(Backends::GL),
        }
    }

    /// eframe's options for this presenter around `viewport`.
    pub fn native_options(self, viewport: egui::ViewportBuilder) -> eframe::NativeOptions {
        let mut o = eframe::NativeOptions {
            viewport,
            ..Default::default()
        };
        match self {
            Presenter::Glow => o.renderer = eframe::Renderer::Glow,
            Presenter::Wgpu(b) => {
                o.renderer = eframe::Renderer::Wgpu;
                o.wgpu_options = super::wgpu_setup::wgpu_configuration_on(b);
            }
        }
        o
    }
}

/// `b` as `WGPU_BACKEND` spells it (`vulkan,gl`).
fn backend_names(b: Backends) -> String {
    let names = [
        (Backends::VULKAN, "vulkan"),
        (Backends::METAL, "metal"),
        (Backends::DX12, "dx12"),
        (Backends::GL, "gl"),
        (Backends::BROWSER_WEBGPU, "webgpu"),
    ];
    let named: Vec<&str> = names
        .iter()
        .filter(|(f, _)| b.contains(*f))
        .map(|(_, n)| *n)
        .collect();
    named.join(",")
}

/// wgpu's primary backends that exist on this platform.
fn native_primary() -> Backends {
    if cfg!(target_vendor = "apple") {
        Backends::METAL
    } else if cfg!(windows) {
        Backends::DX12 | Backends::VULKAN
    } else {
        Backends::VULKAN
    }
}

/// The presenters to try, in order, for `choice` and the user's `WGPU_BACKEND` (`env`).
pub fn plan(choice: WindowRenderer, env: Option<Backends>) -> Vec<Presenter> {
    let primary = native_primary();
    let wgpu: Vec<Presenter> = match env {
        Some(b) => vec![Presenter::Wgpu(b)],
        None => vec![Presenter::Wgpu(primary), Presenter::Wgpu(Backends::GL)],
    };
    // glow is OpenGL: a WGPU_BACKEND without GL excluded it.
    let glow_allowed = env.is_none_or(|b| b.contains(Backends::GL));
    match choice {
        WindowRenderer::Glow => vec![Presenter::Glow],
        WindowRenderer::Wgpu => wgpu,
        WindowRenderer::Auto if glow_allowed => [wgpu, vec![Presenter::Glow]].concat(),
        WindowRenderer::Auto => wgpu,
    }
}

/// What trying one presenter came to.
pub enum Outcome {
    /// The viewer ran (Ok) or failed for a reason no other presenter would change.
    Done(Result<()>),
    /// This presenter could not present; the reason. `poisoned`: a panic ran through the
    /// event loop, which cannot start again in this process.
    CannotPresent { why: String, poisoned: bool },
}

/// Whether `p` must be probed in a child before it runs here (`index` in the plan).
pub fn needs_probe(p: Presenter, index: usize) -> bool {
    index > 0 || p.risky()
}

/// Run eframe with `options`; `create` makes the app once the window presents. Panics are
/// caught: before the app exists they are this presenter's failure (message kept quiet),
/// afterwards they end the viewer with an error (message printed as usual).
pub fn run_guarded(
    app_name: &str,
    options: eframe::NativeOptions,
    create: eframe::AppCreator<'_>,
    created: &Arc<AtomicBool>,
) -> Outcome {
    let hook = QuietPanics::install(Arc::clone(created));
    let result = panic::catch_unwind(AssertUnwindSafe(|| {
        eframe::run_native(app_name, options, create)
    }));
    let last = hook.last_message();
    drop(hook);
    let running = created.load(Ordering::SeqCst);
    match result {
        Ok(Ok(())) => Outcome::Done(Ok(())),
        Ok(Err(e)) if running => Outcome::Done(Err(anyhow!("the viewer stopped: {e}"))),
        Ok(Err(eframe::Error::AppCreation(e))) => Outcome::Done(Err(anyhow!("{e}"))),
        Ok(Err(eframe::Error::WinitEventLoop(e))) => Outcome::Done(Err(anyhow!(
            "cannot open a window: {e} (no X11 or Wayland display: is DISPLAY or \
             WAYLAND_DISPLAY set?); `refract render` renders without one"
        ))),
        Ok(Err(eframe::Error::NoGlutinConfigs(_, e))) => Outcome::CannotPresent {
            why: format!("no OpenGL configuration for the window: {e}"),
            poisoned: false,
        },
        Ok(Err(e)) => Outcome::CannotPresent {
            why: explain(&e.to_string()),
            poisoned: false,
        },
        Err(payload) => {
            let msg = last.unwrap_or_else(|| payload_text(payload.as_ref()));
            if running {
                Outcome::Done(Err(anyhow!(
                    "the viewer stopped on an internal error: {msg}"
                )))
            } else {
                Outcome::CannotPresent {
                    why: format!("panicked: {msg}"),
                    poisoned: true,
                }
            }
        }
    }
}

/// eframe's error text, with what it means where wgpu's is cryptic: a surface "for any
/// enabled backend: {}" failed because none of the backends started (no driver).
fn explain(text: &str) -> String {
    if text.contains("Failed to create surface for any enabled backend: {}") {
        format!(
            "{text} (no driver of these backends started: none installed, or it cannot reach this display)"
        )
    } else {
        text.to_owned()
    }
}

/// A panic payload's text.
fn payload_text(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_owned()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "a panic without a message".to_owned()
    }
}

type Hook = Box<dyn Fn(&PanicHookInfo<'_>) + Sync + Send + 'static>;

/// A panic hook that records the last panic's message and location, and prints it (through
/// the previous hook) only once `loud` is set; the previous hook is back when dropped.
pub struct QuietPanics {
    last: Arc<Mutex<Option<String>>>,
    previous: Arc<Hook>,
}

impl QuietPanics {
    pub fn install(loud: Arc<AtomicBool>) -> QuietPanics {
        let previous: Arc<Hook> = Arc::new(panic::take_hook());
        let last = Arc::new(Mutex::new(None));
        let (prev, store) = (Arc::clone(&previous), Arc::clone(&last));
        panic::set_hook(Box::new(move |info| {
            let msg = payload_text(info.payload());
            let at = info.location().map_or(String::new(), |l| {
                format!(" (at {}:{})", l.file(), l.line())
            });
            if let Ok(mut slot) = store.lock() {
                *slot = Some(format!("{msg}{at}"));
            }
            if loud.load(Ordering::SeqCst) {
                prev(info);
            }
        }));
        QuietPanics { last, previous }
    }

    /// The message of the last panic since `install`.
    pub fn last_message(&self) -> Option<String> {
        self.last.lock().ok().and_then(|s| s.clone())
    }
}

impl Drop for QuietPanics {
    fn drop(&mut self) {
        let previous = Arc::clone(&self.previous);
        panic::set_hook(Box::new(move |info| previous(info)));
    }
}

/// How long a probe may take before it counts as hung.
const PROBE_TIMEOUT: Duration = Duration::from_secs(30);

/// Probe `p` in a child process (`refract __probe-window KEY`): Ok when it opened a window,
/// else what it said, or how it died.
pub fn probe_in_child(p: Presenter) -> Result<(), String> {
    let exe = std::env::current_exe().map_err(|e| format!("cannot find refract itself: {e}"))?;
    let mut child = Command::new(exe)
        .args(["__probe-window", &p.key()])
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| format!("cannot start the probe: {e}"))?;
    let mut stderr = child.stderr.take();
    let reader = std::thread::spawn(move || {
        let mut text = String::new();
        if let Some(s) = stderr.as_mut() {
            let _ = s.read_to_string(&mut text);
        }
        text
    });
    let started = Instant::now();
    let status = loop {
        match child.try_wait() {
            Ok(Some(status)) => break Some(status),
            Ok(None) if started.elapsed() > PROBE_TIMEOUT => {
                let _ = child.kill();
                let _ = child.wait();
                break None;
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(10)),
            Err(e) => return Err(format!("cannot wait for the probe: {e}")),
        }
    };
    let said = reader.join().unwrap_or_default();
    match status {
        Some(s) if s.success() => Ok(()),
        Some(s) => Err(probe_failure(s, &said)),
        None => Err(format!(
            "the probe hung for {} s and was stopped",
            PROBE_TIMEOUT.as_secs()
        )),
    }
}

/// Why a probe that exited with `status` after printing `said` failed.
fn probe_failure(status: ExitStatus, said: &str) -> String {
    let lines: Vec<&str> = said
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect();
    let text = lines
        .iter()
        .rev()
        .find_map(|l| l.strip_prefix("error: "))
        .or(lines.last().copied())
        .unwrap_or("no message")
        .to_owned();
    #[cfg(unix)]
    {
        use std::os::unix::process::ExitStatusExt as _;
        if let Some(sig) = status.signal() {
            return format!("crashed with signal {sig} ({text})");
        }
    }
    match status.code() {
        Some(1) => text,
        Some(c) => format!("exited with code {c} ({text})"),
        None => text,
    }
}

/// The probe itself (in the child): open a small hidden window with `key`'s presenter and
/// close it at the first frame. Ok when the window presented.
pub fn probe_window(key: &str) -> Result<()> {
    let p = Presenter::from_key(key)?;
    let viewport = egui::ViewportBuilder::default()
        .with_title("refract — probing the display")
        .with_inner_size([64.0, 64.0])
        .with_visible(false);
    let created = Arc::new(AtomicBool::new(false));
    let flag = Arc::clone(&created);
    let fault = injected_fault(key);
    let create: eframe::AppCreator<'_> = Box::new(move |_cc| {
        match fault.as_deref() {
            Some("panic") => panic!("injected probe panic ({FAULT_VAR})"),
            Some("abort") => std::process::abort(),
            _ => {}
        }
        flag.store(true, Ordering::SeqCst);
        Ok(Box::new(CloseAtOnce))
    });
    let mut options = p.native_options(viewport);
    // Its own storage, and no window geometry saved: the viewer's must not become 64×64.
    options.persist_window = false;
    match run_guarded("refract-probe", options, create, &created) {
        Outcome::Done(r) => r,
        Outcome::CannotPresent { why, .. } => Err(anyhow!(why)),
    }
}

/// Fault injection for the tests of this module's guards: `KEY=panic` or `KEY=abort` makes
/// the probe of presenter KEY panic or abort once its window presents, as a driver might.
const FAULT_VAR: &str = "REFRACT_TEST_PROBE_FAULT";

/// The fault [`FAULT_VAR`] injects into the probe of `key`, if any.
fn injected_fault(key: &str) -> Option<String> {
    let spec = std::env::var(FAULT_VAR).ok()?;
    let (k, fault) = spec.split_once('=')?;
    (k == key).then(|| fault.to_owned())
}

/// The probe's app: closes its window at the first frame.
struct CloseAtOnce;

impl eframe::App for CloseAtOnce {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        ui.ctx().send_viewport_cmd(egui::ViewportCommand::Close);
    }
}

/// The error when no presenter could present: each one tried and what it said.
pub fn nothing_presents(tried: &[(Presenter, String)], env: Option<Backends>) -> anyhow::Error {
    let mut text = String::from("cannot open the viewer window: no renderer could present to it");
    for (p, why) in tried {
        text.push_str(&format!("\n  {}: {why}", p.key()));
    }
    let env_note = match env {
        Some(b) => format!(
            "WGPU_BACKEND={} limits wgpu to those backends; unset it to try the others",
            backend_names(b)
        ),
        None => "set WGPU_BACKEND (vulkan, gl) to try one wgpu backend".to_owned(),
    };
    text.push_str(&format!(
        "\nTry: {env_note}; `--window-renderer glow` for OpenGL; `--device cpu` to render on \
         the CPU; or render without a window: `refract render --scene … --out image.exr` \
         works here still."
    ));
    anyhow!(text)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_round_trip() {
        for p in [
            Presenter::Glow,
            Presenter::Wgpu(Backends::GL),
            Presenter::Wgpu(Backends::VULKAN | Backends::GL),
        ] {
            assert_eq!(Presenter::from_key(&p.key()).expect("key"), p);
        }
        assert!(Presenter::from_key("wgpu:").is_err());
        assert!(Presenter::from_key("vulkan").is_err());
    }

    #[test]
    fn an_excluded_backend_is_not_planned() {
        let vk = plan(WindowRenderer::Auto, Some(Backends::VULKAN));
        assert_eq!(
            vk,
            vec![Presenter::Wgpu(Backends::VULKAN)],
            "no GL, no glow"
        );
        let gl = plan(WindowRenderer::Auto, Some(Backends::GL));
        assert_eq!(gl, vec![Presenter::Wgpu(Backends::GL), Presenter::Glow]);
        let auto = plan(WindowRenderer::Auto, None);
        assert_eq!(auto[0], Presenter::Wgpu(native_primary()), "primary first");
        assert!(
            !needs_probe(auto[0], 0),
            "the usual start-up spawns nothing"
        );
        assert!(
            auto[1..]
                .iter()
                .enumerate()
                .all(|(i, p)| needs_probe(*p, i + 1))
        );
        assert_eq!(plan(WindowRenderer::Glow, None), vec![Presenter::Glow]);
    }

    #[test]
    fn a_probe_failure_names_the_error_line_or_the_signal() {
        use std::os::unix::process::ExitStatusExt as _;
        let said = "warning: x\nerror: no GLX\n";
        assert_eq!(probe_failure(ExitStatus::from_raw(1 << 8), said), "no GLX");
        let crashed = probe_failure(ExitStatus::from_raw(11), "");
        assert!(crashed.contains("signal 11"), "{crashed}");
    }
}
