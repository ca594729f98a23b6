//! Heckbert path expressions: parsing, DFA semantics against a backtracking oracle, the
//! reversed DFA, minimality, error positions and the state limit.

use refract::paths::{DfaTable, MAX_STATES, PathFilter, PathRegexError, Symbol};

// ---------------------------------------------------------------------------------------------
// Oracle: a hand-built AST and a straightforward backtracking matcher, independent of the
// crate's parser and automata.
// ---------------------------------------------------------------------------------------------

enum Re {
    Sym(char),
    Cat(Vec<Re>),
    Alt(Vec<Re>),
    Star(Box<Re>),
    Plus(Box<Re>),
    Opt(Box<Re>),
}

fn w(s: &str) -> Re {
    Re::Cat(s.chars().map(Re::Sym).collect())
}
fn cat(v: Vec<Re>) -> Re {
    Re::Cat(v)
}
fn alt(v: Vec<Re>) -> Re {
    Re::Alt(v)
}
fn star(r: Re) -> Re {
    Re::Star(Box::new(r))
}
fn plus(r: Re) -> Re {
    Re::Plus(Box::new(r))
}
fn opt(r: Re) -> Re {
    Re::Opt(Box::new(r))
}

/// Calls `k` with every end position of a match of `re` starting at `i`; true if `k` is.
fn m(re: &Re, s: &[char], i: usize, k: &dyn Fn(usize) -> bool) -> bool {
    match re {
        Re::Sym(c) => i < s.len() && s[i] == *c && k(i + 1),
        Re::Cat(v) => m_cat(v, s, i, k),
        Re::Alt(v) => v.iter().any(|r| m(r, s, i, k)),
        Re::Star(r) => m_star(r, s, i, k),
        Re::Plus(r) => m(r, s, i, &|j| m_star(r, s, j, k)),
        Re::Opt(r) => k(i) || m(r, s, i, k),
    }
}
fn m_cat(v: &[Re], s: &[char], i: usize, k: &dyn Fn(usize) -> bool) -> bool {
    match v.split_first() {
        None => k(i),
        Some((first, rest)) => m(first, s, i, &|j| m_cat(rest, s, j, k)),
    }
}
/// Zero or more iterations; each further iteration must consume input (no ε-loops).
fn m_star(r: &Re, s: &[char], i: usize, k: &dyn Fn(usize) -> bool) -> bool {
    k(i) || m(r, s, i, &|j| j > i && m_star(r, s, j, k))
}
fn oracle(re: &Re, s: &[char]) -> bool {
    m(re, s, 0, &|j| j == s.len())
}

/// The expressions of the exhaustive test with their hand-built oracle ASTs.
fn cases() -> Vec<(&'static str, Re)> {
    let (l, d, g, s, e) = (
        || Re::Sym('L'),
        || Re::Sym('D'),
        || Re::Sym('G'),
        || Re::Sym('S'),
        || Re::Sym('E'),
    );
    vec![
        ("LDE", w("LDE")),
        ("L(D|S)*E", cat(vec![l(), star(alt(vec![d(), s()])), e()])),
        ("LS+DE", cat(vec![l(), plus(s()), d(), e()])),
        ("LDS+E", cat(vec![l(), d(), plus(s()), e()])),
        ("L(S|G)+E", cat(vec![l(), plus(alt(vec![s(), g()])), e()])),
        (
            "L D? (G|S)* E",
            cat(vec![l(), opt(d()), star(alt(vec![g(), s()])), e()]),
        ),
        (
            "(L|E)(DG)*S?(D|E)+",
            cat(vec![
                alt(vec![l(), e()]),
                star(w("DG")),
                opt(s()),
                plus(alt(vec![d(), e()])),
            ]),
        ),
        (
            "L((D|G)S)*(SE|E)",
            cat(vec![
                l(),
                star(cat(vec![alt(vec![d(), g()]), s()])),
                alt(vec![w("SE"), e()]),
            ]),
        ),
        ("(D|G)*", star(alt(vec![d(), g()]))),
        (
            "L(DS?|G+)*E|LS*E",
            alt(vec![
                cat(vec![
                    l(),
                    star(alt(vec![cat(vec![d(), opt(s())]), plus(g())])),
                    e(),
                ]),
                cat(vec![l(), star(s()), e()]),
            ]),
        ),
        (
            "(L?D?)*E",
            cat(vec![star(cat(vec![opt(l()), opt(d())])), e()]),
        ),
        (
            "l(d(s|g)*)+e?",
            cat(vec![
                l(),
                plus(cat(vec![d(), star(alt(vec![s(), g()]))])),
                opt(e()),
            ]),
        ),
        (
            "((L|D)(S|E))*G?",
            cat(vec![
                star(cat(vec![alt(vec![l(), d()]), alt(vec![s(), e()])])),
                opt(g()),
            ]),
        ),
    ]
}

