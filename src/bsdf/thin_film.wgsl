// thin_film.wgsl — thin-film interference (twin of src/bsdf/thin_film.rs): the reflectance of
// a dielectric film (index n₂, thickness d nm) between the outside (n₁ = 1) and a substrate of
// complex index N₃ = η + iκ. Born & Wolf, "Principles of Optics", §7.6.1 (the Airy sum);
// Belcour & Barla 2017, "A Practical Extension to Microfacet Theory for the Modeling of Varying
// Iridescence", §4 (its Fourier series integrated against the colour-matching functions):
// the kernels' films are RGB (the exact per-wavelength `ThinFilm::airy` has no twin here).
// Complex numbers are vec2 (re, im); conventions as the Rust module's.

fn cx_mul(a: vec2<f32>, b: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x);
}

fn cx_div(a: vec2<f32>, b: vec2<f32>) -> vec2<f32> {
    let d = b.x * b.x + b.y * b.y;
    return vec2<f32>((a.x * b.x + a.y * b.y) / d, (a.y * b.x - a.x * b.y) / d);
}

fn cx_norm2(a: vec2<f32>) -> f32 {
    return a.x * a.x + a.y * a.y;
}

// The principal square root (Re ≥ 0; Im ≥ 0 on the cut). Twin of `math::Complex::sqrt`
// (which takes the modulus in f64; the same root to f32 rounding): the larger component from
// √((r ± x)/2), the smaller as y / (2 · that) — without the cancellation of r − x where
// |y| ≪ x (a conductor or thin film near normal incidence lost most of Im that way).
fn cx_sqrt(a: vec2<f32>) -> vec2<f32> {
    let r = sqrt(cx_norm2(a));
    if r == 0.0 {
        return vec2<f32>(0.0);
    }
    if a.x >= 0.0 {
        let t = sqrt(0.5 * (r + a.x));
        return vec2<f32>(t, a.y / (2.0 * t));
    }
    let t = sqrt(0.5 * (r - a.x));
    return vec2<f32>(abs(a.y) / (2.0 * t), select(t, -t, a.y < 0.0));
}

fn cx_arg(a: vec2<f32>) -> f32 {
    return atan2(a.y, a.x);
}

// (r⊥, r∥) at an interface a → b (complex indices and cosines), as one vec4 (r⊥.re, r⊥.im,
// r∥.re, r∥.im). Twin of `interface`.
fn film_interface(na: vec2<f32>, ca: vec2<f32>, nb: vec2<f32>, cb: vec2<f32>) -> vec4<f32> {
    let a = cx_mul(na, ca);
    let b = cx_mul(nb, cb);
    let c = cx_mul(nb, ca);
    let d = cx_mul(na, cb);
    return vec4<f32>(cx_div(a - b, a + b), cx_div(c - d, c + d));
}

// The film at incidence cosine `cos1` over the substrate `n3`: cos θ₂ and the amplitude
// coefficients r₁₂, r₂₃ for s (xy) and p (zw). Twin of `ThinFilm::stack`.
struct FilmStack {
    cos2: f32,
    r12: vec4<f32>,
    r23: vec4<f32>,
}

fn film_stack(ior: f32, cos1_in: f32, n3: vec2<f32>) -> FilmStack {
    let n2 = max(ior, 1.0);
    let cos1 = clamp(cos1_in, 0.0, 1.0);
    let sin2_1 = 1.0 - cos1 * cos1;
    let cos2 = sqrt(max(1.0 - sin2_1 / (n2 * n2), 0.0));
    let cos3 = cx_sqrt(vec2<f32>(1.0, 0.0) - cx_div(vec2<f32>(sin2_1, 0.0), cx_mul(n3, n3)));
    let one = vec2<f32>(1.0, 0.0);
    let n2c = vec2<f32>(n2, 0.0);
    let r12 = film_interface(one, vec2<f32>(cos1, 0.0), n2c, vec2<f32>(cos2, 0.0));
    let r23 = film_interface(n2c, vec2<f32>(cos2, 0.0), n3, cos3);
    return FilmStack(cos2, r12, r23);
}

