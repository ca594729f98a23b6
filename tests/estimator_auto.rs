//! The `auto` estimator rule on every built-in scene, the CLI's report of its choice, and time
//! budgets that fill the time (issue 19, parts 1 and 2).

use refract::render::Estimator;
use refract::scene::Scene;

#[test]
fn print_rule() {
    for n in refract::scene::builtin::NAMES {
        let s = Scene::load(&format!("builtin:{n}")).unwrap();
        let (e, why) = Estimator::Auto.resolve_why(&s);
        println!("RULE {n}: {e} ({why}) spp {}", s.settings.spp);
    }
}
