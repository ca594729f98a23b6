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
// (glTF smooth falloff) and directional lights (KHR_lights_punctual), the uniform
// environment and the environment image. The uniform environment is not in the light
// distribution: escaped rays add `light_le` of `light_environment` with MIS weight 1. The
// image is (the last entry, `light_set_environment`), importance-sampled ∝ luminance × sinθ
// from its block in `texels` (`upload::pack_environment`); escaped rays weight it by MIS.
//
// Differences from the Rust twin (tests/light_twin.rs asserts them): `light_sample_le` draws
// a double-sided emitter's side from its sampler (Rust `sample_le` takes `u_side`) and reports
// the emitting side as `n`. Lights at infinity (directional, environments) emit from a disk
// covering the scene's bounding sphere, which their `Light` entry carries (`position`,
// `radius`), as on the CPU: photons (photon.wgsl) start there; lt+pt does not
// (light_tracing.wgsl).
//
// The interface functions' switches on `kind`, `light_is_infinite`, the LIGHT_* constants and
// the HAS_* overrides are generated from the light table (src/scene/light/family.rs, one row
// per `Light` variant; scene::light::family_wgsl writes the WGSL): the arms call the per-kind
// functions below. Adding a light type: its functions here, a row there naming them (see
// src/scene/light/mod.rs), and the light in tests/light_twin.rs `all_lights_scene`, which runs
// the interface through src/gpu/light_probe.wgsl against the Rust methods.

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

// The environment image as a light with its selection probability (prob = 0: none). It is
// the last light of the distribution (`LightSet::build`); twin of `LightSet::env_pick`.
fn light_set_environment() -> LightPick {
    var none: LightPick;
    let n = params.light_count;
    if !HAS_ENV_IMAGE || n == 0u || lights[n - 1u].kind != LIGHT_IMAGE {
        return none;
    }
    var prev = 0.0;
    if n > 1u {
        prev = lights[n - 2u].cdf;
    }
    return LightPick(lights[n - 1u], lights[n - 1u].cdf - prev);
}

// ---------------------------------------------------------------------------------------------
// The environment image (twin of `ImageEnvironment`, src/scene/light/image_environment.rs, and
// `env_map`): three.js's equirectangular mapping, u = atan2(d.z, d.x)/2π + ½, t = θ/π (row 0
// at the top), rotated about +Y by (cos, sin) = light.direction.xy; light.direction.z = 1:
// importance sampling, 0: uniform directions. PBR 4th ed. §12.5.2, §A.5.6.

// Header of the image block: width, height, first texel, first CDF float.
fn light_image_header(light: Light) -> vec4<u32> {
    return bitcast<vec4<u32>>(texels[light.index]);
}

// Float k of the CDF area (four per vec4).
fn light_image_float(h: vec4<u32>, k: u32) -> f32 {
    return texels[h.w + k / 4u][k % 4u];
}

// Twin of `env_map::rotate_y`.
fn env_rotate_y(d: vec3<f32>, c: f32, s: f32) -> vec3<f32> {
    return vec3<f32>(c * d.x + s * d.z, d.y, -s * d.x + c * d.z);
}

// Twin of `env_map::dir_to_uv` (u = 0.5 at the poles: atan2(0, 0) is undefined in WGSL).
fn env_dir_to_uv(d: vec3<f32>) -> vec2<f32> {
    var u = 0.5;
    if d.x != 0.0 || d.z != 0.0 {
        u = atan2(d.z, d.x) * (0.5 / PI) + 0.5;
    }
    return vec2<f32>(u, acos(clamp(d.y, -1.0, 1.0)) / PI);
}

// Twin of `env_map::uv_to_dir`.
fn env_uv_to_dir(uv: vec2<f32>) -> vec3<f32> {
    let phi = (uv.x - 0.5) * 2.0 * PI;
    let theta = uv.y * PI;
    let s = sin(theta);
    return vec3<f32>(s * cos(phi), cos(theta), s * sin(phi));
}

