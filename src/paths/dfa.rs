//! Subset construction, minimisation and canonical numbering of the Glushkov automaton, and
//! the resulting dense table, [`DfaTable`].

use std::collections::{HashMap, VecDeque};

use super::glushkov::{Bits, Glushkov};
use super::parse::Ast;
use super::{MAX_STATES, NUM_SYMBOLS, PathRegexError, Symbol};

/// Largest unminimised DFA the subset construction may build before giving up.
const MAX_SUBSET_STATES: usize = 2048;

/// A complete DFA with arbitrary numbering (before canonicalisation).
struct RawDfa {
    trans: Vec<[usize; NUM_SYMBOLS]>,
    accepting: Vec<bool>,
    start: usize,
}

/// Subset construction over the Glushkov automaton (ASU §3.7.1). The empty set becomes the
/// dead state, so the result is complete.
fn determinise(g: &Glushkov, direction: &'static str) -> Result<RawDfa, PathRegexError> {
    let n = g.symbols.len();
    let follow_by_symbol = follow_by_symbol(g);
    let mut initial = Bits::new(n);
    initial.insert(0);
    let mut subsets = Subsets {
        index: HashMap::new(),
        sets: Vec::new(),
        direction,
    };
    let mut dfa = RawDfa {
        trans: Vec::new(),
        accepting: Vec::new(),
        start: 0,
    };
    subsets.index.insert(initial.clone(), 0);
    subsets.sets.push(initial);
    let mut i = 0;
    while i < subsets.sets.len() {
        let set = subsets.sets[i].clone();
        dfa.accepting
            .push((set.contains(0) && g.nullable) || set.intersects(&g.last));
        let mut row = [0usize; NUM_SYMBOLS];
        for sym in Symbol::ALL {
            let mut next = Bits::new(n);
            for p in set.iter() {
                next.union_with(&follow_by_symbol[p][sym.index()]);
            }
            row[sym.index()] = subsets.id(next)?;
        }
        dfa.trans.push(row);
        i += 1;
    }
    Ok(dfa)
}

/// follow(p) of every position p, split by the symbol of the following position.
fn follow_by_symbol(g: &Glushkov) -> Vec<[Bits; NUM_SYMBOLS]> {
    let n = g.symbols.len();
    g.follow
        .iter()
        .map(|f| {
            Symbol::ALL.map(|sym| {
                let mut b = Bits::new(n);
                for q in f.iter().filter(|&q| g.symbols[q] == sym) {
                    b.insert(q);
                }
                b
            })
        })
        .collect()
}

/// The DFA states found so far by the subset construction: each set of positions and its
/// number, in order of discovery.
struct Subsets {
    index: HashMap<Bits, usize>,
    sets: Vec<Bits>,
    /// Which automaton is being built, for the `TooComplex` error.
    direction: &'static str,
}

impl Subsets {
    /// The number of state `set`, numbering it next if it is new; `TooComplex` when a new
    /// state would exceed `MAX_SUBSET_STATES`.
    fn id(&mut self, set: Bits) -> Result<usize, PathRegexError> {
        if let Some(&id) = self.index.get(&set) {
            return Ok(id);
        }
        if self.sets.len() >= MAX_SUBSET_STATES {
            return Err(PathRegexError::TooComplex {
                limit: MAX_SUBSET_STATES,
                direction: self.direction,
            });
        }
        let id = self.sets.len();
        self.index.insert(set.clone(), id);
        self.sets.push(set);
        Ok(id)
    }
}

/// Moore's partition refinement: start from {accepting, non-accepting} and split blocks by
/// the blocks of their successors until nothing changes. Returns the block of every state.
fn minimise(dfa: &RawDfa) -> (Vec<usize>, usize) {
    let mut block: Vec<usize> = dfa.accepting.iter().map(|&a| usize::from(a)).collect();
    let mut count = 0;
    loop {
        let mut ids: HashMap<(usize, [usize; NUM_SYMBOLS]), usize> = HashMap::new();
        let next: Vec<usize> = (0..dfa.trans.len())
            .map(|s| {
                let key = (block[s], dfa.trans[s].map(|t| block[t]));
                let fresh = ids.len();
                *ids.entry(key).or_insert(fresh)
            })
            .collect();
        let new_count = ids.len();
        block = next;
        if new_count == count {
            return (block, count);
        }
        count = new_count;
    }
}

