//! GPU renderer twins: layouts (naga reflection), kernel parity (probe kernel vs the Rust
//! maths), RNG parity (bit for bit), path parity (same seed → same paths), image parity (GPU vs
//! CPU within noise), the GPU white furnace, and reset after parameter edits.
//! Tests that need an adapter print a SKIP line and return when there is none (CI installs
//! lavapipe, so they run there).

mod common_scenes;
use common_scenes::*;
use glam::{Vec2, Vec3};
use refract::bsdf::fresnel::{fresnel_dielectric_terms, refract};
use refract::bsdf::microfacet::{erf, erfc, erfinv};
use refract::bsdf::thin_film::ThinFilm;
use refract::bsdf::{
    Bsdf, BxDF, ComplexIor, Event, FilmBase, Iridescent, Lambert, Lobe, Metal, MetalRough,
    Microfacet, MicrofacetDistribution, Mirror, RoughConductor, RoughDielectric,
    RoughFresnelConductor, RoughThinDielectric, SmoothConductor, SmoothDielectric, ThinDielectric,
    TransportMode,
};
use refract::cpu::Renderer;
use refract::film::Film;
use refract::gpu::layout::{self, *};
use refract::gpu::pipeline::{integrator_source, light_probe_source, probe_source, run_probe};
use refract::gpu::{GpuContext, GpuRenderer, upload};
use refract::math::rng::{Sampler, pcg_hash};
use refract::math::spectrum::{
    cauchy_from_abbe, rgb_to_spectrum4, sample_hero_wavelengths, spectrum_sample_to_rgb,
};
use refract::paths::PathFilter;
use refract::render::{Estimator, RenderOptions};
use refract::scene::material::{Texture, TextureRef, Wrap};
use refract::scene::{Camera, Features, Material, Mesh, Scene};

fn context(test: &str) -> Option<GpuContext> {
    gpu_context(test)
}

#[test]
fn layout_matches_wgsl() {
    let src = integrator_source();
    check_layout::<BvhNode>(&src).unwrap();
    check_layout::<layout::Triangle>(&src).unwrap();
    check_layout::<Vertex>(&src).unwrap();
    check_layout::<layout::Material>(&src).unwrap();
    check_layout::<Light>(&src).unwrap();
    check_layout::<Params>(&src).unwrap();
    check_layout::<layout::Photon>(&src).unwrap();
    check_layout_with_tail::<Stats>(&src, "debug").unwrap();
    let probe = probe_source();
    check_layout::<ProbeCase>(&probe).unwrap();
    check_layout::<ProbeOut>(&probe).unwrap();
}

/// Every generated prelude constant reaches both kernels with its Rust value (naga's module
/// constants), and no .wgsl file defines one itself: changing one side alone fails here.
#[test]
fn prelude_constants_match_rust() {
    use refract::gpu::pipeline::SHADER_FILES;
    use refract::gpu::prelude::{WGSL_CONSTANTS, WGSL_F32_CONSTANTS, WGSL_VEC3_CONSTANTS};
    for (kernel, src) in [
        ("integrator", integrator_source()),
        ("probe", probe_source()),
        ("light probe", light_probe_source()),
    ] {
        let module = naga::front::wgsl::parse_str(&src).unwrap();
        for &(name, value) in WGSL_CONSTANTS {
            let c = module
                .constants
                .iter()
                .find(|(_, c)| c.name.as_deref() == Some(name))
                .map(|(_, c)| c)
                .unwrap_or_else(|| panic!("{kernel}: no WGSL constant {name}"));
            let init = &module.global_expressions[c.init];
            assert!(
                matches!(init, naga::Expression::Literal(naga::Literal::U32(v)) if *v == value),
                "{kernel}: {name} is {init:?} in WGSL, {value} in Rust"
            );
        }
    }
    check_f32_constants();
    let names = WGSL_CONSTANTS
        .iter()
        .map(|c| c.0)
        .chain(WGSL_F32_CONSTANTS.iter().map(|c| c.0))
        .chain(WGSL_VEC3_CONSTANTS.iter().map(|c| c.0));
    let names: Vec<&str> = names.collect();
    for (file, text) in SHADER_FILES {
        for line in text.lines() {
            let decl = line.trim_start();
            for &name in &names {
                let defines = ["const ", "override ", "var ", "let "].iter().any(|k| {
                    decl.strip_prefix(k)
                        .and_then(|r| r.strip_prefix(name))
                        .is_some_and(|r| r.starts_with([':', ' ', '=']))
                });
                assert!(
                    !defines,
                    "{file} defines the prelude constant {name}: {line}"
                );
            }
        }
    }
}

/// The generated `f32` and `vec3<f32>` constants read back by naga equal their Rust values
/// bit for bit, and no shader writes one of those numbers as a literal of its own (the
/// twin's copy the prelude replaced). Numbers every kernel uses for other reasons — small
/// multiples of 1/4 up to 4, such as 0.5 — are not counted as copies.
fn check_f32_constants() {
    use refract::gpu::pipeline::SHADER_FILES;
    use refract::gpu::prelude::{WGSL_F32_CONSTANTS, WGSL_VEC3_CONSTANTS};
    let module = naga::front::wgsl::parse_str(&integrator_source()).unwrap();
    let literal = |name: &str| -> Vec<f32> {
        let c = module
            .constants
            .iter()
            .find(|(_, c)| c.name.as_deref() == Some(name))
            .map(|(_, c)| c)
            .unwrap_or_else(|| panic!("no WGSL constant {name}"));
        let scalar = |h: naga::Handle<naga::Expression>| match module.global_expressions[h] {
            naga::Expression::Literal(naga::Literal::F32(v)) => v,
            ref e => panic!("{name}: {e:?} is not an f32 literal"),
        };
        match &module.global_expressions[c.init] {
            naga::Expression::Compose { components, .. } => {
                components.iter().map(|&h| scalar(h)).collect()
            }
            _ => vec![scalar(c.init)],
        }
    };
    let mut values = Vec::new();
    for &(name, v) in WGSL_F32_CONSTANTS {
        assert_eq!(literal(name)[0].to_bits(), v.to_bits(), "{name}");
        values.push((name, v));
    }
    for &(name, v) in WGSL_VEC3_CONSTANTS {
        let got: Vec<u32> = literal(name).iter().map(|x| x.to_bits()).collect();
        assert_eq!(got, v.map(f32::to_bits).to_vec(), "{name}");
        values.extend(v.iter().map(|&x| (name, x)));
    }
    let common = |v: f32| (v * 4.0).fract() == 0.0 && v.abs() <= 4.0;
    for (file, text) in SHADER_FILES {
        for (n, line) in text.lines().enumerate() {
            let code = line.split("//").next().unwrap_or("");
            for lit in float_literals(code) {
                for &(name, v) in &values {
                    assert!(
                        common(v) || lit != v,
                        "{file}:{}: the literal {lit} is the prelude constant {name}: {line}",
                        n + 1
                    );
                }
            }
        }
    }
}

