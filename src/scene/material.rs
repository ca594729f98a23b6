//! Scene materials (what the glTF file says) and their mapping to a BSDF at a hit point.

use crate::bsdf::{self, Bsdf, MicrofacetDistribution};
use crate::math::{Color, rgb3};
use glam::{Affine2, Vec2, Vec3, Vec4};

/// Transmission factors at or above this make a material a dielectric (the glTF loader's
/// rule for `KHR_materials_transmission`, applied per texel by [`Material::transmits_at`]).
pub const GLASS_TRANSMISSION_THRESHOLD: f32 = 0.5;

/// How the scene contract classifies a glTF material (docs/design.md, "Scene contract").
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MaterialKind {
    /// metallic 0, roughness 1, no transmission → Lambert.
    Diffuse,
    /// metallic 1, roughness 0 → perfect mirror with reflectance = base colour.
    Mirror,
    /// metallic 1, roughness > 0 → microfacet reflection, reflectance = base colour.
    GlossyMetal,
    /// transmission with volume thickness > 0 → solid dielectric (smooth or rough).
    Glass,
    /// transmission without volume → thin-walled dielectric sheet.
    ThinGlass,
    /// everything else → glTF metallic-roughness BRDF (spec appendix B).
    MetalRough,
}

/// Texture wrap mode (glTF sampler).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Wrap {
    #[default]
    Repeat,
    MirroredRepeat,
    ClampToEdge,
}

/// A decoded texture: linear RGBA floats (base-colour textures are sRGB-decoded at load).
#[derive(Clone, Debug)]
pub struct Texture {
    pub width: u32,
    pub height: u32,
    pub texels: Vec<Vec4>,
    pub wrap_s: Wrap,
    pub wrap_t: Wrap,
    /// Bilinear filtering (else nearest).
    pub linear: bool,
}

/// A reference from a material to a texture (`KHR_texture_transform` folded into `transform`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureRef {
    pub texture: u32,
    pub tex_coord: u32,
    pub transform: Affine2,
}

/// A material as the scene contract describes it.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    pub name: String,
    pub kind: MaterialKind,
    /// Linear RGB base colour (albedo / reflectance / specular tint).
    pub base_color: Vec3,
    pub base_color_texture: Option<TextureRef>,
    pub metallic: f32,
    /// Perceptual roughness; α = roughness².
    pub roughness: f32,
    pub metallic_roughness_texture: Option<TextureRef>,
    /// Tangent-space normal map (glTF `normalTexture`, linear RGB) and its `scale`.
    pub normal_texture: Option<TextureRef>,
    pub normal_scale: f32,
    /// IOR of the inside (outside is 1.0): KHR_materials_ior, default 1.5.
    pub ior: f32,
    /// Abbe number V_d when KHR_materials_dispersion is present (V_d = 20 / dispersion).
    pub abbe: Option<f32>,
    /// Roughness type for rough glass / glossy metal.
    pub distribution: MicrofacetDistribution,
    /// Emitted radiance (emissiveFactor × emissive_strength); zero = not a light.
    pub emission: Vec3,
    /// glTF `emissiveTexture` (sRGB-decoded like base colour): the radiance at a point is
    /// `emission` × texture(uv).rgb (glTF 2.0 §3.9.2, "emissive").
    pub emissive_texture: Option<TextureRef>,
    pub double_sided: bool,
    /// Beer–Lambert absorption inside a solid: colour reached after `attenuation_distance`.
    pub attenuation_color: Vec3,
    /// Infinity = no absorption.
    pub attenuation_distance: f32,
    /// KHR_materials_transmission: the factor and its texture (linear, red channel). The
    /// contract's kind follows the factor (≥ `GLASS_TRANSMISSION_THRESHOLD`: glass); with a
    /// texture, each point is glass where factor × texel ≥ that threshold and the opaque
    /// metal-rough base elsewhere ([`Material::transmits_at`]).
    pub transmission_factor: f32,
    pub transmission_texture: Option<TextureRef>,
    /// KHR_materials_specular factor and colour (metal-rough only).
    pub specular_factor: f32,
    pub specular_color: Vec3,
    /// Nested dielectrics: where closed volumes overlap, the one with the higher priority
    /// is the medium (`material.extras.priority`, Schmidt & Budge 2002); default 0.
    pub priority: i32,
    /// A tabulated metal (`material.extras.conductor`, metallic materials only): the mirror
    /// or glossy metal becomes a conductor with spectral η, k and the exact conductor Fresnel
    /// term, tinted by the base colour (Mitsuba's `specular_reflectance`; white = the bare
    /// metal). `None`: the constant reflectance = base colour of the scene contract.
    pub conductor: Option<bsdf::Metal>,
    /// Teaching switch of the importance-sampling lecture demo (diffuse materials only;
    /// `material.extras.sampling = "uniform"`): directions are sampled uniformly over the
    /// hemisphere instead of cosine-weighted. The same BRDF, so the same image in the mean,
    /// with more noise (`bsdf::Lambert::uniform`).
    pub uniform_sampling: bool,
    /// glTF `KHR_materials_iridescence`: a thin dielectric film on a dielectric or metal
    /// (`bsdf::Iridescent`; other kinds ignore it). `None`: no film.
    pub iridescence: Option<Iridescence>,
}