// The texel (r, g, b, p(u,t)) containing image coordinates uv (nearest: the cell of the
// piecewise-constant density `Distribution2D::pdf`; radiance is `light_image_radiance`).
fn light_image_texel(h: vec4<u32>, uv: vec2<f32>) -> vec4<f32> {
    let x = min(u32(uv.x * f32(h.x)), h.x - 1u);
    let y = min(u32(uv.y * f32(h.y)), h.y - 1u);
    return texels[h.z + y * h.x + x];
}

// World direction towards the environment → image coordinates.
fn light_image_uv(light: Light, wi: vec3<f32>) -> vec2<f32> {
    return env_dir_to_uv(env_rotate_y(wi, light.direction[0], -light.direction[1]));
}

// One axis of a bilinear lookup: (first texel, second texel, weight of the second), texel
// i's centre at (i + ½)/n; wrapping (longitude) or clamped to the edge (rows). Twin of
// `env_map::bilinear`'s `axis`.
fn env_bilinear_axis(c: f32, n: u32, wrap: bool) -> vec3<f32> {
    var cc = 0.0;
    if abs(c) <= 2.0 {
        cc = clamp(c, -1.0, 2.0);
    }
    let x = cc * f32(n) - 0.5;
    let f = floor(x);
    let i = i32(f);
    let ni = i32(n);
    var i0 = clamp(i, 0, ni - 1);
    var i1 = clamp(i + 1, 0, ni - 1);
    if wrap {
        // i ≥ −n − 1 (c ≥ −1): shifted by 2n it is positive, so the remainder is unsigned
        // (a signed % of a negative number differs between backends: llvmpipe's GL).
        i0 = i32(u32(i + 2 * ni) % n);
        i1 = i32(u32(i + 1 + 2 * ni) % n);
    }
    return vec3<f32>(f32(i0), f32(i1), x - f);
}

// Radiance arriving from direction wi, bilinear between texel centres
// (`ImageEnvironment::radiance`, `EnvMap::lookup_uv`).
fn light_image_radiance(light: Light, wi: vec3<f32>) -> vec3<f32> {
    let h = light_image_header(light);
    return light.intensity[0] * light_image_bilinear(h, light_image_uv(light, wi));
}

// The image at (u, t), bilinear between texel centres (`EnvMap::lookup_uv`).
fn light_image_bilinear(h: vec4<u32>, uv: vec2<f32>) -> vec3<f32> {
    let ax = env_bilinear_axis(uv.x, h.x, true);
    let ay = env_bilinear_axis(uv.y, h.y, false);
    let x0 = u32(ax.x);
    let x1 = u32(ax.y);
    let r0 = h.z + u32(ay.x) * h.x;
    let r1 = h.z + u32(ay.y) * h.x;
    let top = mix(texels[r0 + x0].xyz, texels[r0 + x1].xyz, ax.z);
    let bottom = mix(texels[r1 + x0].xyz, texels[r1 + x1].xyz, ax.z);
    return mix(top, bottom, ay.z);
}

// Solid-angle density of the sampled direction wi, p(u,t) / (2π² sinθ) (PBR 3rd ed.
// §14.2.4); 1/4π without importance sampling. Twin of `ImageEnvironment::pdf_dir`.
fn light_image_pdf_dir(light: Light, wi: vec3<f32>) -> f32 {
    if light.direction[2] == 0.0 {
        return UNIFORM_SPHERE_PDF;
    }
    let uv = light_image_uv(light, wi);
    let sin_t = sin(uv.y * PI);
    if sin_t <= 0.0 {
        return 0.0;
    }
    return light_image_texel(light_image_header(light), uv).w / (2.0 * PI * PI * sin_t);
}

