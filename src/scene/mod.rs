//! Scene description: one merged world-space triangle mesh, materials, textures, lights,
//! camera, environment and render settings. Produced by the glTF loader or the built-ins,
//! consumed by the BVH and both renderers.

pub mod builtin;
pub mod camera;
pub mod caustic_casters;
pub mod checked;
pub mod edits;
pub mod env_map;
pub mod features;
pub mod hdri;
pub mod light;
pub mod material;
pub mod nesting;

pub use camera::Camera;
pub use checked::Checked;
pub use features::Features;
pub use material::{Iridescence, Material, MaterialKind, Texture, TextureRef, Wrap};

use glam::{Vec2, Vec3, Vec4};

/// Render settings from `scenes[0].extras.render` (all optional in the file).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RenderSettings {
    pub width: u32,
    pub height: u32,
    /// Mitsuba's meaning: 1 = emitters seen directly, 2 = direct lighting only, …
    pub max_depth: u32,
    /// Russian roulette starts at this depth (Mitsuba's `rr_depth`).
    pub rr_depth: u32,
    pub spp: u32,
    /// A scene-wide light spectrum: None = white (every emitter's RGB uplifted over
    /// 360–830 nm), Some(λ₀) = every emitter — area, punctual, environment — radiates only
    /// at λ₀ nm (a lecture tool for refraction by wavelength; one line for the whole scene).
    /// Turns spectral transport on (`cpu::spectral::LightLine`). glTF
    /// `extras.render.light_line_nm`, CLI `--light-line`.
    #[serde(default)]
    pub light_line_nm: Option<f32>,
}

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings {
            width: 512,
            height: 512,
            max_depth: 64,
            rr_depth: 5,
            spp: 64,
            light_line_nm: None,
        }
    }
}

/// The largest image side we accept (a clear error beyond it, never an allocation failure).
pub const MAX_IMAGE_SIDE: u32 = 16384;

/// World-space triangle soup. All primitives of all nodes are merged (transforms applied).
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    pub positions: Vec<Vec3>,
    /// Per-vertex shading normals (unit length), same length as `positions`.
    pub normals: Vec<Vec3>,
    /// Per-vertex TEXCOORD_0, same length as `positions` (zeros where absent).
    pub uvs: Vec<Vec2>,
    /// Per-vertex tangents (xyz unit, w = bitangent sign ±1; glTF TANGENT or MikkTSpace),
    /// same length as `positions` when some material has a normal map, else empty (zero
    /// where a vertex's material has none or no frame could be built).
    pub tangents: Vec<Vec4>,
    /// Counter-clockwise triangles (front face = CCW seen from the outside).
    pub indices: Vec<[u32; 3]>,
    /// Material index per triangle.
    pub tri_material: Vec<u32>,
}

impl Mesh {
    pub fn triangle_count(&self) -> usize {
        self.indices.len()
    }

    /// Vertex positions of triangle `t`.
    #[inline]
    pub fn tri(&self, t: usize) -> [Vec3; 3] {
        let [a, b, c] = self.indices[t];
        [
            self.positions[a as usize],
            self.positions[b as usize],
            self.positions[c as usize],
        ]
    }

    /// Area of triangle `t`.
    pub fn area(&self, t: usize) -> f32 {
        let [a, b, c] = self.tri(t);
        0.5 * (b - a).cross(c - a).length()
    }

    /// Append another mesh (indices are rebased).
    pub fn append(&mut self, other: &Mesh) {
        let base = self.positions.len() as u32;
        self.positions.extend_from_slice(&other.positions);
        self.normals.extend_from_slice(&other.normals);
        self.uvs.extend_from_slice(&other.uvs);
        self.indices.extend(
            other
                .indices
                .iter()
                .map(|t| [t[0] + base, t[1] + base, t[2] + base]),
        );
        self.tri_material.extend_from_slice(&other.tri_material);
    }
}

/// glTF `KHR_lights_punctual` lights (delta lights: reached only by NEE and light tracing).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PunctualLight {
    /// Radiant intensity per steradian (glTF "cd" used as given), times colour.
    Point { position: Vec3, intensity: Vec3 },
    /// `direction` is where the spot points (local −Z of its node).
    Spot {
        position: Vec3,
        direction: Vec3,
        intensity: Vec3,
        cos_inner: f32,
        cos_outer: f32,
    },
    /// `direction` is the direction light travels (local −Z of its node); irradiance in "lux".
    Directional { direction: Vec3, irradiance: Vec3 },
}

/// A complete scene.
#[derive(Clone, Debug)]
pub struct Scene {
    pub name: String,
    pub mesh: Mesh,
    pub materials: Vec<Material>,
    pub textures: Vec<Texture>,
    pub punctual_lights: Vec<PunctualLight>,
    pub camera: Camera,
    /// Uniform radiance of escaping rays (ignored when `env_map` is set).
    pub environment: Vec3,
    /// An equirectangular environment image (importance-sampled); replaces `environment`.
    pub env_map: Option<env_map::EnvImage>,
    pub settings: RenderSettings,
    /// Non-fatal problems found while loading (unsupported extensions, skipped primitives …).
    pub warnings: Vec<String>,
}