/// A thin film on the surface (glTF `KHR_materials_iridescence`; Belcour & Barla 2017): its
/// index, and its thickness in nm, `thickness_max` everywhere or, with a texture, mixed from
/// `thickness_min` to `thickness_max` by the texture's green channel (the extension's rule).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Iridescence {
    /// `iridescenceFactor` ∈ [0, 1]: blends the base's Fresnel term into the film's.
    pub factor: f32,
    /// `iridescenceIor` (≥ 1; 1.3 by default).
    pub ior: f32,
    pub thickness_min: f32,
    pub thickness_max: f32,
    pub thickness_texture: Option<TextureRef>,
}

impl Default for Iridescence {
    /// The extension's defaults, with the factor at 1 (a film that is there).
    fn default() -> Self {
        Iridescence {
            factor: 1.0,
            ior: 1.3,
            thickness_min: 100.0,
            thickness_max: 400.0,
            thickness_texture: None,
        }
    }
}

impl Iridescence {
    /// The film at `uv`: thickness = mix(min, max, texture.g), or max without a texture.
    pub fn film_at(&self, textures: &[Texture], uv: Vec2) -> bsdf::ThinFilm {
        let thickness_nm = match &self.thickness_texture {
            Some(r) => {
                let g = sample_texture(textures, r, uv).y.clamp(0.0, 1.0);
                self.thickness_min + (self.thickness_max - self.thickness_min) * g
            }
            None => self.thickness_max,
        };
        bsdf::ThinFilm {
            ior: self.ior,
            thickness_nm,
        }
    }

    /// Finite, factor in [0, 1], index ≥ 1, thicknesses in [0, `MAX_FILM_THICKNESS_NM`].
    pub fn validate(&self, material: &str) -> anyhow::Result<()> {
        let max = bsdf::thin_film::MAX_FILM_THICKNESS_NM;
        anyhow::ensure!(
            (0.0..=1.0).contains(&self.factor),
            "material '{material}': iridescence factor {} must be in [0, 1]",
            self.factor
        );
        anyhow::ensure!(
            self.ior.is_finite() && self.ior >= 1.0,
            "material '{material}': film IOR {} must be a finite number ≥ 1",
            self.ior
        );
        for (what, d) in [
            ("minimum", self.thickness_min),
            ("maximum", self.thickness_max),
        ] {
            anyhow::ensure!(
                (0.0..=max).contains(&d),
                "material '{material}': film thickness {what} {d} nm must be in [0, {max}] nm"
            );
        }
        Ok(())
    }
}

