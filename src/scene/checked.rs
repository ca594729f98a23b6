//! [`Checked`]: a value that passed its validation — once, where it was edited. The viewer's
//! backends and the GPU renderer's checked setters take one, so an edited material or camera
//! is validated at the edit and nowhere after it (docs/architecture.md, "One validation per
//! edit").

use super::{Camera, Material};
use anyhow::Result;
use std::ops::Deref;

/// A value with a validation rule.
pub trait Validate {
    /// Reject what no renderer can use, with a message naming the value.
    fn validate(&self) -> Result<()>;
}

impl Validate for Material {
    fn validate(&self) -> Result<()> {
        Material::validate(self)
    }
}

impl Validate for Camera {
    fn validate(&self) -> Result<()> {
        Camera::validate(self)
    }
}

/// A `T` that passed [`Validate::validate`]; the only way to make one is [`Checked::new`].
#[derive(Clone, Debug, PartialEq)]
pub struct Checked<T>(T);

impl<T: Validate> Checked<T> {
    /// `value`, validated.
    pub fn new(value: T) -> Result<Checked<T>> {
        value.validate()?;
        Ok(Checked(value))
    }
}

impl<T> Checked<T> {
    /// The value, no longer marked as checked.
    pub fn into_inner(self) -> T {
        self.0
    }
}

impl<T> Deref for Checked<T> {
    type Target = T;
    fn deref(&self) -> &T {
        &self.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_a_valid_value_is_checked() {
        let mut m = Material::default();
        assert!(Checked::new(m.clone()).is_ok());
        m.ior = f32::NAN;
        let e = format!("{:#}", Checked::new(m).unwrap_err());
        assert!(e.contains("IOR"), "{e}");
        let mut c = Camera::look_at(glam::Vec3::Z, glam::Vec3::ZERO, glam::Vec3::Y, 0.8);
        assert!(Checked::new(c).is_ok());
        c.position.x = f32::INFINITY;
        assert!(Checked::new(c).is_err());
    }
}