/// The floating-point literals of a line of WGSL (digits with a point or an exponent).
fn float_literals(code: &str) -> Vec<f32> {
    let mut out = Vec::new();
    let b = code.as_bytes();
    let mut i = 0;
    while i < b.len() {
        let starts = b[i].is_ascii_digit()
            && (i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_'));
        if !starts {
            i += 1;
            continue;
        }
        let mut j = i;
        while j < b.len()
            && (b[j].is_ascii_digit()
                || b[j] == b'.'
                || b[j] == b'e'
                || ((b[j] == b'-' || b[j] == b'+') && b[j - 1] == b'e'))
        {
            j += 1;
        }
        let s = &code[i..j];
        if s.contains(['.', 'e'])
            && let Ok(v) = s.parse::<f32>()
        {
            out.push(v);
        }
        i = j.max(i + 1);
    }
    out
}

/// The BVH2 repack keeps triangles in `primitive_indices` order and every scene triangle
/// appears exactly once.
#[test]
fn bvh_repack_leaf_order() {
    let scene = Scene::load("builtin:cornell-glass").unwrap();
    let bvh = upload::build_bvh(&scene).unwrap();
    let lights = refract::scene::light::LightSet::build(&scene);
    let tris = upload::pack_triangles(&scene, &bvh, &lights);
    assert_eq!(tris.len(), scene.mesh.triangle_count());
    let mut seen = vec![false; tris.len()];
    for (slot, t) in tris.iter().enumerate() {
        let st = t.scene_tri as usize;
        assert_eq!(bvh.primitive_indices[slot] as usize, st);
        assert_eq!(bvh.slot_of_tri[st] as usize, slot);
        let [a, b, c] = scene.mesh.tri(st);
        assert_eq!(
            [t.p0, t.p1, t.p2],
            [a.to_array(), b.to_array(), c.to_array()]
        );
        assert!(!std::mem::replace(&mut seen[st], true));
    }
    assert!(bvh.depth <= upload::MAX_BVH_DEPTH);
    eprintln!("BVH2: {} nodes, depth {}", bvh.nodes.len(), bvh.depth);
}

/// The kernels' traversal stack is sized from the uploaded tree's depth
/// (`upload::bvh_stack_entries`): each level above a node holds at most one pending sibling,
/// so depth − 1 entries suffice whichever child a ray visits first. Checked by running
/// scene.wgsl's loop with every box hit, nearer child first and farther child first, and on
/// the built-ins the sized stack is well under the full 64.
#[test]
fn traversal_stack_sized_from_the_tree_holds_every_pending_sibling() {
    for name in [
        "cornell-glass",
        "caustic",
        "materials",
        "glass-of-water",
        "env-spheres",
    ] {
        let scene = Scene::load(&format!("builtin:{name}")).unwrap();
        let bvh = upload::build_bvh(&scene).unwrap();
        let entries = upload::bvh_stack_entries(bvh.depth) as usize;
        for first in [0, 1] {
            // scene.wgsl's loop with both children always hit: stack one, visit the other.
            let (mut stack, mut node, mut most) = (Vec::new(), 0u32, 0usize);
            loop {
                let n = bvh.nodes[node as usize];
                if n.prim_count == 0 {
                    stack.push(n.first_index + 1 - first);
                    most = most.max(stack.len());
                    node = n.first_index + first;
                    continue;
                }
                match stack.pop() {
                    Some(next) => node = next,
                    None => break,
                }
            }
            assert!(
                most < bvh.depth as usize,
                "{name}: {most} pending, depth {}",
                bvh.depth
            );
        }
        assert!(
            bvh.depth as usize - 1 <= entries && entries < 64,
            "{name}: depth {}, {entries} entries",
            bvh.depth
        );
    }
    assert_eq!(upload::bvh_stack_entries(1), 8);
    assert_eq!(upload::bvh_stack_entries(23), 24);
    assert_eq!(upload::bvh_stack_entries(25), 24);
    assert_eq!(upload::bvh_stack_entries(26), 32);
    assert_eq!(upload::bvh_stack_entries(64), 64);
}

/// The wavefronts' path states are as large as the host allocates for them, and the
/// live-path queues start where the host's header (cleared per chunk) ends.
#[test]
fn wavefront_states_match_their_wgsl_layouts() {
    use refract::gpu::renderer::wavefront::{LIGHT_PATH_BYTES, PATH_BYTES, QUEUE_HEADER};
    let src = integrator_source();
    for (name, bytes) in [("WfPath", PATH_BYTES), ("LtPath", LIGHT_PATH_BYTES)] {
        let (size, _) = layout::wgsl_struct_layout(&src, name).unwrap();
        assert_eq!(u64::from(size), bytes, "{name}");
    }
    let (_, fields) = layout::wgsl_struct_layout(&src, "WfQueue").unwrap();
    let offset = |f: &str| {
        fields
            .iter()
            .find(|(n, _)| n == f)
            .map(|&(_, o)| u64::from(o))
    };
    assert_eq!(offset("count"), Some(0), "the counts the host clears");
    assert_eq!(offset("items"), Some(QUEUE_HEADER), "{fields:?}");
}

/// The wavefront camera walk (wavefront.wgsl) is the megakernel's walk split into kernels
/// with the path state in memory, and likewise lt+pt's light subpaths (light_wavefront.wgsl):
/// with the same seed they give the same samples — equal up to
/// the compiler's floating-point contractions, which differ between kernels (exactly equal
/// outside spectral code on lavapipe) — the same path segments and the same dropped samples,
/// for path tracing, nested absorbing glass, dispersion, an image environment, light tracing
/// with MIS and a Heckbert filter. (Photon mapping's camera pass runs the same walk; its
/// photon grid is filled by atomics, so two renders differ there run to run either way.)
#[test]
fn wavefront_matches_megakernel() {
    let cases = [
        ("cornell-glass", Estimator::Path, None),
        ("glass-of-water", Estimator::Path, None),
        ("prism", Estimator::Path, None),
        ("env-spheres", Estimator::Path, None),
        ("caustic", Estimator::LtPt, None),
        ("materials", Estimator::Path, Some("L(D|G|S)*DE")),
    ];
    for (name, estimator, filter) in cases {
        let Some(ctx) = context("wavefront_matches_megakernel") else {
            return;
        };
        let mut s = Scene::load(&format!("builtin:{name}")).unwrap();
        small(&mut s, 40, 30);
        let mut opts = RenderOptions::from_scene(&s);
        opts.estimator = estimator;
        opts.seed = 7;
        let mut g = GpuRenderer::with_context(ctx, s, opts).unwrap();
        if let Some(f) = filter {
            g.set_filter(Some(&PathFilter::parse(f).unwrap()));
        }
        let mut run = |wavefront: bool, indirect: bool| {
            g.set_wavefront(Some(wavefront));
            g.set_wavefront_indirect(indirect);
            assert_eq!(g.specialization().wavefront, wavefront);
            // One submission of 3 spp (`render` would split by measured time, which changes
            // the film's order of additions from run to run).
            g.dispatch(3);
            let img = g.image().unwrap();
            (img, g.stats().unwrap().segments)
        };
        let (mega, mega_segments) = run(false, true);
        // Every bounce over the whole chunk (no indirect dispatch): the same samples.
        let (direct, direct_segments) = run(true, false);
        let (wave, wave_segments) = run(true, true);
        assert_eq!(wave_segments, mega_segments, "{name}: path segments");
        assert_eq!(
            direct_segments, wave_segments,
            "{name}: path segments, direct"
        );
        assert!(
            direct.mean == wave.mean,
            "{name}: direct and indirect dispatch differ by {:e}",
            worst_relative_difference(&direct.mean, &wave.mean)
        );
        assert!(mega_segments.is_some_and(|n| n > 0), "{name}");
        assert_eq!(wave.dropped, mega.dropped, "{name}: dropped samples");
        let worst = worst_relative_difference(&mega.mean, &wave.mean);
        eprintln!(
            "{name} ({estimator:?}): wavefront vs megakernel, worst relative difference {worst:e}"
        );
        assert!(worst <= 1e-5, "{name}: {worst}");
    }
}

/// The largest per-pixel difference of two images relative to the first's pixel (at least 1e-3).
fn worst_relative_difference(a: &[Vec3], b: &[Vec3]) -> f32 {
    a.iter()
        .zip(b)
        .map(|(a, b)| (*a - *b).abs().max_element() / a.abs().max_element().max(1e-3))
        .fold(0.0f32, f32::max)
}

const PROBE_COLOR: Vec3 = Vec3::new(0.25, 0.5, 0.875);

fn dist_of(code: u32) -> MicrofacetDistribution {
    if code == DIST_BECKMANN {
        MicrofacetDistribution::Beckmann
    } else {
        MicrofacetDistribution::Ggx
    }
}

/// The Rust twin of the probe kernel's `Bsdf(kind, PROBE_COLOR, eta, alpha, dist, metallic, …)`.
fn probe_bsdf(c: &ProbeCase) -> Bsdf {
    let col = PROBE_COLOR.extend(0.0);
    let (eta, alpha, dist) = (c.eta, c.alpha, dist_of(c.dist));
    match c.kind {
        // The kernel reads a non-zero `metallic` slot of a Lambert as its uniform-sampling
        // switch (material.wgsl); the cases with one check the uniform branch.
        BSDF_LAMBERT => Bsdf::Lambert(Lambert {
            albedo: col,
            uniform: c.metallic != 0.0,
        }),
        BSDF_MIRROR => Bsdf::Mirror(Mirror { reflectance: col }),
        BSDF_SMOOTH_DIELECTRIC => Bsdf::SmoothDielectric(SmoothDielectric { eta }),
        BSDF_THIN_DIELECTRIC => Bsdf::ThinDielectric(ThinDielectric { eta }),
        BSDF_ROUGH_THIN_DIELECTRIC => {
            Bsdf::RoughThinDielectric(RoughThinDielectric { eta, alpha, dist })
        }
        BSDF_ROUGH_DIELECTRIC => Bsdf::RoughDielectric(RoughDielectric { eta, alpha, dist }),
        BSDF_ROUGH_CONDUCTOR => Bsdf::RoughConductor(RoughConductor {
            reflectance: col,
            alpha,
            dist,
        }),
        BSDF_METAL_ROUGH => Bsdf::MetalRough(MetalRough {
            ior: eta,
            ..MetalRough::new(col, c.metallic, alpha)
        }),
        BSDF_SMOOTH_CONDUCTOR => Bsdf::SmoothConductor(SmoothConductor {
            ior: probe_ior(eta),
            tint: col,
        }),
        BSDF_ROUGH_FRESNEL_CONDUCTOR => Bsdf::RoughFresnelConductor(RoughFresnelConductor {
            ior: probe_ior(eta),
            lobe: RoughConductor {
                reflectance: col,
                alpha,
                dist,
            },
        }),
        BSDF_FILM_SMOOTH | BSDF_FILM_ROUGH => Bsdf::Iridescent(Iridescent {
            film: ThinFilm {
                ior: PROBE_FILM_IOR,
                thickness_nm: 250.0 + 400.0 * c.uc,
            },
            factor: PROBE_FILM_FACTOR,
            base: match c.metallic as u32 {
                FILM_ON_DIELECTRIC => FilmBase::Dielectric { eta },
                FILM_ON_SHEET => FilmBase::Sheet { eta },
                FILM_ON_CONDUCTOR => FilmBase::Conductor {
                    ior: probe_ior(eta),
                    tint: col,
                },
                _ => FilmBase::Reflectance { f0: col },
            },
            alpha: if c.kind == BSDF_FILM_ROUGH {
                alpha
            } else {
                0.0
            },
            dist,
            lambdas: None,
        }),
        k => panic!("unknown kind {k}"),
    }
}

/// The probe films' index and factor (probe.wgsl `PROBE_FILM_*`).
const PROBE_FILM_IOR: f32 = 1.42;
const PROBE_FILM_FACTOR: f32 = 0.85;

/// The probe conductors' complex IOR (probe.wgsl `PROBE_COND_ETA`, `PROBE_COND_K`).
fn probe_ior(eta: f32) -> ComplexIor {
    ComplexIor {
        eta: (eta * Vec3::new(0.15, 0.4, 1.2)).extend(0.0),
        k: Vec3::new(4.0, 2.4, 1.6).extend(0.0),
        metal: Metal::Au,
    }
}

const ALL_KINDS: [u32; 12] = [
    BSDF_LAMBERT,
    BSDF_MIRROR,
    BSDF_SMOOTH_DIELECTRIC,
    BSDF_THIN_DIELECTRIC,
    BSDF_ROUGH_DIELECTRIC,
    BSDF_ROUGH_CONDUCTOR,
    BSDF_METAL_ROUGH,
    BSDF_SMOOTH_CONDUCTOR,
    BSDF_ROUGH_FRESNEL_CONDUCTOR,
    BSDF_FILM_SMOOTH,
    BSDF_FILM_ROUGH,
    BSDF_ROUGH_THIN_DIELECTRIC,
];

/// The probe grid: every BSDF × (wo, wi, u) × η × (α ∈ {0.05, 0.3, 1}, GGX/Beckmann) for
/// the rough kinds × both transport modes for the dielectrics.
fn probe_cases() -> Vec<ProbeCase> {
    let etas = [1.0f32, 1.0001, 1.33, 1.5, 2.4, 4.0, 0.67];
    let mut cases = Vec::new();
    let mut i = 0u32;
    for kind in ALL_KINDS {
        let rough = matches!(
            kind,
            BSDF_ROUGH_DIELECTRIC
                | BSDF_ROUGH_CONDUCTOR
                | BSDF_METAL_ROUGH
                | BSDF_ROUGH_FRESNEL_CONDUCTOR
                | BSDF_FILM_ROUGH
                | BSDF_ROUGH_THIN_DIELECTRIC
        );
        let film = matches!(kind, BSDF_FILM_SMOOTH | BSDF_FILM_ROUGH);
        let alphas: &[f32] = if rough { &[0.05, 0.3, 1.0] } else { &[0.3] };
        let dists: &[u32] = if rough && kind != BSDF_METAL_ROUGH {
            &[DIST_GGX, DIST_BECKMANN]
        } else {
            &[DIST_GGX]
        };
        let modes: &[u32] = if film
            || matches!(
                kind,
                BSDF_SMOOTH_DIELECTRIC | BSDF_ROUGH_DIELECTRIC | BSDF_ROUGH_THIN_DIELECTRIC
            ) {
            &[MODE_RADIANCE, MODE_IMPORTANCE]
        } else {
            &[MODE_RADIANCE]
        };
        for &alpha in alphas {
            for &dist in dists {
                for &mode in modes {
                    for &eta in &etas {
                        for it in 0..24 {
                            // cosθ from −1 to 1 (grazing, TIR side and normal incidence included)
                            let cos_t = -0.999 + 1.998 * (it as f32 + 0.5) / 24.0;
                            for ip in 0..4 {
                                let phi = 0.3 + 1.7 * ip as f32;
                                let sin_t = (1.0 - cos_t * cos_t).sqrt();
                                let wo = Vec3::new(sin_t * phi.cos(), sin_t * phi.sin(), cos_t);
                                for iu in 0..4 {
                                    // wi: fixed upper, fixed lower, near-mirror, near-refraction.
                                    let wi = match (iu + ip) % 4 {
                                        0 => Vec3::new(-0.3, 0.4, 0.866),
                                        1 => Vec3::new(0.2, -0.1, -0.97),
                                        2 => Vec3::new(-wo.x + 0.05, -wo.y, wo.z),
                                        _ => {
                                            let n = if wo.z < 0.0 { -Vec3::Z } else { Vec3::Z };
                                            let e = if wo.z < 0.0 { 1.0 / eta } else { eta };
                                            refract(wo, n, e).unwrap_or(-wo) + Vec3::X * 0.03
                                        }
                                    }
                                    .normalize();
                                    let uc = (iu as f32 + 0.37) / 4.0;
                                    let u2 = [
                                        (iu as f32 * 0.29 + 0.11 + it as f32 * 0.013) % 1.0,
                                        (iu as f32 * 0.61 + 0.05 + ip as f32 * 0.17) % 1.0,
                                    ];
                                    cases.push(ProbeCase {
                                        wo: wo.to_array(),
                                        uc,
                                        wi: wi.to_array(),
                                        eta,
                                        u2,
                                        kind,
                                        pixel: i.wrapping_mul(2_654_435_761),
                                        sample: i % 97,
                                        seed: i / 7,
                                        alpha,
                                        dist,
                                        metallic: film_base_or_metallic(kind, it),
                                        mode,
                                        _pad0: 0,
                                        _pad1: 0,
                                    });
                                    i += 1;
                                }
                            }
                        }
                    }
                }
            }
        }
    }
    cases
}

/// A rough dielectric, bare or under a film.
fn rough_dielectric_kind(c: &ProbeCase) -> bool {
    c.kind == BSDF_ROUGH_DIELECTRIC
        || (c.kind == BSDF_FILM_ROUGH && c.metallic as u32 == FILM_ON_DIELECTRIC)
}

/// The probe's `metallic` slot: metal-rough's metallic (and Lambert's uniform switch), or a
/// film's base (`FILM_ON_*`; a rough film lies on a dielectric or a metal: a sheet has no
/// roughness).
fn film_base_or_metallic(kind: u32, it: u32) -> f32 {
    match kind {
        BSDF_FILM_SMOOTH => (it % 4) as f32,
        BSDF_FILM_ROUGH => {
            [FILM_ON_DIELECTRIC, FILM_ON_CONDUCTOR, FILM_ON_REFLECTANCE][(it % 3) as usize] as f32
        }
        _ => [0.0, 0.3, 1.0][(it % 3) as usize],
    }
}

/// Largest relative error on the erf/erfinv-based (Beckmann) paths, per quantity: the Rust and
/// WGSL `erfc`/`erfinv` are the same formulas, but `exp`/`log` of the adapter are not
/// correctly rounded (WGSL allows 3 + 2|x| ULP for exp, 3 ULP for log), and the Newton–
/// bisection solve of the Beckmann sampler stops at |ΔC| ≤ 1e-6·Z, so the sampled slope can
/// differ by up to that tolerance divided by the slope density.
const BECKMANN_REL: f32 = 2e-4;

/// |a − b| ≤ tol (false for NaN).
fn within(a: f32, b: f32, tol: f32) -> bool {
    (a - b).abs() <= tol
}

/// Worst errors and the first mismatches of the probe comparison.
#[derive(Default)]
struct Track {
    worst: f32,
    worst_b: f32,
    /// Largest absolute error of a polarising matrix entry (`check_mueller`).
    worst_m: f32,
    failures: Vec<String>,
    n_fail: usize,
}

impl Track {
    fn val(&mut self, a: f32, b: f32, what: &str, c: &ProbeCase, tol: f32) {
        let e = (a - b).abs() / a.abs().max(b.abs()).max(1e-3);
        let e = if a == b || (a.is_nan() && b.is_nan()) {
            0.0
        } else {
            e
        };
        if c.dist == DIST_BECKMANN {
            self.worst_b = self.worst_b.max(e);
        } else {
            self.worst = self.worst.max(e);
        }
        if !within(e, 0.0, tol) {
            self.fail(format!(
                "{what}: GPU {a} vs CPU {b} (rel {e:.2e}) for {c:?}"
            ));
        }
    }
    fn fail(&mut self, msg: String) {
        self.n_fail += 1;
        if self.failures.len() < 20 || std::env::var_os("PROBE_ALL").is_some() {
            self.failures.push(msg);
        }
    }
}

/// The polarising event of `b` for the case's (wo, wi) (bsdf/polarized.wgsl) against
/// `bsdf::polarized::event_mueller`: the entries a = m₁₁, b = m₀₁, c = m₂₂, s = m₂₃ of the
/// normalised matrix per lane, and `bsdf_mueller_b` against m₀₁ where next-event estimation
/// reaches the kind (0 for the delta kinds). Absolute 1e-4: entries lie in [−1, 1], and the
/// WGSL computes dielectrics in real arithmetic where the Rust uses complex amplitudes, which
/// round differently where the amplitudes cancel (Brewster's angle, the critical angle); measured
/// worst 9.1e-6 (lavapipe).
/// Films: the GPU refuses them (their matrix is their base's on the CPU).
fn check_mueller(t: &mut Track, c: &ProbeCase, o: &ProbeOut, b: &Bsdf) {
    if matches!(c.kind, BSDF_FILM_SMOOTH | BSDF_FILM_ROUGH) {
        return;
    }
    let (wo, wi) = (Vec3::from_array(c.wo), Vec3::from_array(c.wi));
    let event = if wo.z * wi.z >= 0.0 {
        Event::Reflect
    } else {
        Event::Transmit
    };
    let m = refract::bsdf::polarized::event_mueller(b, wo, wi, event, Lobe::G);
    let lanes = if c.kind == BSDF_SMOOTH_CONDUCTOR || c.kind == BSDF_ROUGH_FRESNEL_CONDUCTOR {
        3 // RGB: the conductors' fourth lane holds no IOR
    } else {
        4
    };
    for (l, ml) in m.iter().enumerate().take(lanes) {
        let want = [ml.col(1).y, ml.col(1).x, ml.col(2).z, ml.col(3).z];
        for (k, (what, w)) in ["a", "b", "c", "s"].iter().zip(want).enumerate() {
            let got = o.mueller[4 * k + l];
            t.worst_m = t.worst_m.max((got - w).abs());
            if !within(got, w, 1e-4) {
                t.fail(format!(
                    "mueller {what}[{l}]: GPU {got} vs CPU {w} for {c:?}"
                ));
            }
        }
        // The kinds whose row in the BSDF table gives `bsdf_mueller_b` an arm.
        let nee = refract::bsdf::family::GPU_KIND_CONSTANTS
            .iter()
            .find(|&&(_, v)| v == c.kind)
            .and_then(|&(name, _)| {
                refract::bsdf::family::GPU_KINDS
                    .iter()
                    .find(|k| k.name == name)
            })
            .is_some_and(|k| k.mueller_b.is_some());
        let w = if nee { ml.col(1).x } else { 0.0 };
        let w = if c.kind == BSDF_ROUGH_DIELECTRIC && c.eta == 1.0 {
            0.0
        } else {
            w
        };
        if !within(o.mueller_b[l], w, 1e-4) {
            t.fail(format!(
                "mueller_b[{l}]: GPU {} vs CPU {w} for {c:?}",
                o.mueller_b[l]
            ));
        }
    }
}

/// fresnel, refract, the microfacet pieces, erf/erfinv, the spectral helpers and every BSDF's
/// eval/pdf/eval_lobes/sample through WGSL and Rust on the [`probe_cases`] grid, plus the RNG
/// bit for bit.
#[test]
fn kernel_and_rng_parity() {
    let Some(ctx) = context("kernel_and_rng_parity") else {
        return;
    };
    let cases = probe_cases();
    let t0 = std::time::Instant::now();
    let outs = run_probe(&ctx, &cases).unwrap();
    let gpu_time = t0.elapsed();
    let rel = 1e-5;
    let (mut rng_bad, mut flag_flips, mut sampled) = (0usize, 0usize, 0usize);
    let mut t = Track::default();
    for (c, o) in cases.iter().zip(&outs) {
        let wo = Vec3::from_array(c.wo);
        let wi = Vec3::from_array(c.wi);
        let u2 = Vec2::from_array(c.u2);
        let beck = c.dist == DIST_BECKMANN;
        let tol = if beck { BECKMANN_REL } else { rel };
        let mode = if c.mode == MODE_IMPORTANCE {
            TransportMode::Importance
        } else {
            TransportMode::Radiance
        };
        // RNG: bit for bit.
        let mut s = Sampler::new(c.pixel, c.sample, c.seed);
        let want = [
            pcg_hash(c.pixel),
            s.next_1d().to_bits(),
            s.next_1d().to_bits(),
            s.next_1d().to_bits(),
            s.next_1d().to_bits(),
        ];
        if want != o.rng {
            rng_bad += 1;
        }
        // Fresnel and refraction.
        let fr = fresnel_dielectric_terms(wo.z, c.eta);
        for (k, v) in [fr.r_par, fr.r_perp, fr.f, fr.cos_t]
            .into_iter()
            .enumerate()
        {
            t.val(o.fresnel[k], v, "fresnel", c, rel);
        }
        t.val(o.eta_rel, fr.eta_rel, "eta_rel", c, rel);
        let n = if wo.z < 0.0 { -Vec3::Z } else { Vec3::Z };
        let r = refract(wo, n, fr.eta_rel);
        assert_eq!(
            o.refract_ok == 1.0,
            r.is_some(),
            "refract TIR decision {c:?}"
        );
        if let Some(wt) = r {
            for k in 0..3 {
                t.val(o.refracted[k], wt[k], "refract", c, rel);
            }
        }
        // Microfacet pieces, erf/erfinv, spectral helpers.
        let mf = Microfacet::new(dist_of(c.dist), c.alpha);
        let wo_up = Vec3::new(wo.x, wo.y, wo.z.abs());
        let wi_up = Vec3::new(wi.x, wi.y, wi.z.abs());
        let m = (wo_up + wi_up).normalize_or_zero();
        let mfv = [
            mf.d(m),
            mf.lambda(wo),
            mf.g2(wo, wi),
            mf.pdf_visible(wo_up, m),
        ];
        for (&a, &v) in o.mf.iter().zip(&mfv) {
            // Λ = +∞ is LAMBDA_INF (f32::MAX) in WGSL.
            let v = if v.is_infinite() { f32::MAX } else { v };
            t.val(a, v, "microfacet D/Λ/G2/pdf_visible", c, tol);
        }
        t.val(o.mf_g1, mf.g1(wo_up), "G1", c, tol);
        if wo_up.z > 0.0 {
            let mm = mf.sample_visible(wo_up, u2);
            for k in 0..3 {
                let (a, b) = (o.mf_m[k], mm[k]);
                let tv = if beck { BECKMANN_REL } else { 2e-5 };
                if !within(a, b, tv) {
                    t.fail(format!("sample_visible: GPU {a} vs CPU {b} {c:?}"));
                }
            }
        }
        let sp = [
            erfc(3.0 * wo.x),
            erf(3.0 * wo.y),
            erfinv(2.0 * c.uc - 1.0),
            erfinv(0.9999 * (2.0 * u2.x - 1.0)),
        ];
        for (k, (&a, &b)) in o.special.iter().zip(&sp).enumerate() {
            // erf/erfinv: absolute 2e-6 (a few ULP of exp/log on values of order 1).
            t.worst_b = t.worst_b.max((a - b).abs());
            if !within(a, b, 2e-6 * b.abs().max(1.0)) {
                t.fail(format!("erf/erfinv[{k}]: GPU {a} vs CPU {b} {c:?}"));
            }
        }
        let lambdas = sample_hero_wavelengths(c.uc);
        for (&a, &b) in o.lambdas.iter().zip(&lambdas) {
            t.val(a, b, "hero wavelengths", c, rel);
        }
        let up = rgb_to_spectrum4(PROBE_COLOR, lambdas);
        for k in 0..4 {
            t.val(o.uplift[k], up[k], "rgb_to_spectrum4", c, rel);
        }
        let rgb = spectrum_sample_to_rgb(lambdas, glam::Vec4::new(1.0, u2.x, u2.y, c.uc));
        for k in 0..3 {
            // A sum of terms of order 1 with cancellation: compared in absolute terms.
            let (a, b) = (o.to_rgb[k], rgb[k]);
            if !within(a, b, 1e-5) {
                t.fail(format!("spectrum_sample_to_rgb: GPU {a} vs CPU {b} {c:?}"));
            }
        }
        t.val(
            o.to_rgb[3],
            cauchy_from_abbe(c.eta, 40.0, lambdas[0]),
            "cauchy_from_abbe",
            c,
            rel,
        );
        // BSDF eval / pdf / eval_lobes / sample.
        let b = probe_bsdf(c);
        let f = b.eval(wo, wi, mode);
        // A film's reflectance is a Fourier sum of cos, exp and atan2 terms (WGSL allows a few
        // ULP for each, like the erf-based Beckmann paths) whose terms cancel where the film
        // reflects little: film values agree to 2e-4 (measured worst 3.0e-5, lavapipe).
        let film = matches!(c.kind, BSDF_FILM_SMOOTH | BSDF_FILM_ROUGH);
        let tol = if film { tol.max(2e-4) } else { tol };
        for k in 0..4 {
            t.val(o.eval[k], f[k], "eval", c, tol);
        }
        t.val(o.pdf, b.pdf(wo, wi), "pdf", c, tol);
        check_mueller(&mut t, c, o, &b);
        let lv = b.eval_lobes(wo, wi, mode);
        for k in 0..4 {
            t.val(o.lobes_d[k], lv.d[k], "eval_lobes d", c, tol);
            t.val(o.lobes_g[k], lv.g[k], "eval_lobes g", c, tol);
        }
        let s = b.sample(wo, c.uc, u2, mode);
        let valid = o.sample_flags & 1 == 1;
        let Some(s) = s else {
            if valid {
                // A rejection exactly at a boundary (e.g. wi.z ≈ 0) may differ by rounding.
                flag_flips += 1;
            }
            continue;
        };
        sampled += 1;
        let flags = 1
            | (s.is_delta as u32) << 1
            | ((s.event == Event::Transmit) as u32) << 2
            | (match s.lobe {
                Lobe::D => 0,
                Lobe::G => 1,
                Lobe::S => 2,
            }) << 3;
        if flags != o.sample_flags {
            // A reflect/refract (or class-label) choice exactly at uc ≈ F may flip by one
            // rounding step, a grazing sample may be rejected on one side only.
            flag_flips += 1;
            continue;
        }
        // Directions through cos/sin (Lambert, GGX sampler): 2e-5 absolute; values derived
        // from them inherit the error amplified by the BSDF's slope: 2e-4 relative for the
        // sample values of the rough kinds (measured worst on lavapipe: 8.8e-5).
        let rough = matches!(
            c.kind,
            BSDF_ROUGH_DIELECTRIC
                | BSDF_ROUGH_CONDUCTOR
                | BSDF_METAL_ROUGH
                | BSDF_ROUGH_FRESNEL_CONDUCTOR
                | BSDF_FILM_ROUGH
        );
        let dir_tol = if beck { BECKMANN_REL } else { 2e-5 };
        let val_tol = if beck || rough || film { 2e-4 } else { rel };
        t.val(o.sample_eta_rel, s.eta_rel, "sample eta_rel", c, rel);
        for k in 0..3 {
            let (a, bb) = (o.sample_wi[k], s.wi[k]);
            if !within(a, bb, dir_tol) {
                t.fail(format!("sample wi: GPU {a} vs CPU {bb} {c:?}"));
            }
        }
        // Rough refraction at η ≈ 1 is ill-conditioned (the half vector wo + η wi nearly
        // cancels: condition number ~1/|η − 1| = 10⁴ at η = 1.0001), so a last-bit difference
        // in the sampled direction changes f and pdf at the 1e-3..1e-2 level. There the GPU's
        // sample value is checked against the CPU's eval/pdf at the GPU's own direction.
        // Likewise the rough sheet below index 1: its R' has an infinite slope at the critical
        // angle, so a last-bit difference in the sampled facet changes f and pdf at 1e-5.
        let ill_conditioned = (rough_dielectric_kind(c)
            && s.event == Event::Transmit
            && !s.is_delta
            && (c.eta - 1.0).abs() < 1e-2)
            || (c.kind == BSDF_ROUGH_THIN_DIELECTRIC && c.eta < 1.0);
        let (want_f, want_pdf, want_w) = if ill_conditioned {
            let gwi = Vec3::from_array(o.sample_wi);
            let f = b.eval(wo, gwi, mode);
            let pdf = b.pdf(wo, gwi);
            (f, pdf, f * (gwi.z.abs() / pdf))
        } else {
            (s.f, s.pdf, s.weight)
        };
        t.val(o.sample_pdf, want_pdf, "sample pdf", c, val_tol);
        for k in 0..4 {
            t.val(o.sample_weight[k], want_w[k], "sample weight", c, val_tol);
            t.val(o.sample_f[k], want_f[k], "sample f", c, val_tol);
        }
    }
    eprintln!(
        "kernel parity: {} cases ({sampled} sampled) in {:.2}s on the GPU, worst relative error {:.2e} (GGX/smooth), {:.2e} (Beckmann, erf/erfinv abs), Mueller entries {:.2e} abs, {flag_flips} lobe-choice flips, {rng_bad} RNG mismatches, {} mismatches",
        cases.len(),
        gpu_time.as_secs_f64(),
        t.worst,
        t.worst_b,
        t.worst_m,
        t.n_fail
    );
    assert!(
        t.failures.is_empty(),
        "{} mismatches, the first:\n{}",
        t.n_fail,
        t.failures.join("\n")
    );
    assert_eq!(rng_bad, 0, "RNG streams differ");
    assert!(flag_flips <= cases.len() / 1000, "{flag_flips} flips");
}

fn small(scene: &mut Scene, w: u32, h: u32) {
    scene.settings.width = w;
    scene.settings.height = h;
}

fn cpu_image(scene: &Scene, seed: u32, first: u32, spp: u32) -> (Vec<Vec3>, u64) {
    cpu_image_filtered(scene, seed, first, spp, None)
}

fn cpu_image_filtered(
    scene: &Scene,
    seed: u32,
    first: u32,
    spp: u32,
    filter: Option<&PathFilter>,
) -> (Vec<Vec3>, u64) {
    let r = Renderer::new(scene.clone()).unwrap();
    let mut opts = RenderOptions::from_scene(&r.scene);
    opts.seed = seed;
    opts.set_filter(filter);
    let mut film = Film::new(opts.width, opts.height);
    r.render_pass(&opts, &mut film, first, spp);
    (film.image(), film.dropped)
}

/// Same seed on both devices: the GPU's paths are the CPU's paths. Whole 1-spp images agree
/// pixel by pixel except where rounding differences flip a discrete decision; a handful of
/// recorded paths agree vertex by vertex.
#[test]
fn path_parity_same_seed() {
    let Some(ctx) = context("path_parity_same_seed") else {
        return;
    };
    let mut scene = Scene::load("builtin:cornell-glass").unwrap();
    small(&mut scene, 64, 64);
    let seed = 7;
    let mut opts = RenderOptions::from_scene(&scene);
    opts.seed = seed;
    opts.batch_spp = Some(1);
    let mut g = GpuRenderer::with_context(ctx, scene.clone(), opts).unwrap();
    let gi = g.render(1).unwrap();
    let (ci, _) = cpu_image(&scene, seed, 0, 1);
    let same = gi
        .mean
        .iter()
        .zip(&ci)
        .filter(|(a, b)| (**a - **b).abs().max_element() <= 1e-3 * b.max_element().max(1.0))
        .count();
    let frac = same as f64 / ci.len() as f64;
    eprintln!(
        "path parity: {same}/{} pixels equal within 1e-3 ({:.2}%)",
        ci.len(),
        frac * 100.0
    );
    assert!(
        frac >= 0.97,
        "only {:.2}% of 1-spp pixels agree",
        frac * 100.0
    );

    // Vertex-level check on a few pixels.
    let cpu = Renderer::new(scene.clone()).unwrap();
    let copts = {
        let mut o = RenderOptions::from_scene(&cpu.scene);
        o.seed = seed;
        o
    };
    let integ = cpu.integrator(&copts);
    let cam = &scene.camera;
    let (w, h) = (64u32, 64u32);
    let mut agree = 0;
    let pixels = [2080u32, 1000, 3000, 2100, 1500, 2600];
    for &pixel in &pixels {
        g.reset();
        g.clear_debug();
        g.set_debug_pixel(Some(pixel));
        g.render(1).unwrap();
        let dp = g.debug_path().unwrap();
        let (x, y) = (pixel % w, pixel / w);
        let mut s = Sampler::new(pixel, 0, seed);
        let j = s.next_2d();
        let dir = cam.ray_dir(
            (x as f32 + j.x) / w as f32,
            (y as f32 + j.y) / h as f32,
            1.0,
        );
        assert!(
            (dp.camera_dir - dir).abs().max_element() < 1e-6,
            "camera ray differs at {pixel}"
        );
        let first = cpu
            .bvh
            .intersect(cam.position, dir, f32::INFINITY)
            .map(|hh| integ.surface(&hh));
        if let Some(sh) = first {
            let gp = dp.hits[0].truncate();
            assert!(
                (gp - sh.p).abs().max_element() < 1e-5,
                "first hit {gp} vs {}",
                sh.p
            );
            assert!((dp.hits[0].w - sh.t).abs() < 1e-5);
        }
        let v = integ.li(cam.position, dir, &mut s);
        eprintln!(
            "pixel {pixel}: {} vertices, GPU L = {} (dims {}), CPU L = {} (dims {})",
            dp.hits.len(),
            dp.value,
            dp.dims,
            v,
            s.dim()
        );
        if dp.dims == s.dim()
            && (dp.value - v).abs().max_element() <= 1e-4 * v.max_element().max(1.0)
        {
            agree += 1;
        }
    }
    assert!(
        agree + 1 >= pixels.len(),
        "only {agree}/{} recorded paths agree",
        pixels.len()
    );
}

/// Per 8×8 block Z-test of GPU vs CPU means with different seeds; each side renders `k`
/// independent batches so the block variance is estimated from the batches.
fn image_parity(name: &str, scene: Scene, k: u32, spp: u32) {
    image_parity_filtered(name, scene, k, spp, None)
}

fn image_parity_filtered(name: &str, scene: Scene, k: u32, spp: u32, filter: Option<&str>) {
    let Some(ctx) = context(name) else {
        return;
    };
    let filter = filter.map(|f| PathFilter::parse(f).unwrap());
    let (w, h) = (scene.settings.width, scene.settings.height);
    let mut opts = RenderOptions::from_scene(&scene);
    let mut g = GpuRenderer::with_context(ctx, scene.clone(), opts).unwrap();
    g.set_filter(filter.as_ref());
    let (mut gs, mut cs) = (Vec::new(), Vec::new());
    // Spectral scenes: a single hero-wavelength estimate can have a negative RGB component
    // (out of the sRGB gamut); both films keep those and drop only non-finite samples, so the
    // drop counts are compared (both 0 in practice).
    let spectral = scene.features().contains(Features::DISPERSION);
    let (mut gd, mut cd) = (0u64, 0u64);
    let t0 = std::time::Instant::now();
    for i in 0..k {
        opts.seed = 1000 + i;
        g.set_options(opts).unwrap();
        let img = g.render(spp).unwrap();
        if !spectral {
            assert_eq!(img.dropped, 0);
        }
        gd += img.dropped;
        gs.push(block_means(&img.mean, w, h));
    }
    let tg = t0.elapsed();
    let t0 = std::time::Instant::now();
    for i in 0..k {
        let (img, dropped) = cpu_image_filtered(&scene, i, 0, spp, filter.as_ref());
        if !spectral {
            assert_eq!(dropped, 0);
        }
        cd += dropped;
        cs.push(block_means(&img, w, h));
    }
    let tc = t0.elapsed();
    if spectral {
        let n = (k * spp) as f64 * (w * h) as f64;
        let (pg, pc) = (gd as f64 / n, cd as f64 / n);
        let sd = ((pg * (1.0 - pg) + pc * (1.0 - pc)) / n).sqrt().max(1e-12);
        eprintln!(
            "{name}: dropped (negative RGB) GPU {gd} CPU {cd} of {n} samples, z = {:.2}",
            (pg - pc) / sd
        );
        assert!(((pg - pc) / sd).abs() <= 4.0, "drop rates differ");
    }
    let t = block_z_test(&gs, &cs);
    let (pass, nb, zt, rate) = (t.pass, t.blocks, t.z_image, t.rate());
    eprintln!(
        "{name}: {pass}/{nb} blocks within 3σ ({:.1}%), whole-image z = {zt:.2}; GPU {:.2}s CPU {:.2}s for {k}×{spp} spp",
        rate * 100.0,
        tg.as_secs_f64(),
        tc.as_secs_f64()
    );
    // With k − 1 = 7 degrees of freedom per side a block exceeds |t| = 3 about 2% of the time.
    assert!(
        rate >= 0.9,
        "{name}: only {:.1}% of blocks within 3σ",
        rate * 100.0
    );
    assert!(zt.abs() <= 4.0, "{name}: image means differ by {zt:.2}σ");
}

#[test]
fn image_parity_cornell_glass() {
    let mut s = Scene::load("builtin:cornell-glass").unwrap();
    small(&mut s, 64, 64);
    image_parity("image_parity_cornell_glass", s, 8, 8);
}

#[test]
fn image_parity_rough_glass() {
    let mut s = Scene::load("builtin:rough-glass").unwrap();
    small(&mut s, 64, 48);
    image_parity("image_parity_rough_glass", s, 8, 8);
}

#[test]
fn image_parity_metals() {
    let mut s = Scene::load("builtin:metals").unwrap();
    small(&mut s, 64, 40);
    image_parity("image_parity_metals", s, 8, 8);
}

/// Thin films (bubble and slick with thickness textures, anodised metal smooth and rough,
/// coated gold) under the sun-and-sky HDRI: the GPU's films are the CPU's (RGB).
#[test]
fn image_parity_thin_film() {
    let mut s = Scene::load("builtin:thin-film").unwrap();
    small(&mut s, 64, 36);
    image_parity("image_parity_thin_film", s, 8, 8);
}

/// Frosted thin-walled panes (`bsdf::RoughThinDielectric`) of rising roughness against the
/// studio HDRI and a checkered wall: the GPU's rough sheet is the CPU's.
#[test]
fn image_parity_frosted_panes() {
    let mut s = Scene::load("builtin:frosted-panes").unwrap();
    small(&mut s, 64, 20);
    image_parity("image_parity_frosted_panes", s, 8, 8);
}

#[test]
fn image_parity_materials() {
    let mut s = Scene::load("builtin:materials").unwrap();
    small(&mut s, 64, 40);
    image_parity("image_parity_materials", s, 8, 8);
}

/// A checker (nearest, repeat) and a smooth ramp (bilinear, mirrored repeat, transformed)
/// base-colour texture, and a metallic-roughness texture on a metal-rough quad.
fn textured_scene() -> Scene {
    let mut m = Mesh::default();
    quad(
        &mut m,
        Vec3::new(-2.0, 0.0, -2.0),
        Vec3::Z * 4.0,
        Vec3::X * 2.0,
        0,
    );
    quad(
        &mut m,
        Vec3::new(0.0, 0.0, -2.0),
        Vec3::Z * 4.0,
        Vec3::X * 2.0,
        1,
    );
    quad(
        &mut m,
        Vec3::new(-2.0, 0.0, -2.0),
        Vec3::X * 4.0,
        Vec3::Y * 2.0,
        2,
    );
    quad(&mut m, Vec3::new(-0.5, 3.0, -0.5), Vec3::X, Vec3::Z, 3);
    for q in 0..3 {
        let b = 4 * q;
        for (k, uv) in [[0.0, 0.0], [3.0, 0.0], [3.0, 3.0], [0.0, 3.0]]
            .into_iter()
            .enumerate()
        {
            m.uvs[b + k] = Vec2::from_array(uv) - Vec2::splat(0.3);
        }
    }
    let checker = Texture {
        width: 4,
        height: 4,
        texels: (0..16)
            .map(|i| {
                if (i % 4 + i / 4) % 2 == 0 {
                    glam::Vec4::new(0.9, 0.2, 0.1, 1.0)
                } else {
                    glam::Vec4::new(0.1, 0.7, 0.9, 1.0)
                }
            })
            .collect(),
        wrap_s: Wrap::Repeat,
        wrap_t: Wrap::Repeat,
        linear: false,
    };
    let ramp = Texture {
        width: 3,
        height: 2,
        texels: (0..6)
            .map(|i| glam::Vec4::new(i as f32 / 5.0, 1.0 - i as f32 / 5.0, 0.5, 1.0))
            .collect(),
        wrap_s: Wrap::MirroredRepeat,
        wrap_t: Wrap::ClampToEdge,
        linear: true,
    };
    let mr = Texture {
        width: 2,
        height: 2,
        texels: vec![
            glam::Vec4::new(0.0, 0.1, 1.0, 1.0),
            glam::Vec4::new(0.0, 0.9, 0.0, 1.0),
            glam::Vec4::new(0.0, 0.5, 0.5, 1.0),
            glam::Vec4::new(0.0, 0.3, 1.0, 1.0),
        ],
        wrap_s: Wrap::Repeat,
        wrap_t: Wrap::Repeat,
        linear: true,
    };
    let tref = |texture: u32, transform: glam::Affine2| TextureRef {
        texture,
        tex_coord: 0,
        transform,
    };
    let mut diffuse = Material::diffuse("checker", Vec3::ONE);
    diffuse.base_color_texture = Some(tref(0, glam::Affine2::IDENTITY));
    let mut plastic = Material::diffuse("metal-rough", Vec3::new(0.9, 0.8, 0.7));
    plastic.kind = refract::scene::MaterialKind::MetalRough;
    plastic.metallic = 1.0;
    plastic.roughness = 0.8;
    plastic.base_color_texture = Some(tref(0, glam::Affine2::from_scale(Vec2::splat(2.0))));
    plastic.metallic_roughness_texture = Some(tref(2, glam::Affine2::IDENTITY));
    let mut wall = Material::diffuse("ramp", Vec3::ONE);
    wall.base_color_texture = Some(tref(
        1,
        glam::Affine2::from_scale_angle_translation(Vec2::new(1.5, 0.7), 0.3, Vec2::new(0.1, -0.2)),
    ));
    let mats = vec![
        diffuse,
        plastic,
        wall,
        Material::emitter("light", Vec3::splat(8.0)),
    ];
    let cam = Camera::look_at(
        Vec3::new(0.0, 2.0, 4.0),
        Vec3::new(0.0, 0.5, 0.0),
        Vec3::Y,
        0.9,
    );
    let mut s = scene("textured", m, mats, cam, 0.2);
    s.textures = vec![checker, ramp, mr];
    s
}

#[test]
fn image_parity_textures() {
    let mut s = textured_scene();
    small(&mut s, 48, 32);
    assert!(s.features().contains(Features::TEXTURES));
    image_parity("image_parity_textures", s, 8, 8);
}

/// Heckbert filters on the GPU against the CPU (within noise), on the caustic-rich Cornell box.
#[test]
fn image_parity_filter_caustics() {
    let mut s = Scene::load("builtin:cornell-glass").unwrap();
    small(&mut s, 48, 48);
    image_parity_filtered("image_parity_filter LS+DE", s.clone(), 8, 8, Some("LS+DE"));
    image_parity_filtered("image_parity_filter LDE", s, 8, 8, Some("LDE"));
}

/// The Heckbert classes LE, L(D|G|S)*DE and L(D|G|S)*(G|S)E partition every path: with the
/// same seed their GPU images sum to the unfiltered image, pixel by pixel (up to rounding),
/// on a scene with every class (diffuse, glossy metal, metal-rough, smooth glass).
#[test]
fn filter_class_sum_identity() {
    let Some(ctx) = context("filter_class_sum_identity") else {
        return;
    };
    let mut s = Scene::load("builtin:materials").unwrap();
    small(&mut s, 48, 32);
    let mut opts = RenderOptions::from_scene(&s);
    opts.seed = 3;
    let mut g = GpuRenderer::with_context(ctx, s, opts).unwrap();
    let full = g.render(4).unwrap().mean;
    let compiled = g.pipelines_compiled();
    let mut sum = vec![Vec3::ZERO; full.len()];
    for f in ["LE", "L(D|G|S)*DE", "L(D|G|S)*(G|S)E"] {
        g.set_filter(Some(&PathFilter::parse(f).unwrap()));
        let img = g.render(4).unwrap();
        assert_eq!(img.dropped, 0);
        for (a, b) in sum.iter_mut().zip(&img.mean) {
            *a += *b;
        }
    }
    // The filtered specialisation's kernels once; changing the table does not recompile.
    let kernels = refract::gpu::kernels::kernels_of(&g.specialization()).len() as u32;
    assert_eq!(g.pipelines_compiled(), compiled + kernels);
    let (mut worst, mut bad) = (0.0f32, 0);
    for (a, b) in sum.iter().zip(&full) {
        let e = (*a - *b).abs().max_element() / b.max_element().max(1e-2);
        worst = worst.max(e);
        if e > 1e-4 {
            bad += 1;
        }
    }
    let total: f64 = full.iter().map(|p| p.element_sum() as f64).sum();
    let total_sum: f64 = sum.iter().map(|p| p.element_sum() as f64).sum();
    eprintln!(
        "class sum: {bad}/{} pixels off by > 1e-4, worst {worst:.2e}; image sums {total_sum:.6} vs {total:.6}",
        full.len()
    );
    assert!(bad <= full.len() / 200, "{bad} pixels differ");
    assert!((total_sum - total).abs() <= 1e-4 * total);
}

/// Hero-wavelength dispersion on the GPU against the CPU (within noise).
#[test]
fn image_parity_prism() {
    let mut s = Scene::load("builtin:prism").unwrap();
    small(&mut s, 48, 32);
    assert!(s.features().contains(Features::DISPERSION));
    image_parity("image_parity_prism", s, 8, 8);
}

#[test]
fn image_parity_furnace() {
    let mut s = Scene::load("builtin:furnace").unwrap();
    small(&mut s, 64, 32);
    image_parity("image_parity_furnace", s, 8, 8);
}

/// Flat-shaded closed objects (diffuse albedo 1, mirror 1, smooth glass) in a uniform white
/// environment render exactly 1 (mean over pixels within 3σ, pixels independent).
#[test]
fn gpu_white_furnace() {
    let Some(ctx) = context("gpu_white_furnace") else {
        return;
    };
    let mut m = Mesh::default();
    sphere(&mut m, Vec3::new(-1.1, 0.0, 0.0), 0.5, 24, 48, 0);
    sphere(&mut m, Vec3::new(0.0, 0.0, 0.0), 0.5, 24, 48, 1);
    sphere(&mut m, Vec3::new(1.1, 0.0, 0.0), 0.5, 24, 48, 2);
    let m = flatten(&m);
    let mats = vec![
        Material::diffuse("white", Vec3::ONE),
        Material::mirror("mirror", Vec3::ONE),
        Material::glass("glass", 1.5),
    ];
    let cam = Camera::look_at(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, Vec3::Y, 0.5);
    let mut s = scene("furnace-flat", m, mats, cam, 1.0);
    small(&mut s, 64, 24);
    s.settings.max_depth = 1000;
    let opts = RenderOptions::from_scene(&s);
    let mut g = GpuRenderer::with_context(ctx, s, opts).unwrap();
    let img = g.render(64).unwrap();
    assert_eq!(img.dropped, 0);
    let n = img.mean.len() as f64;
    for ch in 0..3 {
        let m = img.mean.iter().map(|p| p[ch] as f64).sum::<f64>() / n;
        let var = img
            .mean
            .iter()
            .map(|p| (p[ch] as f64 - m).powi(2))
            .sum::<f64>()
            / (n - 1.0);
        let sem = (var / n).sqrt();
        eprintln!("gpu furnace channel {ch}: {m:.5} ± {sem:.5}");
        assert!(
            (m - 1.0).abs() <= 3.0 * sem + 1e-5,
            "channel {ch} = {m} ± {sem}"
        );
    }
}

/// After a parameter edit no sample from before reaches the image, the spp restarts, and no
/// pipeline is recompiled.
#[test]
fn reset_after_parameter_change() {
    let Some(ctx) = context("reset_after_parameter_change") else {
        return;
    };
    let mut m = Mesh::default();
    quad(
        &mut m,
        Vec3::new(-5.0, -5.0, 0.0),
        Vec3::X * 10.0,
        Vec3::Y * 10.0,
        0,
    );
    let cam = Camera::look_at(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, Vec3::Y, 0.8);
    let mut s = scene(
        "emitter",
        m,
        vec![Material::emitter("e", Vec3::new(1.0, 0.0, 0.0))],
        cam,
        0.0,
    );
    small(&mut s, 16, 16);
    let opts = RenderOptions::from_scene(&s);
    let mut g = GpuRenderer::with_context(ctx, s, opts).unwrap();
    let a = g.render(8).unwrap();
    assert!(
        a.mean.iter().all(|p| *p == Vec3::new(1.0, 0.0, 0.0)),
        "{:?}",
        a.mean[0]
    );
    let compiled = g.pipelines_compiled();
    g.set_material(0, Material::emitter("e", Vec3::new(0.0, 0.0, 2.0)))
        .unwrap();
    let b = g.render(1).unwrap();
    assert_eq!(b.spp, 1);
    assert!(
        b.mean.iter().all(|p| *p == Vec3::new(0.0, 0.0, 2.0)),
        "{:?}",
        b.mean[0]
    );
    // IOR / colour edits on a glass scene: no recompilation either.
    assert_eq!(g.pipelines_compiled(), compiled);
    let mut cg = Scene::load("builtin:cornell-glass").unwrap();
    small(&mut cg, 16, 16);
    let o = RenderOptions::from_scene(&cg);
    g.set_scene(cg.clone(), o).unwrap();
    let c1 = g.pipelines_compiled();
    let mut glass = cg.materials[4].clone();
    glass.ior = 1.9;
    g.set_material(4, glass).unwrap();
    let mut white = cg.materials[0].clone();
    white.base_color = Vec3::new(0.2, 0.9, 0.3);
    g.set_material(0, white).unwrap();
    g.set_environment(Vec3::splat(0.3)).unwrap();
    g.render(2).unwrap();
    assert_eq!(
        g.pipelines_compiled(),
        c1,
        "a slider edit recompiled the pipeline"
    );
    eprintln!("pipelines compiled: {}", g.pipelines_compiled());
}

/// The GPU renders scaled scenes alike (the ray-offset floor follows the scene, as on the
/// CPU): cornell-glass and glass-slab at 1e-6 and 1e6 m against 1 m, same seed, image means
/// within 0.5%.
#[test]
fn gpu_scene_scale_invariance() {
    let Some(ctx) = gpu_context("gpu_scene_scale_invariance") else {
        return;
    };
    for name in ["cornell-glass", "glass-slab"] {
        let mean = |s: f32| {
            let mut sc = Scene::load(&format!("builtin:{name}")).expect("builtin");
            sc.settings.width = 32;
            sc.settings.height = 32;
            for p in sc.mesh.positions.iter_mut() {
                *p *= s;
            }
            sc.camera.position *= s;
            let o = refract::render::RenderOptions::from_scene(&sc);
            let mut g = GpuRenderer::with_context(ctx.clone(), sc, o).expect("renderer");
            let img = g.render(16).expect("render");
            img.mean
                .iter()
                .map(|p| (p.x + p.y + p.z) as f64)
                .sum::<f64>()
                / img.mean.len() as f64
        };
        let base = mean(1.0);
        for s in [1e-6f32, 1e6] {
            let m = mean(s);
            assert!(
                (m - base).abs() <= 0.005 * base,
                "{name} at scale {s:e}: GPU mean {m:.5} vs {base:.5} at scale 1"
            );
        }
    }
}

/// GPU errors are an `Err`, never a panic: a buffer over `max_buffer_size` and a pipeline with
/// a missing entry point inside an error scope, the same buffer outside any scope (recorded by
/// the uncaptured-error handler), a device asking for more than the adapter has, and a
/// renderer whose image buffers exceed the device's limits.
#[test]
fn gpu_errors_are_err_not_panic() {
    let Some(ctx) = context("gpu_errors_are_err_not_panic") else {
        return;
    };
    let limits = ctx.device.limits();
    let huge = |label| {
        ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: limits.max_buffer_size.saturating_add(4),
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        })
    };
    let err = ctx.scoped("huge buffer", || huge("huge")).unwrap_err();
    eprintln!("buffer over the limit: {err:#}");
    ctx.check_errors().unwrap();

    // An invalid shader through the kernels' compile path.
    let bad = "@compute @workgroup_size(1) fn main() { let x: u32 = 1.5; }";
    assert!(refract::gpu::pipeline::create_module(&ctx, "bad.wgsl", bad.into()).is_err());
    let module = refract::gpu::pipeline::create_module(
        &ctx,
        "tiny.wgsl",
        "@compute @workgroup_size(1) fn main() {}".into(),
    )
    .unwrap();
    let err = ctx
        .scoped("missing entry point", || {
            ctx.device
                .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: None,
                    layout: None,
                    module: &module,
                    entry_point: Some("no_such_entry_point"),
                    compilation_options: Default::default(),
                    cache: None,
                })
        })
        .unwrap_err();
    eprintln!("invalid pipeline: {err:#}");

    // Outside any scope: recorded, reported once by `check_errors` and the next `wait`.
    let _ = huge("huge, unscoped");
    let err = ctx.wait().unwrap_err();
    eprintln!("uncaptured: {err:#}");
    ctx.wait().unwrap();

    // A device asking for more than the adapter allows.
    let mut more = ctx.adapter.limits();
    more.max_storage_buffers_per_shader_stage += 1;
    assert!(GpuContext::with_limits(ctx.adapter.clone(), more).is_err());

    // The viewer's renderer on a device whose buffers are capped at 1 MiB: its 512x512
    // light-tracing splat film (6 MiB) is over the limit, and the viewer's progressive
    // renderer does not tile (headless renders do: `gpu_lt_tiles_give_the_whole_image`).
    let small_ctx = capped_context(&ctx, 1 << 20);
    let mut scene = Scene::load("builtin:cornell-glass").unwrap();
    small(&mut scene, 512, 512);
    let mut opts = RenderOptions::from_scene(&scene);
    opts.estimator = Estimator::LtPt;
    let err = GpuRenderer::with_context_untiled(small_ctx, scene, opts)
        .err()
        .expect("an Err for buffers over the device's limits");
    eprintln!("renderer over the limits: {err:#}");
}

