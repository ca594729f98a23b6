//! Fuzz target for the glTF loader: any byte string either loads into a scene that passes
//! `Scene::validate` or is rejected with an error — never a panic, hang or abort.
//! Run: `cargo fuzz run gltf_load -- -max_total_time=60` (seeds: `assets/*.glb`).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(scene) = refract::gltf_io::load::load_slice(data, None, "fuzz") {
        scene
            .validate()
            .expect("a scene the loader accepts must validate");
    }
});
