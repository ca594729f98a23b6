//! glTF 2.0 loader following the scene contract in DESIGN.md ("Scene contract").
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
//! - The camera's `aspectRatio` is ignored: the image size comes from `extras.render`.

use super::{Camera, Material, MaterialKind, Mesh, PunctualLight, RenderSettings, Scene};
use super::{Texture, TextureRef, Wrap};
use crate::bsdf::MicrofacetDistribution;
use anyhow::{Context, anyhow, bail};
use glam::{Affine2, Mat2, Mat3, Mat4, Quat, Vec2, Vec3, Vec4};
use gltf::json;
use gltf::json::validation::Checked;
use serde_json::Value;
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
    "KHR_lights_punctual",
    "KHR_texture_transform",
];

/// Transmission factors at or above this make a material a dielectric.
pub const GLASS_TRANSMISSION_THRESHOLD: f32 = 0.5;

/// Largest element count of one accessor we accept.
const MAX_ACCESSOR_COUNT: u64 = 1 << 28;
/// Deepest node hierarchy we follow.
const MAX_NODE_DEPTH: usize = 1024;

/// Load a `.gltf` or `.glb` file.
pub fn load_path(path: &Path) -> anyhow::Result<Scene> {
    let bytes =
        std::fs::read(path).map_err(|e| anyhow!("cannot read scene '{}': {e}", path.display()))?;
    let name = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| path.display().to_string());
    load_slice(&bytes, path.parent(), &name)
        .with_context(|| format!("cannot load glTF scene '{}'", path.display()))
}

/// Load from bytes; `base` resolves relative URIs (None = only embedded data).
pub fn load_slice(bytes: &[u8], base: Option<&Path>, name: &str) -> anyhow::Result<Scene> {
    if bytes.is_empty() {
        bail!("'{name}' is empty (0 bytes): not a glTF file");
    }
    let bytes = check_glb_header(bytes)?;
    let gltf = gltf::Gltf::from_slice_without_validation(bytes)
        .map_err(|e| anyhow!("'{name}' is not valid glTF: {e}"))?;
    let root = gltf.document.as_json();
    check_uris(root)?;
    let buffers = gltf::import_buffers(&gltf.document, base, gltf.blob.clone()).map_err(|e| {
        anyhow!("cannot load the buffers of '{name}': {e} (missing or short buffer?)")
    })?;
    let buffers: Vec<&[u8]> = buffers.iter().map(|b| b.0.as_slice()).collect();
    let mut loader = Loader {
        root,
        buffers,
        base,
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
    };
    loader.run(name)
}

/// Validate the GLB container header ourselves (the `gltf` crate subtracts before checking)
/// and cut the slice to the declared length.
fn check_glb_header(bytes: &[u8]) -> anyhow::Result<&[u8]> {
    if !bytes.starts_with(b"glTF") {
        return Ok(bytes);
    }
    let word = |i: usize| -> Option<u32> {
        let b: [u8; 4] = bytes.get(i..i + 4)?.try_into().ok()?;
        Some(u32::from_le_bytes(b))
    };
    let (Some(version), Some(length)) = (word(4), word(8)) else {
        bail!(
            "truncated .glb: {} bytes, the header alone needs 12",
            bytes.len()
        );
    };
    if version != 2 {
        bail!(".glb container version {version} is not supported (only 2)");
    }
    let length = length as usize;
    if length < 20 {
        bail!("corrupt .glb: declared length {length} is too small for a JSON chunk");
    }
    if length > bytes.len() {
        bail!(
            "truncated .glb: header declares {length} bytes but the file has {}",
            bytes.len()
        );
    }
    let json_len = word(12).unwrap_or(0) as usize;
    if json_len > length - 20 {
        bail!("truncated .glb: JSON chunk of {json_len} bytes does not fit in {length} bytes");
    }
    Ok(&bytes[..length])
}

/// Relative URIs must percent-decode to UTF-8 (the `gltf` importer would panic otherwise).
fn check_uris(root: &json::Root) -> anyhow::Result<()> {
    for (i, b) in root.buffers.iter().enumerate() {
        if let Some(uri) = &b.uri
            && !uri.contains(':')
            && percent_decode(uri).is_none()
        {
            bail!("buffer {i}: URI '{uri}' is not valid percent-encoded UTF-8");
        }
    }
    Ok(())
}

/// Percent-decode a relative URI (invalid escapes are kept literally); None if not UTF-8.
fn percent_decode(s: &str) -> Option<String> {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%'
            && let Some(h) = b.get(i + 1..i + 3)
            && let Ok(hs) = std::str::from_utf8(h)
            && let Ok(v) = u8::from_str_radix(hs, 16)
        {
            out.push(v);
            i += 3;
            continue;
        }
        out.push(b[i]);
        i += 1;
    }
    String::from_utf8(out).ok()
}

/// Minimal standard base64 decoder for `data:` image URIs (padding and whitespace tolerated).
fn base64_decode(s: &str) -> Option<Vec<u8>> {
    let mut out = Vec::with_capacity(s.len() / 4 * 3);
    let mut acc = 0u32;
    let mut bits = 0u32;
    for c in s.bytes() {
        let v = match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' | b'-' => 62,
            b'/' | b'_' => 63,
            b'=' | b' ' | b'\n' | b'\r' | b'\t' => continue,
            _ => return None,
        };
        acc = (acc << 6) | v as u32;
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
            acc &= (1 << bits) - 1;
        }
    }
    Some(out)
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

fn comp_size(c: json::accessor::ComponentType) -> usize {
    use json::accessor::ComponentType as C;
    match c {
        C::I8 | C::U8 => 1,
        C::I16 | C::U16 => 2,
        C::U32 | C::F32 => 4,
    }
}

fn type_comps(t: json::accessor::Type) -> usize {
    use json::accessor::Type as T;
    match t {
        T::Scalar => 1,
        T::Vec2 => 2,
        T::Vec3 => 3,
        T::Vec4 | T::Mat2 => 4,
        T::Mat3 => 9,
        T::Mat4 => 16,
    }
}

fn read_le<const N: usize>(b: &[u8], at: usize) -> Option<[u8; N]> {
    b.get(at..at.checked_add(N)?)?.try_into().ok()
}