impl Scene {
    /// `spec` as a record that names the same scene from any working directory: a file's
    /// canonical absolute path (what the viewer keeps in its settings and screenshot
    /// sidecars, so `render --settings` finds the scene wherever it runs), a built-in or a
    /// path that does not resolve unchanged (loading it reports the error).
    pub fn canonical_spec(spec: &str) -> String {
        if spec.starts_with("builtin:") {
            return spec.to_owned();
        }
        std::fs::canonicalize(spec).map_or_else(|_| spec.to_owned(), |p| p.display().to_string())
    }

    /// Which material kinds, lights and effects the scene uses.
    pub fn features(&self) -> Features {
        features::compute(self)
    }

    /// Indices of triangles whose material emits (area lights).
    pub fn emissive_triangles(&self) -> Vec<u32> {
        (0..self.mesh.triangle_count() as u32)
            .filter(|&t| {
                let m = &self.materials[self.mesh.tri_material[t as usize] as usize];
                m.is_emissive() && self.mesh.area(t as usize) > 0.0
            })
            .collect()
    }

    /// Does anything emit: an emissive triangle, a punctual light or an environment?
    pub fn has_light(&self) -> bool {
        !self.emissive_triangles().is_empty()
            || !self.punctual_lights.is_empty()
            || self.environment.max_element() > 0.0
            || self.env_map.is_some()
    }

    /// Axis-aligned bounds of all vertices (min, max).
    pub fn bounds(&self) -> (Vec3, Vec3) {
        let mut lo = Vec3::splat(f32::INFINITY);
        let mut hi = Vec3::splat(f32::NEG_INFINITY);
        for p in &self.mesh.positions {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        if !lo.is_finite() {
            return (Vec3::ZERO, Vec3::ZERO);
        }
        (lo, hi)
    }

    /// Check invariants the renderers rely on; returns a clear error otherwise.
    pub fn validate(&self) -> anyhow::Result<()> {
        self.validate_settings()?;
        self.validate_mesh()?;
        for mat in &self.materials {
            mat.validate()?;
        }
        self.validate_environment()?;
        self.camera.validate()?;
        Ok(())
    }

    /// The render settings: image size in range, at least one bounce, a valid light line.
    fn validate_settings(&self) -> anyhow::Result<()> {
        use anyhow::ensure;
        let s = &self.settings;
        ensure!(
            s.width >= 1
                && s.height >= 1
                && s.width <= MAX_IMAGE_SIDE
                && s.height <= MAX_IMAGE_SIDE,
            "image size {}x{} is out of range (1..={MAX_IMAGE_SIDE} per side)",
            s.width,
            s.height
        );
        ensure!(s.max_depth >= 1, "max_depth must be at least 1");
        if let Some(nm) = s.light_line_nm {
            crate::math::spectrum::check_light_line(nm, "the render setting light_line_nm")
                .map_err(anyhow::Error::msg)?;
        }
        Ok(())
    }

    /// The mesh: attribute arrays of one length, one material id per triangle, vertex and
    /// material indices in range, finite positions.
    fn validate_mesh(&self) -> anyhow::Result<()> {
        use anyhow::ensure;
        let m = &self.mesh;
        ensure!(
            m.normals.len() == m.positions.len() && m.uvs.len() == m.positions.len(),
            "mesh attribute arrays have different lengths"
        );
        ensure!(
            m.tri_material.len() == m.indices.len(),
            "mesh has {} triangles but {} material ids",
            m.indices.len(),
            m.tri_material.len()
        );
        let nv = m.positions.len() as u32;
        for (i, t) in m.indices.iter().enumerate() {
            ensure!(
                t.iter().all(|&v| v < nv),
                "triangle {i} indexes a vertex out of range"
            );
        }
        for (i, &mi) in m.tri_material.iter().enumerate() {
            ensure!(
                (mi as usize) < self.materials.len(),
                "triangle {i} uses missing material {mi}"
            );
        }
        ensure!(
            m.positions.iter().all(|p| p.is_finite()),
            "mesh has non-finite vertex positions"
        );
        Ok(())
    }

    /// The environment: finite, non-negative radiance; an environment image's strength
    /// finite and ≥ 0 and its rotation finite.
    fn validate_environment(&self) -> anyhow::Result<()> {
        use anyhow::ensure;
        ensure!(
            self.environment.is_finite() && self.environment.min_element() >= 0.0,
            "environment radiance must be finite and non-negative"
        );
        if let Some(e) = &self.env_map {
            ensure!(
                e.strength.is_finite() && e.strength >= 0.0 && e.rotation.is_finite(),
                "environment image strength must be finite and ≥ 0 and its rotation finite"
            );
        }
        Ok(())
    }
}
