//! The light-transport estimator, and the `auto` rule that picks one from a scene's features.

use crate::scene::caustic_casters::{CASTERS, emitter_solid_angle_at_casters};
use crate::scene::{Features, Scene};

/// Light-transport estimator. The serde names ("auto", "path", "bdpt", "lt", "lt+pt" with
/// alias "ltpt") are those of the viewer's settings sidecars.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    Hash,
    serde::Serialize,
    serde::Deserialize,
    clap::ValueEnum,
)]
#[serde(rename_all = "lowercase")]
pub enum Estimator {
    /// Picked from the scene (`Estimator::resolve`): sppm for specular surfaces under a
    /// delta light or light that looks small from them (< 0.3 sr: caustics), lt+pt for
    /// dispersive or rough glass lit so, else path tracing.
    Auto,
    /// Unidirectional path tracing with NEE + MIS.
    #[default]
    Path,
    /// Bidirectional path tracing, MIS over all strategies (incl. light-tracing splats).
    Bdpt,
    /// Pure light tracing (light subpaths connected to the camera only).
    Lt,
    /// Path tracing and light tracing combined by MIS: the GPU estimator for caustics
    /// (src/gpu/light_tracing.wgsl). The CPU renders it with full BDPT, whose strategies
    /// are a superset.
    #[serde(rename = "lt+pt", alias = "ltpt")]
    #[value(name = "lt+pt", alias = "ltpt")]
    LtPt,
    /// Path tracing with the caustics (L S+ D) from progressive photon mapping, radius
    /// shrinking with α = 2/3 (`cpu::sppm`): caustics seen through glass or in mirrors.
    Sppm,
}

impl std::fmt::Display for Estimator {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Estimator::Auto => "auto",
            Estimator::Path => "path",
            Estimator::Bdpt => "bdpt",
            Estimator::Lt => "lt",
            Estimator::LtPt => "lt+pt",
            Estimator::Sppm => "sppm",
        })
    }
}

impl std::str::FromStr for Estimator {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.to_ascii_lowercase().as_str() {
            "auto" => Ok(Estimator::Auto),
            "path" | "pt" => Ok(Estimator::Path),
            "bdpt" => Ok(Estimator::Bdpt),
            "lt" | "light" => Ok(Estimator::Lt),
            "lt+pt" | "ltpt" | "pt+lt" => Ok(Estimator::LtPt),
            "sppm" | "ppm" | "photon" => Ok(Estimator::Sppm),
            _ => Err(format!(
                "unknown estimator '{s}' (use auto, path, bdpt, lt, lt+pt or sppm)"
            )),
        }
    }
}

impl Estimator {
    /// The estimator this choice means for `scene` (never `Auto`).
    pub fn resolve(self, scene: &Scene) -> Estimator {
        self.resolve_why(scene).0
    }

    /// [`Estimator::resolve`] and, for `Auto`, a few words on why (empty otherwise).
    ///
    /// The rule: a delta light, or emitters that look small from the glass and mirrors
    /// (less than [`SMALL_LIGHT_SR`] on average), make caustics that path tracing samples
    /// badly.
    /// With specular surfaces (mirror, smooth or thin glass) their caustics L S+ D are
    /// photon-mapped (`sppm`), which also renders them seen through glass or in a mirror;
    /// with dispersion or only rough glass, the bidirectional estimator (lt+pt: bdpt on the
    /// CPU) takes them — photons of one iteration share one set of wavelengths, which makes
    /// a rainbow noisier than BDPT's, and photons do not end at glossy surfaces.
    pub fn resolve_why(self, scene: &Scene) -> (Estimator, &'static str) {
        if self != Estimator::Auto {
            return (self, "");
        }
        let f = scene.features();
        if !has_small_light(scene, f) {
            let why = if f.intersects(CASTERS) {
                "the lights look large from the glass and mirrors (≥ 0.3 sr): path tracing"
            } else {
                "no glass or mirror: path tracing"
            };
            return (Estimator::Path, why);
        }
        auto_with_small_light(f)
    }

    /// A clap value parser: the [`std::str::FromStr`] spellings and error message (aliases
    /// such as `pt` included), with the [`clap::ValueEnum`] names listed in `--help`.
    pub fn parser() -> EstimatorParser {
        EstimatorParser
    }
}

/// Emitters that subtend less than this solid angle (sr), averaged over the surfaces that
/// cast caustics, count as small. Set from measurements (docs/estimators.md, "Choosing the estimator":
/// relMSE at equal time, path against the photon and bidirectional estimators):
/// cornell-glass (0.093 sr; its light grown 1.5×: 0.21 sr), rough-glass (0.103 sr) and
/// env-spheres (0.003 sr) converge 1.9–6× sooner with them; glass-of-water (0.35 sr),
/// materials (0.44 sr), glass-slab (0.56 sr) and ior-grid (0.87 sr) 1.1–1.9× sooner with
/// path tracing. Not a sharp line — cornell-glass with its light grown 2× (0.37 sr) still
/// photon-maps 1.4–1.6× better — so the threshold sits between the nearest scenes measured
/// on either side.
pub const SMALL_LIGHT_SR: f32 = 0.3;