/// One component at byte `at`, as f32 (normalised integers mapped per glTF §3.11).
fn read_comp(
    b: &[u8],
    at: usize,
    c: json::accessor::ComponentType,
    normalized: bool,
) -> Option<f32> {
    use json::accessor::ComponentType as C;
    Some(match c {
        C::F32 => f32::from_le_bytes(read_le(b, at)?),
        C::U8 => {
            let v = read_le::<1>(b, at)?[0] as f32;
            if normalized { v / 255.0 } else { v }
        }
        C::I8 => {
            let v = i8::from_le_bytes(read_le(b, at)?) as f32;
            if normalized { (v / 127.0).max(-1.0) } else { v }
        }
        C::U16 => {
            let v = u16::from_le_bytes(read_le(b, at)?) as f32;
            if normalized { v / 65535.0 } else { v }
        }
        C::I16 => {
            let v = i16::from_le_bytes(read_le(b, at)?) as f32;
            if normalized {
                (v / 32767.0).max(-1.0)
            } else {
                v
            }
        }
        C::U32 => u32::from_le_bytes(read_le(b, at)?) as f32,
    })
}

fn read_uint(b: &[u8], at: usize, c: json::accessor::ComponentType) -> Option<u32> {
    use json::accessor::ComponentType as C;
    Some(match c {
        C::U8 => read_le::<1>(b, at)?[0] as u32,
        C::U16 => u16::from_le_bytes(read_le(b, at)?) as u32,
        C::U32 => u32::from_le_bytes(read_le(b, at)?),
        _ => return None,
    })
}

/// A located, bounds-checked strided array inside a buffer.
struct Strided<'a> {
    data: &'a [u8],
    start: usize,
    stride: usize,
}

impl Strided<'_> {
    fn at(&self, i: usize) -> usize {
        self.start + i * self.stride
    }
}

/// Decoded accessor data: `count × comps` floats or unsigned integers.
enum AccessorData {
    Float(Vec<f32>),
    Uint(Vec<u32>),
}

struct Loader<'a> {
    root: &'a json::Root,
    buffers: Vec<&'a [u8]>,
    base: Option<&'a Path>,
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
}

