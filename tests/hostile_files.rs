//! Files a hostile or broken glTF may name (issue 16, "hangs and unbounded reads"): only
//! regular files are read (a FIFO would block forever, `/dev/zero` never ends), never more
//! than `byteLength` (and a shorter file is an error), and URIs only inside the scene's folder
//! (absolute paths, `..` and symbolic links out of it are refused). Every case is an error or
//! a warning naming its source, never a hang or a panic.

use refract::gltf_io::load::{LoadLimits, load_path, load_path_with};
use refract::scene::Scene;
use std::path::{Path, PathBuf};

/// A fresh folder for one test.
fn folder(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("refract-hostile-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

/// The 36 bytes of one triangle's positions.
fn triangle_bytes() -> Vec<u8> {
    [[0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
        .iter()
        .flatten()
        .flat_map(|v| v.to_le_bytes())
        .collect()
}

/// A .gltf with one triangle whose buffer is `uri` of `byte_length` bytes, and optionally a
/// base-colour texture from `image_uri`.
fn gltf(dir: &Path, uri: &str, byte_length: usize, image_uri: Option<&str>) -> PathBuf {
    let texture = image_uri.map_or(String::new(), |u| {
        format!(
            r#","images":[{{"uri":"{u}"}}],"textures":[{{"source":0}}],
            "materials":[{{"pbrMetallicRoughness":{{"baseColorTexture":{{"index":0}}}}}}]"#
        )
    });
    let material = if image_uri.is_some() {
        r#","material":0"#
    } else {
        ""
    };
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}{material}}}]}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}}],
        "bufferViews":[{{"buffer":0,"byteLength":36}}],
        "buffers":[{{"uri":"{uri}","byteLength":{byte_length}}}]{texture}}}"#
    );
    let p = dir.join("scene.gltf");
    std::fs::write(&p, json).expect("write gltf");
    p
}

fn err(p: &Path) -> String {
    match load_path(p) {
        Ok(_) => panic!("{} loaded", p.display()),
        Err(e) => format!("{e:#}"),
    }
}

#[test]
fn a_good_file_loads_and_a_longer_buffer_is_cut_to_byte_length() {
    let d = folder("good");
    let mut bytes = triangle_bytes();
    std::fs::write(d.join("tri.bin"), &bytes).expect("bin");
    let s = load_path(&gltf(&d, "tri.bin", 36, None)).expect("a valid file loads");
    assert_eq!(s.mesh.triangle_count(), 1);
    bytes.extend([0xffu8; 64]);
    std::fs::write(d.join("long.bin"), &bytes).expect("bin");
    let s = load_path(&gltf(&d, "long.bin", 36, None)).expect("extra bytes are ignored");
    assert_eq!(s.mesh.triangle_count(), 1);
}

#[test]
fn a_short_buffer_is_an_error_naming_byte_length() {
    let d = folder("short");
    std::fs::write(d.join("tri.bin"), triangle_bytes()).expect("bin");
    let e = err(&gltf(&d, "tri.bin", 1000, None));
    assert!(
        e.contains("buffer 0") && e.contains("byteLength is 1000"),
        "{e}"
    );
}

#[test]
fn pipes_and_devices_are_refused_without_reading() {
    let d = folder("fifo");
    let fifo = d.join("pipe.bin");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    if made.is_ok_and(|s| s.success()) {
        // Opening a FIFO for reading would block forever: it must be refused before that.
        let e = err(&gltf(&d, "pipe.bin", 36, None));
        assert!(
            e.contains("not a regular file") && e.contains("pipe.bin"),
            "{e}"
        );
        let e = format!(
            "{:#}",
            Scene::load(&fifo.display().to_string()).expect_err("a FIFO as the scene")
        );
        assert!(e.contains("not a regular file"), "{e}");
    } else {
        eprintln!("SKIP fifo half: no mkfifo");
    }
    let e = format!(
        "{:#}",
        Scene::load("/dev/zero").expect_err("/dev/zero as the scene")
    );
    assert!(
        e.contains("not a regular file") && e.contains("/dev/zero"),
        "{e}"
    );
}

