//! Heckbert path classes: regular expressions over path events compiled to a small DFA.
//!
//! Heckbert (1990), "Adaptive Radiosity Textures for Bidirectional Ray Tracing", SIGGRAPH '90,
//! names the vertices of a light path with the symbols `L` (light), `D` (diffuse), `G` (glossy),
//! `S` (specular) and `E` (eye) and describes classes of paths with regular expressions such
//! as `LDE`, `L(D|S)*E`, `LS+DE` (caustics seen directly on a diffuse surface).
//!
//! # Syntax
//!
//! Symbols `L D G S E` (lowercase accepted), concatenation, alternation `|`, postfix `*`
//! (zero or more), `+` (one or more), `?` (zero or one), parentheses; whitespace is ignored.
//! The empty string (or only whitespace) accepts every path (no filter). There is no `.`
//! wildcard: write `(L|D|G|S|E)`. Errors name the 0-based character position (counted in
//! Unicode scalar values, whitespace included).
//!
//! # Compilation
//!
//! parse → abstract syntax tree → Glushkov position automaton (an ε-free NFA; Glushkov 1961,
//! Berry & Sethi 1986, "From regular expressions to deterministic automata"; the same
//! `nullable`/`firstpos`/`lastpos`/`followpos` construction as Aho, Lam, Sethi, Ullman,
//! *Compilers*, 2nd ed., §3.9.5) → subset construction (ibid. §3.7.1) → minimisation by
//! Moore's partition refinement (Moore 1956; ibid. §3.9.6, Algorithm 3.39; Hopcroft 1971 is
//! the n log n refinement of the same fixed point and gives the same result) → a dense,
//! canonically numbered table ([`DfaTable`]).
//!
//! # Direction
//!
//! Path strings are read from the light to the eye (`L` first, `E` last), but estimators build
//! paths from either end, so every filter holds two tables of the same layout:
//!
//! - [`PathFilter::forward`] reads events in light→eye order. Light tracing (and the light
//!   subpath of a bidirectional estimator) feeds `L`, then the scattering events in the order
//!   the light subpath meets them, then `E` when it connects to the camera.
//! - [`PathFilter::reversed`] is the DFA of the reversed language and reads events in
//!   eye→light order. The camera path tracer (the default CPU and GPU estimator) feeds `E`
//!   at the camera, then one symbol per scattering event in bounce order, then `L` when the
//!   path reaches an emitter (BSDF-sampled hit or next-event connection; a next-event
//!   connection forks the state: `step(state, L)` for the shadow ray, the path continues
//!   from `state`). A contribution counts iff the state after `L` is accepting; a path whose
//!   state cannot reach an accepting state any more ([`DfaTable::can_reach_accept`]) can be
//!   terminated early.
//!
//! # Table layout (identical for CPU and GPU)
//!
//! [`DfaTable::words`] gives the table as `DfaTable::WORDS` (= 168) `u32` words, in the order
//! of the `#[repr(C)]` fields of [`DfaTable`]:
//!
//! | words | field | meaning |
//! |---|---|---|
//! | 0..160 | `transitions` | `transitions[state * 5 + symbol]`, symbols `L=0 D=1 G=2 S=3 E=4` |
//! | 160 | `accepting` | bit `s` set iff state `s` accepts |
//! | 161 | `live` | bit `s` set iff an accepting state is reachable from `s` |
//! | 162 | `start` | start state |
//! | 163 | `dead` | the dead state (a non-accepting sink; always 0) |
//! | 164 | `num_states` | states in use, dead state included (≤ [`MAX_STATES`]) |
//! | 165..168 | padding | zero (keeps the size a multiple of 16 bytes) |
//!
//! Rows of unused states (≥ `num_states`) point to the dead state. In WGSL, a storage buffer
//! can declare `transitions: array<u32, 160>`; a uniform buffer needs a 16-byte array stride,
//! so declare `transitions: array<vec4<u32>, 40>` and read `t[i / 4u][i % 4u]` (same bytes).

