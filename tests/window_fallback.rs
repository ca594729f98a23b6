//! The viewer never panics while looking for a window surface (issue 39). Each test breaks
//! presentation on purpose — no Vulkan driver (`VK_ICD_FILENAMES` at nothing), no EGL vendor
//! (`__EGL_VENDOR_LIBRARY_FILENAMES` at nothing), an X server without GLX — and checks that
//! the viewer opens with whatever still presents (wgpu's GL backend, or glow), and where
//! nothing does, exits with one `error:` message and code 1: never a panic, never a signal.

mod common_scenes;
mod xvfb;

const NO_FILE: &str = "/nonexistent/refract-none.json";
/// No Vulkan driver at all (the loader's old and new variables).
const NO_VULKAN: [(&str, &str); 2] = [("VK_ICD_FILENAMES", NO_FILE), ("VK_DRIVER_FILES", NO_FILE)];
/// No EGL vendor library for glvnd to load.
const NO_EGL: (&str, &str) = ("__EGL_VENDOR_LIBRARY_FILENAMES", NO_FILE);

/// A short viewer run that exits by itself once it has a sample.
const VIEW: [&str; 6] = ["view", "--frames", "120", "--exit-after", "60s", "--device"];

/// The run succeeded and showed a rendered (non-black) image.
fn assert_shown(run: &xvfb::WindowRun, what: &str) {
    assert!(run.status.success(), "{what}: {}\n{}", run.status, run.log);
    assert!(
        !run.log.contains("panicked"),
        "{what}: a panic\n{}",
        run.log
    );
    assert!(run.shots > 0, "{what}: no screenshot could be taken");
    assert!(
        run.best > 20.0,
        "{what}: the window looked black ({:.1}/255)\n{}",
        run.best,
        run.log
    );
}

#[test]
fn without_vulkan_the_window_presents_with_gl() {
    let test = "without_vulkan_the_window_presents_with_gl";
    let setup = xvfb::Setup {
        server_args: &[],
        env: &NO_VULKAN,
    };
    let args = [&VIEW[..], &["cpu"]].concat();
    let Some(run) = xvfb::run_under_xvfb(test, &args, &setup) else {
        return;
    };
    assert_shown(&run, test);
    assert!(run.log.contains("display: "), "{}", run.log);
}

#[test]
fn without_vulkan_and_egl_glow_presents_and_the_cpu_renders() {
    let test = "without_vulkan_and_egl_glow_presents";
    let env = [NO_VULKAN[0], NO_VULKAN[1], NO_EGL];
    let setup = xvfb::Setup {
        server_args: &[],
        env: &env,
    };
    let args = [&VIEW[..], &["auto"]].concat();
    let Some(run) = xvfb::run_under_xvfb(test, &args, &setup) else {
        return;
    };
    assert_shown(&run, test);
    assert!(run.log.contains("display: OpenGL (glow)"), "{}", run.log);
    assert!(run.log.contains("render: CPU"), "{}", run.log);
}

#[test]
fn glow_with_the_gpu_rendering_headless_shows_its_image() {
    let test = "glow_with_the_gpu_rendering_headless";
    if common_scenes::gpu_context(test).is_none() {
        return;
    }
    let args = [
        "view",
        "--window-renderer",
        "glow",
        "--device",
        "gpu",
        "--frames",
        "10",
        "--exit-after",
        "100s",
    ];
    let Some(run) = xvfb::run_under_xvfb(test, &args, &xvfb::Setup::default()) else {
        return;
    };
    assert_shown(&run, test);
    assert!(run.log.contains("headless, image read back"), "{}", run.log);
    assert!(run.log.contains("display: OpenGL (glow)"), "{}", run.log);
    assert!(
        !run.log.contains(" 0 spp "),
        "closed before a sample:\n{}",
        run.log
    );
}