#[test]
fn uris_outside_the_scene_folder_are_refused() {
    let d = folder("outside");
    let inner = d.join("scene");
    std::fs::create_dir_all(&inner).expect("dir");
    std::fs::write(d.join("secret.bin"), triangle_bytes()).expect("secret");
    for uri in ["../secret.bin", "/dev/zero", "%2E%2E/secret.bin"] {
        let e = err(&gltf(&inner, uri, 36, None));
        assert!(
            e.contains("outside the scene's folder") || e.contains("not a regular file"),
            "{uri}: {e}"
        );
    }
    let abs = d.join("secret.bin");
    let e = err(&gltf(&inner, &abs.display().to_string(), 36, None));
    assert!(e.contains("outside the scene's folder"), "absolute: {e}");
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink(d.join("secret.bin"), inner.join("link.bin")).expect("symlink");
        let e = err(&gltf(&inner, "link.bin", 36, None));
        assert!(e.contains("outside the scene's folder"), "symlink: {e}");
    }
}

#[test]
fn an_image_outside_the_folder_is_refused_with_a_warning() {
    let d = folder("image");
    std::fs::write(d.join("tri.bin"), triangle_bytes()).expect("bin");
    let s = load_path(&gltf(&d, "tri.bin", 36, Some("/etc/hostname")))
        .expect("the geometry still loads");
    let w = s.warnings.join("\n");
    assert!(
        w.contains("outside the scene's folder") && w.contains("image 0"),
        "{w}"
    );
}

/// One policy for "nothing to render": a scene whose every triangle is dropped (zero area) is
/// an error saying so, like one whose primitives are all skipped (before: black, exit 0).
#[test]
fn a_scene_whose_triangles_are_all_dropped_is_an_error() {
    let d = folder("degenerate");
    let collinear: Vec<u8> = [[0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]]
        .iter()
        .flatten()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    std::fs::write(d.join("tri.bin"), collinear).expect("bin");
    let e = err(&gltf(&d, "tri.bin", 36, None));
    assert!(
        e.contains("no usable triangles") && e.contains("zero-area"),
        "{e}"
    );
}

/// `KHR_materials_ior` that is not a positive finite number is an error naming its JSON
/// pointer (docs/scene-contract.md: invalid IOR is an error; before: a warning and 1.5).
#[test]
fn a_non_positive_ior_is_an_error_naming_its_json_pointer() {
    let d = folder("ior");
    std::fs::write(d.join("tri.bin"), triangle_bytes()).expect("bin");
    let p = gltf(&d, "tri.bin", 36, None);
    let text = std::fs::read_to_string(&p).expect("gltf");
    for bad in ["-1.0", "0.0"] {
        let json = text.replace(
            r#""buffers""#,
            &format!(
                r#""extensionsUsed":["KHR_materials_ior"],"materials":[{{"extensions":{{"KHR_materials_ior":{{"ior":{bad}}}}}}}],"buffers""#
            ),
        );
        std::fs::write(&p, json).expect("gltf");
        let e = err(&p);
        assert!(
            e.contains("/materials/0/extensions/KHR_materials_ior/ior"),
            "ior {bad}: {e}"
        );
    }
}

/// `text` with `from` replaced by `to` (which must be present).
fn edit(text: &str, from: &str, to: &str) -> String {
    assert!(text.contains(from), "{from} not in the file");
    text.replacen(from, to, 1)
}