impl Default for Material {
    fn default() -> Self {
        Material {
            name: String::new(),
            kind: MaterialKind::Diffuse,
            base_color: Vec3::splat(0.8),
            base_color_texture: None,
            metallic: 0.0,
            roughness: 1.0,
            metallic_roughness_texture: None,
            normal_texture: None,
            normal_scale: 1.0,
            ior: 1.5,
            abbe: None,
            distribution: MicrofacetDistribution::Ggx,
            emission: Vec3::ZERO,
            emissive_texture: None,
            double_sided: false,
            attenuation_color: Vec3::ONE,
            attenuation_distance: f32::INFINITY,
            transmission_factor: 0.0,
            transmission_texture: None,
            specular_factor: 1.0,
            specular_color: Vec3::ONE,
            priority: 0,
            conductor: None,
            uniform_sampling: false,
            iridescence: None,
        }
    }
}

impl Material {
    pub fn diffuse(name: &str, albedo: Vec3) -> Material {
        Material {
            name: name.into(),
            base_color: albedo,
            ..Default::default()
        }
    }

    pub fn mirror(name: &str, reflectance: Vec3) -> Material {
        Material {
            name: name.into(),
            kind: MaterialKind::Mirror,
            base_color: reflectance,
            metallic: 1.0,
            roughness: 0.0,
            ..Default::default()
        }
    }

    pub fn glass(name: &str, ior: f32) -> Material {
        Material {
            name: name.into(),
            kind: MaterialKind::Glass,
            base_color: Vec3::ONE,
            roughness: 0.0,
            ior,
            ..Default::default()
        }
    }

    pub fn emitter(name: &str, radiance: Vec3) -> Material {
        Material {
            name: name.into(),
            base_color: Vec3::ZERO,
            emission: radiance,
            ..Default::default()
        }
    }

    #[inline]
    pub fn is_emissive(&self) -> bool {
        self.emission.max_element() > 0.0
    }

    /// Transmissive kinds (the path crosses the surface).
    #[inline]
    pub fn is_transmissive(&self) -> bool {
        matches!(self.kind, MaterialKind::Glass | MaterialKind::ThinGlass)
    }

    /// Does the surface transmit at `uv`? Transmissive kinds do, except where a transmission
    /// texture masks them: factor × texel.r below the glass threshold is the opaque base — the
    /// loader's rule for the factor (`GLASS_TRANSMISSION_THRESHOLD`), applied per texel.
    #[inline]
    pub fn transmits_at(&self, textures: &[Texture], uv: Vec2) -> bool {
        self.is_transmissive()
            && self.transmission_texture.is_none_or(|r| {
                self.transmission_factor * sample_texture(textures, &r, uv).x
                    >= GLASS_TRANSMISSION_THRESHOLD
            })
    }

    /// Index of refraction at wavelength `lambda_nm` (Abbe-number dispersion model of
    /// docs/design.md: n(λ) = max(n_d + (n_d − 1)/V_d · (523655/λ² − 1.5168), 1)).
    #[inline]
    pub fn ior_at(&self, lambda_nm: f32) -> f32 {
        match self.abbe {
            Some(v) if v > 0.0 => crate::math::spectrum::cauchy_from_abbe(self.ior, v, lambda_nm),
            _ => self.ior,
        }
    }

    /// Beer–Lambert absorption coefficient σ_a per colour channel (1/m), from
    /// KHR_materials_volume: σ_a = −ln(attenuationColor) / attenuationDistance.
    pub fn sigma_a(&self) -> Vec3 {
        if !self.attenuation_distance.is_finite() || self.attenuation_distance <= 0.0 {
            return Vec3::ZERO;
        }
        let c = self.attenuation_color.clamp(Vec3::splat(1e-6), Vec3::ONE);
        Vec3::new(-c.x.ln(), -c.y.ln(), -c.z.ln()) / self.attenuation_distance
    }