use std::collections::{HashMap, VecDeque};
use std::fmt;
use std::str::FromStr;

use crate::bsdf::Lobe;

/// Number of symbols in the alphabet (`L D G S E`).
pub const NUM_SYMBOLS: usize = 5;
/// Largest number of DFA states a filter may need, the dead state included.
pub const MAX_STATES: usize = 32;
/// Longest accepted expression, in characters.
pub const MAX_SOURCE_CHARS: usize = 1024;
/// Deepest accepted parenthesis nesting.
pub const MAX_NESTING: usize = 32;
/// Largest unminimised DFA the subset construction may build before giving up.
const MAX_SUBSET_STATES: usize = 2048;

/// A path event (Heckbert 1990). The discriminant is the column in [`DfaTable`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[repr(u32)]
pub enum Symbol {
    /// Light (emitter).
    L = 0,
    /// Diffuse scattering.
    D = 1,
    /// Glossy scattering (rough, non-delta lobes other than diffuse).
    G = 2,
    /// Specular scattering (delta lobes: mirror, smooth and thin glass).
    S = 3,
    /// Eye (camera).
    E = 4,
}

impl Symbol {
    /// All symbols in table-column order.
    pub const ALL: [Symbol; NUM_SYMBOLS] = [Symbol::L, Symbol::D, Symbol::G, Symbol::S, Symbol::E];

    /// Column index in the transition table (`L=0, D=1, G=2, S=3, E=4`).
    pub const fn index(self) -> usize {
        self as usize
    }

    /// The symbol for a character (`L D G S E`, either case).
    pub const fn from_char(c: char) -> Option<Symbol> {
        match c {
            'L' | 'l' => Some(Symbol::L),
            'D' | 'd' => Some(Symbol::D),
            'G' | 'g' => Some(Symbol::G),
            'S' | 's' => Some(Symbol::S),
            'E' | 'e' => Some(Symbol::E),
            _ => None,
        }
    }

    /// The uppercase letter of the symbol.
    pub const fn as_char(self) -> char {
        match self {
            Symbol::L => 'L',
            Symbol::D => 'D',
            Symbol::G => 'G',
            Symbol::S => 'S',
            Symbol::E => 'E',
        }
    }

    /// Parses a path string such as `"LDSE"` (whitespace ignored, either case).
    pub fn parse_path(s: &str) -> Result<Vec<Symbol>, PathRegexError> {
        let mut out = Vec::with_capacity(s.len());
        for (position, c) in s.chars().enumerate() {
            if c.is_whitespace() {
                continue;
            }
            match Symbol::from_char(c) {
                Some(sym) => out.push(sym),
                None => return Err(PathRegexError::UnexpectedChar { position, found: c }),
            }
        }
        Ok(out)
    }
}

impl fmt::Display for Symbol {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.as_char())
    }
}

impl From<Lobe> for Symbol {
    fn from(lobe: Lobe) -> Symbol {
        match lobe {
            Lobe::D => Symbol::D,
            Lobe::G => Symbol::G,
            Lobe::S => Symbol::S,
        }
    }
}

