//! Abstract syntax tree and parser of path expressions.

use super::{MAX_NESTING, MAX_SOURCE_CHARS, PathRegexError, Symbol};

/// Regular expression over [`Symbol`]s. The language is never empty (there is no ∅ and no
/// `()`), though it may contain the empty string.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) enum Ast {
    Sym(Symbol),
    Concat(Vec<Ast>),
    Alt(Vec<Ast>),
    Star(Box<Ast>),
    Plus(Box<Ast>),
    Opt(Box<Ast>),
}

impl Ast {
    /// `(L|D|G|S|E)*`.
    pub(super) fn any_star() -> Ast {
        Ast::Star(Box::new(Ast::Alt(Symbol::ALL.map(Ast::Sym).to_vec())))
    }

    /// The expression of the reversed language: concatenations reversed, recursively.
    pub(super) fn reversed(&self) -> Ast {
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
pub(super) fn parse_ast(source: &str) -> Result<Option<Ast>, PathRegexError> {
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
