//! Edits of a loaded scene, stored relative to it as loaded: material overrides by index,
//! light scale/colour/placement and the camera orbit. The settings sidecar
//! (`render::settings::ViewerSettings`) holds them; the viewer and `refract render --settings`
//! apply them through the same functions, so both render the same scene.

mod camera;
mod light;
mod main_light;
mod material;
#[cfg(test)]
mod tests;

pub use camera::{CameraEdit, Orbit};
pub use light::{LightEdit, LightSpectrum};
pub use main_light::MainLight;
pub use material::{MaterialEdit, apply_materials};
