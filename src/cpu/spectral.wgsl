// spectral.wgsl — the colour representation of one path (twin of `cpu::Spectral`): RGB
// (w = 0) or four hero wavelengths (Wilkie et al. 2014, "Hero Wavelength Spectral Sampling").

// Hero-wavelength spectral transport (scenes with a dispersive material).
override HAS_SPECTRAL: bool = true;

struct Spectral {
    on: bool,
    lambdas: vec4<f32>,
}

// The path's colour representation: hero wavelengths drawn from `sampler` (one dimension)
// when the kernel is spectral, RGB otherwise.
fn spectral_new(sampler: ptr<function, Sampler>) -> Spectral {
    var sp = Spectral(false, vec4<f32>(0.0));
    if HAS_SPECTRAL {
        sp = Spectral(true, sample_hero_wavelengths(sampler_next_1d(sampler)));
    }
    return sp;
}

// RGB parameter → the path's colour lanes (smooth uplift in spectral mode). Twin of `Spectral::c`.
fn spectral_c(sp: Spectral, rgb: vec3<f32>) -> vec4<f32> {
    if HAS_SPECTRAL && sp.on {
        return rgb_to_spectrum4(rgb, sp.lambdas);
    }
    return vec4<f32>(rgb, 0.0);
}

// The path's colour lanes → RGB (the spectral estimate integrated against the CMFs).
fn spectral_to_rgb(sp: Spectral, c: vec4<f32>) -> vec3<f32> {
    if HAS_SPECTRAL && sp.on {
        return spectrum_sample_to_rgb(sp.lambdas, c);
    }
    return c.xyz;
}

// Keep only the hero wavelength (lane 0, ×4: it now carries the whole estimate) once a
// wavelength-dependent direction was sampled. Wilkie et al. 2014, §4.2.
fn spectral_collapse(c: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(4.0 * c.x, 0.0, 0.0, 0.0);
}