// Sample one piecewise-constant CDF of n cells starting at float `base` with u: the
// continuous coordinate in [0,1) and the cell. Twin of `Distribution1D::sample`
// (PBR 4th ed. §A.5.1, `FindInterval`).
fn light_image_sample_1d(h: vec4<u32>, base: u32, n: u32, u: f32) -> vec2<f32> {
    var lo = 0u;
    var hi = n + 1u;
    while lo < hi {
        let mid = (lo + hi) / 2u;
        if light_image_float(h, base + mid) <= u {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    let i = clamp(lo, 1u, n) - 1u;
    let c0 = light_image_float(h, base + i);
    let c1 = light_image_float(h, base + i + 1u);
    var du = 0.5;
    if c1 > c0 {
        du = (u - c0) / (c1 - c0);
    }
    let x = min((f32(i) + clamp(du, 0.0, 1.0)) / f32(n), 1.0 - 1.1920929e-7);
    return vec2<f32>(x, f32(i));
}

// A sampled direction towards the environment: (wi, solid-angle density; 0: none) and the
// radiance from it.
struct ImageDirSample {
    d: vec4<f32>,
    l: vec3<f32>,
}

// A direction towards the environment, its density and radiance. Twin of
// `ImageEnvironment::sample_dir` (PBR 4th ed. §12.5.2 `ImageInfiniteLight::SampleLi`). The
// radiance is read at the sampled (u, t) itself rather than at the direction's round trip
// through acos and atan2, whose error on some drivers (llvmpipe's GL) moved the bilinear
// lookup by up to 1e-3 of the image.
fn light_image_sample_dir(light: Light, u: vec2<f32>) -> ImageDirSample {
    if light.direction[2] == 0.0 {
        let wi = uniform_sphere(u);
        return ImageDirSample(vec4<f32>(wi, UNIFORM_SPHERE_PDF), light_image_radiance(light, wi));
    }
    let h = light_image_header(light);
    let row = light_image_sample_1d(h, h.y * (h.x + 1u), h.y, u.y);
    let col = light_image_sample_1d(h, u32(row.y) * (h.x + 1u), h.x, u.x);
    let uv = vec2<f32>(col.x, row.x);
    let p = texels[h.z + u32(row.y) * h.x + u32(col.y)].w;
    let sin_t = sin(uv.y * PI);
    if p <= 0.0 || sin_t <= 0.0 {
        return ImageDirSample(vec4<f32>(0.0), vec3<f32>(0.0));
    }
    let wi = env_rotate_y(env_uv_to_dir(uv), light.direction[0], light.direction[1]);
    let l = light.intensity[0] * light_image_bilinear(h, uv);
    return ImageDirSample(vec4<f32>(wi, p / (2.0 * PI * PI * sin_t)), l);
}

// glTF spot-light angular falloff (KHR_lights_punctual spec, "Spot"): smooth, squared
// linear ramp of cosθ between the outer and inner cone. Twin of `scene::light::spot_falloff`.
fn spot_falloff(cos_theta: f32, cos_inner: f32, cos_outer: f32) -> f32 {
    let scale = 1.0 / max(cos_inner - cos_outer, SPOT_MIN_RAMP_COS);
    let offset = -cos_outer * scale;
    let a = clamp(cos_theta * scale + offset, 0.0, 1.0);
    return a * a;
}

// A point on an area light: position, unit geometric normal (the triangle's winding), the
// triangle's area and the point's barycentrics (b1, b2). Twin of `TriangleLight::sample_point`
// with the normal and area of `TriangleLight::new` (PBR 4th ed. §6.5.4).
struct TrianglePoint {
    p: vec3<f32>,
    n: vec3<f32>,
    area: f32,
    // The triangle has a positive area.
    ok: bool,
    bc: vec2<f32>,
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
    return TrianglePoint(p, nn / len, 0.5 * len, len > 0.0, bc);
}

// Barycentrics (b1, b2) of a point p on the triangle in leaf slot `slot`, clamped into it.
// Twin of `TriangleLight::barycentric` (Ericson 2005, "Real-Time Collision Detection" §3.4).
fn light_triangle_barycentric(slot: u32, p: vec3<f32>) -> vec2<f32> {
    let tri = triangles[slot];
    let a = v3(tri.p0);
    let e1 = v3(tri.p1) - a;
    let e2 = v3(tri.p2) - a;
    let d = p - a;
    let d00 = dot3(e1, e1);
    let d01 = dot3(e1, e2);
    let d11 = dot3(e2, e2);
    let d20 = dot3(d, e1);
    let d21 = dot3(d, e2);
    let den = d00 * d11 - d01 * d01;
    if !(den > 0.0) {
        return vec2<f32>(0.0);
    }
    let b1 = clamp((d11 * d20 - d01 * d21) / den, 0.0, 1.0);
    let b2 = clamp((d00 * d21 - d01 * d20) / den, 0.0, 1.0 - b1);
    return vec2<f32>(b1, b2);
}

// Emitted radiance of the area light at barycentrics bc: emission × the emissive texture at
// the interpolated TEXCOORD_0 (glTF 2.0 §3.9.2). Twin of `TriangleLight::emission_at`.
fn light_triangle_emission(light: Light, m: Material, bc: vec2<f32>) -> vec3<f32> {
    if !HAS_TEXTURES || m.emit_tex == NO_TEXTURE {
        return v3(m.emission);
    }
    let tri = triangles[light.index];
    let v0 = vertices[tri.i0];
    let v1 = vertices[tri.i1];
    let v2 = vertices[tri.i2];
    let uv = vec2<f32>(v0.u, v0.v) * (1.0 - bc.x - bc.y) + vec2<f32>(v1.u, v1.v) * bc.x + vec2<f32>(v2.u, v2.v) * bc.y;
    return v3(m.emission) * max(sample_texture(m.emit_tex, uv).xyz, vec3<f32>(0.0));
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

// `light_sample_li` (generated, light::family_wgsl): incident illumination at `p_ref` from
// `light` (picked with probability `pick`), by kind. PBR 4th ed. §12.2–12.5 (`Light::SampleLi`);
// area lights sample the triangle uniformly and convert to solid angle, pdf = pick / area · d² /
// |cos θl| (PBR 4th ed. §12.5.1, Veach 1997 §9.2).

// Directional light: irradiance from −direction, a delta direction.
fn light_directional_sample_li(light: Light, pick: f32) -> LightLiSample {
    // Shadow ray to infinity (KHR_lights_punctual "Directional").
    let wi = -v3(light.direction);
    return LightLiSample(true, v3(light.intensity), wi, pick, vec3<f32>(0.0), vec3<f32>(0.0), true, true);
}

// Uniform environment: a uniform sphere of directions, pdf = pick / 4π (PBR 4th ed. §12.5.2,
// §A.5.2).
fn light_environment_sample_li(light: Light, u: vec2<f32>, pick: f32) -> LightLiSample {
    let wi = uniform_sphere(u);
    return LightLiSample(true, v3(light.intensity), wi, pick * UNIFORM_SPHERE_PDF, vec3<f32>(0.0), vec3<f32>(0.0), false, true);
}

// Environment image: a direction importance-sampled from the image (invalid where its density
// is 0). PBR 4th ed. §12.5.2 (`ImageInfiniteLight::SampleLi`).
fn light_image_sample_li(light: Light, u: vec2<f32>, pick: f32) -> LightLiSample {
    var s: LightLiSample;
    let ds = light_image_sample_dir(light, u);
    let d = ds.d;
    if d.w > 0.0 {
        s = LightLiSample(true, ds.l, d.xyz, pick * d.w, vec3<f32>(0.0), vec3<f32>(0.0), false, true);
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
    let l = light_triangle_emission(light, m, tp.bc);
    return LightLiSample(true, l, wi, pick / tp.area * dist2 / cos_l, tp.p, tp.n, false, false);
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

// `light_pdf_li` (generated): the solid-angle density with which `light_sample_li` would
// choose the point at distance `dist` along `wi` with geometric normal `n_light` (0 for delta
// lights; the environments' 1/4π and the image's density are the table's expressions).
// Area lights, PBR 4th ed. §12.5.1 (`DiffuseAreaLight::PDF_Li`): pick / area · d² / |cos θl|.
fn light_triangle_pdf_li(light: Light, pick: f32, dist: f32, n_light: vec3<f32>, wi: vec3<f32>) -> f32 {
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

// `light_le` (generated): radiance (area, environment) or intensity (punctual, with the spot falloff) emitted
// towards `w` from the point `p` with geometric normal `n_light` (an area light's emissive
// texture is read at p; lights at infinity ignore p and n); area lights are one-sided
// unless double-sided (glTF `doubleSided`). PBR 4th ed. §12.5.1 (`DiffuseAreaLight::L`),
// §12.1 (`SpotLight::I`, KHR_lights_punctual falloff). The area light's:
fn light_triangle_le(light: Light, p: vec3<f32>, n_light: vec3<f32>, w: vec3<f32>) -> vec3<f32> {
    let m = light_material(light);
    let emits = (m.flags & MAT_EMISSIVE) != 0u;
    if emits && (dot3(w, n_light) > 0.0 || (m.flags & MAT_DOUBLE_SIDED) != 0u) {
        if HAS_TEXTURES && m.emit_tex != NO_TEXTURE {
            return light_triangle_emission(light, m, light_triangle_barycentric(light.index, p));
        }
        return v3(m.emission);
    }
    return vec3<f32>(0.0);
}

// ---------------------------------------------------------------------------------------------
// Emission (light subpaths)

// The start of a light subpath (pbrt-v4 `LightLeSample`): origin point `p` with normal `n`
// (the emitting side; 0 for point lights), direction `dir`, emitted radiance / intensity `l`,
// the position density `pdf_pos` (pick / area, pick for a delta position, pick / (π r²) for
// the bounding disk of a light at infinity, whose `n` is `dir`) and the solid-angle density
// `pdf_dir`. `cos_n` = |n·dir| in the emitter's frame (1 for punctual lights and at infinity).
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

// `light_sample_le` (generated): an emitted ray of `light` (picked with probability `pick`): u_pos picks the point,
// u_dir the direction; a double-sided area light draws its side from `sampler` (one dimension,
// as `bdpt::light_path`). Lights at infinity emit from their bounding disk.
// PBR 4th ed. §12.1–12.5 (`Light::SampleLe`).

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
    let l = light_triangle_emission(light, m, tp.bc);
    return LightLeSample(true, tp.p, side, dir, l, pick / tp.area, pdf_dir, local.z, false);
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

// ---------------------------------------------------------------------------------------------
// Lights at infinity: rays from the disk of radius r perpendicular to the emission direction
// that covers the scene's bounding sphere (centre light.position, radius light.radius),
// placed behind the scene. PBR 4th ed. §12.4 (`DistantLight::SampleLe`), §12.5.

// The disk point for u_pos behind the scene, for rays along `dir`: c − r·dir + r·disk(u_pos)
// in dir's frame (the expression of the Rust `sample_le`s; PBR 4th ed. §12.4).
fn light_infinite_disk_point(light: Light, dir: vec3<f32>, u_pos: vec2<f32>) -> vec3<f32> {
    let frame = frame_from_normal(dir);
    let d = concentric_disk(u_pos) * light.radius;
    return v3(light.position) - light.radius * dir + frame_to_world(frame, vec3<f32>(d, 0.0));
}

// Area density of the disk point with the selection probability, pick / (π r²)
// (`UniformEnvironment::pdf_le`, `ImageEnvironment::pdf_le`).
fn light_infinite_pdf_pos(light: Light, pick: f32) -> f32 {
    return pick / (PI * light.radius * light.radius);
}

// Area density of the bounding disk, 1/(πr²). Twin of `DirectionalLight::pdf_pos`.
fn light_directional_pdf_pos(light: Light) -> f32 {
    return 1.0 / (PI * light.radius * light.radius);
}

// A ray along `direction` through a uniform point of the disk that covers the scene's
// bounding sphere, placed behind it; irradiance E, pdf_dir = 1 (a delta direction). Twin of
// `DirectionalLight::sample_le` (PBR 4th ed. §12.4 `DistantLight::SampleLe`).
fn light_directional_sample_le(light: Light, u_pos: vec2<f32>, pick: f32) -> LightLeSample {
    let dir = v3(light.direction);
    let p = light_infinite_disk_point(light, dir, u_pos);
    return LightLeSample(true, p, dir, dir, v3(light.intensity), pick * light_directional_pdf_pos(light), 1.0, 1.0, false);
}

// A uniform direction and a point on the disk perpendicular to it that covers the bounding
// sphere, behind the scene. Twin of `UniformEnvironment::sample_le` (PBR 4th ed. §12.5.1
// `UniformInfiniteLight::SampleLe`).
fn light_environment_sample_le(light: Light, u_pos: vec2<f32>, u_dir: vec2<f32>, pick: f32) -> LightLeSample {
    let dir = -uniform_sphere(u_dir);
    let p = light_infinite_disk_point(light, dir, u_pos);
    return LightLeSample(true, p, dir, dir, v3(light.intensity), light_infinite_pdf_pos(light, pick), UNIFORM_SPHERE_PDF, 1.0, false);
}

// A direction importance-sampled from the environment image (`light_image_sample_dir`) and a
// point on the disk perpendicular to it that covers the bounding sphere, behind the scene;
// invalid where the map's density is 0. Twin of `ImageEnvironment::sample_le` (PBR 4th ed.
// §12.5.2 `ImageInfiniteLight::SampleLe`).
fn light_image_sample_le(light: Light, u_pos: vec2<f32>, u_dir: vec2<f32>, pick: f32) -> LightLeSample {
    var s: LightLeSample;
    let ds = light_image_sample_dir(light, u_dir);
    let d = ds.d;
    if !(d.w > 0.0) {
        return s;
    }
    let dir = -d.xyz;
    let p = light_infinite_disk_point(light, dir, u_pos);
    return LightLeSample(true, p, dir, dir, ds.l, light_infinite_pdf_pos(light, pick), d.w, 1.0, false);
}

// Origin of the first ray of a light subpath: pushed off an area light's emitting side
// (Wächter & Binder 2019, `offset_ray_origin`); the sampled point itself for point-like lights
// and the bounding disk of lights at infinity (as `sppm::photon::trace_photon`).
fn light_le_sample_origin(light: Light, s: LightLeSample) -> vec3<f32> {
    if s.delta_pos || light_is_infinite(light) {
        return s.p;
    }
    return offset_ray_origin(s.p, s.n);
}

// Emission densities of `light_sample_le` (pbrt-v4 `Light::PDF_Le`).
struct LightLePdf {
    pdf_pos: f32,
    pdf_dir: f32,
}

// `light_pdf_le` (generated): densities with which `light_sample_le` of `light` (selection probability `pick`) emits from
// a point with normal `n_light` towards `w`: area lights pdf_pos = pick / area (the mesh area),
// pdf_dir cosine-weighted; a delta position reports pdf_pos = pick, as `light_sample_le` does
// (the walks read pdf_dir only); lights at infinity the bounding disk's pick / (π r²) and the
// direction's density (0 for a delta direction, Veach 1997 §10.3.5).
// PBR 4th ed. §12.1, §12.4, §12.5 (`PDF_Le`). The area light's:
fn light_triangle_pdf_le(light: Light, pick: f32, n_light: vec3<f32>, w: vec3<f32>) -> LightLePdf {
    let m = light_material(light);
    let c = dot3(n_light, w);
    var pdf_dir = 0.0;
    if c > 0.0 || (m.flags & MAT_DOUBLE_SIDED) != 0u {
        pdf_dir = light_area_pdf_dir(m, abs(c));
    }
    return LightLePdf(pick / triangles[light.index].area, pdf_dir);
}

// Spot light: the cone's density inside the outer angle, 0 outside.
fn light_spot_pdf_le(light: Light, pick: f32, w: vec3<f32>) -> LightLePdf {
    var pdf_dir = 0.0;
    if dot3(w, v3(light.direction)) >= light.cos_outer {
        pdf_dir = light_punctual_pdf_dir(light);
    }
    return LightLePdf(pick, pdf_dir);
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
