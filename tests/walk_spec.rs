//! The camera walk specialised on the scene's features (`cpu::walk_spec`, issue 14 part 2):
//! the lean instance gives bit for bit the radiance of the general walk, is chosen exactly
//! for scenes that lack what it leaves out, and neither allocates per sample.

use glam::Vec3;
use refract::cpu::Renderer;
use refract::cpu::camera_ray::camera_ray;
use refract::cpu::spectral::Spectral;
use refract::cpu::walk_spec::{General, Lean, Spec, WalkFeatures};
use refract::math::rng::Sampler;
use refract::paths::PathFilter;
use refract::render::RenderOptions;
use refract::scene::Scene;
use refract::scene::camera::CameraRays;
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

/// Counts the allocations of the current thread (tests run on several threads at once).
struct CountingAlloc;

thread_local! {
    static ALLOCS: Cell<u64> = const { Cell::new(0) };
}

// SAFETY: forwards every call unchanged to the system allocator; the counter is a
// thread-local `Cell` with const initialisation, which never allocates.
unsafe impl GlobalAlloc for CountingAlloc {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCS.with(|c| c.set(c.get() + 1));
        // SAFETY: the caller's contract for `alloc` is passed on as is.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: `ptr` came from `System.alloc` with this layout (every allocation does).
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCS.with(|c| c.set(c.get() + 1));
        // SAFETY: as for `dealloc`; the caller guarantees `new_size` is valid for `layout`.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: CountingAlloc = CountingAlloc;

fn allocations() -> u64 {
    ALLOCS.with(|c| c.get())
}

const W: u32 = 24;
const H: u32 = 24;

fn renderer(name: &str) -> Renderer {
    let mut s = Scene::load(&format!("builtin:{name}")).expect("builtin");
    s.settings.width = W;
    s.settings.height = H;
    Renderer::new(s).expect("valid")
}

/// Every sample of a `W`×`H`, `spp` image through the dispatching walk (`li`) and through
/// the general instance, as (dispatched, general) radiance bits; also whether the camera
/// paths were lean.
fn both_walks(r: &Renderer, opts: &RenderOptions, spp: u32) -> (Vec<[u32; 6]>, bool) {
    let integ = r.integrator(opts);
    let cam = &CameraRays::new(&r.scene.camera);
    let mut out = Vec::with_capacity((W * H * spp) as usize);
    let mut lean = true;
    for pixel in 0..W * H {
        let (x, y) = (pixel % W, pixel / W);
        for s in 0..spp {
            let mut a = Sampler::new(pixel, s, 7);
            let dir = camera_ray(cam, (x, y), (W, H), &mut a);
            let mut b = a;
            let va = integ.li(cam.position, dir, &mut a);
            let sp = integ.lanes(|| b.next_1d());
            lean &= integ.walk_features(&sp).lean();
            let ray = (cam.position, dir);
            let vb = integ.li_spec::<General, (), ()>(ray, &mut b, sp, &mut (), &());
            assert_eq!(a.dim(), b.dim(), "both walks draw the same dimensions");
            let bits = |v: Vec3| [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()];
            let (ba, bb) = (bits(va), bits(vb));
            out.push([ba[0], ba[1], ba[2], bb[0], bb[1], bb[2]]);
        }
    }
    (out, lean)
}

/// On scenes without spectral lanes, filter, media or textures the lean instance runs and
/// returns exactly the general walk's radiance, sample for sample.
#[test]
fn lean_walk_is_bit_identical_to_the_general_walk() {
    for name in ["cornell-glass", "glass-slab", "caustic", "rough-glass"] {
        let r = renderer(name);
        let mut opts = RenderOptions::from_scene(&r.scene);
        opts.max_depth = 64;
        let (samples, lean) = both_walks(&r, &opts, 4);
        assert!(lean, "{name}: expected the lean instance");
        let nonzero = samples.iter().filter(|s| s[..3] != [0; 3]).count();
        assert!(
            nonzero > samples.len() / 4,
            "{name}: the image is mostly black"
        );
        for (i, s) in samples.iter().enumerate() {
            assert_eq!(s[..3], s[3..], "{name}: sample {i} differs");
        }
    }
}

/// Scenes that need a feature the lean instance leaves out run the general walk.
#[test]
fn scenes_needing_a_feature_run_the_general_walk() {
    let prism = renderer("prism");
    let prism_opts = RenderOptions::from_scene(&prism.scene);
    let (_, lean) = both_walks(&prism, &prism_opts, 1);
    assert!(!lean, "prism is spectral");

    let cg = renderer("cornell-glass");
    let mut opts = RenderOptions::from_scene(&cg.scene);
    opts.set_filter(Some(&PathFilter::parse("LS+DE").expect("filter")));
    let (samples, lean) = both_walks(&cg, &opts, 2);
    assert!(!lean, "a path filter needs the general walk");
    assert!(samples.iter().all(|s| s[..3] == s[3..]));

    // Asking for the lean instance where it does not fit runs the general one.
    let integ = prism.integrator(&prism_opts);
    let cam = &CameraRays::new(&prism.scene.camera);
    for pixel in 0..W * H {
        let mut a = Sampler::new(pixel, 0, 5);
        let dir = camera_ray(cam, (pixel % W, pixel / W), (W, H), &mut a);
        let mut b = a;
        let sp_a = Spectral::new(true, None, || a.next_1d());
        let sp_b = Spectral::new(true, None, || b.next_1d());
        let ray = (cam.position, dir);
        let va = integ.li_spec::<Lean, (), ()>(ray, &mut a, sp_a, &mut (), &());
        let vb = integ.li_spec::<General, (), ()>(ray, &mut b, sp_b, &mut (), &());
        assert_eq!(
            va.to_array().map(f32::to_bits),
            vb.to_array().map(f32::to_bits)
        );
    }

    let f = WalkFeatures {
        textures: true,
        ..WalkFeatures::default()
    };
    assert!(!f.lean() && !f.fits::<Lean>() && f.fits::<General>());
    assert!(f.fits::<Spec<false, false, false, true>>());
    assert!(!f.fits::<Spec<true, true, true, false>>());
    assert!(WalkFeatures::default().fits::<Lean>());
}

/// No allocation per sample: a whole image of camera walks on this thread allocates
/// nothing (the renderer, BVH and lights are built before counting starts).
#[test]
fn camera_walks_do_not_allocate() {
    for name in ["cornell-glass", "prism"] {
        let r = renderer(name);
        let mut opts = RenderOptions::from_scene(&r.scene);
        opts.max_depth = 64;
        let integ = r.integrator(&opts);
        let cam = &CameraRays::new(&r.scene.camera);
        let before = allocations();
        let mut sum = Vec3::ZERO;
        for pixel in 0..W * H {
            for s in 0..8 {
                let mut sampler = Sampler::new(pixel, s, 3);
                let dir = camera_ray(cam, (pixel % W, pixel / W), (W, H), &mut sampler);
                sum += integ.li(cam.position, dir, &mut sampler);
            }
        }
        let n = allocations() - before;
        assert!(sum.max_element() > 0.0, "{name}: black image");
        assert_eq!(n, 0, "{name}: {n} allocations in {} samples", W * H * 8);
    }
}
