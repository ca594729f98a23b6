//! glTF 2.0 in and out: the layer above the scene data model (`crate::scene`), which it
//! reads (`load`, and `Scene::load` for a path or a built-in) and writes (`export`). The
//! scene knows nothing of glTF.

pub mod export;
pub mod load;
mod scene_load;
