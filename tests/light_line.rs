//! A scene-wide light with one spectral line (`RenderSettings::light_line_nm`): the image is
//! the line's colour only, dispersive glass refracts with n(λ₀), a grey scene keeps its
//! brightness, and bad wavelengths are errors naming their source.

use glam::Vec3;
use refract::cpu::Renderer;
use refract::math::{color::luminance, prism, spectrum};
use refract::render::{Estimator, RenderOptions};
use refract::scene::{MaterialKind, Scene};

fn render(scene: Scene, w: u32, h: u32, spp: u32, est: Estimator) -> Vec<Vec3> {
    let r = Renderer::new(scene).expect("valid scene");
    let mut opts = RenderOptions::from_scene(&r.scene);
    opts.width = w;
    opts.height = h;
    opts.estimator = est;
    let (film, _) = r.render(&opts, spp, None, |_| {});
    film.image()
}

fn with_line(mut s: Scene, nm: Option<f32>) -> Scene {
    s.settings.light_line_nm = nm;
    s
}

/// (a) Every pixel's RGB is a non-negative multiple of c(λ₀), for every estimator.
#[test]
fn every_pixel_is_the_line_colour() {
    for (name, nm) in [("prism", 589.3), ("cornell-glass", 405.0), ("prism", 632.8)] {
        let c = spectrum::light_line_rgb(nm);
        for est in [Estimator::Path, Estimator::Bdpt, Estimator::Sppm] {
            let s = with_line(Scene::load(&format!("builtin:{name}")).unwrap(), Some(nm));
            let img = render(s, 40, 30, 2, est);
            let mut lit = 0;
            for p in &img {
                let k = p.dot(c) / c.dot(c);
                assert!(k >= 0.0, "{name} {nm} {est:?}: {p} has a negative share");
                let err = (*p - k * c).length();
                assert!(
                    err <= 1e-5 * p.length().max(1e-6),
                    "{name} {nm} nm {est:?}: pixel {p} is not a multiple of {c} (off by {err})"
                );
                lit += (k > 0.0) as usize;
            }
            assert!(lit > img.len() / 4, "{name} {est:?}: only {lit} lit pixels");
        }
    }
}

/// c(λ₀) has luminance 1 and no negative channel; sodium D is orange, 405 nm violet.
#[test]
fn line_colour_is_in_gamut_with_unit_luminance() {
    for nm in [380.0, 405.0, 486.1, 532.0, 589.3, 632.8, 656.3, 780.0] {
        let c = spectrum::light_line_rgb(nm);
        assert!(c.min_element() >= 0.0, "{nm}: {c}");
        assert!((luminance(c) - 1.0).abs() < 1e-5, "{nm}: {c}");
    }
    let na = spectrum::light_line_rgb(589.3);
    assert!(na.x > na.y && na.y > na.z, "sodium {na}");
    let v = spectrum::light_line_rgb(405.0);
    assert!(v.z > v.y && v.x > v.y, "violet {v}");
}

/// (c) A grey scene (cornell-glass with its coloured walls and light made grey, its glass
/// non-dispersive) has the same mean luminance under white light
/// and under any line: the lanes see the same path, only the hue changes.
#[test]
fn grey_scene_keeps_its_brightness() {
    let mut base = Scene::load("builtin:cornell-glass").unwrap();
    for m in &mut base.materials {
        m.abbe = None;
        if m.kind == MaterialKind::Diffuse {
            m.base_color = Vec3::splat(luminance(m.base_color));
        }
        if m.is_emissive() {
            m.emission = Vec3::splat(luminance(m.emission));
        }
    }
    let mean =
        |img: &[Vec3]| img.iter().map(|p| luminance(*p) as f64).sum::<f64>() / img.len() as f64;
    let white = mean(&render(base.clone(), 48, 48, 8, Estimator::Path));
    for nm in [405.0, 532.0, 589.3, 632.8] {
        let line = mean(&render(
            with_line(base.clone(), Some(nm)),
            48,
            48,
            8,
            Estimator::Path,
        ));
        // The same random numbers drive both renders: only float rounding differs.
        assert!(
            (line / white - 1.0).abs() < 1e-3,
            "{nm} nm: mean luminance {line} vs white {white}"
        );
    }
}