/// A second device on `ctx`'s adapter whose buffers and bindings are capped at `bytes`.
fn capped_context(ctx: &GpuContext, bytes: u64) -> GpuContext {
    let mut limits = ctx.adapter.limits();
    limits.max_buffer_size = bytes;
    limits.max_storage_buffer_binding_size = bytes;
    GpuContext::with_limits(ctx.adapter.clone(), limits).unwrap()
}

/// Images larger than one binding render in tiles of rows (issue 15, part 4): on a device
/// whose buffers are capped at 1 MiB, a 128x1152 path-traced image (2.25 MiB of film) renders
/// in tiles of 512, 512 and 128 rows and equals the same image rendered whole on the unrestricted device
/// (the same counter-based samples; batch sizes may differ, so equal to float rounding);
/// the viewer's progressive dispatch records an error instead of rendering garbage.
#[test]
fn gpu_tiles_give_the_whole_image() {
    let Some(ctx) = context("gpu_tiles_give_the_whole_image") else {
        return;
    };
    let small_ctx = capped_context(&ctx, 1 << 20);
    let mut scene = Scene::load("builtin:cornell-glass").unwrap();
    small(&mut scene, 128, 1152);
    scene.settings.max_depth = 2;
    let mut opts = RenderOptions::from_scene(&scene);
    opts.estimator = Estimator::Path;
    let mut tiled = GpuRenderer::with_context(small_ctx, scene.clone(), opts).unwrap();
    assert_eq!(tiled.film_rows(), 512, "1 MiB holds 512 rows of 128 pixels");
    let mut whole = GpuRenderer::with_context(ctx, scene, opts).unwrap();
    assert_eq!(whole.film_rows(), 1152);
    // Two calls: the running mean of every tile continues across them.
    tiled.render(1).unwrap();
    let a = tiled.render(2).unwrap();
    let b = whole.render(3).unwrap();
    assert_eq!((a.spp, b.spp), (3, 3));
    let worst = worst_relative_difference(&b.mean, &a.mean);
    eprintln!("tiled vs whole: worst relative difference {worst:e}");
    assert!(
        worst < 1e-4,
        "tiled image differs from the whole one by {worst}"
    );
    assert!(
        b.mean.iter().map(|p| p.x).sum::<f32>() > 0.0,
        "a black image proves nothing"
    );
    tiled.dispatch(1);
    assert!(
        tiled.context().check_errors().is_err(),
        "the viewer's dispatch refuses tiles"
    );
}

