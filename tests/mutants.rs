//! Seeded mutation loop (issue 16, part 7): 2,000 mutants of each built-in scene's .glb —
//! byte flips in the JSON chunk, hostile values spliced in place of JSON numbers, flips in
//! the binary chunk and truncations — must each load into a scene that validates or be
//! refused with an error; never a panic. The whole loop runs in well under 60 s (release).

use refract::gltf_io::export::export_glb;
use refract::gltf_io::load::load_slice;
use refract::scene::Scene;

/// xorshift64 (Marsaglia 2003): a reproducible stream for the mutations.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// Values that break loaders: extremes, wrong types, huge counts and indices.
const HOSTILE: &[&str] = &[
    "0",
    "-1",
    "1e39",
    "-1e39",
    "1e-45",
    "4294967295",
    "4294967296",
    "18446744073709551615",
    "268435456",
    "2147483648",
    "null",
    "true",
    "\"x\"",
    "[]",
    "{}",
    "[1e39,1e39,1e39]",
    "[0,0,0,0]",
    "-0",
    "0.5",
    "3",
    "65535",
];

/// The byte range of a GLB's JSON chunk.
fn json_range(glb: &[u8]) -> std::ops::Range<usize> {
    let len = u32::from_le_bytes([glb[12], glb[13], glb[14], glb[15]]) as usize;
    20..20 + len
}

/// Splice a hostile value over one number of the JSON chunk (keeping the chunk's length
/// field honest by padding or re-declaring it).
fn splice_value(glb: &[u8], rng: &mut Rng) -> Vec<u8> {
    let r = json_range(glb);
    let json = &glb[r.clone()];
    let starts: Vec<usize> = (1..json.len())
        .filter(|&i| {
            json[i].is_ascii_digit() && !json[i - 1].is_ascii_alphanumeric() && json[i - 1] != b'.'
        })
        .collect();
    let Some(&at) = starts.get(rng.below(starts.len())) else {
        return glb.to_vec();
    };
    let end = (at..json.len())
        .find(|&i| !(json[i].is_ascii_digit() || b".eE+-".contains(&json[i])))
        .unwrap_or(json.len());
    let mut text = json[..at].to_vec();
    text.extend(HOSTILE[rng.below(HOSTILE.len())].as_bytes());
    text.extend(&json[end..]);
    while !text.len().is_multiple_of(4) {
        text.push(b' ');
    }
    let bin = &glb[r.end..];
    let mut out = glb[..12].to_vec();
    out[8..12].copy_from_slice(&((20 + text.len() + bin.len()) as u32).to_le_bytes());
    out.extend((text.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(text);
    out.extend(bin);
    out
}

/// One mutant of `glb`.
fn mutate(glb: &[u8], rng: &mut Rng) -> Vec<u8> {
    let mut v = glb.to_vec();
    let json = json_range(glb);
    match rng.below(8) {
        0..=2 => {
            for _ in 0..1 + rng.below(4) {
                let i = json.start + rng.below(json.len());
                v[i] = rng.next() as u8;
            }
        }
        3..=5 => v = splice_value(glb, rng),
        6 => {
            for _ in 0..1 + rng.below(8) {
                let i = rng.below(v.len());
                v[i] = rng.next() as u8;
            }
        }
        _ => v.truncate(rng.below(v.len())),
    }
    v
}

#[test]
fn two_thousand_mutants_of_every_built_in_never_panic() {
    let t0 = std::time::Instant::now();
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let (mut ok, mut err) = (0usize, 0usize);
    for name in refract::scene::builtin::NAMES {
        let glb = export_glb(&Scene::load(&format!("builtin:{name}")).expect("built-in"))
            .expect("export");
        for k in 0..2000 {
            let m = mutate(&glb, &mut rng);
            let got = std::panic::catch_unwind(|| load_slice(&m, None, "mutant"));
            match got {
                Ok(Ok(s)) => {
                    if let Err(e) = s.validate() {
                        panic!("{name} mutant {k} loaded but does not validate: {e:#}");
                    }
                    ok += 1;
                }
                Ok(Err(_)) => err += 1,
                Err(_) => panic!("{name} mutant {k} panicked the loader"),
            }
        }
    }
    let took = t0.elapsed();
    eprintln!("mutants: {ok} loaded, {err} refused in {took:.1?}");
    assert!(ok > 0 && err > 0, "ok {ok}, err {err}");
    assert!(took.as_secs_f64() < 60.0, "took {took:?}");
}

/// Splice a hostile value over one number of a JSON text.
fn splice_text(json: &str, rng: &mut Rng) -> String {
    let b = json.as_bytes();
    let starts: Vec<usize> = (1..b.len())
        .filter(|&i| b[i].is_ascii_digit() && !b[i - 1].is_ascii_alphanumeric() && b[i - 1] != b'.')
        .collect();
    let Some(&at) = starts.get(rng.below(starts.len())) else {
        return json.to_owned();
    };
    let end = (at..b.len())
        .find(|&i| !(b[i].is_ascii_digit() || b".eE+-".contains(&b[i])))
        .unwrap_or(b.len());
    format!(
        "{}{}{}",
        &json[..at],
        HOSTILE[rng.below(HOSTILE.len())],
        &json[end..]
    )
}

/// The same for settings sidecars (the path `render --settings` takes: parse, check each
/// edit, apply, validate): 2,000 mutants of a sidecar with every kind of edit, never a panic,
/// and a sidecar that passes the checks gives a scene that validates or a clear error.
#[test]
fn two_thousand_sidecar_mutants_never_panic() {
    use refract::render::settings::ViewerSettings;
    let base = Scene::load("builtin:prism").expect("built-in");
    let mut s = ViewerSettings::for_scene("builtin:prism");
    for (i, m) in base.materials.iter().enumerate() {
        s.set_material(i, m);
    }
    s.render.max_depth = Some(12);
    let seed = serde_json::to_string(&s).expect("json");
    let mut rng = Rng(0xd1b5_4a32_d192_ed03);
    let (mut applied, mut refused) = (0, 0);
    for k in 0..2000 {
        let text = if rng.below(4) == 0 {
            let mut t = seed.clone().into_bytes();
            let i = rng.below(t.len());
            t[i] = b"{}[],:\"0-e"[rng.below(10)];
            String::from_utf8(t).expect("ascii")
        } else {
            splice_text(&seed, &mut rng)
        };
        let run = std::panic::catch_unwind(|| {
            let s = ViewerSettings::parse(&text).ok()?;
            let checked = s.materials.iter().all(|m| m.check().is_ok()) && s.light.check().is_ok();
            checked.then(|| s.apply(&base).0.validate().is_ok())
        });
        match run {
            Ok(Some(_)) => applied += 1,
            Ok(None) => refused += 1,
            Err(_) => panic!("sidecar mutant {k} panicked: {text}"),
        }
    }
    eprintln!("sidecar mutants: {applied} applied, {refused} refused");
    assert!(
        applied > 0 && refused > 0,
        "applied {applied}, refused {refused}"
    );
}