#[test]
fn when_nothing_presents_the_error_lists_what_was_tried() {
    let test = "when_nothing_presents";
    let env = [NO_VULKAN[0], NO_VULKAN[1], NO_EGL];
    let setup = xvfb::Setup {
        server_args: &["-extension", "GLX"],
        env: &env,
    };
    let args = [&VIEW[..], &["gpu"]].concat();
    let Some(run) = xvfb::run_under_xvfb(test, &args, &setup) else {
        return;
    };
    assert_eq!(
        run.status.code(),
        Some(1),
        "exit code 1, no signal:\n{}",
        run.log
    );
    assert!(
        !run.log.contains("panicked"),
        "a panic reached the user:\n{}",
        run.log
    );
    let errors: Vec<&str> = run
        .log
        .lines()
        .filter(|l| l.starts_with("error: "))
        .collect();
    assert_eq!(errors.len(), 1, "one error line:\n{}", run.log);
    assert!(
        errors[0].contains("cannot open the viewer window"),
        "{}",
        run.log
    );
    for tried in ["wgpu:vulkan", "wgpu:gl", "glow"] {
        assert!(
            run.log.contains(tried),
            "'{tried}' not reported:\n{}",
            run.log
        );
    }
    assert!(
        run.log.contains("refract render"),
        "no way out named:\n{}",
        run.log
    );
}

#[test]
fn an_excluded_backend_is_not_probed() {
    let test = "an_excluded_backend_is_not_probed";
    let env = [NO_VULKAN[0], NO_VULKAN[1], ("WGPU_BACKEND", "vulkan")];
    let setup = xvfb::Setup {
        server_args: &[],
        env: &env,
    };
    let args = [&VIEW[..], &["cpu"]].concat();
    let Some(run) = xvfb::run_under_xvfb(test, &args, &setup) else {
        return;
    };
    assert_eq!(run.status.code(), Some(1), "{}", run.log);
    assert!(run.log.contains("wgpu:vulkan"), "{}", run.log);
    assert!(
        !run.log.contains("wgpu:gl") && !run.log.contains("  glow"),
        "{}",
        run.log
    );
    assert!(run.log.contains("WGPU_BACKEND=vulkan"), "{}", run.log);
}

/// A presenter whose probe crashes (a driver's abort, injected) or panics is reported and the
/// next one presents: the crash never reaches the user.
#[test]
fn a_probe_that_crashes_or_panics_is_skipped() {
    for fault in ["abort", "panic"] {
        let test = format!("a_probe_that_{fault}s");
        let inject = format!("wgpu:gl={fault}");
        let env = [
            NO_VULKAN[0],
            NO_VULKAN[1],
            ("REFRACT_TEST_PROBE_FAULT", inject.as_str()),
        ];
        let setup = xvfb::Setup {
            server_args: &[],
            env: &env,
        };
        let args = [&VIEW[..], &["cpu"]].concat();
        let Some(run) = xvfb::run_under_xvfb(&test, &args, &setup) else {
            return;
        };
        assert_shown(&run, &test);
        assert!(run.log.contains("display: OpenGL (glow)"), "{}", run.log);
    }
}

/// Where nothing else presents, the crashed probe is named in the error, with its signal.
#[test]
fn a_crashed_probe_is_named_in_the_error() {
    let test = "a_crashed_probe_is_named";
    let setup = xvfb::Setup {
        server_args: &[],
        env: &[("REFRACT_TEST_PROBE_FAULT", "glow=abort")],
    };
    let args = [&VIEW[..], &["cpu", "--window-renderer", "glow"]].concat();
    let Some(run) = xvfb::run_under_xvfb(test, &args, &setup) else {
        return;
    };
    assert_eq!(run.status.code(), Some(1), "{}", run.log);
    assert!(
        run.log.contains("glow: crashed with signal 6"),
        "{}",
        run.log
    );
    assert!(!run.log.contains("panicked"), "{}", run.log);
}
