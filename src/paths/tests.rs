use super::*;

fn ast(s: &str) -> Ast {
    parse_ast(s).unwrap().unwrap()
}

#[test]
fn reversal_reverses_concatenations() {
    assert_eq!(ast("LS+DE").reversed(), ast("ED(S)+L"));
    assert_eq!(ast("L(DG|S)*E").reversed(), ast("E(GD|S)*L"));
}

#[test]
fn stacked_operators_fold() {
    assert_eq!(ast("L**"), ast("L*"));
    assert_eq!(ast("L+?"), ast("L*"));
    assert_eq!(ast("L?+"), ast("L*"));
    assert_eq!(ast("L??"), ast("L?"));
    assert_eq!(ast("L++"), ast("L+"));
}

#[test]
fn accept_all_table_matches_compiled_any_star() {
    assert_eq!(
        compile(&Ast::any_star(), "forward").unwrap(),
        accept_all_table()
    );
}

#[test]
fn canonical_numbering_makes_equivalent_expressions_equal() {
    let a = PathFilter::parse("L(D|S)*E").unwrap();
    let b = PathFilter::parse("L(S|D)*E | LE").unwrap();
    assert_eq!(a.forward(), b.forward());
    assert_eq!(a.reversed(), b.reversed());
    let c = PathFilter::parse("LS+DE").unwrap();
    let d = PathFilter::parse("LSS*DE").unwrap();
    assert_eq!(c.forward(), d.forward());
}

#[test]
fn unused_rows_point_to_dead_and_words_match_fields() {
    let f = PathFilter::parse("LDS+E").unwrap();
    let t = f.forward();
    assert_eq!(t.dead(), 0);
    for i in t.num_states() as usize * NUM_SYMBOLS..MAX_STATES * NUM_SYMBOLS {
        assert_eq!(t.transitions()[i], 0);
    }
    let w = t.words();
    assert_eq!(&w[..160], &t.transitions()[..]);
    assert_eq!(
        w[160..165],
        [
            t.accepting_mask(),
            t.live_mask(),
            t.start(),
            0,
            t.num_states()
        ]
    );
    assert_eq!(std::mem::size_of::<DfaTable>(), DfaTable::WORDS * 4);
}

#[test]
fn nesting_and_length_limits() {
    let deep = "(".repeat(MAX_NESTING + 1) + "L" + &")".repeat(MAX_NESTING + 1);
    assert_eq!(
        PathFilter::parse(&deep).unwrap_err(),
        PathRegexError::TooDeep {
            position: MAX_NESTING,
            max: MAX_NESTING
        }
    );
    let ok = "(".repeat(MAX_NESTING) + "L" + &")".repeat(MAX_NESTING);
    assert!(PathFilter::parse(&ok).unwrap().accepts_str("L"));
    let long = "L".repeat(MAX_SOURCE_CHARS + 1);
    assert!(matches!(
        PathFilter::parse(&long),
        Err(PathRegexError::TooLong { .. })
    ));
}

#[test]
fn adversarial_inputs_fail_fast() {
    let t = std::time::Instant::now();
    let any = "(L|D|G|S|E)*";
    let cases = [
        // Longest accepted input, many positions, tiny DFA.
        "(L|D|G|S|E)".repeat(MAX_SOURCE_CHARS / 11),
        // Exponential subset construction.
        format!("{any}L{}", "(L|D|G|S|E)".repeat(80)),
        format!("{}{}", "(L*D*G*S*E*)*".repeat(70), "L"),
        "(".repeat(MAX_NESTING) + &"L|".repeat(400) + "D" + &")*".repeat(MAX_NESTING),
        "L".repeat(10 * MAX_SOURCE_CHARS),
    ];
    for src in &cases {
        let _ = PathFilter::parse(src);
    }
    assert!(t.elapsed().as_secs_f64() < 5.0, "{:?}", t.elapsed());
}