/// lt+pt renders an image larger than one binding in tiles (issue 37, item 3): on a device
/// whose buffers are capped at 1 MiB, 128x1152 `cornell-glass` switched from path tracing
/// (tiles of 512 rows) to lt+pt renders in tiles of 336 rows (the 24-byte splat film binds
/// fewer), each tracing every light subpath of the image again and keeping the splats on its
/// rows — the megakernel and the wavefront alike. The light subpaths and camera paths are the
/// whole image's, the splats integer sums, so the image equals lt+pt on the unrestricted
/// device to float rounding of the running mean.
#[test]
fn gpu_lt_tiles_give_the_whole_image() {
    let Some(ctx) = context("gpu_lt_tiles_give_the_whole_image") else {
        return;
    };
    let small_ctx = capped_context(&ctx, 1 << 20);
    let mut scene = Scene::load("builtin:cornell-glass").unwrap();
    small(&mut scene, 128, 1152);
    scene.settings.max_depth = 4;
    let mut opts = RenderOptions::from_scene(&scene);
    opts.estimator = Estimator::Path;
    let mut tiled = GpuRenderer::with_context(small_ctx, scene.clone(), opts).unwrap();
    assert_eq!(tiled.film_rows(), 512);
    tiled.set_estimator(Estimator::LtPt).expect("lt+pt tiles");
    assert_eq!(tiled.film_rows(), 336, "1 MiB of splats holds 336 rows");
    opts.estimator = Estimator::LtPt;
    let mut whole = GpuRenderer::with_context(ctx, scene, opts).unwrap();
    for wavefront in [false, true] {
        for g in [&mut tiled, &mut whole] {
            g.set_wavefront(Some(wavefront));
        }
        tiled.render(1).unwrap();
        let a = tiled.render(2).unwrap();
        let b = whole.render(3).unwrap();
        assert_eq!((a.spp, b.spp), (3, 3));
        let worst = worst_relative_difference(&b.mean, &a.mean);
        eprintln!(
            "lt+pt (wavefront {wavefront}) tiled vs whole: worst relative difference {worst:e}"
        );
        assert!(
            worst < 1e-4,
            "wavefront {wavefront}: tiled lt+pt differs from the whole image by {worst}"
        );
        let lit = b.mean.iter().filter(|p| p.x > 0.0).count();
        assert!(lit > b.mean.len() / 2, "a black image proves nothing");
    }
}

