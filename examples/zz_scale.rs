use refract::cpu::Renderer;
use refract::film::Film;
use refract::render::RenderOptions;
use refract::scene::Scene;
fn main() {
    for name in ["cornell-glass", "glass-slab", "furnace"] {
        for s in [1.0f32, 1e-4, 1e-5, 1e-6, 1e4, 1e6] {
            let mut sc = Scene::load(&format!("builtin:{name}")).unwrap();
            sc.settings.width = 48;
            sc.settings.height = 48;
            for p in sc.mesh.positions.iter_mut() {
                *p *= s;
            }
            sc.camera.position *= s;
            let r = Renderer::new(sc).unwrap();
            let o = RenderOptions::from_scene(&r.scene);
            let mut f = Film::new(o.width, o.height);
            r.render_pass(&o, &mut f, 0, 64);
            let img = f.image();
            let m: f64 = img
                .iter()
                .map(|p| (p.x + p.y + p.z) as f64 / 3.0)
                .sum::<f64>()
                / img.len() as f64;
            println!("{name} scale {s:e}: mean {m:.5}");
        }
    }
}