/// Why a path expression was rejected.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum PathRegexError {
    /// A character that is not a symbol, operator, parenthesis or whitespace.
    #[error(
        "position {position}: unexpected character '{found}' (expected one of L D G S E ( ) | * + ?; there is no '.' wildcard, write (L|D|G|S|E))"
    )]
    UnexpectedChar { position: usize, found: char },
    /// A `)` without a matching `(`.
    #[error("position {position}: unexpected ')' (no matching '(')")]
    UnexpectedClose { position: usize },
    /// A `(` that is never closed; the position is that of the `(`.
    #[error("position {position}: '(' is never closed")]
    UnclosedGroup { position: usize },
    /// `*`, `+` or `?` with nothing before it to repeat.
    #[error("position {position}: dangling operator '{op}' (nothing before it to repeat)")]
    DanglingOperator { position: usize, op: char },
    /// An alternative of `|` is empty; the position is where it should start.
    #[error("position {position}: empty alternative (expected a symbol or '(' here)")]
    EmptyAlternative { position: usize },
    /// `()`; the position is that of the `(`.
    #[error("position {position}: empty group '()'")]
    EmptyGroup { position: usize },
    /// Parentheses nested too deeply; the position is that of the offending `(`.
    #[error("position {position}: parentheses nested deeper than {max}")]
    TooDeep { position: usize, max: usize },
    /// The expression is longer than [`MAX_SOURCE_CHARS`].
    #[error("path expression has {len} characters, at most {max} are supported")]
    TooLong { len: usize, max: usize },
    /// The minimal DFA (of the forward or the reversed language) needs too many states.
    #[error(
        "path expression needs {states} DFA states in the {direction} direction (dead state included); at most {max} are supported"
    )]
    TooManyStates {
        states: usize,
        max: usize,
        direction: &'static str,
    },
    /// The subset construction exceeded its working limit before minimisation.
    #[error(
        "path expression is too complex: its {direction} subset construction exceeds {limit} states"
    )]
    TooComplex {
        limit: usize,
        direction: &'static str,
    },
}

// ---------------------------------------------------------------------------------------------
// Abstract syntax tree and parser
// ---------------------------------------------------------------------------------------------

/// Regular expression over [`Symbol`]s. The language is never empty (there is no ∅ and no
/// `()`), though it may contain the empty string.
#[derive(Clone, Debug, PartialEq, Eq)]
enum Ast {
    Sym(Symbol),
    Concat(Vec<Ast>),
    Alt(Vec<Ast>),
    Star(Box<Ast>),
    Plus(Box<Ast>),
    Opt(Box<Ast>),
}

impl Ast {
    /// `(L|D|G|S|E)*`.
    fn any_star() -> Ast {
        Ast::Star(Box::new(Ast::Alt(Symbol::ALL.map(Ast::Sym).to_vec())))
    }

    /// The expression of the reversed language: concatenations reversed, recursively.
    fn reversed(&self) -> Ast {
        match self {
            Ast::Sym(s) => Ast::Sym(*s),
            Ast::Concat(v) => Ast::Concat(v.iter().rev().map(Ast::reversed).collect()),
            Ast::Alt(v) => Ast::Alt(v.iter().map(Ast::reversed).collect()),
            Ast::Star(a) => Ast::Star(Box::new(a.reversed())),
            Ast::Plus(a) => Ast::Plus(Box::new(a.reversed())),
            Ast::Opt(a) => Ast::Opt(Box::new(a.reversed())),
        }
    }

    /// Applies a postfix operator, folding stacked operators into one (`x**` = `x*`,
    /// `x+?` = `x*`, …) so that operator runs never deepen the tree.
    fn apply(self, op: char) -> Ast {
        let inner = match self {
            Ast::Star(a) => return Ast::Star(a),
            Ast::Plus(a) => {
                return match op {
                    '+' => Ast::Plus(a),
                    _ => Ast::Star(a),
                };
            }
            Ast::Opt(a) => {
                return match op {
                    '?' => Ast::Opt(a),
                    _ => Ast::Star(a),
                };
            }
            other => Box::new(other),
        };
        match op {
            '*' => Ast::Star(inner),
            '+' => Ast::Plus(inner),
            _ => Ast::Opt(inner),
        }
    }
}

struct Parser {
    /// Non-whitespace characters with their 0-based character positions.
    tokens: Vec<(usize, char)>,
    next: usize,
    /// Character count of the whole input (position reported at the end of input).
    end: usize,
}

impl Parser {
    fn peek(&self) -> Option<(usize, char)> {
        self.tokens.get(self.next).copied()
    }

    fn here(&self) -> usize {
        self.peek().map_or(self.end, |(p, _)| p)
    }