/// sppm renders an image larger than one binding in tiles (issue 37, item 3): on a device
/// whose buffers are capped at 1 MiB, 128x1152 `cornell-glass` with sppm renders in tiles of
/// rows, each tracing the iteration's photons again, with the photon store capped to what
/// 1 MiB binds (21,000 photon paths per iteration where the whole image aims 73,000): a
/// consistent estimate of the same image, so it agrees with sppm on the unrestricted device
/// (block Z-test, 6 runs of 2 spp each side).
#[test]
fn gpu_sppm_tiles_agree_with_the_whole_image() {
    let Some(ctx) = context("gpu_sppm_tiles_agree_with_the_whole_image") else {
        return;
    };
    let small_ctx = capped_context(&ctx, 1 << 20);
    let mut scene = Scene::load("builtin:cornell-glass").unwrap();
    small(&mut scene, 128, 1152);
    scene.settings.max_depth = 5;
    let mut opts = RenderOptions::from_scene(&scene);
    opts.estimator = Estimator::Sppm;
    let mut tiled = GpuRenderer::with_context(small_ctx, scene.clone(), opts).unwrap();
    assert_eq!(tiled.film_rows(), 512, "1 MiB holds 512 rows of 128 pixels");
    let mut whole = GpuRenderer::with_context(ctx, scene, opts).unwrap();
    let mut runs = |g: &mut GpuRenderer| -> Vec<Vec<f64>> {
        (0..6)
            .map(|i| {
                opts.seed = 40 + i;
                g.set_options(opts).unwrap();
                let img = g.render(2).unwrap();
                assert!(img.mean.iter().all(|p| p.is_finite()));
                block_means(&img.mean, 128, 1152)
            })
            .collect()
    };
    let a = runs(&mut tiled);
    let b = runs(&mut whole);
    assert!(
        a[0].iter().sum::<f64>() > 0.0,
        "a black image proves nothing"
    );
    assert_blocks_agree("sppm tiled (1 MiB bindings) vs whole", &a, &b);
}

