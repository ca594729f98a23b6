//! A scene path's folder is found the same way whatever form the path has (issue 41): a
//! `.gltf` with an external `.bin` and a texture loads by a bare file name, `./name`, a
//! relative path with folders, an absolute path, through a symbolic link to the file and
//! through a linked folder — and in every form the URI confinement still refuses `../` and
//! absolute URIs inside the file.
//!
//! The library checks change the process's current directory, so they are one test (the
//! only one in this binary that does); the command-line checks run `refract` in a test-made
//! current directory instead.

use refract::gltf_io::load::load_path;
use refract::scene::Scene;
use std::path::{Path, PathBuf};
use std::process::Command;

/// A fresh folder for one test.
fn folder(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("refract-paths-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

/// The bytes of one triangle: positions (36 bytes) then texture coordinates (24 bytes).
fn triangle_bytes() -> Vec<u8> {
    let positions = [[0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let uvs = [[0f32, 0.0], [1.0, 0.0], [0.0, 1.0]];
    let p = positions.iter().flatten();
    p.chain(uvs.iter().flatten())
        .flat_map(|v| v.to_le_bytes())
        .collect()
}

/// A .gltf named `file` in `dir`: one textured triangle whose buffer is `buffer_uri` and
/// whose base colour comes from `tex.png`, lit by an emissive material.
fn write_gltf(dir: &Path, file: &str, buffer_uri: &str) -> PathBuf {
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"TEXCOORD_0":1}},"material":0}}]}}],
        "accessors":[
          {{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}},
          {{"bufferView":1,"componentType":5126,"count":3,"type":"VEC2"}}],
        "bufferViews":[{{"buffer":0,"byteLength":36}},{{"buffer":0,"byteOffset":36,"byteLength":24}}],
        "buffers":[{{"uri":"{buffer_uri}","byteLength":60}}],
        "images":[{{"uri":"tex.png"}}],"textures":[{{"source":0}}],
        "materials":[{{"pbrMetallicRoughness":{{"baseColorTexture":{{"index":0}}}},
          "emissiveFactor":[1,1,1]}}]}}"#
    );
    let p = dir.join(file);
    std::fs::write(&p, json).expect("write gltf");
    p
}

/// A scene folder `root/sub` holding `scene.gltf` + `scene.bin` + `tex.png`, a `secret.bin`
/// beside `sub` (outside it), and two hostile files in `sub`: `up.gltf` reads `../secret.bin`,
/// `abs.gltf` reads it by its absolute path.
fn scene_folder(root: &Path) -> PathBuf {
    let sub = root.join("sub");
    std::fs::create_dir_all(&sub).expect("sub");
    std::fs::write(sub.join("scene.bin"), triangle_bytes()).expect("bin");
    std::fs::write(root.join("secret.bin"), triangle_bytes()).expect("secret");
    let texture = image::RgbaImage::from_pixel(2, 2, image::Rgba([200, 40, 10, 255]));
    texture.save(sub.join("tex.png")).expect("png");
    write_gltf(&sub, "scene.gltf", "scene.bin");
    write_gltf(&sub, "up.gltf", "../secret.bin");
    let abs = root.join("secret.bin").display().to_string();
    write_gltf(&sub, "abs.gltf", &abs);
    sub
}

/// The scene at `spec` loaded, with its external buffer and its texture.
fn assert_loads(spec: &str) {
    let s = Scene::load(spec).unwrap_or_else(|e| panic!("'{spec}' does not load: {e:#}"));
    assert_eq!(s.mesh.triangle_count(), 1, "'{spec}': the triangle");
    assert_eq!(
        s.textures.len(),
        1,
        "'{spec}': the texture ({:?})",
        s.warnings
    );
    assert!(s.warnings.is_empty(), "'{spec}': {:?}", s.warnings);
}