impl Loader<'_> {
    fn run(&mut self, name: &str) -> anyhow::Result<Scene> {
        let root = self.root;
        self.check_extensions();
        if !root.skins.is_empty() || !root.animations.is_empty() {
            self.warnings.push(
                "skins and animations are ignored (the scene is loaded in its rest pose)".into(),
            );
        }
        let settings_value = root.scenes.first().and_then(|s| extras_value(&s.extras));
        let settings = parse_render_settings(settings_value.as_ref())?;
        let environment = parse_environment(settings_value.as_ref())?;

        for (i, m) in root.materials.iter().enumerate() {
            let mat = self.convert_material(i, m);
            self.material_map.push(self.materials.len() as u32);
            self.materials.push(mat);
        }

        // Scene traversal: the default scene (or scenes[0]); with no scenes, every root node.
        let roots: Vec<usize> = match root.scene.map(|s| s.value()).or(if root.scenes.is_empty() {
            None
        } else {
            Some(0)
        }) {
            Some(si) => {
                let scene = root
                    .scenes
                    .get(si)
                    .ok_or_else(|| anyhow!("default scene {si} does not exist"))?;
                scene.nodes.iter().map(|n| n.value()).collect()
            }
            None => {
                self.warnings
                    .push("the file has no scenes: rendering every root node".into());
                let mut is_child = vec![false; root.nodes.len()];
                for n in &root.nodes {
                    for c in n.children.iter().flatten() {
                        if let Some(f) = is_child.get_mut(c.value()) {
                            *f = true;
                        }
                    }
                }
                (0..root.nodes.len()).filter(|&i| !is_child[i]).collect()
            }
        };
        self.traverse(&roots)?;

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
            self.warnings.push("the scene has no triangles".into());
        }

        let camera = match self.camera {
            Some(c) => c,
            None => default_camera(&self.mesh, &settings),
        };
        let scene = Scene {
            name: name.to_string(),
            mesh: std::mem::take(&mut self.mesh),
            materials: std::mem::take(&mut self.materials),
            textures: std::mem::take(&mut self.textures),
            punctual_lights: std::mem::take(&mut self.lights),
            camera,
            environment,
            settings,
            warnings: std::mem::take(&mut self.warnings.list),
        };
        scene
            .validate()
            .with_context(|| format!("'{name}' loaded but is not renderable"))?;
        Ok(scene)
    }

    fn check_extensions(&mut self) {
        let root = self.root;
        let mut names: Vec<&str> = root
            .extensions_required
            .iter()
            .chain(&root.extensions_used)
            .map(|s| s.as_str())
            .collect();
        for m in &root.materials {
            if let Some(e) = &m.extensions {
                names.extend(e.others.keys().map(|k| k.as_str()));
            }
        }
        for n in names {
            if !SUPPORTED_EXTENSIONS.contains(&n) {
                let required = root.extensions_required.iter().any(|r| r == n);
                self.warnings.once(&format!("ext:{n}"), || {
                    format!(
                        "unsupported extension {n}{} is ignored",
                        if required {
                            " (listed as required)"
                        } else {
                            ""
                        }
                    )
                });
            }
        }
    }

    fn skip_primitive(&mut self, what: String) {
        self.skipped_primitives += 1;
        if self.first_skip_reason.is_none() {
            self.first_skip_reason = Some(what.clone());
        }
        self.warnings.push(format!("skipped primitive: {what}"));
    }

    /// Depth-first pre-order traversal (the first camera found wins).
    fn traverse(&mut self, roots: &[usize]) -> anyhow::Result<()> {
        let root = self.root;
        let mut visited = vec![false; root.nodes.len()];
        let mut stack: Vec<(usize, Mat4, usize)> = roots
            .iter()
            .rev()
            .map(|&n| (n, Mat4::IDENTITY, 0))
            .collect();
        while let Some((ni, parent, depth)) = stack.pop() {
            let Some(node) = root.nodes.get(ni) else {
                self.warnings.push(format!(
                    "node {ni} does not exist (index out of range): skipped"
                ));
                continue;
            };
            if visited[ni] {
                self.warnings.push(format!(
                    "node {ni} is reached twice (cycle or shared child): visited once only"
                ));
                continue;
            }
            visited[ni] = true;
            if depth > MAX_NODE_DEPTH {
                bail!("node hierarchy deeper than {MAX_NODE_DEPTH} levels");
            }
            let local = match node_local_matrix(node) {
                Ok(m) => m,
                Err(e) => {
                    self.warnings
                        .push(format!("node {ni}: {e}; node and children skipped"));
                    continue;
                }
            };
            let world = parent * local;
            if !world.is_finite() {
                self.warnings
                    .push(format!("node {ni}: world transform is not finite; skipped"));
                continue;
            }
            if let Some(ci) = node.camera {
                self.camera_node(ni, ci.value(), world)?;
            }
            if let Some(mi) = node.mesh {
                self.mesh_node(ni, mi.value(), world)?;
            }
            if let Some(l) = node
                .extensions
                .as_ref()
                .and_then(|e| e.khr_lights_punctual.as_ref())
            {
                self.light_node(ni, l.light.value(), world);
            }
            for c in node.children.iter().flatten().rev() {
                stack.push((c.value(), world, depth + 1));
            }
        }
        Ok(())
    }

    fn camera_node(&mut self, ni: usize, ci: usize, world: Mat4) -> anyhow::Result<()> {
        if self.camera.is_some() {
            return Ok(());
        }
        let Some(cam) = self.root.cameras.get(ci) else {
            self.warnings.push(format!(
                "node {ni}: camera {ci} does not exist (index out of range)"
            ));
            return Ok(());
        };
        match (&cam.type_, &cam.perspective) {
            (Checked::Valid(json::camera::Type::Perspective), Some(p))
            | (Checked::Invalid, Some(p)) => {
                let yfov = p.yfov;
                if !(yfov.is_finite() && yfov > 1e-4 && yfov < std::f32::consts::PI - 1e-3) {
                    bail!("camera {ci}: yfov {yfov} is outside (0, π) radians");
                }
                let c = Camera::from_matrix(world, yfov);
                c.validate()
                    .with_context(|| format!("camera {ci} on node {ni}"))?;
                self.camera = Some(c);
            }
            _ => self.warnings.push(format!(
                "camera {ci}: only perspective cameras are supported; ignored"
            )),
        }
        Ok(())
    }

    fn light_node(&mut self, ni: usize, li: usize, world: Mat4) {
        let light = self
            .root
            .extensions
            .as_ref()
            .and_then(|e| e.khr_lights_punctual.as_ref())
            .and_then(|l| l.lights.get(li));
        let Some(light) = light else {
            self.warnings.push(format!(
                "node {ni}: KHR_lights_punctual light {li} does not exist (index out of range)"
            ));
            return;
        };
        use json::extensions::scene::khr_lights_punctual::Type as LT;
        let color = Vec3::from(light.color);
        let intensity = color * light.intensity;
        if !intensity.is_finite() || intensity.min_element() < 0.0 {
            self.warnings.push(format!(
                "light {li}: colour × intensity must be finite and non-negative; ignored"
            ));
            return;
        }
        if light.range.is_some() {
            self.warnings.once("light-range", || {
                "KHR_lights_punctual 'range' is ignored (lights fall off with inverse square)"
                    .into()
            });
        }
        let position = world.transform_point3(Vec3::ZERO);
        let direction = world.transform_vector3(Vec3::NEG_Z).normalize_or_zero();
        let needs_dir = !matches!(light.type_, Checked::Valid(LT::Point));
        if needs_dir && direction == Vec3::ZERO {
            self.warnings.push(format!(
                "light {li}: node {ni} has a degenerate rotation; ignored"
            ));
            return;
        }
        let l = match light.type_ {
            Checked::Valid(LT::Point) => PunctualLight::Point {
                position,
                intensity,
            },
            Checked::Valid(LT::Directional) => PunctualLight::Directional {
                direction,
                irradiance: intensity,
            },
            Checked::Valid(LT::Spot) => {
                let (inner, outer) = light
                    .spot
                    .as_ref()
                    .map(|s| (s.inner_cone_angle, s.outer_cone_angle))
                    .unwrap_or((0.0, std::f32::consts::FRAC_PI_4));
                let outer = outer.clamp(0.0, std::f32::consts::FRAC_PI_2);
                let inner = inner.clamp(0.0, outer);
                PunctualLight::Spot {
                    position,
                    direction,
                    intensity,
                    cos_inner: inner.cos(),
                    cos_outer: outer.cos(),
                }
            }
            Checked::Invalid => {
                self.warnings
                    .push(format!("light {li}: unknown light type; ignored"));
                return;
            }
        };
        self.lights.push(l);
    }

    fn material_for(&mut self, index: Option<usize>) -> Result<u32, String> {
        match index {
            Some(i) => self
                .material_map
                .get(i)
                .copied()
                .ok_or_else(|| format!("material {i} does not exist (index out of range)")),
            None => {
                if let Some(d) = self.default_material {
                    return Ok(d);
                }
                // glTF default material: base colour 1, metallic 1, roughness 1.
                let m = self.convert_material(usize::MAX, &json::Material::default());
                let id = self.materials.len() as u32;
                self.materials.push(Material {
                    name: "default".into(),
                    ..m
                });
                self.default_material = Some(id);
                Ok(id)
            }
        }
    }

    fn mesh_node(&mut self, ni: usize, mi: usize, world: Mat4) -> anyhow::Result<()> {
        let Some(mesh) = self.root.meshes.get(mi) else {
            self.skip_primitive(format!(
                "node {ni}: mesh {mi} does not exist (index out of range)"
            ));
            return Ok(());
        };
        for (pi, prim) in mesh.primitives.iter().enumerate() {
            match self.primitive(prim, world) {
                Ok(()) => {}
                Err(e) => self.skip_primitive(format!("mesh {mi} primitive {pi}: {e}")),
            }
        }
        Ok(())
    }

    /// Locate accessor `ai`'s elements, checking every offset against the buffer.
    fn locate(&self, ai: usize) -> Result<(&json::Accessor, Option<Strided<'_>>, usize), String> {
        let acc = self
            .root
            .accessors
            .get(ai)
            .ok_or_else(|| format!("accessor {ai} does not exist (index out of range)"))?;
        let Checked::Valid(ty) = acc.type_ else {
            return Err(format!("accessor {ai} has an invalid type"));
        };
        let Checked::Valid(ct) = acc.component_type else {
            return Err(format!("accessor {ai} has an invalid component type"));
        };
        let count = acc.count.0;
        if count > MAX_ACCESSOR_COUNT {
            return Err(format!("accessor {ai} count {count} is too large"));
        }
        let count = count as usize;
        let elem = type_comps(ty) * comp_size(ct.0);
        let Some(vi) = acc.buffer_view else {
            return Ok((acc, None, elem));
        };
        let view =
            self.root.buffer_views.get(vi.value()).ok_or_else(|| {
                format!("accessor {ai}: buffer view {} does not exist", vi.value())
            })?;
        let data = self.view_bytes(vi.value(), view)?;
        let stride = view.byte_stride.map(|s| s.0).unwrap_or(elem);
        if stride < elem {
            return Err(format!(
                "accessor {ai}: byte stride {stride} is smaller than the element size {elem}"
            ));
        }
        let start = acc.byte_offset.map(|o| o.0).unwrap_or(0);
        let start =
            usize::try_from(start).map_err(|_| format!("accessor {ai}: offset too large"))?;
        if count > 0 {
            let end = (count - 1)
                .checked_mul(stride)
                .and_then(|x| x.checked_add(start))
                .and_then(|x| x.checked_add(elem));
            match end {
                Some(e) if e <= data.len() => {}
                _ => {
                    return Err(format!(
                        "accessor {ai} (count {count}, offset {start}, stride {stride}) reads past the end of its {}-byte buffer view (accessor out of bounds)",
                        data.len()
                    ));
                }
            }
        }
        Ok((
            acc,
            Some(Strided {
                data,
                start,
                stride,
            }),
            elem,
        ))
    }

    fn view_bytes(&self, vi: usize, view: &json::buffer::View) -> Result<&[u8], String> {
        let bi = view.buffer.value();
        let buf = self.buffers.get(bi).ok_or_else(|| {
            format!("buffer view {vi}: buffer {bi} does not exist (missing buffer)")
        })?;
        let off = view.byte_offset.map(|o| o.0).unwrap_or(0);
        let len = view.byte_length.0;
        let end = off.checked_add(len);
        match end {
            Some(e) if e <= buf.len() as u64 => Ok(&buf[off as usize..e as usize]),
            _ => Err(format!(
                "buffer view {vi} (offset {off}, length {len}) exceeds buffer {bi} of {} bytes",
                buf.len()
            )),
        }
    }

    /// Read accessor `ai` as floats (`want` components) or unsigned integers.
    fn read_accessor(&self, ai: usize, want_uint: bool) -> Result<(AccessorData, usize), String> {
        let (acc, strided, _elem) = self.locate(ai)?;
        let (Checked::Valid(ty), Checked::Valid(ct)) = (acc.type_, acc.component_type) else {
            return Err(format!("accessor {ai} has an invalid type"));
        };
        let ct = ct.0;
        let comps = type_comps(ty);
        let count = acc.count.0 as usize;
        let cs = comp_size(ct);
        let bad = || format!("accessor {ai} reads out of bounds");
        let mut data = if want_uint {
            if !matches!(
                ct,
                json::accessor::ComponentType::U8
                    | json::accessor::ComponentType::U16
                    | json::accessor::ComponentType::U32
            ) {
                return Err(format!("accessor {ai}: indices must be unsigned integers"));
            }
            let mut v = Vec::with_capacity(count * comps);
            match &strided {
                Some(s) => {
                    for i in 0..count {
                        for k in 0..comps {
                            v.push(read_uint(s.data, s.at(i) + k * cs, ct).ok_or_else(bad)?);
                        }
                    }
                }
                None => v.resize(count * comps, 0),
            }
            AccessorData::Uint(v)
        } else {
            let mut v = Vec::with_capacity(count * comps);
            match &strided {
                Some(s) => {
                    for i in 0..count {
                        for k in 0..comps {
                            v.push(
                                read_comp(s.data, s.at(i) + k * cs, ct, acc.normalized)
                                    .ok_or_else(bad)?,
                            );
                        }
                    }
                }
                None => v.resize(count * comps, 0.0),
            }
            AccessorData::Float(v)
        };
        if let Some(sp) = &acc.sparse {
            self.apply_sparse(ai, sp, count, comps, ct, acc.normalized, &mut data)?;
        }
        Ok((data, comps))
    }

    #[allow(clippy::too_many_arguments)]
    fn apply_sparse(
        &self,
        ai: usize,
        sp: &json::accessor::sparse::Sparse,
        count: usize,
        comps: usize,
        ct: json::accessor::ComponentType,
        normalized: bool,
        data: &mut AccessorData,
    ) -> Result<(), String> {
        let n = sp.count.0;
        if n > count as u64 {
            return Err(format!(
                "accessor {ai}: sparse count {n} exceeds count {count}"
            ));
        }
        let n = n as usize;
        let Checked::Valid(ict) = sp.indices.component_type else {
            return Err(format!("accessor {ai}: invalid sparse index type"));
        };
        let get_view = |vi: usize| -> Result<&[u8], String> {
            let v =
                self.root.buffer_views.get(vi).ok_or_else(|| {
                    format!("accessor {ai}: sparse buffer view {vi} does not exist")
                })?;
            self.view_bytes(vi, v)
        };
        let ib = get_view(sp.indices.buffer_view.value())?;
        let io = sp.indices.byte_offset.0 as usize;
        let vb = get_view(sp.values.buffer_view.value())?;
        let vo = sp.values.byte_offset.0 as usize;
        let ics = comp_size(ict.0);
        let cs = comp_size(ct);
        let bad = || format!("accessor {ai}: sparse data out of bounds");
        for s in 0..n {
            let idx = read_uint(ib, io + s * ics, ict.0).ok_or_else(bad)? as usize;
            if idx >= count {
                return Err(format!("accessor {ai}: sparse index {idx} out of range"));
            }
            for k in 0..comps {
                let at = vo + (s * comps + k) * cs;
                match data {
                    AccessorData::Float(v) => {
                        v[idx * comps + k] = read_comp(vb, at, ct, normalized).ok_or_else(bad)?
                    }
                    AccessorData::Uint(v) => {
                        v[idx * comps + k] = read_uint(vb, at, ct).ok_or_else(bad)?
                    }
                }
            }
        }
        Ok(())
    }

    fn read_floats(&self, ai: usize, comps: usize, what: &str) -> Result<Vec<f32>, String> {
        let (data, c) = self.read_accessor(ai, false)?;
        if c != comps {
            return Err(format!(
                "{what} accessor {ai} has {c} components, expected {comps}"
            ));
        }
        match data {
            AccessorData::Float(v) => Ok(v),
            AccessorData::Uint(_) => Err(format!("{what} accessor {ai} is not float")),
        }
    }

    fn primitive(&mut self, prim: &json::mesh::Primitive, world: Mat4) -> Result<(), String> {
        match prim.mode {
            Checked::Valid(json::mesh::Mode::Triangles) => {}
            Checked::Valid(m) => {
                self.warnings.once(&format!("mode:{m:?}"), || {
                    format!("primitives with mode {m:?} are skipped (triangles only)")
                });
                return Ok(());
            }
            Checked::Invalid => return Err("invalid primitive mode".into()),
        }
        let attr =
            |s: json::mesh::Semantic| prim.attributes.get(&Checked::Valid(s)).map(|i| i.value());
        let pos_i = attr(json::mesh::Semantic::Positions).ok_or("it has no POSITION attribute")?;
        let positions = self.read_floats(pos_i, 3, "POSITION")?;
        let nv = positions.len() / 3;
        let normals = match attr(json::mesh::Semantic::Normals) {
            Some(i) => {
                let n = self.read_floats(i, 3, "NORMAL")?;
                if n.len() != positions.len() {
                    return Err(format!(
                        "NORMAL count {} differs from POSITION count {nv}",
                        n.len() / 3
                    ));
                }
                Some(n)
            }
            None => None,
        };
        let uvs = match attr(json::mesh::Semantic::TexCoords(0)) {
            Some(i) => match self.read_floats(i, 2, "TEXCOORD_0") {
                Ok(t) if t.len() / 2 == nv => Some(t),
                Ok(_) => {
                    self.warnings
                        .push("TEXCOORD_0 count differs from POSITION count; UVs ignored".into());
                    None
                }
                Err(e) => {
                    self.warnings.push(format!("{e}; UVs ignored"));
                    None
                }
            },
            None => None,
        };
        let indices: Vec<u32> = match prim.indices {
            Some(ii) => match self.read_accessor(ii.value(), true)? {
                (AccessorData::Uint(v), 1) => v,
                _ => return Err(format!("index accessor {} must be scalar", ii.value())),
            },
            None => (0..nv as u32).collect(),
        };
        if let Some(&bad) = indices.iter().find(|&&i| i as usize >= nv) {
            return Err(format!("vertex index {bad} out of range ({nv} vertices)"));
        }
        if !indices.len().is_multiple_of(3) {
            self.warnings.push(format!(
                "index count {} is not a multiple of 3; trailing indices ignored",
                indices.len()
            ));
        }
        let material = self.material_for(prim.material.map(|m| m.value()))?;

        // World transform; normals with the inverse-transpose; mirrored → flip winding.
        let m3 = Mat3::from_mat4(world);
        let det = m3.determinant();
        if !(det.is_finite() && det != 0.0) {
            return Err("its node transform is singular".into());
        }
        let normal_m = m3.inverse().transpose();
        let flip = det < 0.0;
        let p = |i: usize| {
            world.transform_point3(Vec3::new(
                positions[3 * i],
                positions[3 * i + 1],
                positions[3 * i + 2],
            ))
        };
        let wpos: Vec<Vec3> = (0..nv).map(p).collect();
        let wnrm: Option<Vec<Vec3>> = normals.as_ref().map(|n| {
            (0..nv)
                .map(|i| {
                    let v = normal_m * Vec3::new(n[3 * i], n[3 * i + 1], n[3 * i + 2]);
                    if v.is_finite() {
                        v.normalize_or_zero()
                    } else {
                        Vec3::ZERO
                    }
                })
                .collect()
        });
        let uv = |i: usize| -> Vec2 {
            match &uvs {
                Some(t) => {
                    let v = Vec2::new(t[2 * i], t[2 * i + 1]);
                    if v.is_finite() { v } else { Vec2::ZERO }
                }
                None => Vec2::ZERO,
            }
        };

        let mut remap = vec![u32::MAX; nv];
        let out = &mut self.mesh;
        let push_vertex = |out: &mut Mesh, p: Vec3, n: Vec3, t: Vec2| -> Result<u32, String> {
            let id =
                u32::try_from(out.positions.len()).map_err(|_| "too many vertices".to_string())?;
            out.positions.push(p);
            out.normals.push(n);
            out.uvs.push(t);
            Ok(id)
        };
        let mut bad_normals = 0usize;
        for tri in indices.chunks_exact(3) {
            let mut t = [tri[0] as usize, tri[1] as usize, tri[2] as usize];
            if flip {
                t.swap(1, 2);
            }
            let [a, b, c] = [wpos[t[0]], wpos[t[1]], wpos[t[2]]];
            let g = (b - a).cross(c - a);
            if !(a.is_finite() && b.is_finite() && c.is_finite() && g.is_finite())
                || g.length_squared() <= 0.0
            {
                self.dropped_triangles += 1;
                continue;
            }
            let gn = g.normalize_or_zero();
            if gn == Vec3::ZERO {
                self.dropped_triangles += 1;
                continue;
            }
            let mut ids = [0u32; 3];
            for k in 0..3 {
                let v = t[k];
                let n = wnrm.as_ref().map(|n| n[v]).unwrap_or(Vec3::ZERO);
                if n == Vec3::ZERO {
                    // No normal (flat shading) or a broken one: the geometric normal.
                    if wnrm.is_some() {
                        bad_normals += 1;
                    }
                    ids[k] = push_vertex(out, wpos[v], gn, uv(v))?;
                } else {
                    if remap[v] == u32::MAX {
                        remap[v] = push_vertex(out, wpos[v], n, uv(v))?;
                    }
                    ids[k] = remap[v];
                }
            }
            out.indices.push(ids);
            out.tri_material.push(material);
        }
        if bad_normals > 0 {
            self.warnings.push(format!(
                "{bad_normals} vertex normals were zero or non-finite; used the geometric normal"
            ));
        }
        Ok(())
    }

    fn convert_material(&mut self, i: usize, m: &json::Material) -> Material {
        let name = m.name.clone().unwrap_or_else(|| format!("material{i}"));
        let pbr = &m.pbr_metallic_roughness;
        let bc = pbr.base_color_factor.0;
        let mut base_color = Vec3::new(bc[0], bc[1], bc[2]);
        if !(base_color.is_finite() && base_color.min_element() >= 0.0) {
            self.warnings.push(format!(
                "material '{name}': invalid baseColorFactor; using white"
            ));
            base_color = Vec3::ONE;
        }
        let metallic = clamp01(
            pbr.metallic_factor.0,
            &name,
            "metallicFactor",
            &mut self.warnings,
        );
        let roughness = clamp01(
            pbr.roughness_factor.0,
            &name,
            "roughnessFactor",
            &mut self.warnings,
        );
        let ext = m.extensions.as_ref();
        let transmission = ext
            .and_then(|e| e.transmission.as_ref())
            .map(|t| t.transmission_factor.0)
            .unwrap_or(0.0);
        let mut ior = ext
            .and_then(|e| e.ior.as_ref())
            .map(|i| i.ior.0)
            .unwrap_or(1.5);
        if !(ior.is_finite() && ior >= 1.0) {
            self.warnings.push(format!(
                "material '{name}': IOR {ior} is not ≥ 1; using 1.5"
            ));
            ior = 1.5;
        }
        let volume = ext.and_then(|e| e.volume.as_ref());
        let thickness = volume.map(|v| v.thickness_factor.0).unwrap_or(0.0);
        let mut attenuation_color = volume
            .map(|v| Vec3::from(v.attenuation_color.0))
            .unwrap_or(Vec3::ONE);
        let mut attenuation_distance = volume
            .map(|v| v.attenuation_distance.0)
            .unwrap_or(f32::INFINITY);
        if !(attenuation_color.is_finite() && attenuation_color.min_element() >= 0.0)
            || attenuation_distance.is_nan()
            || attenuation_distance <= 0.0
        {
            self.warnings.push(format!(
                "material '{name}': invalid volume attenuation; ignored"
            ));
            attenuation_color = Vec3::ONE;
            attenuation_distance = f32::INFINITY;
        }
        let strength = ext
            .and_then(|e| e.emissive_strength.as_ref())
            .map(|s| s.emissive_strength.0)
            .unwrap_or(1.0);
        let mut emission = Vec3::from(m.emissive_factor.0) * strength;
        if !(emission.is_finite() && emission.min_element() >= 0.0) {
            self.warnings
                .push(format!("material '{name}': invalid emission; ignored"));
            emission = Vec3::ZERO;
        }
        let spec = ext.and_then(|e| e.specular.as_ref());
        let specular_factor = spec.map(|s| s.specular_factor.0).unwrap_or(1.0);
        let specular_color = spec
            .map(|s| Vec3::from(s.specular_color_factor.0))
            .unwrap_or(Vec3::ONE);
        if spec.is_some_and(|s| s.specular_texture.is_some() || s.specular_color_texture.is_some())
        {
            self.warnings.once("specular-tex", || {
                "KHR_materials_specular textures are ignored".into()
            });
        }
        if ext
            .and_then(|e| e.transmission.as_ref())
            .is_some_and(|t| t.transmission_texture.is_some())
        {
            self.warnings.once("transmission-tex", || {
                "transmission textures are ignored".into()
            });
        }
        if m.normal_texture.is_some()
            || m.occlusion_texture.is_some()
            || m.emissive_texture.is_some()
        {
            self.warnings.once("ignored-tex", || {
                "normal, occlusion and emissive textures are ignored".into()
            });
        }
        if !matches!(
            m.alpha_mode,
            Checked::Valid(json::material::AlphaMode::Opaque)
        ) {
            self.warnings.once("alpha", || {
                "alpha modes MASK/BLEND are ignored (treated as opaque)".into()
            });
        }

        // KHR_materials_dispersion from the raw extension JSON.
        let mut abbe = None;
        if let Some(d) = ext.and_then(|e| e.others.get("KHR_materials_dispersion")) {
            match d.get("dispersion").map(|v| v.as_f64()) {
                None => {}
                Some(Some(x)) if x.is_finite() && x >= 0.0 => {
                    // dispersion 0 = none; otherwise V_d = 20 / dispersion.
                    abbe = (x > 0.0).then(|| (20.0 / x) as f32);
                }
                Some(_) => self.warnings.push(format!(
                    "material '{name}': KHR_materials_dispersion.dispersion must be a number ≥ 0; ignored"
                )),
            }
        }

        let mut distribution = MicrofacetDistribution::Ggx;
        if let Some(x) = extras_value(&m.extras) {
            match x.get("microfacet_distribution") {
                None => {}
                Some(Value::String(s)) if s.eq_ignore_ascii_case("ggx") => {}
                Some(Value::String(s)) if s.eq_ignore_ascii_case("beckmann") => {
                    distribution = MicrofacetDistribution::Beckmann
                }
                Some(v) => self.warnings.push(format!(
                    "material '{name}': microfacet_distribution {v} is not \"ggx\" or \"beckmann\"; using GGX"
                )),
            }
        }

        let base_color_texture = pbr
            .base_color_texture
            .as_ref()
            .and_then(|t| self.texture_ref(t, true, &name));
        let metallic_roughness_texture = pbr
            .metallic_roughness_texture
            .as_ref()
            .and_then(|t| self.texture_ref(t, false, &name));

        let eps = 1e-6;
        let kind = if transmission >= GLASS_TRANSMISSION_THRESHOLD {
            if thickness > 0.0 {
                MaterialKind::Glass
            } else {
                self.warnings.once("thin-glass", || {
                    format!(
                        "material '{name}' is thin-walled glass (transmission without KHR_materials_volume, as Blender exports glass): rendered as a thin sheet; switch it to solid glass in the viewer if the object is a solid"
                    )
                });
                MaterialKind::ThinGlass
            }
        } else {
            if transmission > 0.0 {
                self.warnings.push(format!(
                    "material '{name}': partial transmission {transmission} (< {GLASS_TRANSMISSION_THRESHOLD}) is ignored; treated as opaque"
                ));
            }
            let has_mr_tex = metallic_roughness_texture.is_some();
            if has_mr_tex {
                MaterialKind::MetalRough
            } else if (metallic - 1.0).abs() <= eps && roughness <= eps {
                MaterialKind::Mirror
            } else if (metallic - 1.0).abs() <= eps {
                MaterialKind::GlossyMetal
            } else if metallic <= eps && (roughness - 1.0).abs() <= eps && transmission == 0.0 {
                MaterialKind::Diffuse
            } else {
                MaterialKind::MetalRough
            }
        };
        let mut mat = Material {
            name,
            kind,
            base_color,
            base_color_texture,
            metallic,
            roughness,
            metallic_roughness_texture,
            ior,
            abbe,
            distribution,
            emission,
            double_sided: m.double_sided,
            attenuation_color,
            attenuation_distance,
            specular_factor,
            specular_color,
        };
        if mat.is_emissive() {
            // Contract: an emitter's surface is otherwise black.
            mat.kind = MaterialKind::Diffuse;
            mat.base_color = Vec3::ZERO;
            mat.base_color_texture = None;
            mat.metallic_roughness_texture = None;
        }
        mat
    }

    fn texture_ref(
        &mut self,
        info: &json::texture::Info,
        srgb: bool,
        mat: &str,
    ) -> Option<TextureRef> {
        let ti = info.index.value();
        let tex = match self.texture_cache.get(&(ti, srgb)) {
            Some(t) => *t,
            None => {
                let t = match self.load_texture(ti, srgb) {
                    Ok(t) => {
                        self.textures.push(t);
                        Some(self.textures.len() as u32 - 1)
                    }
                    Err(e) => {
                        self.warnings.push(format!(
                            "material '{mat}': texture {ti} cannot be used ({e}); using no texture"
                        ));
                        None
                    }
                };
                self.texture_cache.insert((ti, srgb), t);
                t
            }
        }?;
        let mut tex_coord = info.tex_coord;
        let mut transform = Affine2::IDENTITY;
        if let Some(tt) = info
            .extensions
            .as_ref()
            .and_then(|e| e.texture_transform.as_ref())
        {
            // KHR_texture_transform: uv' = T · R · S · uv with
            // R = [[cos, sin], [−sin, cos]] (row-major, as in the extension spec).
            let (s, c) = tt.rotation.0.sin_cos();
            let rot = Mat2::from_cols(glam::Vec2::new(c, -s), glam::Vec2::new(s, c));
            let scale = Mat2::from_diagonal(Vec2::from(tt.scale.0));
            transform = Affine2::from_mat2_translation(rot * scale, Vec2::from(tt.offset.0));
            if let Some(tc) = tt.tex_coord {
                tex_coord = tc;
            }
            if !transform.is_finite() {
                self.warnings.push(format!(
                    "material '{mat}': non-finite KHR_texture_transform ignored"
                ));
                transform = Affine2::IDENTITY;
            }
        }
        if tex_coord != 0 {
            self.warnings.once("texcoord", || {
                "only TEXCOORD_0 is loaded; textures using other sets read TEXCOORD_0".into()
            });
        }
        Some(TextureRef {
            texture: tex,
            tex_coord,
            transform,
        })
    }

    fn load_texture(&self, ti: usize, srgb: bool) -> Result<Texture, String> {
        let root = self.root;
        let t = root
            .textures
            .get(ti)
            .ok_or_else(|| "index out of range".to_string())?;
        let ii = t.source.value();
        let img = root
            .images
            .get(ii)
            .ok_or_else(|| format!("image {ii} does not exist"))?;
        let bytes: Vec<u8> = if let Some(vi) = img.buffer_view {
            let view = root
                .buffer_views
                .get(vi.value())
                .ok_or_else(|| format!("image {ii}: buffer view does not exist"))?;
            self.view_bytes(vi.value(), view)?.to_vec()
        } else if let Some(uri) = &img.uri {
            if let Some(rest) = uri.strip_prefix("data:") {
                let data = rest
                    .split_once(',')
                    .map(|(_, d)| d)
                    .ok_or_else(|| format!("image {ii}: malformed data URI"))?;
                base64_decode(data).ok_or_else(|| format!("image {ii}: bad base64 data"))?
            } else if uri.contains(':') && !uri.starts_with("file:") {
                return Err(format!("image {ii}: unsupported URI scheme"));
            } else {
                let rel = uri
                    .strip_prefix("file://")
                    .or(uri.strip_prefix("file:"))
                    .unwrap_or(uri);
                let rel = percent_decode(rel).ok_or_else(|| format!("image {ii}: bad URI"))?;
                let base = self.base.ok_or_else(|| {
                    format!("image {ii}: external file '{rel}' but no base directory")
                })?;
                std::fs::read(base.join(&rel)).map_err(|e| format!("image '{rel}': {e}"))?
            }
        } else {
            return Err(format!("image {ii} has neither bufferView nor uri"));
        };
        let dynimg = image::load_from_memory(&bytes).map_err(|e| format!("image {ii}: {e}"))?;
        let (w, h) = (dynimg.width(), dynimg.height());
        if w == 0 || h == 0 || w > super::MAX_IMAGE_SIDE || h > super::MAX_IMAGE_SIDE {
            return Err(format!("image {ii}: size {w}x{h} out of range"));
        }
        let rgba = dynimg.to_rgba32f();
        let texels = rgba
            .pixels()
            .map(|p| {
                let v = Vec4::from(p.0);
                let v = if v.is_finite() { v } else { Vec4::ZERO };
                if srgb {
                    Vec4::new(
                        srgb_to_linear(v.x),
                        srgb_to_linear(v.y),
                        srgb_to_linear(v.z),
                        v.w,
                    )
                } else {
                    v
                }
            })
            .collect();
        let (mut wrap_s, mut wrap_t, mut linear) = (Wrap::Repeat, Wrap::Repeat, true);
        if let Some(si) = t.sampler
            && let Some(s) = root.samplers.get(si.value())
        {
            wrap_s = wrap_mode(&s.wrap_s);
            wrap_t = wrap_mode(&s.wrap_t);
            linear = !matches!(
                s.mag_filter,
                Some(Checked::Valid(json::texture::MagFilter::Nearest))
            );
        }
        Ok(Texture {
            width: w,
            height: h,
            texels,
            wrap_s,
            wrap_t,
            linear,
        })
    }
}