/// 4K with the default flags, with sppm and with lt+pt on this device (issue 37, item 3):
/// sppm's photon store (8.3 M slots, 379 MiB) and lt+pt's splat film (190 MiB) no longer have
/// to fit one binding — lavapipe binds 128 MiB, as do many laptop GPUs and WebGPU's defaults;
/// the store is capped and the films tile where needed. `auto` (whatever it resolves to on the
/// default scene), `sppm` and `lt+pt`, 1 spp at depth 3 each: every pixel finite, the image
/// not black.
#[test]
fn gpu_renders_4k_with_default_flags_sppm_and_lt_pt() {
    let Some(ctx) = context("gpu_renders_4k_with_default_flags_sppm_and_lt_pt") else {
        return;
    };
    eprintln!(
        "device binds at most {} MiB per buffer",
        ctx.max_binding_bytes() >> 20
    );
    let mut scene = Scene::load(refract::render::settings::DEFAULT_SCENE).unwrap();
    small(&mut scene, 3840, 2160);
    scene.settings.max_depth = 3;
    let opts = RenderOptions::from_scene(&scene);
    let mut g = GpuRenderer::with_context(ctx, scene.clone(), opts).expect("4K, default flags");
    for est in [opts.estimator, Estimator::Sppm, Estimator::LtPt] {
        g.set_estimator(est).expect("the estimator at 4K");
        let img = g.render(1).unwrap();
        assert_eq!(img.mean.len(), 3840 * 2160);
        assert!(
            img.mean.iter().all(|p| p.is_finite()),
            "{est}: non-finite pixels"
        );
        let mean = img.mean.iter().map(|p| p.y as f64).sum::<f64>() / img.mean.len() as f64;
        eprintln!(
            "{est} ({}) at 4K: mean luminance {mean:.6}",
            g.effective_estimator()
        );
        assert!(mean > 0.01, "{est}: mean luminance {mean}: black");
    }
}