/// Whether `scene` (with features `f`) has a delta light, or light (emissive triangles and
/// the environment) that looks small from its caustic casters ([`SMALL_LIGHT_SR`]), so that
/// BSDF-sampled caustic paths rarely reach it. (No light at all: nothing to trace from, so
/// not small.)
fn has_small_light(scene: &Scene, f: Features) -> bool {
    f.contains(Features::PUNCTUAL_LIGHTS)
        || emitter_solid_angle_at_casters(scene).is_some_and(|sr| sr < SMALL_LIGHT_SR)
}

/// The `auto` choice, and why, for a scene with features `f` and a small or delta light:
/// bidirectional for dispersion, photon mapping for specular surfaces, bidirectional for
/// rough glass alone, else path tracing.
fn auto_with_small_light(f: Features) -> (Estimator, &'static str) {
    let specular = f.intersects(
        Features::SMOOTH_GLASS
            | Features::THIN_GLASS
            | Features::MIRROR
            | Features::SMOOTH_CONDUCTOR,
    );
    let glass = specular || f.contains(Features::ROUGH_GLASS);
    let punctual = f.contains(Features::PUNCTUAL_LIGHTS);
    if f.contains(Features::DISPERSION) {
        (
            Estimator::LtPt,
            "dispersive glass and a small light: bidirectional",
        )
    } else if specular && punctual {
        (
            Estimator::Sppm,
            "specular surfaces and a delta light: photon-mapped caustics",
        )
    } else if specular {
        (
            Estimator::Sppm,
            "specular surfaces and a light that looks small from them: photon-mapped caustics",
        )
    } else if glass {
        (
            Estimator::LtPt,
            "rough glass and a light that looks small from it: bidirectional",
        )
    } else {
        (Estimator::Path, "no glass or mirror: path tracing")
    }
}

/// See [`Estimator::parser`].
#[derive(Clone, Copy, Debug)]
pub struct EstimatorParser;

impl clap::builder::TypedValueParser for EstimatorParser {
    type Value = Estimator;

    fn parse_ref(
        &self,
        cmd: &clap::Command,
        arg: Option<&clap::Arg>,
        value: &std::ffi::OsStr,
    ) -> Result<Estimator, clap::Error> {
        let from_str: fn(&str) -> Result<Estimator, String> = str::parse;
        from_str.parse_ref(cmd, arg, value)
    }

    fn possible_values(
        &self,
    ) -> Option<Box<dyn Iterator<Item = clap::builder::PossibleValue> + '_>> {
        use clap::ValueEnum;
        Some(Box::new(
            Estimator::value_variants()
                .iter()
                .filter_map(|e| e.to_possible_value()),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `auto` picks light + path tracing for glass lit by a small light (caustics), path
    /// tracing otherwise; `lt+pt` survives a settings round trip under its own name.
    #[test]
    fn auto_estimator_picks_by_scene_features() {
        let caustic = Scene::load("builtin:caustic").unwrap();
        let furnace = Scene::load("builtin:furnace").unwrap();
        assert_eq!(Estimator::Auto.resolve(&caustic), Estimator::Sppm);
        assert_eq!(Estimator::Sppm.resolve(&caustic), Estimator::Sppm);
        assert_eq!(Estimator::Auto.resolve(&furnace), Estimator::Path);
        // The reason states the threshold the rule uses (a literal in a `&'static str`).
        let (_, why) = Estimator::Auto.resolve_why(&furnace);
        assert!(why.contains(&format!("≥ {SMALL_LIGHT_SR} sr")), "{why}");
        let text = serde_json::to_string(&Estimator::LtPt).unwrap();
        assert_eq!(text, "\"lt+pt\"");
        let back: Estimator = serde_json::from_str(&text).unwrap();
        assert_eq!(back, Estimator::LtPt);
    }

    /// Every spelling parses to its estimator and prints back under the serde name.
    #[test]
    fn names_round_trip() {
        for (s, e) in [
            ("auto", Estimator::Auto),
            ("path", Estimator::Path),
            ("pt", Estimator::Path),
            ("bdpt", Estimator::Bdpt),
            ("lt", Estimator::Lt),
            ("lt+pt", Estimator::LtPt),
            ("LTPT", Estimator::LtPt),
        ] {
            assert_eq!(s.parse::<Estimator>(), Ok(e), "{s}");
            let json = serde_json::to_string(&e).unwrap();
            assert_eq!(json, format!("\"{e}\""));
        }
        let back: Estimator = serde_json::from_str("\"ltpt\"").unwrap();
        assert_eq!(back, Estimator::LtPt);
        let furnace = Scene::load("builtin:furnace").unwrap();
        assert_eq!(Estimator::Bdpt.resolve_why(&furnace), (Estimator::Bdpt, ""));
    }
}
