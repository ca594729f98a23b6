// light.wgsl — lights as one interface, the WGSL twin of the Rust `Light` (src/scene/light/;
// pbrt-v4 `Light`, Mitsuba 3 `Emitter`). A `Light` entry (scene.wgsl) is one variant, told
// apart by `kind` (LIGHT_*); every walk calls only the functions below and never matches on
// the kind itself:
//   light_sample_li  next-event estimation: a direction to the light and its radiance
//   light_pdf_li     solid-angle density of light_sample_li for a BSDF-sampled hit (MIS)
//   light_le         radiance emitted towards a direction
//   light_sample_le  start of a light subpath (light tracing)
//   light_pdf_le     position and direction densities of light_sample_le (MIS)
// Densities include the light-selection probability `pick` (LightSet::pick). Colours are
// RGB; the walk maps them to its colour lanes (`spectral_c`).
//
// Variants: emissive triangles (area lights, one-sided unless double-sided), point, spot
// (glTF smooth falloff) and directional lights (KHR_lights_punctual), and the uniform
// environment. The environment is not in the light distribution yet: escaped rays add
// `light_le` of `light_environment` with MIS weight 1.
//
// Differences from the Rust twin (tests/light_twin.rs asserts them): `light_sample_le` draws
// a double-sided emitter's side from its sampler (Rust `sample_le` takes `u_side`), reports
// the emitting side as `n`, and is invalid for lights at infinity (directional, environment:
// no light subpaths start there on the GPU; their `light_pdf_le` is (0, 0)).
//
// Adding a light type: the Rust file and `Light` variant in src/scene/light/ (see its module
// docs), a LIGHT_* kind in gpu::layout packed by `upload::pack_lights`, a `case LIGHT_*` in
// every light_* function below, and the light in tests/light_twin.rs `all_lights_scene`, which
// runs these functions through src/shaders/light_probe.wgsl against the Rust methods.

// Pipeline specialisation: area and punctual lights compiled out when a scene has none.
override HAS_LIGHTS: bool = true;
override HAS_PUNCTUAL: bool = true;

// A light picked from the distribution, with its selection probability (0 = none).
struct LightPick {
    light: Light,
    prob: f32,
}