    /// alternation := concat ('|' concat)*
    fn alternation(&mut self, depth: usize) -> Result<Ast, PathRegexError> {
        let mut alts = Vec::new();
        loop {
            match self.concat(depth)? {
                Some(a) => alts.push(a),
                None => {
                    return Err(match self.peek() {
                        Some((position, ')')) if depth == 0 && alts.is_empty() => {
                            PathRegexError::UnexpectedClose { position }
                        }
                        _ => PathRegexError::EmptyAlternative {
                            position: self.here(),
                        },
                    });
                }
            }
            match self.peek() {
                Some((_, '|')) => self.next += 1,
                _ => break,
            }
        }
        Ok(if alts.len() == 1 {
            alts.swap_remove(0)
        } else {
            Ast::Alt(alts)
        })
    }

    /// concat := (atom ('*' | '+' | '?')*)*  — `None` when empty.
    fn concat(&mut self, depth: usize) -> Result<Option<Ast>, PathRegexError> {
        let mut items: Vec<Ast> = Vec::new();
        while let Some((position, c)) = self.peek() {
            match c {
                '|' | ')' => break,
                '*' | '+' | '?' => {
                    let Some(last) = items.pop() else {
                        return Err(PathRegexError::DanglingOperator { position, op: c });
                    };
                    items.push(last.apply(c));
                    self.next += 1;
                }
                '(' => {
                    if depth + 1 > MAX_NESTING {
                        return Err(PathRegexError::TooDeep {
                            position,
                            max: MAX_NESTING,
                        });
                    }
                    self.next += 1;
                    if let Some((_, ')')) = self.peek() {
                        return Err(PathRegexError::EmptyGroup { position });
                    }
                    let inner = self.alternation(depth + 1)?;
                    match self.peek() {
                        Some((_, ')')) => self.next += 1,
                        _ => return Err(PathRegexError::UnclosedGroup { position }),
                    }
                    items.push(inner);
                }
                _ => match Symbol::from_char(c) {
                    Some(s) => {
                        items.push(Ast::Sym(s));
                        self.next += 1;
                    }
                    None => return Err(PathRegexError::UnexpectedChar { position, found: c }),
                },
            }
        }
        Ok(match items.len() {
            0 => None,
            1 => items.pop(),
            _ => Some(Ast::Concat(items)),
        })
    }
}

/// Parses an expression; `Ok(None)` for the empty (accept-all) expression.
fn parse_ast(source: &str) -> Result<Option<Ast>, PathRegexError> {
    let len = source.chars().count();
    if len > MAX_SOURCE_CHARS {
        return Err(PathRegexError::TooLong {
            len,
            max: MAX_SOURCE_CHARS,
        });
    }
    let tokens: Vec<(usize, char)> = source
        .chars()
        .enumerate()
        .filter(|(_, c)| !c.is_whitespace())
        .collect();
    if tokens.is_empty() {
        return Ok(None);
    }
    let mut p = Parser {
        tokens,
        next: 0,
        end: len,
    };
    let ast = p.alternation(0)?;
    if let Some((position, c)) = p.peek() {
        // `alternation` stops only at ')' or the end of input at depth 0.
        return Err(if c == ')' {
            PathRegexError::UnexpectedClose { position }
        } else {
            PathRegexError::UnexpectedChar { position, found: c }
        });
    }
    Ok(Some(ast))
}

// ---------------------------------------------------------------------------------------------
// Glushkov automaton, subset construction, minimisation
// ---------------------------------------------------------------------------------------------

/// Fixed-width bit set over NFA positions.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
struct Bits(Vec<u64>);

impl Bits {
    fn new(n: usize) -> Bits {
        Bits(vec![0; n.div_ceil(64)])
    }
    fn insert(&mut self, i: usize) {
        self.0[i / 64] |= 1 << (i % 64);
    }
    fn contains(&self, i: usize) -> bool {
        self.0[i / 64] >> (i % 64) & 1 == 1
    }
    fn union_with(&mut self, other: &Bits) {
        for (a, b) in self.0.iter_mut().zip(&other.0) {
            *a |= b;
        }
    }
    fn intersects(&self, other: &Bits) -> bool {
        self.0.iter().zip(&other.0).any(|(a, b)| a & b != 0)
    }
    fn iter(&self) -> impl Iterator<Item = usize> + '_ {
        self.0.iter().enumerate().flat_map(|(w, &word)| {
            (0..64)
                .filter(move |b| word >> b & 1 == 1)
                .map(move |b| w * 64 + b)
        })
    }
}

