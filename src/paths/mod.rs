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

mod dfa;
mod error;
mod glushkov;
mod parse;
mod symbol;
#[cfg(test)]
mod tests;

use std::fmt;
use std::str::FromStr;

use dfa::{accept_all_table, compile};
use parse::{Ast, parse_ast};

pub use dfa::DfaTable;
pub use error::PathRegexError;
pub use symbol::Symbol;

/// Number of symbols in the alphabet (`L D G S E`).
pub const NUM_SYMBOLS: usize = 5;
/// Largest number of DFA states a filter may need, the dead state included.
pub const MAX_STATES: usize = 32;
/// Longest accepted expression, in characters.
pub const MAX_SOURCE_CHARS: usize = 1024;
/// Deepest accepted parenthesis nesting.
pub const MAX_NESTING: usize = 32;

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
