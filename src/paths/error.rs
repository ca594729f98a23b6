//! [`PathRegexError`]: why a path expression was rejected.

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
    /// The expression is longer than [`MAX_SOURCE_CHARS`](super::MAX_SOURCE_CHARS).
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
