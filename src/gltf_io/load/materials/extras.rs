//! A material's `extras` (refract's own keys in the scene contract): microfacet distribution,
//! nested-dielectric priority and tabulated conductor.

use crate::bsdf::{Metal, MicrofacetDistribution};
use crate::gltf_io::load::Loader;
use crate::gltf_io::load::extras::extras_value;
use gltf::json;
use serde_json::Value;

impl Loader<'_> {
    /// `extras.microfacet_distribution`: "ggx" (default) or "beckmann".
    pub(super) fn microfacet_distribution(
        &mut self,
        m: &json::Material,
        name: &str,
        i: usize,
    ) -> anyhow::Result<MicrofacetDistribution> {
        let mut distribution = MicrofacetDistribution::Ggx;
        if let Some(x) = extras_value(&m.extras, &format!("/materials/{i}/extras"))? {
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
        Ok(distribution)
    }

    /// `extras.priority`: an integer (nested dielectrics: where closed volumes overlap, the
    /// higher priority is the medium; Schmidt & Budge 2002). Default 0; anything else is
    /// replaced by 0 with a warning.
    pub(super) fn priority(
        &mut self,
        m: &json::Material,
        name: &str,
        i: usize,
    ) -> anyhow::Result<i32> {
        let Some(x) = extras_value(&m.extras, &format!("/materials/{i}/extras"))? else {
            return Ok(0);
        };
        let Some(v) = x.get("priority") else {
            return Ok(0);
        };
        match v.as_i64().and_then(|p| i32::try_from(p).ok()) {
            Some(p) => Ok(p),
            None => {
                self.warnings.push(format!(
                    "material '{name}': extras.priority {v} is not a 32-bit integer; using 0"
                ));
                Ok(0)
            }
        }
    }
}

/// `extras.sampling`: "cosine" (default) or "uniform" (the importance-sampling teaching
/// switch, `Material::uniform_sampling`); anything else is an error naming the material.
pub(super) fn uniform_sampling(m: &json::Material, name: &str, i: usize) -> anyhow::Result<bool> {
    let Some(x) = extras_value(&m.extras, &format!("/materials/{i}/extras"))? else {
        return Ok(false);
    };
    match x.get("sampling") {
        None | Some(Value::Null) => Ok(false),
        Some(Value::String(s)) if s.eq_ignore_ascii_case("cosine") => Ok(false),
        Some(Value::String(s)) if s.eq_ignore_ascii_case("uniform") => Ok(true),
        Some(v) => anyhow::bail!(
            "material '{name}': extras.sampling must be \"cosine\" or \"uniform\", got {v}"
        ),
    }
}

/// `extras.conductor`: "Au", "Ag", "Cu" or "Al" (a tabulated metal); anything else is an
/// error naming the material and the value.
pub(super) fn conductor(m: &json::Material, name: &str, i: usize) -> anyhow::Result<Option<Metal>> {
    let Some(x) = extras_value(&m.extras, &format!("/materials/{i}/extras"))? else {
        return Ok(None);
    };
    let known = || Metal::ALL.map(|m| format!("\"{}\"", m.symbol())).join(", ");
    match x.get("conductor") {
        None | Some(Value::Null) => Ok(None),
        Some(Value::String(s)) => Metal::from_symbol(s).map(Some).ok_or_else(|| {
            anyhow::anyhow!(
                "material '{name}': extras.conductor \"{s}\" is not a known metal (known: {})",
                known()
            )
        }),
        Some(v) => anyhow::bail!(
            "material '{name}': extras.conductor must be a string (one of {}), got {v}",
            known()
        ),
    }
}