fn wrap_mode(w: &Checked<json::texture::WrappingMode>) -> Wrap {
    use json::texture::WrappingMode as W;
    match w {
        Checked::Valid(W::ClampToEdge) => Wrap::ClampToEdge,
        Checked::Valid(W::MirroredRepeat) => Wrap::MirroredRepeat,
        _ => Wrap::Repeat,
    }
}

/// sRGB electro-optical transfer function (IEC 61966-2-1).
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

fn clamp01(x: f32, mat: &str, what: &str, w: &mut Warnings) -> f32 {
    if (0.0..=1.0).contains(&x) {
        x
    } else {
        w.push(format!("material '{mat}': {what} {x} clamped to [0, 1]"));
        if x.is_nan() { 0.0 } else { x.clamp(0.0, 1.0) }
    }
}

fn extras_value(extras: &json::Extras) -> Option<Value> {
    extras
        .as_ref()
        .and_then(|raw| serde_json::from_str::<Value>(raw.get()).ok())
}

/// A node's local matrix: `matrix` if present, else T · R · S.
fn node_local_matrix(node: &json::Node) -> Result<Mat4, String> {
    let m = if let Some(m) = node.matrix {
        Mat4::from_cols_array(&m)
    } else {
        let t = Vec3::from(node.translation.unwrap_or([0.0; 3]));
        let s = Vec3::from(node.scale.unwrap_or([1.0; 3]));
        let r = node.rotation.map(|q| q.0).unwrap_or([0.0, 0.0, 0.0, 1.0]);
        let q = Quat::from_array(r);
        let len = q.length();
        if !(len.is_finite() && len > 1e-6) {
            return Err("rotation quaternion has zero or non-finite length".into());
        }
        Mat4::from_scale_rotation_translation(s, q / len, t)
    };
    if m.is_finite() {
        Ok(m)
    } else {
        Err("transform is not finite".into())
    }
}

