// path_filter.wgsl — the Heckbert path filter on the GPU: twin of `paths::DfaTable`
// (src/paths.rs, "Table layout"). The table is `PathFilter::reversed().words()` (eye→light
// order) in the parameters (`params.path_filter`, rows of four words: word i is row i / 4, lane
// i % 4). Offsets (DFA_*) and symbols (SYM_*, `paths::Symbol`) come from the generated
// prelude.

// A Heckbert path filter is set (the table is data; only its presence is specialised).
override HAS_FILTER: bool = true;

fn dfa_word(i: u32) -> u32 {
    return params.path_filter[i / 4u][i % 4u];
}

// The start state. Twin of `DfaTable::start`.
fn dfa_table_start() -> u32 {
    return dfa_word(DFA_START);
}

// The state after reading `symbol` in `state`; out-of-range states go to the dead state.
// Twin of `DfaTable::step`.
fn dfa_table_step(state: u32, symbol: u32) -> u32 {
    if state >= dfa_word(DFA_NUM_STATES) {
        return dfa_word(DFA_DEAD);
    }
    return dfa_word(state * DFA_NUM_SYMBOLS + symbol);
}

// Twin of `DfaTable::is_accepting`.
fn dfa_table_is_accepting(state: u32) -> bool {
    return state < dfa_word(DFA_NUM_STATES) && ((dfa_word(DFA_ACCEPTING) >> state) & 1u) == 1u;
}

// Twin of `DfaTable::can_reach_accept`.
fn dfa_table_can_reach_accept(state: u32) -> bool {
    return state < dfa_word(DFA_NUM_STATES) && ((dfa_word(DFA_LIVE) >> state) & 1u) == 1u;
}