/// Glushkov (position) automaton. Position 0 is the initial state; positions `1..=n` are the
/// symbol occurrences of the expression.
struct Glushkov {
    symbols: Vec<Symbol>, // symbols[0] is unused
    follow: Vec<Bits>,
    last: Bits,
    nullable: bool,
}

struct NodeInfo {
    nullable: bool,
    first: Bits,
    last: Bits,
}

fn count_positions(ast: &Ast) -> usize {
    match ast {
        Ast::Sym(_) => 1,
        Ast::Concat(v) | Ast::Alt(v) => v.iter().map(count_positions).sum(),
        Ast::Star(a) | Ast::Plus(a) | Ast::Opt(a) => count_positions(a),
    }
}

impl Glushkov {
    fn build(ast: &Ast) -> Glushkov {
        let n = count_positions(ast) + 1;
        let mut g = Glushkov {
            symbols: vec![Symbol::L; 1],
            follow: Vec::new(),
            last: Bits::new(n),
            nullable: false,
        };
        g.follow = vec![Bits::new(n); n];
        let info = g.visit(ast, n);
        g.follow[0] = info.first;
        g.last = info.last;
        g.nullable = info.nullable;
        g
    }

    /// Number the symbol occurrences of `ast` (from the next free position) and add its
    /// follow pairs; returns its nullable, first and last sets over `n` positions.
    fn visit(&mut self, ast: &Ast, n: usize) -> NodeInfo {
        match ast {
            Ast::Sym(s) => self.visit_sym(*s, n),
            Ast::Concat(items) => self.visit_concat(items, n),
            Ast::Alt(items) => self.visit_alt(items, n),
            Ast::Star(a) | Ast::Plus(a) | Ast::Opt(a) => {
                let mut b = self.visit(a, n);
                if !matches!(ast, Ast::Opt(_)) {
                    for p in b.last.iter() {
                        self.follow[p].union_with(&b.first);
                    }
                }
                if !matches!(ast, Ast::Plus(_)) {
                    b.nullable = true;
                }
                b
            }
        }
    }

    /// A symbol occurrence: the next position, first and last of itself, not nullable.
    fn visit_sym(&mut self, s: Symbol, n: usize) -> NodeInfo {
        let p = self.symbols.len();
        self.symbols.push(s);
        let mut b = Bits::new(n);
        b.insert(p);
        NodeInfo {
            nullable: false,
            first: b.clone(),
            last: b,
        }
    }

    /// A concatenation: each item's first positions follow the last positions so far, which
    /// reach back over nullable items; first extends while the prefix is nullable.
    fn visit_concat(&mut self, items: &[Ast], n: usize) -> NodeInfo {
        let mut acc = NodeInfo {
            nullable: true,
            first: Bits::new(n),
            last: Bits::new(n),
        };
        for item in items {
            let b = self.visit(item, n);
            for p in acc.last.iter() {
                self.follow[p].union_with(&b.first);
            }
            if acc.nullable {
                acc.first.union_with(&b.first);
            }
            let mut last = b.last;
            if b.nullable {
                last.union_with(&acc.last);
            }
            acc.last = last;
            acc.nullable &= b.nullable;
        }
        acc
    }

