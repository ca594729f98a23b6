//! Path classes in one pass (`render --decompose 'LE,LDE,LS+DE'`): one unfiltered camera
//! walk whose every contribution (emission reached by a BSDF sample, next-event connection,
//! environment) is routed to the first class whose Heckbert expression (`crate::paths`)
//! accepts the contribution's full light→eye string, else to `rest`. The classes and `rest`
//! therefore partition the image: summed, they are the plain render of the same seed.
//!
//! The router keeps one state per class in the class's reversed DFA (the camera walk reads
//! eye→light, as the `--paths` filter does: `E` at the camera, one symbol per bounce, then
//! `L` — or the connection's class and `L` — to test a contribution). A next-event
//! connection at a BSDF with a diffuse and a glossy lobe (metal-rough) is split exactly by
//! the lobes' share of f (`Bsdf::eval_lobes`), which is how the `--paths` filter counts such
//! a connection: a class image equals the `--paths CLASS` render wherever classes are
//! disjoint.

use super::interaction::Interaction;
use super::layers::LayerObserver;
use super::observer::{PathEnd, PathObserver};
use super::path_state::PathState;
use super::spectral::Spectral;
use crate::bsdf::{Bsdf, BsdfSample, TransportMode};
use crate::math::Color;
use crate::paths::{DfaTable, PathFilter, Symbol};
use crate::scene::Scene;
use crate::scene::light::LiSample;
use glam::Vec3;

/// The most classes one decomposition may name (plus `rest`).
pub const MAX_CLASSES: usize = 16;

/// The name of the layer that takes every contribution no class accepts.
pub const REST: &str = "rest";

/// One named class of a decomposition.
#[derive(Clone, Debug)]
pub struct PathClass {
    /// The file-name-safe name (`OUT.<name>.exr`).
    pub name: String,
    pub filter: PathFilter,
}

/// The classes of `--decompose`, in priority order (first match wins).
#[derive(Clone, Debug)]
pub struct Decomposition {
    pub classes: Vec<PathClass>,
    /// The classes' eye→light tables, in order.
    tables: Vec<DfaTable>,
}

/// The file-name spelling of a class expression: symbols upper case, whitespace dropped,
/// `+` → `p`, `*` → `x`, `?` → `q`, `|` → `o`, `(` → `_`, `)` → `-` (lower-case letters are
/// never symbols there, so the spelling is unambiguous and safe on every file system and in
/// every shell). `LS+DE` → `LSpDE`, `L(D|S)*E` → `L_DoS-xE`.
pub fn file_name_of(expr: &str) -> String {
    expr.chars()
        .filter(|c| !c.is_whitespace())
        .map(|c| match c {
            '+' => 'p',
            '*' => 'x',
            '?' => 'q',
            '|' => 'o',
            '(' => '_',
            ')' => '-',
            c => c.to_ascii_uppercase(),
        })
        .collect()
}

impl Decomposition {
    /// Parse `C1,C2,…`; each item is an expression or `name=expression` (a name of letters,
    /// digits, `_` and `-`). Errors name the item.
    pub fn parse(spec: &str) -> anyhow::Result<Decomposition> {
        let mut classes: Vec<PathClass> = Vec::new();
        for (i, item) in spec.split(',').enumerate() {
            let (name, expr) = match item.split_once('=') {
                Some((n, e)) => (n.trim().to_owned(), e),
                None => (file_name_of(item), item),
            };
            anyhow::ensure!(
                !expr.trim().is_empty(),
                "class {} of '{}' is empty (write C1,C2,… e.g. 'LE,LDE,LS+DE')",
                i + 1,
                spec.trim()
            );
            let filter = PathFilter::parse(expr)
                .map_err(|e| anyhow::anyhow!("class {} '{}': {e}", i + 1, expr.trim()))?;
            anyhow::ensure!(
                !name.is_empty()
                    && name
                        .chars()
                        .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-'),
                "class {} name '{name}': use letters, digits, '_' and '-'",
                i + 1
            );
            anyhow::ensure!(
                name != REST && classes.iter().all(|c| c.name != name),
                "class {} name '{name}' is taken (by '{REST}' or an earlier class; name it \
                 with NAME=EXPR)",
                i + 1
            );
            classes.push(PathClass { name, filter });
        }
        anyhow::ensure!(
            classes.len() <= MAX_CLASSES,
            "{} classes: at most {MAX_CLASSES}",
            classes.len()
        );
        let tables = classes.iter().map(|c| *c.filter.reversed()).collect();
        Ok(Decomposition { classes, tables })
    }

    /// Layer names in order: the classes, then `rest`.
    pub fn layer_names(&self) -> Vec<String> {
        let mut v: Vec<String> = self.classes.iter().map(|c| c.name.clone()).collect();
        v.push(REST.to_owned());
        v
    }

    /// A router over these classes (one per worker).
    pub fn router(&self) -> ClassRouter<'_> {
        ClassRouter {
            tables: &self.tables,
            states: [0; MAX_CLASSES],
            sums: [Color::ZERO; MAX_CLASSES + 1],
            sp: Spectral::RGB,
            poisoned: false,
        }
    }
}

/// Routes each contribution of a camera walk to its class.
#[derive(Clone)]
pub struct ClassRouter<'a> {
    tables: &'a [DfaTable],
    /// Each class's DFA state after the vertices walked so far.
    states: [u32; MAX_CLASSES],
    /// This sample's contributions per class (`rest` last), in the path's colour lanes.
    sums: [Color; MAX_CLASSES + 1],
    sp: Spectral,
    /// The walk returned a poisoned (NaN) sample: the film drops it, so do the layers.
    poisoned: bool,
}