/// 4K and 8K render on the GPU in path mode (issue 15, part 4): the splat film is allocated
/// only for lt+pt (it was 24 B per pixel always, against a fixed 128 MiB cap: 5.6 MP at most),
/// and buffers are checked against the device's own binding limit. 1 spp of the furnace at
/// depth 2, every pixel finite and the mean close to the furnace's white. 8K's 531 MB film
/// is larger than lavapipe's 128 MiB binding: it renders in tiles of rows.
#[test]
fn gpu_renders_4k_and_8k_in_path_mode() {
    let Some(ctx) = context("gpu_renders_4k_and_8k_in_path_mode") else {
        return;
    };
    let cap = ctx.max_binding_bytes();
    eprintln!("device binds at most {} MiB per buffer", cap >> 20);
    let mut scene = Scene::load("builtin:furnace").unwrap();
    scene.settings.max_depth = 2;
    let mut opts = RenderOptions::from_scene(&scene);
    opts.width = 3840;
    opts.height = 2160;
    let mut g = GpuRenderer::with_context(ctx, scene.clone(), opts).unwrap();
    for (w, h) in [(3840u32, 2160u32), (7680, 4320)] {
        if u64::from(w) * u64::from(h) * 16 > cap {
            eprintln!("{w}x{h}: the accumulation film exceeds this device's binding: tiles");
        }
        g.set_options(RenderOptions {
            width: w,
            height: h,
            ..opts
        })
        .unwrap();
        let img = g.render(1).unwrap();
        assert_eq!(
            (img.width, img.height, img.mean.len()),
            (w, h, (w * h) as usize)
        );
        let px = &img.mean;
        assert!(
            px.iter().all(|p| p.is_finite()),
            "{w}x{h}: non-finite pixels"
        );
        let mean = px.iter().map(|p| f64::from(p.x)).sum::<f64>() / px.len() as f64;
        assert!(mean > 0.2 && mean < 2.0, "{w}x{h}: mean {mean}");
    }
}

/// Bounded submissions (issue 15, part 5): with a 1 µs budget every submission is one sample
/// of an 8-row band; the image equals that of whole-image batches of many samples (the same
/// counter-based samples, summed in another order: equal to float rounding).
#[test]
fn gpu_bands_and_batches_give_the_same_image() {
    let Some(ctx) = context("gpu_bands_and_batches_give_the_same_image") else {
        return;
    };
    let scene = Scene::load("builtin:cornell-glass").unwrap();
    let mut opts = RenderOptions::from_scene(&scene);
    opts.width = 64;
    opts.height = 44; // not a multiple of 8: the last band is short
    let mut tiny = GpuRenderer::with_context(ctx, scene.clone(), opts).unwrap();
    tiny.set_submission_budget(std::time::Duration::from_micros(1));
    tiny.render(1).unwrap(); // the first, untimed submission is a probe
    let a = tiny.render(5).unwrap();
    assert_eq!(
        tiny.batch_spp(),
        1,
        "a 1 µs budget plans one sample per submission"
    );
    let Some(ctx) = context("gpu_bands_and_batches_give_the_same_image") else {
        return;
    };
    let mut big = GpuRenderer::with_context(ctx, scene, opts).unwrap();
    big.set_submission_budget(std::time::Duration::from_secs(100));
    big.render(1).unwrap();
    let b = big.render(5).unwrap();
    assert_eq!(
        big.batch_spp(),
        5,
        "a 100 s budget plans all 5 samples at once"
    );
    assert_eq!((a.spp, b.spp), (6, 6));
    for (i, (p, q)) in a.mean.iter().zip(&b.mean).enumerate() {
        let tol = 1e-4 * q.abs().max_element().max(1.0);
        assert!(
            (*p - *q).abs().max_element() <= tol,
            "pixel {i}: {p} vs {q}"
        );
    }
}