// Optical path difference of one round trip, 2 n₂ d cos θ₂ (nm). Twin of `ThinFilm::opd`.
fn film_opd(ior: f32, thickness_nm: f32, cos2: f32) -> f32 {
    return 2.0 * max(ior, 1.0) * max(thickness_nm, 0.0) * cos2;
}

// One Gaussian of the fitted XYZ sensitivity at phase 2π·opd, against the harmonic's phasor
// h = Σ 2 C_m (cos mφ, sin mφ) over the polarisations: a √(2π v) e^{−v phase²} Re(e^{iμ phase} h)
// (Belcour & Barla 2017 §4.3; FILM_FIT_* = bsdf::thin_film::SENSITIVITY_FIT). Twin of `lobe`.
fn film_fit_lobe(fit: vec3<f32>, phase: f32, h: vec2<f32>) -> f32 {
    let a = fit.y * phase;
    return fit.x * sqrt(2.0 * PI * fit.z) * exp(-fit.z * phase * phase) * (cos(a) * h.x - sin(a) * h.y);
}

// The fitted XYZ sensitivity of one harmonic at optical path difference `opd_nm`. Twin of
// `xyz_harmonic`.
fn film_xyz_harmonic(opd_nm: f32, h: vec2<f32>) -> vec3<f32> {
    let phase = 2.0 * PI * opd_nm * 1e-9;
    return vec3<f32>(
        film_fit_lobe(FILM_FIT_X, phase, h) + film_fit_lobe(FILM_FIT_X2, phase, h),
        film_fit_lobe(FILM_FIT_Y, phase, h),
        film_fit_lobe(FILM_FIT_Z, phase, h)
    );
}

// Reflectance integrated against the matching functions, series truncated after m = 2
// (Belcour & Barla 2017 eq. 12). The sensitivity is linear in cos(μ·phase + mφ), so each
// harmonic's Gaussians are evaluated once for both polarisations, against the sum of their
// phasors. Twin of `ThinFilm::rgb` and `ThinFilm::fourier`.
fn film_rgb(ior: f32, thickness_nm: f32, cos1: f32, n3: vec2<f32>) -> vec3<f32> {
    let s = film_stack(ior, cos1, n3);
    let opd = film_opd(ior, thickness_nm, s.cos2);
    var c0 = 0.0;
    var h1 = vec2<f32>(0.0);
    var h2 = vec2<f32>(0.0);
    for (var k = 0u; k < 2u; k++) {
        var r12 = s.r12.xy;
        var r23 = s.r23.xy;
        if k == 1u {
            r12 = s.r12.zw;
            r23 = s.r23.zw;
        }
        let r12_2 = cx_norm2(r12);
        let t121 = 1.0 - r12_2;
        let r23_2 = cx_norm2(r23);
        let r123_2 = min(r12_2 * r23_2, FILM_MAX_R123_SQ);
        let rs = t121 * t121 * r23_2 / (1.0 - r123_2);
        let ratio = sqrt(r123_2);
        let phi = cx_arg(-r12) + cx_arg(r23);
        c0 += r12_2 + rs;
        let c1 = (rs - t121) * ratio;
        let c2 = c1 * ratio;
        h1 += 2.0 * c1 * vec2<f32>(cos(phi), sin(phi));
        h2 += 2.0 * c2 * vec2<f32>(cos(2.0 * phi), sin(2.0 * phi));
    }
    let white = xyz_to_linear_srgb(film_xyz_harmonic(0.0, vec2<f32>(1.0, 0.0)));
    let xyz = film_xyz_harmonic(opd, h1) + film_xyz_harmonic(2.0 * opd, h2);
    let r = vec3<f32>(c0) + xyz_to_linear_srgb(xyz) / white;
    return clamp(0.5 * r, vec3<f32>(0.0), vec3<f32>(1.0));
}
