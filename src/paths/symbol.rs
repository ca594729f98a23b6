//! [`Symbol`]: the path events of Heckbert's notation, one column each of the DFA table.

use std::fmt;

use super::{NUM_SYMBOLS, PathRegexError};
use crate::bsdf::Lobe;

/// A path event (Heckbert 1990). The discriminant is the column in [`DfaTable`](super::DfaTable).
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