/// Every string over {L,D,G,S,E} of length ≤ `max_len`.
fn all_strings(max_len: usize) -> Vec<Vec<Symbol>> {
    let mut out = vec![vec![]];
    let mut layer: Vec<Vec<Symbol>> = vec![vec![]];
    for _ in 0..max_len {
        let mut next = Vec::with_capacity(layer.len() * 5);
        for p in &layer {
            for sym in Symbol::ALL {
                let mut q = p.clone();
                q.push(sym);
                next.push(q);
            }
        }
        out.extend(next.iter().cloned());
        layer = next;
    }
    out
}

fn chars(p: &[Symbol]) -> Vec<char> {
    p.iter().map(|s| s.as_char()).collect()
}

/// Table-filling minimality check (Hopcroft & Ullman 1979, §3.4): every state other than the
/// dead state is reachable from the start, and every pair of distinct states is
/// distinguishable by some string. Also checks the dead state and the live mask.
fn assert_minimal(t: &DfaTable, what: &str) {
    let n = t.num_states();
    assert!((2..=MAX_STATES as u32).contains(&n), "{what}: {n} states");
    assert!(t.is_dead(t.dead()) && !t.is_accepting(t.dead()));
    for sym in Symbol::ALL {
        assert_eq!(
            t.step(t.dead(), sym),
            t.dead(),
            "{what}: dead state is a sink"
        );
    }
    // Reachability.
    let mut seen = vec![false; n as usize];
    let mut stack = vec![t.start()];
    seen[t.start() as usize] = true;
    while let Some(q) = stack.pop() {
        for sym in Symbol::ALL {
            let r = t.step(q, sym);
            assert!(r < n, "{what}: transition out of range");
            if !seen[r as usize] {
                seen[r as usize] = true;
                stack.push(r);
            }
        }
    }
    for q in 0..n {
        assert!(
            seen[q as usize] || q == t.dead(),
            "{what}: state {q} unreachable"
        );
        assert_eq!(
            t.can_reach_accept(q),
            q != t.dead(),
            "{what}: in a minimal DFA only the dead state is not live (state {q})"
        );
    }
    // Distinguishability.
    let idx = |p: u32, q: u32| (p * n + q) as usize;
    let mut dist = vec![false; (n * n) as usize];
    for p in 0..n {
        for q in 0..n {
            dist[idx(p, q)] = t.is_accepting(p) != t.is_accepting(q);
        }
    }
    loop {
        let mut changed = false;
        for p in 0..n {
            for q in 0..n {
                if !dist[idx(p, q)]
                    && Symbol::ALL
                        .iter()
                        .any(|&s| dist[idx(t.step(p, s), t.step(q, s))])
                {
                    dist[idx(p, q)] = true;
                    changed = true;
                }
            }
        }
        if !changed {
            break;
        }
    }
    for p in 0..n {
        for q in 0..n {
            assert!(
                p == q || dist[idx(p, q)],
                "{what}: states {p} and {q} are equivalent"
            );
        }
    }
}

fn f(src: &str) -> PathFilter {
    PathFilter::parse(src).unwrap_or_else(|e| panic!("{src:?}: {e}"))
}

// ---------------------------------------------------------------------------------------------
// Semantics
// ---------------------------------------------------------------------------------------------

#[test]
fn lde_accepts_only_lde() {
    let p = f("LDE");
    for s in all_strings(6) {
        assert_eq!(
            p.accepts(&s),
            s == [Symbol::L, Symbol::D, Symbol::E],
            "{s:?}"
        );
    }
    assert!(p.accepts_str("LDE"));
    assert!(p.accepts_str("l d e"));
    assert!(!p.accepts_str("LDX"));
}

#[test]
fn diffuse_or_specular_chains() {
    let p = f("L(D|S)*E");
    for s in ["LE", "LDE", "LSDSE", "LDDDDDDDDDDDDDDDDDDDDDDDDDDDDDDDSE"] {
        assert!(p.accepts_str(s), "{s}");
    }
    for s in ["LGE", "L", "E", "", "DE", "LDEE", "LDGE"] {
        assert!(!p.accepts_str(s), "{s}");
    }
}