    pub fn has_absorption(&self) -> bool {
        self.kind == MaterialKind::Glass && self.sigma_a().max_element() > 0.0
    }

    /// Reject parameters no renderer can use (NaN, IOR ≤ 0 …) with a clear message.
    pub fn validate(&self) -> anyhow::Result<()> {
        let n = &self.name;
        anyhow::ensure!(
            self.ior.is_finite() && self.ior > 0.0,
            "material '{n}': IOR {} must be a finite number > 0",
            self.ior
        );
        anyhow::ensure!(
            self.base_color.is_finite() && self.base_color.min_element() >= 0.0,
            "material '{n}': base colour must be finite and non-negative"
        );
        anyhow::ensure!(
            self.emission.is_finite() && self.emission.min_element() >= 0.0,
            "material '{n}': emission must be finite and non-negative"
        );
        anyhow::ensure!(
            self.roughness.is_finite() && self.metallic.is_finite(),
            "material '{n}': roughness/metallic must be finite"
        );
        if let Some(v) = self.abbe {
            anyhow::ensure!(
                v.is_finite() && v > 0.0,
                "material '{n}': Abbe number {v} must be finite and > 0"
            );
        }
        if let Some(i) = &self.iridescence {
            i.validate(n)?;
        }
        Ok(())
    }

    /// The BSDF at a hit. `uv` is the interpolated TEXCOORD_0, `eta` the IOR to use (already
    /// evaluated at the path's wavelength for dispersive materials), `textures` the scene's.
    /// A film (`iridescence`) replaces the Fresnel term of dielectrics and metals.
    pub fn bsdf(&self, textures: &[Texture], uv: Vec2, eta: f32) -> Bsdf {
        let bare = self.bare_bsdf(textures, uv, eta);
        match &self.iridescence {
            Some(film) if film.factor > 0.0 => {
                bsdf::Iridescent::over(bare, film.film_at(textures, uv), film.factor)
            }
            _ => bare,
        }
    }

    /// The BSDF without the film.
    fn bare_bsdf(&self, textures: &[Texture], uv: Vec2, eta: f32) -> Bsdf {
        let base = self.base_color_at(textures, uv);
        if self.transmission_texture.is_some() && !self.transmits_at(textures, uv) {
            // A texel masked out of a transmissive material: its opaque metal-rough base.
            return Bsdf::MetalRough(self.metal_rough_at(textures, uv, base));
        }
        if let Some(metal) = self.conductor.filter(|_| self.is_metal_kind()) {
            return self.conductor_bsdf(metal, base);
        }
        match self.kind {
            MaterialKind::Mirror => Bsdf::Mirror(bsdf::Mirror {
                reflectance: rgb3(base),
            }),
            MaterialKind::Glass => {
                let alpha = bsdf::roughness_to_alpha(self.roughness);
                if bsdf::effectively_smooth(alpha) || eta == 1.0 {
                    Bsdf::SmoothDielectric(bsdf::SmoothDielectric { eta })
                } else {
                    Bsdf::RoughDielectric(bsdf::RoughDielectric {
                        eta,
                        alpha,
                        dist: self.distribution,
                    })
                }
            }
            // Thin-walled (glTF transmission without volume): two interfaces, no bending.
            // Rough faces blur what passes through; a film lies on a smooth sheet only
            // (`bsdf::Iridescent`), and η = 1 is no interface at all.
            MaterialKind::ThinGlass if self.sheet_is_smooth(eta) => {
                Bsdf::ThinDielectric(bsdf::ThinDielectric { eta })
            }
            MaterialKind::ThinGlass => Bsdf::RoughThinDielectric(bsdf::RoughThinDielectric {
                eta,
                alpha: bsdf::roughness_to_alpha(self.roughness),
                dist: self.distribution,
            }),
            MaterialKind::GlossyMetal => {
                let alpha = bsdf::roughness_to_alpha(self.roughness);
                if bsdf::effectively_smooth(alpha) {
                    Bsdf::Mirror(bsdf::Mirror {
                        reflectance: rgb3(base),
                    })
                } else {
                    Bsdf::RoughConductor(bsdf::RoughConductor {
                        reflectance: rgb3(base),
                        alpha,
                        dist: self.distribution,
                    })
                }
            }
            MaterialKind::MetalRough => Bsdf::MetalRough(self.metal_rough_at(textures, uv, base)),
            MaterialKind::Diffuse => Bsdf::Lambert(bsdf::Lambert {
                albedo: rgb3(base),
                uniform: self.uniform_sampling,
            }),
        }
    }

