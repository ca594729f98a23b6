// material.wgsl — a scene material at a hit: twin of `scene::Material::bsdf` (src/scene/material.rs).

// Index of refraction at wavelength `lambda_nm` (Abbe-number dispersion). Twin of `Material::ior_at`.
fn material_ior_at(m: Material, lambda_nm: f32) -> f32 {
    if m.abbe > 0.0 {
        return cauchy_from_abbe(m.eta, m.abbe, lambda_nm);
    }
    return m.eta;
}

// Does the material's refraction depend on the wavelength (a dispersive transmissive
// material in a spectral path)? Only the hero wavelength can then follow a sampled direction.
fn material_is_dispersive(m: Material, sp: Spectral) -> bool {
    return HAS_SPECTRAL && sp.on && m.abbe > 0.0 && (m.flags & MAT_TRANSMISSIVE) != 0u;
}

// The normal-mapped shading normal (glTF 2.0 §3.9.3 `normalTexture`): with the interpolated
// normal n, tangent t (xyz; w = handedness, B = w · n × t) and the texel c ∈ [0, 1]³,
// n' = normalize(T·x + B·y + N·z) where (x, y, z) = (2c − 1) · (s, s, 1) and T is t
// re-orthogonalised against n (Gram–Schmidt; Mikkelsen 2008, "Simulation of wrinkled surfaces
// revisited", §3). Returns (n', 1), or w = 0 when the frame or the result is degenerate.
// Twin of `scene::material::perturb_normal`.
fn perturb_normal(n: vec3<f32>, t: vec4<f32>, texel: vec3<f32>, scale: f32) -> vec4<f32> {
    let none = vec4<f32>(0.0);
    let t3 = normalize_or_zero3(t.xyz - n * dot3(n, t.xyz));
    if all(t3 == vec3<f32>(0.0)) || !is_finite_v3(t3) {
        return none;
    }
    var handed = 1.0;
    if t.w < 0.0 {
        handed = -1.0;
    }
    let b = cross3(n, t3) * handed;
    let m = (texel * 2.0 - vec3<f32>(1.0)) * vec3<f32>(scale, scale, 1.0);
    let out = normalize_or_zero3(t3 * m.x + b * m.y + n * m.z);
    if all(out == vec3<f32>(0.0)) || !is_finite_v3(out) {
        return none;
    }
    return vec4<f32>(out, 1.0);
}

// The BSDF at a hit: base colour × texture, metal-rough metallic/roughness × texture,
// `eta` already chosen for the path's wavelength, colours mapped to the path's lanes.
// Twin of `scene::Material::bsdf` (+ `metal_rough_at`, `base_color_at`) and `Bsdf::map_colors`.
fn material_bsdf(m: Material, uv: vec2<f32>, eta: f32, sp: Spectral) -> Bsdf {
    var base = v3(m.base_color);
    if HAS_TEXTURES && m.base_tex != NO_TEXTURE {
        base = base * sample_texture(m.base_tex, uv).xyz;
    }
    var b = bsdf_new(m.bsdf, spectral_c(sp, base), eta, m.alpha, m.dist);
    if HAS_METAL_ROUGH && m.bsdf == BSDF_METAL_ROUGH {
        var metallic = m.metallic;
        var roughness = m.roughness;
        if HAS_TEXTURES && m.mr_tex != NO_TEXTURE {
            let t = sample_texture(m.mr_tex, uv);
            metallic *= t.z;
            roughness *= t.y;
        }
        b.alpha = max(roughness_to_alpha(roughness), SMOOTH_ALPHA);
        b.metallic = clamp(metallic, 0.0, 1.0);
        // Metal-rough uses the material's own IOR (not the wavelength's).
        b.ior = m.eta;
        b.specular_factor = m.specular_factor;
        b.specular_color = spectral_c(sp, v3(m.specular_color));
    }
    if HAS_LAMBERT && m.bsdf == BSDF_LAMBERT && (m.flags & MAT_UNIFORM_SAMPLING) != 0u {
        // Lambert does not read the metal-rough slots: `metallic` = 1 marks uniform sampling.
        b.metallic = 1.0;
    }
    if HAS_IRIDESCENCE && (m.bsdf == BSDF_FILM_SMOOTH || m.bsdf == BSDF_FILM_ROUGH) {
        // Twin of `Iridescence::film_at`: thickness = mix(min, max, texture.g), else max.
        var thickness = m.film_max;
        if HAS_TEXTURES && m.film_tex != NO_TEXTURE {
            let g = clamp(sample_texture(m.film_tex, uv).y, 0.0, 1.0);
            thickness = m.film_min + (m.film_max - m.film_min) * g;
        }
        b.film = vec4<f32>(m.film_ior, thickness, m.film_factor, f32(m.film_base));
    }
    if (HAS_CONDUCTOR || HAS_IRIDESCENCE) && m.metal != METAL_NONE {
        // RGB η, k (gpu::upload::check_supported keeps conductors out of spectral kernels).
        bsdf_set_conductor_ior(&b, v3(m.cond_eta), v3(m.cond_k));
    }
    return b;
}