// Pick a light with `u` ∈ [0,1): (light, probability); prob = 0 for none. Twin of
// `LightSet::pick` (first CDF entry > u, clamped to the last light).
fn light_set_pick(u: f32) -> LightPick {
    var none: LightPick;
    let n = params.light_count;
    if n == 0u {
        return none;
    }
    var lo = 0u;
    var hi = n;
    while lo < hi {
        let mid = (lo + hi) / 2u;
        if lights[mid].cdf <= u {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    let i = min(lo, n - 1u);
    var prev = 0.0;
    if i > 0u {
        prev = lights[i - 1u].cdf;
    }
    return LightPick(lights[i], lights[i].cdf - prev);
}

// The area light of the triangle in leaf slot `slot` (a BSDF-sampled ray hit it) with its
// selection probability `LightSet::tri_pick_prob` (pbrt-v4 `SurfaceInteraction::areaLight`).
fn light_set_area(slot: u32) -> LightPick {
    var l: Light;
    l.kind = LIGHT_TRIANGLE;
    l.index = slot;
    return LightPick(l, triangles[slot].pick_prob);
}

// The uniform environment of radiance `radiance` as a light.
fn light_environment(radiance: vec3<f32>) -> Light {
    var l: Light;
    l.kind = LIGHT_ENVIRONMENT;
    l.intensity = array<f32, 3>(radiance.x, radiance.y, radiance.z);
    return l;
}

// glTF spot-light angular falloff (KHR_lights_punctual spec, "Spot"): smooth, squared
// linear ramp of cosθ between the outer and inner cone. Twin of `scene::light::spot_falloff`.
fn spot_falloff(cos_theta: f32, cos_inner: f32, cos_outer: f32) -> f32 {
    let scale = 1.0 / max(cos_inner - cos_outer, 1e-3);
    let offset = -cos_outer * scale;
    let a = clamp(cos_theta * scale + offset, 0.0, 1.0);
    return a * a;
}

// A point on an area light: position, unit geometric normal (the triangle's winding) and
// the triangle's area. Twin of `TriangleLight::sample_point` with the normal and area of
// `TriangleLight::new` (PBR 4th ed. §6.5.4).
struct TrianglePoint {
    p: vec3<f32>,
    n: vec3<f32>,
    area: f32,
    // The triangle has a positive area.
    ok: bool,
}

fn light_triangle_point(slot: u32, u: vec2<f32>) -> TrianglePoint {
    let tri = triangles[slot];
    let a = v3(tri.p0);
    let b = v3(tri.p1);
    let c = v3(tri.p2);
    let bc = uniform_triangle(u);
    let p = a * (1.0 - bc.x - bc.y) + b * bc.x + c * bc.y;
    let nn = cross3(b - a, c - a);
    let len = sqrt(dot3(nn, nn));
    return TrianglePoint(p, nn / len, 0.5 * len, len > 0.0);
}

// The material of an area light (its emission and sidedness).
fn light_material(light: Light) -> Material {
    return materials[triangles[light.index].material];
}

// ---------------------------------------------------------------------------------------------
// Next-event estimation

// A sampled direction towards a light (pbrt-v4 `LightLiSample`). `l` is the radiance arriving
// along −wi (area, environment), intensity × falloff / d² (point, spot) or irradiance
// (directional). `pdf` is the solid-angle density with the selection probability included
// (delta lights: pdf = pick). `p_light` / `n_light` locate the sampled point (n = 0 for
// point-like lights); `infinite`: the shadow ray goes to infinity along wi.
struct LightLiSample {
    valid: bool,
    l: vec3<f32>,
    wi: vec3<f32>,
    pdf: f32,
    p_light: vec3<f32>,
    n_light: vec3<f32>,
    is_delta: bool,
    infinite: bool,
}

// Sample incident illumination at `p_ref` from `light` (picked with probability `pick`).
// PBR 4th ed. §12.2–12.5 (`Light::SampleLi`); area lights sample the triangle uniformly and
// convert to solid angle, pdf = pick / area · d² / |cos θl| (PBR 4th ed. §12.5.1, Veach 1997 §9.2).
fn light_sample_li(light: Light, p_ref: vec3<f32>, u: vec2<f32>, pick: f32) -> LightLiSample {
    var s: LightLiSample;
    switch light.kind {
        case LIGHT_TRIANGLE: {
            if HAS_LIGHTS {
                s = light_triangle_sample_li(light, p_ref, u, pick);
            }
        }
        case LIGHT_POINT, LIGHT_SPOT: {
            if HAS_PUNCTUAL {
                s = light_punctual_sample_li(light, p_ref, pick);
            }
        }
        case LIGHT_DIRECTIONAL: {
            if HAS_PUNCTUAL {
                // Irradiance from −direction, shadow ray to infinity (KHR_lights_punctual "Directional").
                let wi = -v3(light.direction);
                s = LightLiSample(true, v3(light.intensity), wi, pick, vec3<f32>(0.0), vec3<f32>(0.0), true, true);
            }
        }
        case LIGHT_ENVIRONMENT: {
            // Uniform sphere of directions, pdf = pick / 4π (PBR 4th ed. §12.5.2, §A.5.2).
            let wi = uniform_sphere(u);
            s = LightLiSample(true, v3(light.intensity), wi, pick * UNIFORM_SPHERE_PDF, vec3<f32>(0.0), vec3<f32>(0.0), false, true);
        }
        default: {}
    }
    return s;
}

// Area light: a uniform point on the triangle seen from p_ref (one-sided unless double-sided).
// PBR 4th ed. §12.5.1 (`DiffuseAreaLight::SampleLi`).
fn light_triangle_sample_li(light: Light, p_ref: vec3<f32>, u: vec2<f32>, pick: f32) -> LightLiSample {
    var s: LightLiSample;
    let tp = light_triangle_point(light.index, u);
    let m = light_material(light);
    let to = tp.p - p_ref;
    let dist2 = dot3(to, to);
    if dist2 <= 0.0 {
        return s;
    }
    let dist = sqrt(dist2);
    let wi = to / dist;
    var cos_l = -dot3(wi, tp.n);
    if cos_l <= 0.0 && (m.flags & MAT_DOUBLE_SIDED) == 0u {
        return s;
    }
    cos_l = abs(cos_l);
    if cos_l <= 0.0 {
        return s;
    }
    return LightLiSample(true, v3(m.emission), wi, pick / tp.area * dist2 / cos_l, tp.p, tp.n, false, false);
}

// Point and spot lights: intensity / d², times the spot falloff. KHR_lights_punctual spec
// ("Point", "Spot"); PBR 4th ed. §12.1–12.2 (`PointLight::SampleLi`, `SpotLight::SampleLi`).
fn light_punctual_sample_li(light: Light, p_ref: vec3<f32>, pick: f32) -> LightLiSample {
    var s: LightLiSample;
    let lp = v3(light.position);
    let intensity = v3(light.intensity);
    let to = lp - p_ref;
    let d2 = dot3(to, to);
    if d2 <= 0.0 {
        return s;
    }
    let wi = to / sqrt(d2);
    var l: vec3<f32>;
    if light.kind == LIGHT_SPOT {
        let fall = spot_falloff(dot3(-wi, v3(light.direction)), light.cos_inner, light.cos_outer);
        if fall <= 0.0 {
            return s;
        }
        l = intensity * fall / d2;
    } else {
        l = intensity / d2;
    }
    return LightLiSample(true, l, wi, pick, lp, vec3<f32>(0.0), true, false);
}

// Solid-angle density with which `light_sample_li` would choose the point at distance `dist`
// along `wi` with geometric normal `n_light` (area lights; 0 for delta lights).
// PBR 4th ed. §12.5.1 (`DiffuseAreaLight::PDF_Li`): pick / area · d² / |cos θl|.
fn light_pdf_li(light: Light, pick: f32, dist: f32, n_light: vec3<f32>, wi: vec3<f32>) -> f32 {
    switch light.kind {
        case LIGHT_TRIANGLE: {
            if pick <= 0.0 {
                return 0.0;
            }
            let area = triangles[light.index].area;
            let cos_l = abs(dot3(n_light, wi));
            if cos_l <= 0.0 || area <= 0.0 {
                return 0.0;
            }
            return pick / area * dist * dist / cos_l;
        }
        case LIGHT_ENVIRONMENT: {
            return pick * UNIFORM_SPHERE_PDF;
        }
        default: {
            return 0.0;
        }
    }
}

// Radiance (area, environment) or intensity (punctual, with the spot falloff) emitted
// towards `w` from a point with geometric normal `n_light`; area lights are one-sided
// unless double-sided (glTF `doubleSided`). PBR 4th ed. §12.5.1 (`DiffuseAreaLight::L`),
// §12.1 (`SpotLight::I`, KHR_lights_punctual falloff).
fn light_le(light: Light, n_light: vec3<f32>, w: vec3<f32>) -> vec3<f32> {
    switch light.kind {
        case LIGHT_TRIANGLE: {
            let m = light_material(light);
            let emits = (m.flags & MAT_EMISSIVE) != 0u;
            if emits && (dot3(w, n_light) > 0.0 || (m.flags & MAT_DOUBLE_SIDED) != 0u) {
                return v3(m.emission);
            }
        }
        case LIGHT_SPOT: {
            return v3(light.intensity) * spot_falloff(dot3(w, v3(light.direction)), light.cos_inner, light.cos_outer);
        }
        case LIGHT_POINT, LIGHT_DIRECTIONAL, LIGHT_ENVIRONMENT: {
            return v3(light.intensity);
        }
        default: {}
    }
    return vec3<f32>(0.0);
}

// ---------------------------------------------------------------------------------------------
// Emission (light subpaths)

// The start of a light subpath (pbrt-v4 `LightLeSample`): origin point `p` with normal `n`
// (the emitting side; 0 for point lights), direction `dir`, emitted radiance / intensity `l`,
// the position density `pdf_pos` (pick / area, or pick for a delta position) and the
// solid-angle density `pdf_dir`. `cos_n` = |n·dir| in the emitter's frame (1 for punctual).
struct LightLeSample {
    valid: bool,
    p: vec3<f32>,
    n: vec3<f32>,
    dir: vec3<f32>,
    l: vec3<f32>,
    pdf_pos: f32,
    pdf_dir: f32,
    cos_n: f32,
    delta_pos: bool,
}

// Sample an emitted ray of `light` (picked with probability `pick`): u_pos picks the point,
// u_dir the direction; a double-sided area light draws its side from `sampler` (one dimension,
// as `bdpt::light_path`). Directional lights and the environment are reached by next-event
// estimation only (valid = false). PBR 4th ed. §12.1–12.5 (`Light::SampleLe`).
fn light_sample_le(light: Light, u_pos: vec2<f32>, u_dir: vec2<f32>, sampler: ptr<function, Sampler>, pick: f32) -> LightLeSample {
    var s: LightLeSample;
    switch light.kind {
        case LIGHT_TRIANGLE: {
            if HAS_LIGHTS {
                s = light_triangle_sample_le(light, u_pos, u_dir, sampler, pick);
            }
        }
        case LIGHT_POINT, LIGHT_SPOT: {
            if HAS_PUNCTUAL {
                s = light_punctual_sample_le(light, u_dir, pick);
            }
        }
        default: {}
    }
    return s;
}

// Area light: uniform point, cosine-weighted direction about the emitting side (Lambertian
// emitter; half the density on each side when double-sided). PBR 4th ed. §12.5.1
// (`DiffuseAreaLight::SampleLe`).
fn light_triangle_sample_le(light: Light, u_pos: vec2<f32>, u_dir: vec2<f32>, sampler: ptr<function, Sampler>, pick: f32) -> LightLeSample {
    var s: LightLeSample;
    let tp = light_triangle_point(light.index, u_pos);
    if !tp.ok {
        return s;
    }
    let m = light_material(light);
    var side = tp.n;
    if (m.flags & MAT_DOUBLE_SIDED) != 0u && sampler_next_1d(sampler) < 0.5 {
        side = -tp.n;
    }
    var local = cosine_hemisphere(u_dir);
    if local.z <= 0.0 {
        return s;
    }
    local.z = max(local.z, 1e-7);
    let dir = frame_to_world(frame_from_normal(side), local);
    let pdf_dir = light_area_pdf_dir(m, local.z);
    return LightLeSample(true, tp.p, side, dir, v3(m.emission), pick / tp.area, pdf_dir, local.z, false);
}

// Point light: uniform sphere; spot light: uniform cone inside the outer angle, intensity ×
// falloff. PBR 4th ed. §12.1 (`PointLight::SampleLe`, `SpotLight::SampleLe`), §A.5.2, §A.5.4.
fn light_punctual_sample_le(light: Light, u_dir: vec2<f32>, pick: f32) -> LightLeSample {
    var intensity = v3(light.intensity);
    var dir: vec3<f32>;
    if light.kind == LIGHT_SPOT {
        let local = uniform_cone(u_dir, light.cos_outer);
        dir = frame_to_world(frame_from_normal(v3(light.direction)), local);
        intensity *= spot_falloff(local.z, light.cos_inner, light.cos_outer);
    } else {
        dir = uniform_sphere(u_dir);
    }
    let pdf_dir = light_punctual_pdf_dir(light);
    return LightLeSample(true, v3(light.position), vec3<f32>(0.0), dir, intensity, pick, pdf_dir, 1.0, true);
}

// Origin of the first ray of a light subpath: pushed off an area light's emitting side
// (Wächter & Binder 2019, `offset_ray_origin`), the light's position for point-like lights.
fn light_le_sample_origin(s: LightLeSample) -> vec3<f32> {
    if s.delta_pos {
        return s.p;
    }
    return offset_ray_origin(s.p, s.n);
}

// Emission densities of `light_sample_le` (pbrt-v4 `Light::PDF_Le`).
struct LightLePdf {
    pdf_pos: f32,
    pdf_dir: f32,
}

// Densities with which `light_sample_le` of `light` (selection probability `pick`) emits from
// a point with normal `n_light` towards `w`: area lights pdf_pos = pick / area (the mesh area),
// pdf_dir cosine-weighted; a delta position reports pdf_pos = pick, as `light_sample_le` does
// (the walks read pdf_dir only). Lights at infinity emit no subpaths here: (0, 0).
// PBR 4th ed. §12.1, §12.5.1 (`PDF_Le`).
fn light_pdf_le(light: Light, pick: f32, n_light: vec3<f32>, w: vec3<f32>) -> LightLePdf {
    switch light.kind {
        case LIGHT_TRIANGLE: {
            let m = light_material(light);
            let c = dot3(n_light, w);
            var pdf_dir = 0.0;
            if c > 0.0 || (m.flags & MAT_DOUBLE_SIDED) != 0u {
                pdf_dir = light_area_pdf_dir(m, abs(c));
            }
            return LightLePdf(pick / triangles[light.index].area, pdf_dir);
        }
        case LIGHT_POINT: {
            return LightLePdf(pick, light_punctual_pdf_dir(light));
        }
        case LIGHT_SPOT: {
            var pdf_dir = 0.0;
            if dot3(w, v3(light.direction)) >= light.cos_outer {
                pdf_dir = light_punctual_pdf_dir(light);
            }
            return LightLePdf(pick, pdf_dir);
        }
        default: {
            return LightLePdf(0.0, 0.0);
        }
    }
}

// Solid-angle density with which an area light emits towards a direction at cosθ (≥ 0) to
// its emitting normal: cosθ/π, half of it on each side when double-sided. PBR 4th ed. §A.5.3.
fn light_area_pdf_dir(m: Material, cos_l: f32) -> f32 {
    var two = 1.0;
    if (m.flags & MAT_DOUBLE_SIDED) != 0u {
        two = 0.5;
    }
    return two * cos_l * FRAC_1_PI;
}

// Solid-angle density of a punctual light's emitted direction: 1/4π (point, uniform sphere)
// or 1 / (2π (1 − cos θ_outer)) (spot, uniform cone). PBR 4th ed. §A.5.2, §A.5.4.
fn light_punctual_pdf_dir(light: Light) -> f32 {
    if light.kind == LIGHT_SPOT {
        return 1.0 / (2.0 * PI * max(1.0 - light.cos_outer, 1e-7));
    }
    return UNIFORM_SPHERE_PDF;
}
