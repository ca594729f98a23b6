//! glTF 2.0 loader following the scene contract in docs/design.md ("Scene contract").
//!
//! The file is parsed with `gltf::Gltf::from_slice_without_validation` (the crate's validation
//! rejects `extensionsRequired` containing volume/dispersion) and every index, offset and
//! count is checked here instead: malformed input yields a clear error or a skipped
//! primitive/triangle with a warning, never a panic. Only the raw JSON (`gltf::json::Root`) is
//! used, never the `gltf` wrapper types (they index without bounds checks).
//!
//! Decisions beyond the contract's wording (documented for the reference comparison):
//! - `KHR_materials_transmission` factor ≥ 0.5 makes a dielectric; 0 < factor < 0.5 is
//!   treated as opaque (metallic-roughness) with a warning.
//! - A metallic-roughness texture makes the material `MetalRough` even when the factors
//!   alone would say Diffuse/Mirror/GlossyMetal (the texture changes them per texel).
//! - Emissive materials are area lights whose surface is black (kind Diffuse, albedo 0).
//! - The base colour of glass is kept as written (the contract's dielectric ignores it).
//! - The image size comes from `extras.render`; without a width or height there, the chosen
//!   camera's `aspectRatio` shapes it (longer side 512).
//!
//! Files: raw decoding (`decode`: the GLB container; `uri`: percent-encoded and base64 URIs;
//! `accessor`: bounds-checked strided and sparse accessor reads) apart from the mapping onto
//! the scene contract (`nodes`: hierarchy and transforms; `cameras`; `mesh`: primitives →
//! triangles; `materials`; `textures`; `lights`: `KHR_lights_punctual`; `extras`: render
//! settings and environment).

mod accessor;
mod buffers;
mod cameras;
mod decode;
mod environment;
mod extras;
use crate::files;
mod json_error;
mod lights;
pub mod limits;
mod materials;
mod mesh;
mod meshopt;
mod nodes;
mod textures;
mod uri;

pub use cameras::default_camera;
pub use files::{read_regular_file, scene_folder};
pub use limits::LoadLimits;

use crate::scene::env_map::EnvImage;
use crate::scene::{Camera, Material, Mesh, PunctualLight, RenderSettings, Scene, Texture};
use crate::text::abbreviate;
use anyhow::{Context, anyhow, bail};
use glam::Vec3;
use gltf::json;
use std::collections::{HashMap, HashSet};
use std::path::Path;

/// Extensions the contract covers (anything else gets one warning and is ignored).
pub const SUPPORTED_EXTENSIONS: &[&str] = &[
    "KHR_materials_transmission",
    "KHR_materials_ior",
    "KHR_materials_volume",
    "KHR_materials_dispersion",
    "KHR_materials_emissive_strength",
    "KHR_materials_specular",
    materials::extensions::IRIDESCENCE,
    "KHR_lights_punctual",
    "KHR_texture_transform",
    "KHR_mesh_quantization",
    meshopt::EXT,
];

pub use crate::scene::material::GLASS_TRANSMISSION_THRESHOLD;

/// Load a `.gltf` or `.glb` file with the default limits.
pub fn load_path(path: &Path) -> anyhow::Result<Scene> {
    load_path_with(path, &LoadLimits::default())
}

/// Load a `.gltf` or `.glb` file within `limits`.
pub fn load_path_with(path: &Path, limits: &LoadLimits) -> anyhow::Result<Scene> {
    let bytes =
        files::read_regular_file(path, limits.max_file_bytes, "scene").map_err(|e| anyhow!(e))?;
    let name = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| path.display().to_string());
    let load = || {
        let folder = files::scene_folder(path).map_err(|e| anyhow!(e))?;
        load_slice_with(&bytes, Some(&folder), &name, limits)
    };
    load().with_context(|| format!("cannot load glTF scene '{}'", path.display()))
}

/// Load from bytes; `base` resolves relative URIs (None = only embedded data).
pub fn load_slice(bytes: &[u8], base: Option<&Path>, name: &str) -> anyhow::Result<Scene> {
    load_slice_with(bytes, base, name, &LoadLimits::default())
}