/// Values that would silently break the render are errors naming their JSON source:
/// emission that overflows f32 light power, `extras` nested beyond what can be read (before,
/// every render setting in it was dropped silently), and a projective node matrix (a warning
/// and the node skipped — here the only node, so nothing is left to render).
#[test]
fn silently_broken_values_name_their_source() {
    let d = folder("values");
    std::fs::write(d.join("tri.bin"), triangle_bytes()).expect("bin");
    let p = gltf(&d, "tri.bin", 36, None);
    let text = std::fs::read_to_string(&p).expect("gltf");
    let hot = edit(
        &text,
        r#""buffers""#,
        r#""materials":[{"emissiveFactor":[1,1,1],"extensions":{"KHR_materials_emissive_strength":{"emissiveStrength":3e38}}}],"buffers""#,
    );
    std::fs::write(&p, hot).expect("gltf");
    let e = err(&p);
    assert!(
        e.contains("/materials/0/emissiveFactor") && e.contains("overflows"),
        "{e}"
    );
    let deep = format!("{}1{}", "[".repeat(200), "]".repeat(200));
    let nested = edit(
        &text,
        r#""scenes":[{"nodes":[0]}]"#,
        &format!(r#""scenes":[{{"nodes":[0],"extras":{{"render":{{"width":0}},"deep":{deep}}}}}]"#),
    );
    std::fs::write(&p, nested).expect("gltf");
    let e = err(&p);
    assert!(e.contains("/scenes/0/extras"), "{e}");
    let projective = edit(
        &text,
        r#""nodes":[{"mesh":0}]"#,
        r#""nodes":[{"mesh":0,"matrix":[1,0,0,0.5, 0,1,0,0, 0,0,1,0, 0,0,0,1]}]"#,
    );
    std::fs::write(&p, projective).expect("gltf");
    let e = err(&p);
    assert!(e.contains("no triangles"), "{e}");
}

/// Budgets checked before allocating (issue 16, class 2): 100,000 nodes instancing one
/// 1,000-triangle mesh (100 M triangles, more than the 100 M budget allows with the mesh's own
/// node) and an accessor without a buffer view claiming 2²⁸ vec3 (3 GiB of zeros) are errors
/// naming the budget, quickly and without the memory.
#[test]
fn budgets_are_checked_before_allocating() {
    let d = folder("budget");
    let tris = 1000usize;
    let bytes: Vec<u8> = (0..tris)
        .flat_map(|t| {
            let x = t as f32;
            [[x, 0.0, 0.0], [x + 1.0, 0.0, 0.0], [x, 1.0, 0.0]]
        })
        .flatten()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    std::fs::write(d.join("mesh.bin"), &bytes).expect("bin");
    let n = 100_001;
    let nodes: Vec<String> = (0..n).map(|_| r#"{"mesh":0}"#.to_string()).collect();
    let list: Vec<String> = (0..n).map(|i| i.to_string()).collect();
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[{}]}}],"nodes":[{}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":{},"type":"VEC3","min":[0,0,0],"max":[1001,1,0]}}],
        "bufferViews":[{{"buffer":0,"byteLength":{}}}],"buffers":[{{"uri":"mesh.bin","byteLength":{}}}]}}"#,
        list.join(","),
        nodes.join(","),
        3 * tris,
        bytes.len(),
        bytes.len()
    );
    let p = d.join("instances.gltf");
    std::fs::write(&p, json).expect("gltf");
    let t0 = std::time::Instant::now();
    let e = err(&p);
    assert!(e.contains("triangles after instancing"), "{e}");
    assert!(t0.elapsed().as_secs_f64() < 10.0, "took {:?}", t0.elapsed());
    // An accessor of 2^28 zero vec3 (no buffer view).
    std::fs::write(d.join("tri.bin"), triangle_bytes()).expect("bin");
    let p = gltf(&d, "tri.bin", 36, None);
    let text = std::fs::read_to_string(&p).expect("gltf");
    let huge = edit(
        &text,
        r#""attributes":{"POSITION":0}"#,
        r#""attributes":{"POSITION":0,"NORMAL":1}"#,
    );
    let huge = edit(
        &huge,
        r#""accessors":["#,
        r#""accessors":[{"componentType":5126,"count":268435456,"type":"VEC3"},"#,
    );
    // The new accessor is index 0; the positions move to 1.
    let huge = huge.replacen(
        r#""POSITION":0,"NORMAL":1"#,
        r#""POSITION":1,"NORMAL":0"#,
        1,
    );
    std::fs::write(&p, huge).expect("gltf");
    match load_path(&p) {
        Err(e) => {
            eprintln!("huge accessor: {e:#}");
            let e = format!("{e:#}");
            assert!(e.contains("accessor 0") && e.contains("allowed"), "{e}")
        }
        Ok(s) => {
            let w = s.warnings.join("\n");
            assert!(w.contains("accessor 0") && w.contains("allowed"), "{w}");
        }
    }
}