fn get_u32(obj: &Value, key: &str) -> anyhow::Result<Option<u32>> {
    match obj.get(key) {
        None | Some(Value::Null) => Ok(None),
        Some(v) => {
            let x = v
                .as_f64()
                .filter(|x| x.fract() == 0.0 && *x >= 0.0 && *x <= u32::MAX as f64);
            match x {
                Some(x) => Ok(Some(x as u32)),
                None => bail!("extras.render.{key} must be a non-negative integer, got {v}"),
            }
        }
    }
}

/// `scenes[0].extras.render` → settings (defaults for what is missing).
fn parse_render_settings(extras: Option<&Value>) -> anyhow::Result<RenderSettings> {
    let mut s = RenderSettings::default();
    let Some(r) = extras.and_then(|e| e.get("render")) else {
        return Ok(s);
    };
    if !r.is_object() {
        bail!("extras.render must be an object, got {r}");
    }
    if let Some(v) = get_u32(r, "width")? {
        s.width = v;
    }
    if let Some(v) = get_u32(r, "height")? {
        s.height = v;
    }
    if let Some(v) = get_u32(r, "max_depth")? {
        s.max_depth = v;
    }
    if let Some(v) = get_u32(r, "rr_depth")? {
        s.rr_depth = v;
    }
    if let Some(v) = get_u32(r, "spp")? {
        s.spp = v;
    }
    Ok(s)
}