/// Load glTF JSON or GLB bytes within `limits` (`base`: the folder external URIs are read
/// from).
pub fn load_slice_with(
    bytes: &[u8],
    base: Option<&Path>,
    name: &str,
    limits: &LoadLimits,
) -> anyhow::Result<Scene> {
    if bytes.is_empty() {
        bail!("'{name}' is empty (0 bytes): not a glTF file");
    }
    let bytes = decode::check_glb_header(bytes)?;
    let gltf = gltf::Gltf::from_slice_without_validation(bytes).map_err(|e| {
        let why = json_error::describe(decode::json_text(bytes), &e);
        anyhow!("'{name}' is not valid glTF: {why}")
    })?;
    let root = gltf.document.as_json();
    check_version(&root.asset)?;
    // Required extensions first: an unsupported one is the reason, whatever it does to buffers.
    check_required_extensions(root)?;
    uri::check_uris(root)?;
    let buffers = buffers::load_buffers(root, gltf.blob.clone(), base, limits)
        .map_err(|e| anyhow!("cannot load the buffers of '{name}': {e}"))?;
    let decoded = meshopt::decode_views(root, &buffers)
        .map_err(|e| anyhow!("cannot decode the buffers of '{name}': {e}"))?;
    let buffers: Vec<&[u8]> = buffers.iter().map(|b| b.as_slice()).collect();
    let mut loader = Loader {
        root,
        buffers,
        decoded,
        base,
        limits: *limits,
        camera_aspect: None,
        texture_pixels: 0,
        warnings: Warnings::default(),
        textures: vec![],
        texture_cache: HashMap::new(),
        materials: vec![],
        material_map: vec![],
        default_material: None,
        mesh: Mesh::default(),
        camera: None,
        lights: vec![],
        dropped_triangles: 0,
        skipped_primitives: 0,
        first_skip_reason: None,
        needs_tangents: false,
    };
    loader.run(name)
}

/// glTF 2.0 §5.3 (asset): a loader must refuse a major version it does not know, and a
/// `minVersion` above the one it implements.
fn check_version(asset: &json::Asset) -> anyhow::Result<()> {
    let major = |v: &str| v.split('.').next().map(str::to_owned).unwrap_or_default();
    let short = |v: &str| abbreviate(v);
    if major(&asset.version) != "2" {
        bail!(
            "/asset/version is '{}': only glTF 2.x is supported",
            short(&asset.version)
        );
    }
    if let Some(min) = &asset.min_version
        && min.as_str() != "2.0"
    {
        bail!(
            "/asset/minVersion is '{}': this loader implements glTF 2.0",
            short(min)
        );
    }
    Ok(())
}

/// Warnings, with "once" semantics for repeated problems.
#[derive(Default)]
struct Warnings {
    list: Vec<String>,
    seen: HashSet<String>,
}

impl Warnings {
    fn push(&mut self, msg: String) {
        if self.seen.insert(msg.clone()) {
            self.list.push(msg);
        }
    }
    /// Warn only the first time `key` is seen.
    fn once(&mut self, key: &str, msg: impl FnOnce() -> String) {
        if self.seen.insert(format!("\u{0}{key}")) {
            self.list.push(msg());
        }
    }
}

/// The state of one load: the parsed JSON and buffers, and the scene built so far.
struct Loader<'a> {
    root: &'a json::Root,
    buffers: Vec<&'a [u8]>,
    /// Decoded bytes of each `EXT_meshopt_compression` buffer view (None: not compressed).
    decoded: Vec<Option<Vec<u8>>>,
    base: Option<&'a Path>,
    limits: LoadLimits,
    /// The chosen camera's `aspectRatio`, if it has a valid one.
    camera_aspect: Option<f32>,
    /// Texels of the textures loaded so far (against `limits.max_texture_pixels`).
    texture_pixels: u64,
    warnings: Warnings,
    textures: Vec<Texture>,
    /// (glTF texture index, sRGB) → scene texture (None = failed to load).
    texture_cache: HashMap<(usize, bool), Option<u32>>,
    materials: Vec<Material>,
    /// glTF material index → scene material index.
    material_map: Vec<u32>,
    default_material: Option<u32>,
    mesh: Mesh,
    camera: Option<Camera>,
    lights: Vec<PunctualLight>,
    dropped_triangles: usize,
    skipped_primitives: usize,
    first_skip_reason: Option<String>,
    /// Some material has a normal map: the mesh stores per-vertex tangents.
    needs_tangents: bool,
}

/// The scene-level `extras` (render settings and environment) of a file, parsed.
struct SceneExtras {
    settings: RenderSettings,
    /// `extras.render` gives a width or height (else the camera's aspect ratio shapes it).
    sized: bool,
    environment: Vec3,
    env_map: Option<EnvImage>,
}