    /// An alternation: the union of its items' first and last sets, nullable if any item is.
    fn visit_alt(&mut self, items: &[Ast], n: usize) -> NodeInfo {
        let mut acc = NodeInfo {
            nullable: false,
            first: Bits::new(n),
            last: Bits::new(n),
        };
        for item in items {
            let b = self.visit(item, n);
            acc.nullable |= b.nullable;
            acc.first.union_with(&b.first);
            acc.last.union_with(&b.last);
        }
        acc
    }
}

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
fn compile(ast: &Ast, direction: &'static str) -> Result<DfaTable, PathRegexError> {
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

// ---------------------------------------------------------------------------------------------
// Public tables
// ---------------------------------------------------------------------------------------------

/// A minimal complete DFA over [`Symbol`]s as a dense table, laid out identically for the CPU
/// and the GPU (see the module documentation). Always valid: built only by [`PathFilter`].
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

/// A compiled Heckbert path class: the DFA of the language (light→eye order) and of the
/// reversed language (eye→light order). The convenience methods on the filter itself
/// (`start`, `step`, `accepts`, …) use the forward table.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PathFilter {
    source: String,
    forward: DfaTable,
    reversed: DfaTable,
}

impl PathFilter {
    /// Compiles a path expression such as `"L(D|S)*E"`. The empty string (or whitespace)
    /// gives [`PathFilter::accept_all`] (keeping `source` as given).
    pub fn parse(source: &str) -> Result<PathFilter, PathRegexError> {
        let ast = parse_ast(source)?.unwrap_or_else(Ast::any_star);
        let forward = compile(&ast, "forward")?;
        let reversed = compile(&ast.reversed(), "reversed")?;
        Ok(PathFilter {
            source: source.to_owned(),
            forward,
            reversed,
        })
    }

    /// The filter that accepts every path (source `""`).
    pub fn accept_all() -> PathFilter {
        let table = accept_all_table();
        PathFilter {
            source: String::new(),
            forward: table,
            reversed: table,
        }
    }

    /// Whether the filter accepts every path (the empty expression or one equivalent to
    /// `(L|D|G|S|E)*`); renderers may then skip the DFA altogether.
    pub fn is_accept_all(&self) -> bool {
        self.forward == accept_all_table()
    }

    /// The expression as given.
    pub fn source(&self) -> &str {
        &self.source
    }

    /// DFA reading light→eye (`L` first): light tracing, light subpaths.
    pub fn forward(&self) -> &DfaTable {
        &self.forward
    }

    /// DFA of the reversed language, reading eye→light (`E` first): the camera path tracer.
    pub fn reversed(&self) -> &DfaTable {
        &self.reversed
    }

    /// Start state of the forward DFA.
    pub fn start(&self) -> u32 {
        self.forward.start()
    }

    /// Forward DFA transition.
    pub fn step(&self, state: u32, symbol: Symbol) -> u32 {
        self.forward.step(state, symbol)
    }

    /// Whether `state` of the forward DFA accepts.
    pub fn is_accepting(&self, state: u32) -> bool {
        self.forward.is_accepting(state)
    }

    /// Whether `state` is the dead state of the forward DFA.
    pub fn is_dead(&self, state: u32) -> bool {
        self.forward.is_dead(state)
    }

    /// Whether an accepting state of the forward DFA is reachable from `state`.
    pub fn can_reach_accept(&self, state: u32) -> bool {
        self.forward.can_reach_accept(state)
    }

    /// Whether the path (light→eye order) belongs to the class.
    pub fn accepts(&self, path: &[Symbol]) -> bool {
        self.forward.accepts(path)
    }

    /// Whether a path string such as `"LDDE"` (light→eye order, whitespace ignored, either
    /// case) belongs to the class; a string with any other character is rejected (`false`).
    pub fn accepts_str(&self, path: &str) -> bool {
        Symbol::parse_path(path).is_ok_and(|p| self.accepts(&p))
    }
}

fn accept_all_table() -> DfaTable {
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

impl Default for PathFilter {
    fn default() -> PathFilter {
        PathFilter::accept_all()
    }
}

impl FromStr for PathFilter {
    type Err = PathRegexError;
    fn from_str(s: &str) -> Result<PathFilter, PathRegexError> {
        PathFilter::parse(s)
    }
}

impl fmt::Display for PathFilter {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.source)
    }
}

#[cfg(test)]
mod tests {
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
}