/// `scenes[0].extras.environment` → uniform radiance `[r, g, b]` (a single number = grey).
fn parse_environment(extras: Option<&Value>) -> anyhow::Result<Vec3> {
    let Some(e) = extras.and_then(|e| e.get("environment")) else {
        return Ok(Vec3::ZERO);
    };
    let bad = || anyhow!("extras.environment must be [r, g, b] with finite values ≥ 0, got {e}");
    let v = match e {
        Value::Number(n) => Vec3::splat(n.as_f64().ok_or_else(bad)? as f32),
        Value::Array(a) if a.len() == 3 => {
            let c: Option<Vec<f64>> = a.iter().map(|x| x.as_f64()).collect();
            let c = c.ok_or_else(bad)?;
            Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32)
        }
        _ => return Err(bad()),
    };
    if !(v.is_finite() && v.min_element() >= 0.0) {
        return Err(bad());
    }
    Ok(v)
}

/// No camera in the file: look down −Z at the bounding sphere, framing it in the smaller FOV.
pub fn default_camera(mesh: &Mesh, settings: &RenderSettings) -> Camera {
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    for p in &mesh.positions {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    let (center, mut radius) = if lo.is_finite() && hi.is_finite() {
        (0.5 * (lo + hi), 0.5 * (hi - lo).length())
    } else {
        (Vec3::ZERO, 1.0)
    };
    if !(radius.is_finite() && radius > 0.0) {
        radius = 1.0;
    }
    let yfov = 0.6911_f32; // 39.6°, the Cornell box camera
    let aspect = settings.width.max(1) as f32 / settings.height.max(1) as f32;
    let half_x = ((0.5 * yfov).tan() * aspect).atan();
    let half = (0.5 * yfov).min(half_x);
    let dist = radius / half.sin() * 1.05;
    Camera::look_at(center + Vec3::Z * dist, center, Vec3::Y, yfov)
}