    /// Whether thin glass of relative index `eta` is the smooth sheet (a delta BSDF): smooth
    /// faces, no interface (η = 1), or a film (films lie on smooth sheets only); else the
    /// rough sheet. Also what sppm's photon aiming asks (`render::photon_aim`).
    #[inline]
    pub fn sheet_is_smooth(&self, eta: f32) -> bool {
        bsdf::effectively_smooth(bsdf::roughness_to_alpha(self.roughness))
            || eta == 1.0
            || self.iridescence.is_some_and(|f| f.factor > 0.0)
    }

    /// Mirror or glossy metal (the kinds `extras.conductor` applies to).
    #[inline]
    pub fn is_metal_kind(&self) -> bool {
        matches!(self.kind, MaterialKind::Mirror | MaterialKind::GlossyMetal)
    }

    /// A tabulated metal with RGB η, k (spectral paths re-evaluate them with
    /// `Bsdf::at_wavelengths`): smooth below the α threshold, else the microfacet lobe of
    /// glossy metal (same roughness and distribution) with the exact Fresnel term.
    fn conductor_bsdf(&self, metal: bsdf::Metal, base: Vec3) -> Bsdf {
        let ior = bsdf::ComplexIor::rgb(metal);
        let tint = rgb3(base);
        let alpha = match self.kind {
            MaterialKind::Mirror => 0.0,
            _ => bsdf::roughness_to_alpha(self.roughness),
        };
        if bsdf::effectively_smooth(alpha) {
            Bsdf::SmoothConductor(bsdf::SmoothConductor { ior, tint })
        } else {
            Bsdf::RoughFresnelConductor(bsdf::RoughFresnelConductor {
                ior,
                lobe: bsdf::RoughConductor {
                    reflectance: tint,
                    alpha,
                    dist: self.distribution,
                },
            })
        }
    }

    /// The glTF metallic-roughness BRDF at `uv`: metallic × texture B, roughness × texture G
    /// (glTF 2.0 spec §3.9.2 `metallicRoughnessTexture`). α is clamped to the smooth threshold
    /// (this BRDF has no delta lobe).
    pub fn metal_rough_at(&self, textures: &[Texture], uv: Vec2, base: Vec3) -> bsdf::MetalRough {
        let (mut metallic, mut roughness) = (self.metallic, self.roughness);
        if let Some(r) = &self.metallic_roughness_texture {
            let t = sample_texture(textures, r, uv);
            metallic *= t.z;
            roughness *= t.y;
        }
        let alpha = bsdf::roughness_to_alpha(roughness).max(bsdf::SMOOTH_ALPHA);
        bsdf::MetalRough {
            base_color: rgb3(base),
            metallic: metallic.clamp(0.0, 1.0),
            alpha,
            ior: self.ior,
            specular_factor: self.specular_factor.clamp(0.0, 1.0),
            specular_color: rgb3(self.specular_color.max(Vec3::ZERO)),
        }
    }

    /// Base colour × texture at `uv`.
    pub fn base_color_at(&self, textures: &[Texture], uv: Vec2) -> Vec3 {
        match self.base_color_texture {
            Some(r) => self.base_color * sample_texture(textures, &r, uv).truncate(),
            None => self.base_color,
        }
    }
}

