//! `Scene::load`: a scene from a path (glTF) or `builtin:NAME`. Defined here, above the
//! data model, so `scene` does not depend on its loader.

use super::load::{LoadLimits, load_path_with};
use crate::scene::{Scene, builtin};
use std::path::Path;

impl Scene {
    /// Load from a path or `builtin:NAME`.
    pub fn load(spec: &str) -> anyhow::Result<Scene> {
        Self::load_with(spec, &LoadLimits::default())
    }

    /// `load` with the budgets and URI permission of `limits` (glTF files only; built-ins are
    /// within every budget).
    pub fn load_with(spec: &str, limits: &LoadLimits) -> anyhow::Result<Scene> {
        if let Some(name) = spec.strip_prefix("builtin:") {
            builtin::load(name)
        } else {
            load_path_with(Path::new(spec), limits)
        }
    }
}
