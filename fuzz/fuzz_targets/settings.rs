//! Fuzz target for the settings sidecar: any byte string is parsed, checked and applied to a
//! built-in scene as `render --settings` does — an error or a scene that validates, never a
//! panic. Run: `cargo fuzz run settings -- -max_total_time=60` (seeds: any screenshot sidecar).
#![no_main]

use libfuzzer_sys::fuzz_target;
use refract::render::settings::ViewerSettings;
use refract::scene::Scene;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(s) = ViewerSettings::parse(text) else {
        return;
    };
    if s.materials.iter().any(|m| m.check().is_err()) || s.light.check().is_err() {
        return;
    }
    let base = Scene::load("builtin:cornell-glass").expect("built-in");
    let (scene, _warnings) = s.apply(&base);
    // Light edits may overflow emission: that is an error `render` reports, not a panic.
    let _ = scene.validate();
});