#[test]
fn caustic_paths() {
    let p = f("LS+DE");
    for s in ["LSDE", "LSSDE", "LSSSSSDE"] {
        assert!(p.accepts_str(s), "{s}");
    }
    for s in ["LDE", "LSE", "LSDDE", "LGDE", "LSD"] {
        assert!(!p.accepts_str(s), "{s}");
    }
    let p = f("LDS+E");
    for s in ["LDSE", "LDSSSE"] {
        assert!(p.accepts_str(s), "{s}");
    }
    for s in ["LDE", "LSE", "LSDE", "LDSDE", "LDSGE"] {
        assert!(!p.accepts_str(s), "{s}");
    }
    let p = f("L(S|G)+E");
    for s in ["LSE", "LGE", "LSGSGGE"] {
        assert!(p.accepts_str(s), "{s}");
    }
    for s in ["LE", "LDE", "LSDE", "LGSDGE"] {
        assert!(!p.accepts_str(s), "{s}");
    }
}

#[test]
fn optional_and_one_or_more() {
    let p = f("LD?E");
    assert!(p.accepts_str("LE") && p.accepts_str("LDE"));
    assert!(!p.accepts_str("LDDE") && !p.accepts_str("LSE"));
    let p = f("LD+E");
    assert!(p.accepts_str("LDE") && p.accepts_str("LDDDE"));
    assert!(!p.accepts_str("LE"));
    let p = f("L(DS)?E");
    assert!(p.accepts_str("LE") && p.accepts_str("LDSE"));
    assert!(!p.accepts_str("LDE") && !p.accepts_str("LDSDSE"));
    let p = f("(LD)+E");
    assert!(p.accepts_str("LDE") && p.accepts_str("LDLDLDE"));
    assert!(!p.accepts_str("E") && !p.accepts_str("LDLE"));
    // Stacked operators: `?` of `+` and `+` of `?` are `*`.
    for (a, b) in [("LD+?E", "LD*E"), ("LD?+E", "LD*E"), ("LD**E", "LD*E")] {
        assert_eq!(f(a).forward(), f(b).forward(), "{a} vs {b}");
    }
}

#[test]
fn empty_expression_accepts_all() {
    for p in [
        f(""),
        f("   \t\n"),
        PathFilter::accept_all(),
        PathFilter::default(),
    ] {
        assert!(p.is_accept_all());
        assert_eq!(p.forward().num_states(), 2);
        for s in all_strings(5) {
            assert!(p.accepts(&s));
            assert!(p.reversed().accepts(&s));
        }
    }
    assert_eq!(f("   ").source(), "   ");
    assert!(f("(L|D|G|S|E)*").is_accept_all());
    assert!(f("(l|d|g|s|e)+?").is_accept_all());
    assert!(!f("L*").is_accept_all());
    assert!(!f("(L|D|G|S|E)+").is_accept_all());
}

#[test]
fn lowercase_and_whitespace() {
    assert_eq!(f("l ( d | s ) * e").forward(), f("L(D|S)*E").forward());
    assert_eq!(f("l ( d | s ) * e").source(), "l ( d | s ) * e");
    assert_eq!(f("LDE").to_string(), "LDE");
    assert_eq!("LDE".parse::<PathFilter>().unwrap(), f("LDE"));
}

/// For every case, every string of length ≤ 7 (97 656 strings): the forward DFA accepts it
/// iff the oracle matches it, the reversed DFA accepts its reversal exactly then, and no
/// prefix of an accepted string is reported as unable to reach acceptance.
#[test]
fn exhaustive_against_backtracking_oracle() {
    let strings = all_strings(7);
    assert_eq!(strings.len(), (0..=7).map(|k| 5usize.pow(k)).sum::<usize>());
    for (src, re) in cases() {
        let p = f(src);
        let (fwd, rev) = (p.forward(), p.reversed());
        let mut accepted = 0usize;
        for s in &strings {
            let expected = oracle(&re, &chars(s));
            accepted += usize::from(expected);
            assert_eq!(p.accepts(s), expected, "{src}: forward on {:?}", chars(s));
            let r: Vec<Symbol> = s.iter().rev().copied().collect();
            assert_eq!(
                rev.accepts(&r),
                expected,
                "{src}: reversed on {:?}",
                chars(&r)
            );
            if expected {
                let mut q = fwd.start();
                let mut qr = rev.start();
                assert!(fwd.can_reach_accept(q) && rev.can_reach_accept(qr));
                for (&a, &b) in s.iter().zip(&r) {
                    q = fwd.step(q, a);
                    qr = rev.step(qr, b);
                    assert!(fwd.can_reach_accept(q), "{src}: prefix of {:?}", chars(s));
                    assert!(rev.can_reach_accept(qr), "{src}: prefix of {:?}", chars(&r));
                }
            }
        }
        assert!(
            accepted > 0,
            "{src}: the test should exercise accepted strings"
        );
        assert_minimal(fwd, src);
        assert_minimal(rev, src);
    }
}