impl ClassRouter<'_> {
    /// The first class that accepts a contribution whose next symbols are `via` then `L`
    /// (`rest` when none does).
    #[inline]
    fn class_of(&self, via: Option<Symbol>) -> usize {
        let k = self.tables.len();
        (0..k)
            .find(|&i| {
                let t = &self.tables[i];
                let q = via.map_or(self.states[i], |s| t.step(self.states[i], s));
                t.is_accepting(t.step(q, Symbol::L))
            })
            .unwrap_or(k)
    }

    #[inline]
    fn add(&mut self, via: Option<Symbol>, c: Color) {
        if c != Color::ZERO {
            let i = self.class_of(via);
            self.sums[i] += c;
        }
    }
}

impl PathObserver for ClassRouter<'_> {
    fn start(&mut self, _origin: Vec3, _dir: Vec3, sp: &Spectral) {
        self.sp = *sp;
        self.poisoned = false;
        self.sums = [Color::ZERO; MAX_CLASSES + 1];
        for (q, t) in self.states.iter_mut().zip(self.tables) {
            *q = t.step(t.start(), Symbol::E);
        }
    }

    fn emitted(&mut self, contribution: Color) {
        self.add(None, contribution);
    }

    fn connection(&mut self, it: &Interaction, ls: &LiSample, c: Color, _occluded: bool) {
        if c == Color::ZERO {
            return;
        }
        if let Bsdf::MetalRough(_) = it.bsdf {
            // Split by the lobes' share of f, as the filter's class mask evaluates them.
            let lv = it
                .bsdf
                .eval_lobes(it.wo, it.frame.to_local(ls.wi), TransportMode::Radiance);
            let total = lv.d + lv.g;
            let share = Color::select(total.cmpgt(Color::ZERO), lv.d / total, Color::ZERO);
            let cd = c * share;
            self.add(Some(Symbol::D), cd);
            self.add(Some(Symbol::G), c - cd);
        } else {
            self.add(Some(Symbol::from(it.bsdf.class())), c);
        }
    }

    fn bounce(&mut self, _: &Scene, _: &Interaction, _: &PathState, s: &BsdfSample, _: Vec3) {
        let sym = Symbol::from(s.lobe);
        for (q, t) in self.states.iter_mut().zip(self.tables) {
            *q = t.step(*q, sym);
        }
    }

    fn escaped(&mut self, _dir: Vec3, contribution: Color) {
        self.add(None, contribution);
    }

    fn end(&mut self, why: PathEnd) {
        self.poisoned = why == PathEnd::Poisoned;
    }
}

impl LayerObserver for ClassRouter<'_> {
    fn layers(&self) -> usize {
        self.tables.len() + 1
    }

    fn commit(&mut self, accepted: bool, px: &mut [[f64; 3]]) {
        if !accepted || self.poisoned {
            return;
        }
        for (p, &c) in px.iter_mut().zip(&self.sums) {
            if c != Color::ZERO {
                let v = self.sp.to_rgb(c);
                p[0] += v.x as f64;
                p[1] += v.y as f64;
                p[2] += v.z as f64;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn file_names_are_safe_and_distinct() {
        assert_eq!(file_name_of("LS+DE"), "LSpDE");
        assert_eq!(file_name_of("l(d|s)*e"), "L_DoS-xE");
        assert_eq!(file_name_of(" LD?E "), "LDqE");
        assert_ne!(file_name_of("LS+DE"), file_name_of("LS*DE"));
    }

    #[test]
    fn parse_names_and_errors() {
        let d = Decomposition::parse("LE, caustic=LS+DE ,LDE").unwrap();
        assert_eq!(d.layer_names(), ["LE", "caustic", "LDE", "rest"]);
        let e = Decomposition::parse("LE,L(DE").unwrap_err().to_string();
        assert!(e.contains("class 2 'L(DE'"), "{e}");
        assert!(Decomposition::parse("LE,,LDE").is_err());
        assert!(Decomposition::parse("LE,LE").is_err(), "duplicate names");
        assert!(Decomposition::parse("rest=LDE").is_err());
        let many = vec!["LE"; 17]
            .iter()
            .enumerate()
            .map(|(i, e)| format!("c{i}={e}"))
            .collect::<Vec<_>>()
            .join(",");
        assert!(Decomposition::parse(&many).is_err());
    }

    #[test]
    fn first_match_wins() {
        let d = Decomposition::parse("LDE,L(D|S)*E").unwrap();
        let mut r = d.router();
        r.start(Vec3::ZERO, Vec3::Z, &Spectral::RGB);
        // E, then a diffuse vertex: LDE is class 0 (also accepted by class 1).
        assert_eq!(r.class_of(Some(Symbol::D)), 0);
        // A specular then diffuse connection: LDSE is class 1 only.
        let t = d.tables[1];
        r.states[1] = t.step(r.states[1], Symbol::S);
        r.states[0] = d.tables[0].step(r.states[0], Symbol::S);
        assert_eq!(r.class_of(Some(Symbol::D)), 1);
        // LGSE matches neither: rest.
        assert_eq!(r.class_of(Some(Symbol::G)), 2);
    }
}
