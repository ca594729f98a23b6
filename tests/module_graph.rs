//! The crate's import graph, read from the sources (issue 44: "no import circle; layers
//! still point down"): sibling modules never import each other in a circle, at any of the
//! first three levels (`scene::env_map` ↔ `scene::gltf_load`, `cpu::render` ↔ `cpu::sppm`
//! were such circles), and the top-level modules form layers in which every import points
//! to a lower layer (the scene data model knows nothing of glTF, the renderers nothing of
//! the viewer).
//!
//! Imports are the paths `crate::…`, `refract::…` and `super::…` in the code (comments and
//! `#[cfg(test)]` modules left out; one level of `{a, b::c}` groups expanded). The binary
//! (`src/main.rs`, `src/cli/`) counts as the module `cli`.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

type Module = Vec<String>;

/// The layers, lowest first: a module may import only modules of lower layers (and its
/// own submodules).
const LAYERS: &[&[&str]] = &[
    &["math", "text", "files"],
    &["bsdf", "film"],
    &["paths"],
    &["scene"],
    &["bvh", "gltf_io", "render"],
    &["cpu", "gpu"],
    &["denoise"],
    &["bench", "app"],
    &["cli"],
];

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).expect("src/ is readable") {
        let p = e.expect("a directory entry").path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// The module a source file defines (`src/cpu/render.rs` → cpu::render; the binary → cli).
fn module_of(src: &Path, file: &Path) -> Module {
    let rel = file
        .strip_prefix(src)
        .expect("under src/")
        .with_extension("");
    let mut m: Module = rel
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    if m.last().is_some_and(|l| l == "mod" || l == "lib") {
        m.pop();
    }
    if m == ["main"] {
        m = vec!["cli".to_owned()];
    }
    m
}

/// The code of `text` without comment lines and without its `#[cfg(test)]` tail, on one
/// line, with `prefix::{a, b::c}` groups expanded to `prefix::a prefix::b::c`.
fn code(text: &str) -> String {
    let body = text.split("#[cfg(test)]").next().unwrap_or("");
    let joined: Vec<&str> = body
        .lines()
        .map(str::trim)
        .filter(|l| !l.starts_with("//"))
        .collect();
    expand_groups(&joined.join(" "))
}

fn expand_groups(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    let mut rest = s;
    while let Some(i) = rest.find("::{") {
        let Some(close) = rest[i..].find('}') else {
            break;
        };
        let inner = &rest[i + 3..i + close];
        if inner.contains('{') {
            out.push_str(&rest[..i + 3]);
            rest = &rest[i + 3..];
            continue;
        }
        let start = rest[..i]
            .rfind(|c: char| !(c.is_alphanumeric() || c == '_' || c == ':'))
            .map_or(0, |k| k + 1);
        let prefix = &rest[start..i];
        out.push_str(&rest[..start]);
        for item in inner.split(',').map(str::trim).filter(|x| !x.is_empty()) {
            out.push_str(&format!("{prefix}::{item} "));
        }
        rest = &rest[i + close + 1..];
    }
    out.push_str(rest);
    out
}

/// The modules `code` (of module `me`) refers to by path.
fn imports(me: &Module, code: &str) -> BTreeSet<Module> {
    let bin = me.first().is_some_and(|m| m == "cli");
    let mut out = BTreeSet::new();
    let bytes = code.as_bytes();
    for head in ["crate::", "refract::", "super::"] {
        for (i, _) in code.match_indices(head) {
            let before = i.checked_sub(1).map(|k| bytes[k] as char);
            if before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':') {
                continue;
            }
            let path: Vec<&str> = code[i..]
                .split(|c: char| !(c.is_alphanumeric() || c == '_' || c == ':'))
                .next()
                .unwrap_or("")
                .split("::")
                .collect();
            let supers = path.iter().take_while(|s| **s == "super").count();
            let mut target: Module = match path[0] {
                "crate" if bin => vec![],
                "crate" | "refract" => vec![],
                _ => me[..me.len().saturating_sub(supers)].to_vec(),
            };
            let skip = if path[0] == "super" { supers } else { 1 };
            target.extend(
                path[skip..]
                    .iter()
                    .take_while(|s| s.starts_with(|c: char| c.is_ascii_lowercase()))
                    .map(|s| (*s).to_owned()),
            );
            out.insert(target);
        }
    }
    out
}