#[test]
fn minimality() {
    // (D|G)*: start (accepting, loops on D and G) and the dead state.
    let p = f("(D|G)*");
    assert_eq!(p.forward().num_states(), 2);
    assert_eq!(p.reversed().num_states(), 2);
    // LDE: dead, start, after L, after LD, after LDE.
    assert_eq!(f("LDE").forward().num_states(), 5);
    // L(D|S)*E: dead, start, loop state, accepting.
    assert_eq!(f("L(D|S)*E").forward().num_states(), 4);
    // Redundant expressions minimise to the same table.
    assert_eq!(f("L(D|S)*E").forward(), f("L(D*S*)*E|LE|LDE").forward());
    for src in ["LS+DE", "LDS+E", "L(S|G)+E", "(L|D|G|S|E)*", "L?E?"] {
        assert_minimal(f(src).forward(), src);
        assert_minimal(f(src).reversed(), src);
    }
}

#[test]
fn camera_path_tracer_uses_the_reversed_table() {
    // A camera path E → S → D → L (eye to light) is the light→eye string "LDSE".
    let p = f("LDS+E");
    let t = p.reversed();
    let mut q = t.start();
    for sym in [Symbol::E, Symbol::S, Symbol::D] {
        q = t.step(q, sym);
        assert!(t.can_reach_accept(q));
    }
    // Next-event estimation forks the state: the light connection is accepted…
    assert!(t.is_accepting(t.step(q, Symbol::L)));
    // …while continuing with another diffuse bounce can never be accepted: terminate.
    let q2 = t.step(q, Symbol::D);
    assert!(!t.can_reach_accept(q2) && t.is_dead(q2));
    // The forward table reads the same path from the light.
    assert!(p.accepts(&[Symbol::L, Symbol::D, Symbol::S, Symbol::E]));
    assert!(
        !p.forward()
            .accepts(&[Symbol::E, Symbol::S, Symbol::D, Symbol::L])
    );
}

#[test]
fn table_layout() {
    let p = f("L(D|S)*E");
    let t = p.forward();
    assert_eq!(std::mem::size_of::<DfaTable>(), 4 * DfaTable::WORDS);
    assert_eq!(DfaTable::WORDS, 168);
    let words = t.words();
    assert_eq!(t.dead(), 0);
    assert_eq!(t.start(), 1);
    for s in 0..MAX_STATES as u32 {
        for sym in Symbol::ALL {
            let expect = if s < t.num_states() {
                t.step(s, sym)
            } else {
                0
            };
            assert_eq!(words[s as usize * 5 + sym.index()], expect);
        }
    }
    assert_eq!(words[160], t.accepting_mask());
    assert_eq!(words[161], t.live_mask());
    assert_eq!(words[162], t.start());
    assert_eq!(words[163], t.dead());
    assert_eq!(words[164], t.num_states());
    assert_eq!(words[165..], [0, 0, 0]);
    // Out-of-range states are safe.
    assert_eq!(t.step(1000, Symbol::L), t.dead());
    assert!(!t.is_accepting(1000) && !t.can_reach_accept(1000) && !t.is_accepting(32));
    assert_eq!(
        Symbol::ALL.map(Symbol::index),
        [0, 1, 2, 3, 4],
        "symbol columns L D G S E"
    );
}

#[test]
fn lobes_map_to_symbols() {
    use refract::bsdf::Lobe;
    assert_eq!(Symbol::from(Lobe::D), Symbol::D);
    assert_eq!(Symbol::from(Lobe::G), Symbol::G);
    assert_eq!(Symbol::from(Lobe::S), Symbol::S);
}

// ---------------------------------------------------------------------------------------------
// Errors
// ---------------------------------------------------------------------------------------------