/// Render `spp` samples (after a 1-spp probe) of `scene` with `estimator` under a 1 µs
/// submission budget (every submission one sample per pixel, in 8-row bands where the estimator
/// allows: a plan that does not depend on timing) with `in_flight` batches queued.
fn render_in_flight(
    ctx: GpuContext,
    scene: &Scene,
    estimator: refract::render::Estimator,
    in_flight: usize,
    spp: u32,
) -> (refract::gpu::GpuImage, refract::render::RenderStats) {
    let mut opts = RenderOptions::from_scene(scene);
    opts.width = 64;
    opts.height = 44; // not a multiple of 8: the last band and its workgroups are short
    opts.estimator = estimator;
    let mut r = GpuRenderer::with_context(ctx, scene.clone(), opts).unwrap();
    r.set_batches_in_flight(in_flight);
    r.set_submission_budget(std::time::Duration::from_micros(1));
    r.render(1).unwrap();
    let img = r.render(spp).unwrap();
    assert_eq!(
        r.batch_spp(),
        1,
        "a 1 µs budget plans one sample per submission"
    );
    (img, r.stats().unwrap())
}

/// Two batches in flight (the next submitted before waiting for the one running) add exactly
/// the samples one at a time adds: the same image bit for bit, the same counters.
#[test]
fn gpu_two_batches_in_flight_give_the_same_image() {
    use refract::render::Estimator;
    for (name, estimator) in [
        ("builtin:cornell-glass", Estimator::Path),
        ("builtin:caustic", Estimator::LtPt),
    ] {
        let scene = Scene::load(name).unwrap();
        let Some(ctx) = context("gpu_two_batches_in_flight_give_the_same_image") else {
            return;
        };
        let (a, sa) = render_in_flight(ctx.clone(), &scene, estimator, 1, 4);
        let (b, sb) = render_in_flight(ctx, &scene, estimator, 2, 4);
        assert_eq!((a.spp, b.spp), (5, 5), "{name}");
        assert!(
            a.mean.iter().any(|p| p.max_element() > 0.0),
            "{name}: a lit image"
        );
        assert!(
            a.mean == b.mean,
            "{name} {estimator}: the images differ with two batches in flight"
        );
        assert_eq!(
            (sa.segments, sa.dropped),
            (sb.segments, sb.dropped),
            "{name}"
        );
    }
}

/// The path-segment counter, reduced per workgroup before one global atomic add: with the
/// camera looking away from the scene every camera path is one segment (the ray that
/// escapes), so the count is exactly width × height × spp, on an image whose edge
/// workgroups are partly outside it (their idle invocations must add nothing).
#[test]
fn gpu_segment_counter_counts_every_path_once() {
    let Some(ctx) = context("gpu_segment_counter_counts_every_path_once") else {
        return;
    };
    let mut scene = Scene::load("builtin:cornell-glass").unwrap();
    let (lo, hi) = scene.bounds();
    // Behind the scene's far −Z side, looking further down −Z: nothing in view.
    let eye = Vec3::new(
        0.5 * (lo.x + hi.x),
        0.5 * (lo.y + hi.y),
        lo.z - 10.0 * (hi - lo).length(),
    );
    scene.camera = Camera::look_at(eye, eye - Vec3::Z, Vec3::Y, 0.6);
    let mut opts = RenderOptions::from_scene(&scene);
    opts.width = 61;
    opts.height = 45;
    let mut r = GpuRenderer::with_context(ctx, scene, opts).unwrap();
    r.render(3).unwrap();
    let s = r.stats().unwrap();
    assert_eq!(s.spp, 3);
    assert_eq!(s.segments, Some(61 * 45 * 3));
    assert_eq!(s.dropped, 0);
}

/// A fresh directory for a test's pipeline cache.
fn cache_dir(test: &str) -> std::path::PathBuf {
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos());
    let d = std::env::temp_dir().join(format!("refract-{test}-{}-{nanos}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The driver pipeline cache (where the device has `Features::PIPELINE_CACHE`): written to
/// its file after compilation, loaded by the next device on the adapter, and a corrupt file
/// is only a cold start. The same image every time.
#[test]
fn gpu_pipeline_cache_is_saved_loaded_and_survives_corruption() {
    let test = "gpu_pipeline_cache_is_saved_loaded_and_survives_corruption";
    let Some(mut ctx) = context(test) else {
        return;
    };
    if !ctx
        .device
        .features()
        .contains(eframe::wgpu::Features::PIPELINE_CACHE)
    {
        eprintln!("SKIP {test}: {} has no pipeline cache", ctx.describe());
        return;
    }
    let dir = cache_dir("pipeline-cache");
    let scene = Scene::load("builtin:cornell-glass").unwrap();
    let mut opts = RenderOptions::from_scene(&scene);
    opts.width = 32;
    opts.height = 24;
    let render = |ctx: GpuContext| {
        let mut r = GpuRenderer::with_context(ctx, scene.clone(), opts).unwrap();
        let t = r.last_compile_time().unwrap();
        let loaded = r.pipeline_cache_loaded();
        let path = r.pipeline_cache_path().map(|p| p.to_owned());
        (r.render(2).unwrap().mean, t, loaded, path)
    };
    ctx.pipeline_cache_dir = Some(dir.clone());
    let (cold, t_cold, loaded, path) = render(ctx);
    assert_eq!(loaded, Some(0), "an empty directory is a cold start");
    let path = path.expect("a cache file");
    assert!(path.starts_with(&dir));
    let bytes = std::fs::read(&path).expect("the cache was written");
    assert!(!bytes.is_empty());

    let mut ctx = context(test).unwrap();
    ctx.pipeline_cache_dir = Some(dir.clone());
    let (warm, t_warm, loaded, _) = render(ctx);
    assert_eq!(loaded, Some(bytes.len()), "the next device loads the file");
    assert!(warm == cold, "the same kernels from the cache");

    std::fs::write(&path, b"not a pipeline cache").unwrap();
    let mut ctx = context(test).unwrap();
    ctx.pipeline_cache_dir = Some(dir.clone());
    let (again, _, _, _) = render(ctx);
    assert!(again == cold, "a corrupt cache file is only a cold start");
    eprintln!(
        "pipeline creation: cold {:.0} ms, warm {:.0} ms ({} bytes of cache data)",
        t_cold.as_secs_f64() * 1e3,
        t_warm.as_secs_f64() * 1e3,
        bytes.len()
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Pipelines compiled on a worker thread: the renderer answers at once, reports when they are
/// ready, and renders what a renderer that compiled them before returning renders; a new
/// specialisation (a material made dispersive) is compiled in the background too.
#[test]
fn gpu_background_compilation_renders_the_same_image() {
    let test = "gpu_background_compilation_renders_the_same_image";
    let Some(ctx) = context(test) else {
        return;
    };
    let scene = Scene::load("builtin:cornell-glass").unwrap();
    let mut opts = RenderOptions::from_scene(&scene);
    opts.width = 32;
    opts.height = 24;
    let glass = scene
        .materials
        .iter()
        .position(|m| m.is_transmissive())
        .expect("cornell-glass has glass");
    let mut dispersive = scene.materials[glass].clone();
    dispersive.abbe = Some(30.0);

    let mut sync = GpuRenderer::with_context(ctx.clone(), scene.clone(), opts).unwrap();
    assert!(!sync.is_compiling());
    let a = sync.render(2).unwrap().mean;
    sync.set_material(glass, dispersive.clone()).unwrap();
    assert!(
        !sync.is_compiling(),
        "blocking renderers compile in the edit"
    );
    let a2 = sync.render(2).unwrap().mean;

    let mut bg = GpuRenderer::with_context_in_background(ctx, scene, opts).unwrap();
    let wait = |r: &mut GpuRenderer| {
        let start = std::time::Instant::now();
        while !r.pipelines_ready().unwrap() {
            assert!(
                start.elapsed().as_secs() < 300,
                "compilation never finished"
            );
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
    };
    wait(&mut bg);
    assert!(!bg.is_compiling());
    assert!(bg.render(2).unwrap().mean == a);
    bg.set_material(glass, dispersive).unwrap();
    assert!(bg.specialization().spectral);
    assert!(
        bg.is_compiling(),
        "the new specialisation compiles on a worker thread"
    );
    wait(&mut bg);
    assert!(bg.render(2).unwrap().mean == a2);
}

/// The effect of a second batch in flight on `render_with` (a measurement, not a check:
/// `cargo test --release --test gpu -- --ignored --nocapture gpu_batches_in_flight_timing`):
/// cornell-glass 256×256, 16 spp, one and two in flight alternately, three times each.
#[test]
#[ignore]
fn gpu_batches_in_flight_timing() {
    let Some(ctx) = context("gpu_batches_in_flight_timing") else {
        return;
    };
    let scene = Scene::load("builtin:cornell-glass").unwrap();
    let mut opts = RenderOptions::from_scene(&scene);
    opts.width = 256;
    opts.height = 256;
    for round in 0..3 {
        for n in [1, 2] {
            let mut r = GpuRenderer::with_context(ctx.clone(), scene.clone(), opts).unwrap();
            r.set_batches_in_flight(n);
            r.render(1).unwrap();
            let t = std::time::Instant::now();
            r.render(16).unwrap();
            eprintln!(
                "round {round}: {n} in flight: 16 spp in {:.3} s",
                t.elapsed().as_secs_f64()
            );
        }
    }
}

#[test]
fn gpu_refuses_a_spectral_conductor_scene() {
    // The GPU has RGB conductors only: a tabulated metal next to a dispersive glass is refused
    // with a message naming both (no device needed: the check runs before any upload).
    let mut s = Scene::load("builtin:metals").unwrap();
    upload::check_supported(&s).unwrap();
    let glass = s
        .materials
        .iter()
        .position(|m| m.name == "checker-dark")
        .unwrap();
    s.materials[glass] = Material {
        abbe: Some(30.0),
        ..Material::glass("flint", 1.6)
    };
    let e = upload::check_supported(&s).expect_err("refused");
    let msg = format!("{e:#}");
    assert!(
        msg.contains("conductor") && msg.contains("dispersive"),
        "{msg}"
    );
}