/// Brightness-weighted centroid (x, pixels) of the wall region of the prism image: the
/// right third of the frame, where the beam lands (builtin::prism's camera).
fn beam_centroid(img: &[Vec3], w: u32) -> f64 {
    let (mut sx, mut s) = (0.0, 0.0);
    for (i, p) in img.iter().enumerate() {
        let x = (i as u32 % w) as f64;
        if x > 0.75 * w as f64 {
            let l = luminance(*p) as f64;
            sx += l * x;
            s += l;
        }
    }
    sx / s
}

/// (b) On the prism the beam's spot moves with λ₀ as `math::prism` predicts: 405 nm is
/// deviated more than 650 nm, and the spot of each line lies where a non-dispersive prism of
/// index n(λ₀) puts it (that prism's shift with n gives the screen direction of "more
/// deviation").
#[test]
fn prism_beam_moves_with_the_wavelength() {
    let base = Scene::load("builtin:prism").unwrap();
    let glass = base
        .materials
        .iter()
        .position(|m| m.abbe.is_some())
        .unwrap();
    let (n_d, abbe) = (
        base.materials[glass].ior,
        base.materials[glass].abbe.unwrap(),
    );
    let apex = 60f32.to_radians();
    let n = |nm| spectrum::cauchy_from_abbe(n_d, abbe, nm);
    let theta = prism::min_deviation_incidence(n_d, apex).unwrap();
    let dev = |nm| prism::deviation(n(nm), apex, theta).unwrap();
    assert!(dev(405.0) > dev(650.0));
    let (w, h, spp) = (160, 100, 16);
    let line = |nm| {
        beam_centroid(
            &render(
                with_line(base.clone(), Some(nm)),
                w,
                h,
                spp,
                Estimator::Bdpt,
            ),
            w,
        )
    };
    let plain = |nm| {
        let mut s = base.clone();
        s.materials[glass].abbe = None;
        s.materials[glass].ior = n(nm);
        beam_centroid(&render(s, w, h, spp, Estimator::Bdpt), w)
    };
    let (l405, l650, p405, p650) = (line(405.0), line(650.0), plain(405.0), plain(650.0));
    eprintln!("centroids: line 405 {l405:.2}, 650 {l650:.2}; n-prisms {p405:.2}, {p650:.2}");
    let shift = l405 - l650;
    let expected = p405 - p650;
    assert!(
        expected.abs() > 1.0,
        "non-dispersive prisms barely differ: {p405} vs {p650}"
    );
    assert!(
        shift * expected > 0.0,
        "405 nm spot at x={l405}, 650 nm at {l650}; n(405)-prism {p405}, n(650)-prism {p650}"
    );
    assert!(
        (shift / expected - 1.0).abs() < 0.25,
        "shift {shift} px vs {expected} px"
    );
}

/// (f) Bad wavelengths are errors naming their source.
#[test]
fn bad_wavelengths_name_their_source() {
    for nm in [0.0, -5.0, f32::NAN, 359.0, 831.0, f32::INFINITY] {
        let e = spectrum::check_light_line(nm, "--light-line").unwrap_err();
        assert!(e.contains("--light-line") && e.contains("360"), "{e}");
        let s = with_line(Scene::load("builtin:prism").unwrap(), Some(nm));
        let e = format!("{:#}", Renderer::new(s).err().expect("refused"));
        assert!(e.contains("light_line_nm"), "{e}");
    }
    assert_eq!(spectrum::check_light_line(589.3, "x"), Ok(589.3));
}

/// (3) The GPU kernel has no light line yet: it refuses the scene with a clear error rather
/// than rendering white light.
#[test]
fn gpu_refuses_a_light_line_clearly() {
    let s = with_line(Scene::load("builtin:prism").unwrap(), Some(589.3));
    let e = refract::gpu::upload::check_supported(&s).unwrap_err();
    assert!(format!("{e:#}").contains("light line"), "{e:#}");
    let white = Scene::load("builtin:prism").unwrap();
    assert!(refract::gpu::upload::check_supported(&white).is_ok());
}