/// `--allow-absolute-uris` (LoadLimits::allow_absolute_uris) lets a URI leave the scene's
/// folder, but still only to a regular file.
#[test]
fn absolute_uris_load_only_when_allowed() {
    let d = folder("allow-abs");
    let inner = d.join("scene");
    std::fs::create_dir_all(&inner).expect("dir");
    std::fs::write(d.join("outside.bin"), triangle_bytes()).expect("bin");
    let allow = LoadLimits {
        allow_absolute_uris: true,
        ..LoadLimits::default()
    };
    let abs = d.join("outside.bin").display().to_string();
    for uri in ["../outside.bin", abs.as_str()] {
        let p = gltf(&inner, uri, 36, None);
        let e = err(&p);
        assert!(e.contains("--allow-absolute-uris"), "{uri}: {e}");
        let s = load_path_with(&p, &allow).expect("allowed");
        assert_eq!(s.mesh.triangle_count(), 1, "{uri}");
    }
    let e = format!(
        "{:#}",
        load_path_with(&gltf(&inner, "/dev/zero", 36, None), &allow).expect_err("a device")
    );
    assert!(e.contains("not a regular file"), "{e}");
}

/// The triangle and texture-pixel budgets are the caller's (CLI flags): a scene over a lowered
/// budget is one error naming the budget, the value and the flag that raises it.
#[test]
fn lowered_budgets_name_the_flag_that_raises_them() {
    let d = folder("lowered");
    std::fs::write(d.join("tri.bin"), triangle_bytes()).expect("bin");
    let png = d.join("tex.png");
    image::RgbaImage::from_pixel(64, 32, image::Rgba([200, 100, 50, 255]))
        .save(&png)
        .expect("png");
    let p = gltf(&d, "tri.bin", 36, Some("tex.png"));
    let s = load_path(&p).expect("within the default budgets");
    assert_eq!(s.textures.len(), 1);
    let tight = |t, px| LoadLimits {
        max_triangles: t,
        max_texture_pixels: px,
        ..LoadLimits::default()
    };
    load_path_with(&p, &tight(1, 2048)).expect("exactly at both budgets");
    let e = format!(
        "{:#}",
        load_path_with(&p, &tight(0, 2048)).expect_err("0 triangles")
    );
    assert!(
        e.contains("more than 0 triangles") && e.contains("--max-triangles"),
        "{e}"
    );
    let e = format!(
        "{:#}",
        load_path_with(&p, &tight(1, 2047)).expect_err("texels")
    );
    assert!(
        e.contains("64x32") && e.contains("2048 texels") && e.contains("--max-texture-pixels"),
        "{e}"
    );
}

/// A PNG whose header claims 16385² pixels is refused from its header, before decoding.
#[test]
fn an_image_too_large_for_its_header_is_refused_before_decoding() {
    let d = folder("huge-png");
    std::fs::write(d.join("tri.bin"), triangle_bytes()).expect("bin");
    let mut png = Vec::new();
    image::RgbaImage::from_pixel(2, 2, image::Rgba([1, 2, 3, 255]))
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .expect("png");
    // IHDR width and height are the big-endian u32 at bytes 16..24 (PNG spec §11.2.2).
    png[16..20].copy_from_slice(&16385u32.to_be_bytes());
    png[20..24].copy_from_slice(&16385u32.to_be_bytes());
    let crc = crc32(&png[12..29]);
    png[29..33].copy_from_slice(&crc.to_be_bytes());
    std::fs::write(d.join("huge.png"), &png).expect("png");
    let t0 = std::time::Instant::now();
    let s = load_path(&gltf(&d, "tri.bin", 36, Some("huge.png"))).expect("loads untextured");
    let w = s.warnings.join("\n");
    assert!(w.contains("image 0") && w.contains("out of range"), "{w}");
    assert!(s.textures.is_empty());
    assert!(t0.elapsed().as_secs_f64() < 5.0, "took {:?}", t0.elapsed());
}

/// CRC-32 (ISO-HDLC, as PNG chunks use; PNG spec Annex D), bit by bit.
fn crc32(bytes: &[u8]) -> u32 {
    let mut c = 0xffff_ffffu32;
    for &b in bytes {
        c ^= u32::from(b);
        for _ in 0..8 {
            c = if c & 1 != 0 {
                0xedb8_8320 ^ (c >> 1)
            } else {
                c >> 1
            };
        }
    }
    !c
}