/// Minimal DFA table in canonical numbering: dead state 0, start state 1 (0 if the language
/// were empty), the rest in breadth-first order of first discovery, symbols in column order.
pub(super) fn compile(ast: &Ast, direction: &'static str) -> Result<DfaTable, PathRegexError> {
    let g = Glushkov::build(ast);
    let raw = determinise(&g, direction)?;
    let (block, nblocks) = minimise(&raw);
    let q = Quotient::new(&raw, &block, nblocks);
    let numbering = Numbering::canonical(&q);
    let num_states = numbering.order.len() + 1;
    if num_states > MAX_STATES {
        return Err(PathRegexError::TooManyStates {
            states: num_states,
            max: MAX_STATES,
            direction,
        });
    }
    Ok(dfa_table(&q, &numbering))
}

/// The quotient automaton of a DFA by its minimisation blocks (one state per block).
struct Quotient {
    trans: Vec<[usize; NUM_SYMBOLS]>,
    accepting: Vec<bool>,
    /// Blocks from which acceptance is reachable.
    live: Vec<bool>,
    /// The block of the start state.
    start: usize,
}

impl Quotient {
    /// Merge the states of `raw` by `block` (as `minimise` returns it, `nblocks` blocks).
    fn new(raw: &RawDfa, block: &[usize], nblocks: usize) -> Quotient {
        let mut trans = vec![[0usize; NUM_SYMBOLS]; nblocks];
        let mut accepting = vec![false; nblocks];
        for s in 0..raw.trans.len() {
            trans[block[s]] = raw.trans[s].map(|t| block[t]);
            accepting[block[s]] = raw.accepting[s];
        }
        let live = live_states(&trans, &accepting);
        Quotient {
            trans,
            accepting,
            live,
            start: block[raw.start],
        }
    }
}

/// The canonical numbering of a quotient automaton's blocks.
struct Numbering {
    /// New state id of each block (None: unreachable from the start).
    new_id: Vec<Option<usize>>,
    /// Blocks in new order (state `i + 1`), excluding the dead block (state 0).
    order: Vec<usize>,
}

impl Numbering {
    /// Dead block 0, then breadth-first order from the start block.
    fn canonical(q: &Quotient) -> Numbering {
        let nblocks = q.trans.len();
        // In a minimal complete DFA all states that cannot reach acceptance are equivalent,
        // so there is at most one; add it when the language needs none (e.g. all paths).
        let dead_block = (0..nblocks).find(|&b| !q.live[b]);
        let mut new_id: Vec<Option<usize>> = vec![None; nblocks];
        let mut order: Vec<usize> = Vec::new();
        if let Some(d) = dead_block {
            new_id[d] = Some(0);
        }
        let mut queue = VecDeque::new();
        if new_id[q.start].is_none() {
            new_id[q.start] = Some(order.len() + 1);
            order.push(q.start);
            queue.push_back(q.start);
        }
        while let Some(b) = queue.pop_front() {
            for t in q.trans[b] {
                if new_id[t].is_none() {
                    new_id[t] = Some(order.len() + 1);
                    order.push(t);
                    queue.push_back(t);
                }
            }
        }
        Numbering { new_id, order }
    }
}

/// The GPU table of quotient `q` in numbering `n` (at most `MAX_STATES` states).
fn dfa_table(q: &Quotient, n: &Numbering) -> DfaTable {
    let mut table = DfaTable {
        transitions: [0; MAX_STATES * NUM_SYMBOLS],
        accepting: 0,
        live: 0,
        start: n.new_id[q.start].unwrap_or(0) as u32,
        dead: 0,
        num_states: (n.order.len() + 1) as u32,
        _pad: [0; 3],
    };
    for (i, &b) in n.order.iter().enumerate() {
        let s = i + 1;
        for (c, &t) in q.trans[b].iter().enumerate() {
            table.transitions[s * NUM_SYMBOLS + c] = n.new_id[t].unwrap_or(0) as u32;
        }
        if q.accepting[b] {
            table.accepting |= 1 << s;
        }
        if q.live[b] {
            table.live |= 1 << s;
        }
    }
    table
}

