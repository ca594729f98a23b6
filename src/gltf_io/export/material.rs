//! Scene materials as glTF materials: metallic-roughness factors, the KHR_materials_*
//! extensions (emissive strength, transmission, IOR, volume, dispersion, specular,
//! iridescence) and `extras`.

use super::split_color;
use crate::bsdf::MicrofacetDistribution;
use crate::scene::{Material, MaterialKind};
use glam::Vec3;
use serde_json::{Map, Value, json};

/// glTF material of `m` (metallic-roughness + KHR extensions, recorded in `used`).
pub(super) fn material_json(m: &Material, used: &mut Vec<&'static str>) -> Value {
    let (metallic, roughness) = metallic_roughness(m);
    let bc = m.base_color;
    let mut j = json!({
        "name": m.name,
        "pbrMetallicRoughness": {
            "baseColorFactor": [bc.x, bc.y, bc.z, 1.0],
            "metallicFactor": metallic,
            "roughnessFactor": roughness
        }
    });
    if m.double_sided {
        j["doubleSided"] = json!(true);
    }
    let mut ext = Map::new();
    if m.is_emissive() {
        emission_json(m, &mut j, &mut ext, used);
    }
    if m.is_transmissive() {
        transmission_extensions(m, &mut ext, used);
    }
    specular_extension(m, &mut ext, used);
    iridescence_extension(m, &mut ext, used);
    if !ext.is_empty() {
        j["extensions"] = Value::Object(ext);
    }
    let extras = material_extras(m);
    if !extras.is_empty() {
        j["extras"] = Value::Object(extras);
    }
    j
}

/// The glTF (metallicFactor, roughnessFactor) that the loader maps back to `m`'s kind.
fn metallic_roughness(m: &Material) -> (f32, f32) {
    match m.kind {
        MaterialKind::Diffuse => (0.0, 1.0),
        MaterialKind::Mirror => (1.0, 0.0),
        MaterialKind::GlossyMetal => (1.0, m.roughness),
        MaterialKind::Glass | MaterialKind::ThinGlass => (0.0, m.roughness),
        MaterialKind::MetalRough => (m.metallic, m.roughness),
    }
}

/// `emissiveFactor` of an emissive material, with KHR_materials_emissive_strength (recorded
/// in `used`) when a component exceeds 1.
fn emission_json(
    m: &Material,
    j: &mut Value,
    ext: &mut Map<String, Value>,
    used: &mut Vec<&'static str>,
) {
    let (c, s) = split_color(m.emission);
    if s <= 1.0 {
        j["emissiveFactor"] = json!(m.emission.to_array());
    } else {
        j["emissiveFactor"] = json!(c.to_array());
        ext.insert(
            "KHR_materials_emissive_strength".into(),
            json!({ "emissiveStrength": s }),
        );
        used.push("KHR_materials_emissive_strength");
    }
}

/// KHR_materials_specular of a metallic-roughness material whose specular factor or colour
/// is not the default, recorded in `used`.
fn specular_extension(m: &Material, ext: &mut Map<String, Value>, used: &mut Vec<&'static str>) {
    if m.kind == MaterialKind::MetalRough
        && (m.specular_factor != 1.0 || m.specular_color != Vec3::ONE)
    {
        ext.insert(
            "KHR_materials_specular".into(),
            json!({
                "specularFactor": m.specular_factor,
                "specularColorFactor": m.specular_color.to_array()
            }),
        );
        used.push("KHR_materials_specular");
    }
}

/// KHR_materials_iridescence of a material with a film, recorded in `used` (a thickness
/// texture is not exported: the exporter writes no textures).
fn iridescence_extension(m: &Material, ext: &mut Map<String, Value>, used: &mut Vec<&'static str>) {
    let Some(i) = m.iridescence else { return };
    ext.insert(
        "KHR_materials_iridescence".into(),
        json!({
            "iridescenceFactor": i.factor,
            "iridescenceIor": i.ior,
            "iridescenceThicknessMinimum": i.thickness_min,
            "iridescenceThicknessMaximum": i.thickness_max
        }),
    );
    used.push("KHR_materials_iridescence");
}

/// The material's `extras` (the loader's contract): the microfacet distribution of glass and
/// glossy metal, a tabulated `conductor`, a non-zero `priority` (nested dielectrics) and
/// uniform `sampling` (the importance-sampling teaching switch).
fn material_extras(m: &Material) -> Map<String, Value> {
    let mut extras = Map::new();
    if matches!(
        m.kind,
        MaterialKind::Glass | MaterialKind::ThinGlass | MaterialKind::GlossyMetal
    ) {
        let d = match m.distribution {
            MicrofacetDistribution::Ggx => "ggx",
            MicrofacetDistribution::Beckmann => "beckmann",
        };
        extras.insert("microfacet_distribution".into(), json!(d));
    }
    if let Some(metal) = m.conductor {
        extras.insert("conductor".into(), json!(metal.symbol()));
    }
    if m.priority != 0 {
        extras.insert("priority".into(), json!(m.priority));
    }
    if m.uniform_sampling {
        extras.insert("sampling".into(), json!("uniform"));
    }
    extras
}

/// KHR_materials_transmission, _ior, _volume (solid glass) and _dispersion of a transmissive
/// material, recorded in `used`.
fn transmission_extensions(
    m: &Material,
    ext: &mut Map<String, Value>,
    used: &mut Vec<&'static str>,
) {
    ext.insert(
        "KHR_materials_transmission".into(),
        json!({ "transmissionFactor": 1.0 }),
    );
    ext.insert("KHR_materials_ior".into(), json!({ "ior": m.ior }));
    used.extend(["KHR_materials_transmission", "KHR_materials_ior"]);
    if m.kind == MaterialKind::Glass {
        let mut v = json!({ "thicknessFactor": 1.0 });
        if m.attenuation_distance.is_finite() {
            v["attenuationDistance"] = json!(m.attenuation_distance);
            v["attenuationColor"] = json!(m.attenuation_color.to_array());
        }
        ext.insert("KHR_materials_volume".into(), v);
        used.push("KHR_materials_volume");
    }
    if let Some(abbe) = m.abbe {
        ext.insert(
            "KHR_materials_dispersion".into(),
            json!({ "dispersion": 20.0 / abbe }),
        );
        used.push("KHR_materials_dispersion");
    }
}