#[test]
fn error_positions() {
    use PathRegexError::*;
    let cases: Vec<(&str, PathRegexError)> = vec![
        (
            "L.*",
            UnexpectedChar {
                position: 1,
                found: '.',
            },
        ),
        (
            "L x E",
            UnexpectedChar {
                position: 2,
                found: 'x',
            },
        ),
        (
            "LDÉ",
            UnexpectedChar {
                position: 2,
                found: 'É',
            },
        ),
        ("LDE)", UnexpectedClose { position: 3 }),
        (")", UnexpectedClose { position: 0 }),
        ("L(D))E", UnexpectedClose { position: 4 }),
        ("L(DE", UnclosedGroup { position: 1 }),
        ("L((D)E", UnclosedGroup { position: 1 }),
        (
            "*LE",
            DanglingOperator {
                position: 0,
                op: '*',
            },
        ),
        (
            "L|+E",
            DanglingOperator {
                position: 2,
                op: '+',
            },
        ),
        (
            "L(?D)E",
            DanglingOperator {
                position: 2,
                op: '?',
            },
        ),
        ("L||E", EmptyAlternative { position: 2 }),
        ("|LE", EmptyAlternative { position: 0 }),
        ("LE|", EmptyAlternative { position: 3 }),
        ("LE | ", EmptyAlternative { position: 5 }),
        ("L(|D)E", EmptyAlternative { position: 2 }),
        ("L(D|)E", EmptyAlternative { position: 4 }),
        ("L()E", EmptyGroup { position: 1 }),
        ("L( )E", EmptyGroup { position: 1 }),
    ];
    for (src, expected) in cases {
        let err = PathFilter::parse(src).expect_err(src);
        assert_eq!(err, expected, "{src}");
        let msg = err.to_string();
        let position = match expected {
            UnexpectedChar { position, .. }
            | UnexpectedClose { position }
            | UnclosedGroup { position }
            | DanglingOperator { position, .. }
            | EmptyAlternative { position }
            | EmptyGroup { position } => position,
            _ => unreachable!(),
        };
        assert!(
            msg.starts_with(&format!("position {position}: ")),
            "{src}: {msg}"
        );
    }
    assert!(
        PathFilter::parse("LDE)")
            .unwrap_err()
            .to_string()
            .starts_with("position 3: unexpected ')'")
    );
    assert!(
        PathFilter::parse("L.*")
            .unwrap_err()
            .to_string()
            .contains("unexpected character '.'")
    );
}

#[test]
fn too_many_states_is_rejected() {
    // Distinct long words share no prefixes after L and no suffixes before E: the minimal
    // DFA needs a state for almost every prefix.
    let src = "LDDDDDDDDE|LGGGGGGGGE|LSSSSSSSSE|LDGDGDGDGE|LGSGSGSGSE";
    match PathFilter::parse(src) {
        Err(PathRegexError::TooManyStates {
            states,
            max,
            direction,
        }) => {
            assert!(states > MAX_STATES && max == MAX_STATES, "{states}");
            assert_eq!(direction, "forward");
        }
        other => panic!("expected TooManyStates, got {other:?}"),
    }
    // "The 6th symbol from the end is L" needs 2^k states (the DFA must remember the last
    // k symbols); read from the other end the same class needs only k + few states. So the
    // class is small forwards and too big reversed, or the other way round.
    let any = "(L|D|G|S|E)*";
    let ld5 = "(L|D)(L|D)(L|D)(L|D)(L|D)";
    let rev_big = format!("{ld5}L{any}");
    let err = PathFilter::parse(&rev_big).unwrap_err();
    assert!(
        matches!(
            err,
            PathRegexError::TooManyStates {
                direction: "reversed",
                ..
            }
        ),
        "{err}"
    );
    assert!(err.to_string().contains("at most 32"), "{err}");
    assert!(err.to_string().contains("reversed"), "{err}");
    let fwd_big = format!("{any}L{ld5}");
    assert!(matches!(
        PathFilter::parse(&fwd_big),
        Err(PathRegexError::TooManyStates {
            direction: "forward",
            ..
        })
    ));
    // Two symbols fewer fit: 2^4 = 16 combinations of the last four symbols.
    let ok = f(&format!("{any}L(L|D)(L|D)(L|D)"));
    let n = ok.forward().num_states() as usize;
    assert!(n > 16 && n <= MAX_STATES, "{n}");
    assert_minimal(ok.forward(), "Σ*L(L|D)^3");
    assert!(ok.accepts_str("GLDDL") && !ok.accepts_str("GDDDL"));
}