impl Loader<'_> {
    /// Load the whole file: extensions, extras, materials, the node tree, then the scene.
    fn run(&mut self, name: &str) -> anyhow::Result<Scene> {
        let root = self.root;
        self.check_extensions();
        if !root.skins.is_empty() || !root.animations.is_empty() {
            self.warnings.push(
                "skins and animations are ignored (the scene is loaded in its rest pose)".into(),
            );
        }
        let extras = self.scene_extras()?;
        self.convert_materials()?;

        let roots = self.scene_roots()?;
        self.check_instanced_triangles(&roots)?;
        self.traverse(&roots)?;

        self.check_triangles(name)?;
        self.build_scene(name, extras)
    }

    /// Parse `scenes[0].extras`: the render settings and the environment.
    fn scene_extras(&mut self) -> anyhow::Result<SceneExtras> {
        let settings_value = match self.root.scenes.first() {
            Some(s) => extras::extras_value(&s.extras, "/scenes/0/extras")?,
            None => None,
        };
        let settings =
            extras::parse_render_settings(settings_value.as_ref(), &mut self.warnings.list)?;
        let sized = extras::has_image_size(settings_value.as_ref());
        let (environment, env_map) = environment::parse(
            settings_value.as_ref(),
            self.base,
            &self.limits,
            &mut self.warnings,
        )?;
        Ok(SceneExtras {
            settings,
            sized,
            environment,
            env_map,
        })
    }

    /// Convert every glTF material (in order, so glTF index i → scene index i) and note
    /// whether any has a normal map.
    fn convert_materials(&mut self) -> anyhow::Result<()> {
        let root = self.root;
        for (i, m) in root.materials.iter().enumerate() {
            let mat = self.convert_material(i, m)?;
            self.material_map.push(self.materials.len() as u32);
            self.materials.push(mat);
        }
        self.needs_tangents = self.materials.iter().any(|m| m.normal_texture.is_some());
        Ok(())
    }

    /// Warn about dropped triangles, and refuse a file left with none, saying why.
    fn check_triangles(&mut self, name: &str) -> anyhow::Result<()> {
        if self.dropped_triangles > 0 {
            self.warnings.push(format!(
                "dropped {} zero-area or non-finite triangles",
                self.dropped_triangles
            ));
        }
        if self.mesh.indices.is_empty() {
            if let Some(reason) = &self.first_skip_reason {
                bail!(
                    "'{name}' has no usable triangles: {} primitive(s) skipped, first because {reason}",
                    self.skipped_primitives
                );
            }
            // One policy for "nothing to render": an error with the reason, whatever emptied it.
            if self.dropped_triangles > 0 {
                bail!(
                    "'{name}' has no usable triangles: all {} were dropped as zero-area or non-finite",
                    self.dropped_triangles
                );
            }
            bail!(
                "'{name}' has no triangles to render (no mesh is reachable from the scene's nodes)"
            );
        }
        Ok(())
    }

    /// Assemble the scene from what was loaded: image size, camera, lighting fallback,
    /// warnings, and the final renderability check.
    fn build_scene(&mut self, name: &str, extras: SceneExtras) -> anyhow::Result<Scene> {
        let SceneExtras {
            mut settings,
            sized,
            environment,
            env_map,
        } = extras;
        if !sized && let Some(a) = self.camera_aspect {
            (settings.width, settings.height) = cameras::size_for_aspect(a);
        }
        let camera = match self.camera {
            Some(c) => c,
            None => default_camera(&self.mesh, &settings),
        };
        let mut scene = Scene {
            name: name.to_string(),
            mesh: std::mem::take(&mut self.mesh),
            materials: std::mem::take(&mut self.materials),
            textures: std::mem::take(&mut self.textures),
            punctual_lights: std::mem::take(&mut self.lights),
            camera,
            environment,
            env_map,
            settings,
            warnings: vec![],
        };
        environment::light_the_lightless(&mut scene, &mut self.warnings);
        scene.warnings = std::mem::take(&mut self.warnings.list);
        scene
            .validate()
            .with_context(|| format!("'{name}' loaded but is not renderable"))?;
        Ok(scene)
    }

    /// Extensions used but not supported: one warning each, and ignored (the required ones
    /// were refused before the buffers were read: `check_required_extensions`).
    fn check_extensions(&mut self) {
        let root = self.root;
        let mut names: Vec<&str> = root.extensions_used.iter().map(|s| s.as_str()).collect();
        for m in &root.materials {
            if let Some(e) = &m.extensions {
                names.extend(e.others.keys().map(|k| k.as_str()));
            }
        }
        for n in names {
            if !SUPPORTED_EXTENSIONS.contains(&n) {
                self.warnings.once(&format!("ext:{n}"), || {
                    format!("unsupported extension {n} is ignored")
                });
            }
        }
    }
}

/// Unsupported extensions in `extensionsRequired` are refused (glTF 2.0 §3.12: a loader must
/// not load an asset whose required extensions it does not support). Checked before any
/// buffer is read, so the message names the extension rather than a symptom of it (a meshopt
/// fallback buffer without data, a Draco primitive without accessors' buffer views).
fn check_required_extensions(root: &json::Root) -> anyhow::Result<()> {
    for (i, n) in root.extensions_required.iter().enumerate() {
        if !SUPPORTED_EXTENSIONS.contains(&n.as_str()) {
            bail!(
                "/extensionsRequired/{i}: the file requires the extension '{}', which \
                 refract does not support (supported: {}){}",
                abbreviate(n),
                SUPPORTED_EXTENSIONS.join(", "),
                workaround(n)
            );
        }
    }
    Ok(())
}

/// What to do about an unsupported required extension, where there is a standard tool for it.
/// Draco: no maintained Rust decoder fit for untrusted input exists (docs/scene-contract.md,
/// "Compressed meshes"); gltf-transform re-encodes the file with meshopt, which refract reads.
fn workaround(ext: &str) -> &'static str {
    match ext {
        "KHR_draco_mesh_compression" => {
            "; re-encode it with meshopt, which refract reads: \
             `npx @gltf-transform/cli meshopt IN.glb OUT.glb`"
        }
        _ => "",
    }
}