/// States from which an accepting state is reachable (backward closure of the accepting set).
fn live_states(trans: &[[usize; NUM_SYMBOLS]], accepting: &[bool]) -> Vec<bool> {
    let mut live = accepting.to_vec();
    loop {
        let mut changed = false;
        for s in 0..trans.len() {
            if !live[s] && trans[s].iter().any(|&t| live[t]) {
                live[s] = true;
                changed = true;
            }
        }
        if !changed {
            return live;
        }
    }
}

/// A minimal complete DFA over [`Symbol`]s as a dense table, laid out identically for the CPU
/// and the GPU (see the documentation of the `paths` module). Always valid: built only by
/// [`PathFilter`](super::PathFilter).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(C)]
pub struct DfaTable {
    transitions: [u32; MAX_STATES * NUM_SYMBOLS],
    accepting: u32,
    live: u32,
    start: u32,
    dead: u32,
    num_states: u32,
    _pad: [u32; 3],
}

impl DfaTable {
    /// Size of the table in `u32` words (672 bytes).
    pub const WORDS: usize = MAX_STATES * NUM_SYMBOLS + 8;

    /// The start state.
    pub fn start(&self) -> u32 {
        self.start
    }

    /// The state after reading `symbol` in `state`. States out of range go to the dead state.
    pub fn step(&self, state: u32, symbol: Symbol) -> u32 {
        let s = state as usize;
        if s >= self.num_states as usize {
            return self.dead;
        }
        self.transitions[s * NUM_SYMBOLS + symbol.index()]
    }

    /// Whether a path ending in `state` belongs to the class.
    pub fn is_accepting(&self, state: u32) -> bool {
        state < self.num_states && self.accepting >> state & 1 == 1
    }

    /// Whether `state` is the dead state (a non-accepting sink).
    pub fn is_dead(&self, state: u32) -> bool {
        state == self.dead
    }

    /// Whether some continuation from `state` can still be accepted; `false` means the path
    /// can be terminated. In a minimal DFA this is false only for the dead state.
    pub fn can_reach_accept(&self, state: u32) -> bool {
        state < self.num_states && self.live >> state & 1 == 1
    }

    /// Runs the whole string from the start state.
    pub fn accepts(&self, path: &[Symbol]) -> bool {
        let mut s = self.start;
        for &sym in path {
            s = self.step(s, sym);
            if !self.can_reach_accept(s) {
                return false;
            }
        }
        self.is_accepting(s)
    }

    /// The index of the dead state (always 0).
    pub fn dead(&self) -> u32 {
        self.dead
    }

    /// Number of states in use, the dead state included (2 ..= [`MAX_STATES`]).
    pub fn num_states(&self) -> u32 {
        self.num_states
    }

    /// Transition table, `transitions[state * 5 + symbol.index()]`.
    pub fn transitions(&self) -> &[u32; MAX_STATES * NUM_SYMBOLS] {
        &self.transitions
    }

    /// Bit `s` set iff state `s` accepts.
    pub fn accepting_mask(&self) -> u32 {
        self.accepting
    }

    /// Bit `s` set iff [`DfaTable::can_reach_accept`]`(s)`.
    pub fn live_mask(&self) -> u32 {
        self.live
    }

    /// The table as `u32` words in `#[repr(C)]` field order, ready for a GPU buffer
    /// (`bytemuck::cast_slice(&table.words())`).
    pub fn words(&self) -> [u32; Self::WORDS] {
        let mut w = [0u32; Self::WORDS];
        let n = MAX_STATES * NUM_SYMBOLS;
        w[..n].copy_from_slice(&self.transitions);
        w[n] = self.accepting;
        w[n + 1] = self.live;
        w[n + 2] = self.start;
        w[n + 3] = self.dead;
        w[n + 4] = self.num_states;
        w
    }
}

pub(super) fn accept_all_table() -> DfaTable {
    let mut t = DfaTable {
        transitions: [0; MAX_STATES * NUM_SYMBOLS],
        accepting: 0b10,
        live: 0b10,
        start: 1,
        dead: 0,
        num_states: 2,
        _pad: [0; 3],
    };
    t.transitions[NUM_SYMBOLS..2 * NUM_SYMBOLS].fill(1);
    t
}