/// `spec` (a hostile file) is refused because its buffer lies outside its folder.
fn assert_refused(spec: &str) {
    match load_path(Path::new(spec)) {
        Ok(_) => panic!("'{spec}' loaded a buffer from outside its folder"),
        Err(e) => {
            let e = format!("{e:#}");
            assert!(e.contains("outside the scene's folder"), "'{spec}': {e}");
        }
    }
}

#[test]
fn every_form_of_a_scene_path_finds_its_folder_and_keeps_the_confinement() {
    let root = folder("forms");
    let sub = scene_folder(&root);
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink(sub.join("scene.gltf"), root.join("link.gltf")).expect("ln");
        std::os::unix::fs::symlink(sub.join("up.gltf"), root.join("up-link.gltf")).expect("ln");
        std::os::unix::fs::symlink(&sub, root.join("linked")).expect("ln dir");
    }
    let home = std::env::current_dir().expect("cwd");

    std::env::set_current_dir(&sub).expect("cd sub");
    for (good, bad) in [("scene.gltf", "up.gltf"), ("./scene.gltf", "./abs.gltf")] {
        assert_loads(good);
        assert_refused(bad);
    }
    assert_refused("abs.gltf");

    std::env::set_current_dir(&root).expect("cd root");
    assert_loads("sub/scene.gltf");
    assert_loads("sub/../sub/scene.gltf");
    assert_refused("sub/up.gltf");
    assert_loads(&sub.join("scene.gltf").display().to_string());
    assert_refused(&sub.join("abs.gltf").display().to_string());
    #[cfg(unix)]
    {
        assert_loads("link.gltf");
        assert_loads("linked/scene.gltf");
        assert_refused("up-link.gltf");
        assert_refused("linked/up.gltf");
    }
    std::env::set_current_dir(home).expect("cd back");
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn canonical_specs_name_the_same_file_from_anywhere() {
    let root = folder("canonical");
    let sub = scene_folder(&root);
    let spec = Scene::canonical_spec(&sub.join("./scene.gltf").display().to_string());
    assert!(Path::new(&spec).is_absolute(), "{spec}");
    assert_eq!(
        Path::new(&spec),
        std::fs::canonicalize(sub.join("scene.gltf")).expect("canonical")
    );
    assert_eq!(
        Scene::canonical_spec("builtin:caustic"),
        "builtin:caustic",
        "built-ins stay as they are"
    );
    assert_eq!(Scene::canonical_spec("no/such.gltf"), "no/such.gltf");
    let _ = std::fs::remove_dir_all(&root);
}

/// `refract ARGS` run in `dir`: (success, stderr).
fn refract_in(dir: &Path, args: &[&str]) -> (bool, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_refract"))
        .current_dir(dir)
        .args(args)
        .output()
        .expect("run refract");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn the_commands_open_a_bare_file_name_in_the_current_directory() {
    let root = folder("cli");
    let sub = scene_folder(&root);
    let size = ["--width", "8", "--height", "8"];
    let render = [
        &["render", "--scene", "scene.gltf", "--spp", "1"][..],
        &size[..],
    ]
    .concat();
    let (ok, err) = refract_in(&sub, &[&render[..], &["--out", "x.exr"]].concat());
    assert!(ok, "render of a bare name: {err}");
    assert!(sub.join("x.exr").is_file(), "render wrote no image");
    let render_up = [
        &["render", "--scene", "up.gltf", "--spp", "1"][..],
        &size[..],
    ]
    .concat();
    let (ok, err) = refract_in(&sub, &[&render_up[..], &["--out", "y.exr"]].concat());
    assert!(!ok && err.contains("outside the scene's folder"), "{err}");
    assert!(!err.contains("panicked"), "{err}");

    let trace = [
        "trace",
        "--scene",
        "scene.gltf",
        "--pixel",
        "4",
        "4",
        "--paths",
        "2",
    ];
    let (ok, err) = refract_in(&sub, &[&trace[..], &size[..]].concat());
    assert!(ok, "trace of a bare name: {err}");
    let _ = std::fs::remove_dir_all(&root);
}