/// The normal-mapped shading normal (glTF 2.0 §3.9.3 `normalTexture`): with the
/// interpolated normal `n`, tangent `t` (xyz; w = handedness, B = w · n × t) and the texel
/// c ∈ [0, 1]³, n' = normalize(T·x + B·y + N·z) where (x, y, z) = (2c − 1) · (s, s, 1) and
/// T is t re-orthogonalised against n (Gram–Schmidt; Mikkelsen 2008, "Simulation of wrinkled
/// surfaces revisited", §3). None when the frame or the result is degenerate.
pub fn perturb_normal(n: Vec3, t: Vec4, texel: Vec3, scale: f32) -> Option<Vec3> {
    let t3 = (t.truncate() - n * n.dot(t.truncate())).normalize_or_zero();
    if t3 == Vec3::ZERO || !t3.is_finite() {
        return None;
    }
    let handed = if t.w < 0.0 { -1.0 } else { 1.0 };
    let b = n.cross(t3) * handed;
    let m = (texel * 2.0 - Vec3::ONE) * Vec3::new(scale, scale, 1.0);
    let out = (t3 * m.x + b * m.y + n * m.z).normalize_or_zero();
    (out != Vec3::ZERO && out.is_finite()).then_some(out)
}

/// Look a texture up at `uv` (wrap mode, nearest or bilinear). Missing texture → white.
pub fn sample_texture(textures: &[Texture], r: &TextureRef, uv: Vec2) -> Vec4 {
    match textures.get(r.texture as usize) {
        Some(t) => sample_one(t, r.transform, uv),
        None => Vec4::ONE,
    }
}

/// Look `t` up at `uv` mapped by `transform` (`KHR_texture_transform`); an empty texture
/// reads white. The lookup of [`sample_texture`] for a texture held outside the scene's
/// list (emissive textures of area lights).
pub fn sample_one(t: &Texture, transform: Affine2, uv: Vec2) -> Vec4 {
    if t.width == 0 || t.height == 0 || t.texels.len() < (t.width * t.height) as usize {
        return Vec4::ONE;
    }
    let uv = transform.transform_point2(uv);
    let fx = uv.x * t.width as f32 - 0.5;
    let fy = uv.y * t.height as f32 - 0.5;
    let texel = |x: i64, y: i64| -> Vec4 {
        let xi = wrap_index(x, t.width, t.wrap_s);
        let yi = wrap_index(y, t.height, t.wrap_t);
        t.texels[(yi * t.width + xi) as usize]
    };
    if !fx.is_finite() || !fy.is_finite() {
        return Vec4::ONE;
    }
    if t.linear {
        let x0 = fx.floor();
        let y0 = fy.floor();
        let (ax, ay) = (fx - x0, fy - y0);
        let (x0, y0) = (x0 as i64, y0 as i64);
        let top = texel(x0, y0) * (1.0 - ax) + texel(x0 + 1, y0) * ax;
        let bot = texel(x0, y0 + 1) * (1.0 - ax) + texel(x0 + 1, y0 + 1) * ax;
        top * (1.0 - ay) + bot * ay
    } else {
        texel((fx + 0.5).floor() as i64, (fy + 0.5).floor() as i64)
    }
}

fn wrap_index(i: i64, n: u32, w: Wrap) -> u32 {
    let n = n as i64;
    let r = match w {
        Wrap::Repeat => i.rem_euclid(n),
        Wrap::ClampToEdge => i.clamp(0, n - 1),
        Wrap::MirroredRepeat => {
            let m = i.rem_euclid(2 * n);
            if m < n { m } else { 2 * n - 1 - m }
        }
    };
    r as u32
}

/// Colour helper re-exported for callers building throughput values.
#[inline]
pub fn to_color(c: Vec3) -> Color {
    rgb3(c)
}
