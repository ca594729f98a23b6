//! The Glushkov position automaton of an expression (`nullable`/`firstpos`/`lastpos`/
//! `followpos`), over a fixed-width bit set of positions.

use super::Symbol;
use super::parse::Ast;

/// Fixed-width bit set over NFA positions.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub(super) struct Bits(Vec<u64>);

impl Bits {
    pub(super) fn new(n: usize) -> Bits {
        Bits(vec![0; n.div_ceil(64)])
    }
    pub(super) fn insert(&mut self, i: usize) {
        self.0[i / 64] |= 1 << (i % 64);
    }
    pub(super) fn contains(&self, i: usize) -> bool {
        self.0[i / 64] >> (i % 64) & 1 == 1
    }
    pub(super) fn union_with(&mut self, other: &Bits) {
        for (a, b) in self.0.iter_mut().zip(&other.0) {
            *a |= b;
        }
    }
    pub(super) fn intersects(&self, other: &Bits) -> bool {
        self.0.iter().zip(&other.0).any(|(a, b)| a & b != 0)
    }
    pub(super) fn iter(&self) -> impl Iterator<Item = usize> + '_ {
        self.0.iter().enumerate().flat_map(|(w, &word)| {
            (0..64)
                .filter(move |b| word >> b & 1 == 1)
                .map(move |b| w * 64 + b)
        })
    }
}

/// Glushkov (position) automaton. Position 0 is the initial state; positions `1..=n` are the
/// symbol occurrences of the expression.
pub(super) struct Glushkov {
    pub(super) symbols: Vec<Symbol>, // symbols[0] is unused
    pub(super) follow: Vec<Bits>,
    pub(super) last: Bits,
    pub(super) nullable: bool,
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
    pub(super) fn build(ast: &Ast) -> Glushkov {
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