/// Every module of the crate and what it imports.
fn graph() -> BTreeMap<Module, BTreeSet<Module>> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut g: BTreeMap<Module, BTreeSet<Module>> = BTreeMap::new();
    for f in files {
        if f.file_name().is_some_and(|n| n == "tests.rs") {
            continue;
        }
        let me = module_of(&src, &f);
        let text = std::fs::read_to_string(&f).expect("a source file");
        g.entry(me.clone())
            .or_default()
            .extend(imports(&me, &code(&text)));
    }
    g
}

/// Edges between sibling units at `depth` (modules cut to `depth` names, same parent).
fn sibling_edges(
    g: &BTreeMap<Module, BTreeSet<Module>>,
    depth: usize,
) -> BTreeMap<Module, BTreeSet<Module>> {
    let mut e: BTreeMap<Module, BTreeSet<Module>> = BTreeMap::new();
    for (a, ts) in g {
        for t in ts {
            let (ua, ut) = (cut(a, depth), cut(t, depth));
            let siblings =
                ua.len() == depth && ut.len() == depth && ua[..depth - 1] == ut[..depth - 1];
            if siblings && ua != ut {
                e.entry(ua).or_default().insert(ut);
            }
        }
    }
    e
}

fn cut(m: &Module, depth: usize) -> Module {
    m[..m.len().min(depth)].to_vec()
}

/// A cycle of `e`, if it has one (depth-first search).
fn find_cycle(e: &BTreeMap<Module, BTreeSet<Module>>) -> Option<Vec<Module>> {
    fn visit(
        v: &Module,
        e: &BTreeMap<Module, BTreeSet<Module>>,
        stack: &mut Vec<Module>,
        done: &mut BTreeSet<Module>,
    ) -> Option<Vec<Module>> {
        if let Some(k) = stack.iter().position(|s| s == v) {
            return Some(stack[k..].to_vec());
        }
        if !done.insert(v.clone()) {
            return None;
        }
        stack.push(v.clone());
        for w in e.get(v).into_iter().flatten() {
            if let Some(c) = visit(w, e, stack, done) {
                return Some(c);
            }
        }
        stack.pop();
        None
    }
    let mut done = BTreeSet::new();
    e.keys()
        .find_map(|v| visit(v, e, &mut Vec::new(), &mut done))
}

#[test]
fn sibling_modules_import_each_other_in_no_circle() {
    let g = graph();
    assert!(g.len() > 100, "only {} modules found", g.len());
    for depth in 1..=3 {
        if let Some(c) = find_cycle(&sibling_edges(&g, depth)) {
            let names: Vec<String> = c.iter().map(|m| m.join("::")).collect();
            panic!("import circle: {} → back", names.join(" → "));
        }
    }
}

#[test]
fn top_level_modules_import_only_lower_layers() {
    let layer = |m: &str| LAYERS.iter().position(|l| l.contains(&m));
    let g = graph();
    // A `super::` inside an inline module resolves one level too high here; such a name is
    // no top-level module and is left out.
    let top: BTreeSet<&String> = g.keys().filter_map(|m| m.first()).collect();
    let mut bad = Vec::new();
    for (a, ts) in &g {
        let Some(from) = a.first() else { continue };
        let Some(la) = layer(from) else {
            bad.push(format!("{from}: not in LAYERS"));
            continue;
        };
        for t in ts {
            let Some(to) = t.first() else { continue };
            if to == from || !top.contains(to) {
                continue;
            }
            match layer(to) {
                Some(lt) if lt < la => {}
                _ => bad.push(format!("{} imports {}", a.join("::"), t.join("::"))),
            }
        }
    }
    assert!(
        bad.is_empty(),
        "imports that do not point down:\n{}",
        bad.join("\n")
    );
}

/// The reader itself: a circle and a group are found where they are.
#[test]
fn the_reader_finds_paths_groups_and_circles() {
    let me: Module = vec!["scene".into(), "env_map".into()];
    let code =
        code("use super::{hdri, gltf::load};\n// crate::app::x\nfn f() { crate::files::read(); }");
    let got = imports(&me, &code);
    let want: BTreeSet<Module> = [
        vec!["scene", "hdri"],
        vec!["scene", "gltf", "load"],
        vec!["files", "read"],
    ]
    .iter()
    .map(|v| v.iter().map(|s| s.to_string()).collect())
    .collect();
    assert_eq!(got, want);
    let mut g = BTreeMap::new();
    g.insert(me.clone(), want);
    g.insert(
        vec!["scene".into(), "hdri".into()],
        [me].into_iter().collect(),
    );
    assert!(find_cycle(&sibling_edges(&g, 2)).is_some());
}
