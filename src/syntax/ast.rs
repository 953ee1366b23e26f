//! The syntax tree: terms exactly as written, with a span on every node.
//!
//! The AST knows nothing about actions or problems; it is Prolog terms and clauses. Operators
//! are already resolved into compounds (`a :- b` is `:-(a, b)`), but the tree remembers the
//! notation so the printer and diagnostics can show terms the way the user wrote them.
//! `TermKind::Error` stands where the parser recovered from a syntax error, so later stages
//! can still look at the rest of the clause.
//!
//! A compound's functor, notation and arguments are boxed, so the numbers, atoms and
//! variables that make up most of a KB stay small (a term is 48 bytes).

use crate::intern::Symbol;
use crate::source::{FileId, Span};

/// A term with its span.
#[derive(Clone, Debug, PartialEq)]
pub struct Term {
    /// What the term is.
    pub kind: TermKind,
    /// The text it was parsed from.
    pub span: Span,
}

/// The kinds of term.
#[derive(Clone, Debug, PartialEq)]
pub enum TermKind {
    /// An atom: `foo`, `'a b'`, `[]` is a `List` with no items instead.
    Atom(Symbol),
    /// A variable; `_` is anonymous (each occurrence distinct).
    Var(Symbol),
    /// An integer.
    Int(i64),
    /// A float.
    Float(f64),
    /// A double-quoted string.
    Str(Symbol),
    /// A compound term, in any notation.
    Compound(Box<Compound>),
    /// A list `[a, b | T]`; `[]` has no items and no tail. Boxed, as a compound is: inline
    /// it would make every term 56 bytes rather than 32 (a body of a million goals is two
    /// million terms).
    List(Box<List>),
    /// Where the parser recovered from an error.
    Error,
}

/// How a compound was written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Notation {
    /// `f(a, b)`.
    Canonical,
    /// `a + b`.
    Infix,
    /// `- a`, `\+ a`, `:- a`.
    Prefix,
    /// `a, b, c, ...`: an xfy operator chain of three operands or more, kept flat. It stands
    /// for the right-nested binary term `','(a, ','(b, c))`: the compound's arity (as
    /// [`Term::callable`] reports it) is 2, and [`Term::xfy_operands`] gives the operands.
    /// The chains of `,`, `->` and `;` are kept flat.
    Chain,
}

/// A compound term.
#[derive(Clone, Debug, PartialEq)]
pub struct Compound {
    /// The name.
    pub functor: Symbol,
    /// Where the name (or operator) is.
    pub functor_span: Span,
    /// The arguments; empty for `f()`.
    pub args: Vec<Term>,
    /// How it was written.
    pub notation: Notation,
}

/// A list.
#[derive(Clone, Debug, PartialEq)]
pub struct List {
    /// The elements before any `|`.
    pub items: Vec<Term>,
    /// The tail after `|`, if written.
    pub tail: Option<Box<Term>>,
}

/// A clause or directive, ended by `.`.
#[derive(Clone, Debug, PartialEq)]
pub struct Clause {
    /// The term, e.g. `:-(head, body)`.
    pub term: Term,
    /// The clause's text including its `.` (or up to where the `.` was missing).
    pub span: Span,
    /// True if the parser recovered from a syntax error somewhere in the clause, so `term`
    /// holds an `Error` node.
    pub recovered: bool,
}

/// One parsed file.
#[derive(Clone, Debug, PartialEq)]
pub struct SourceAst {
    /// The file.
    pub file: FileId,
    /// Its clauses in order, including ones with recovered errors.
    pub clauses: Vec<Clause>,
}

impl Term {
    /// A term of `kind` at `span`.
    pub fn new(kind: TermKind, span: Span) -> Term {
        Term { kind, span }
    }

    /// The placeholder for a recovered error.
    pub fn error(span: Span) -> Term {
        Term { kind: TermKind::Error, span }
    }

    /// An operator application `lhs op rhs`.
    pub fn infix(op: Symbol, op_span: Span, lhs: Term, rhs: Term) -> Term {
        let span = lhs.span.to(rhs.span);
        Term::compound(op, op_span, vec![lhs, rhs], Notation::Infix, span)
    }

    /// A prefix operator application `op arg`.
    pub fn prefix(op: Symbol, op_span: Span, arg: Term) -> Term {
        let span = op_span.to(arg.span);
        Term::compound(op, op_span, vec![arg], Notation::Prefix, span)
    }

    /// A compound term.
    pub fn compound(functor: Symbol, functor_span: Span, args: Vec<Term>, notation: Notation, span: Span) -> Term {
        Term { kind: TermKind::Compound(Box::new(Compound { functor, functor_span, args, notation })), span }
    }

    /// A flat xfy chain `a op b op c ...` of three operands or more ([`Notation::Chain`]).
    pub fn chain(op: Symbol, op_span: Span, operands: Vec<Term>, span: Span) -> Term {
        Term::compound(op, op_span, operands, Notation::Chain, span)
    }

    /// The name and arity if this is an atom or compound (a callable term). A flat chain is
    /// binary.
    pub fn callable(&self) -> Option<(Symbol, usize)> {
        match &self.kind {
            TermKind::Atom(name) => Some((*name, 0)),
            TermKind::Compound(c) if c.notation == Notation::Chain => Some((c.functor, 2)),
            TermKind::Compound(c) => Some((c.functor, c.args.len())),
            _ => None,
        }
    }

    /// The compound if this is one with the given functor and arity, written as one (a flat
    /// chain is not: see [`Term::xfy_operands`]).
    pub fn as_compound(&self, functor: Symbol, arity: usize) -> Option<&Compound> {
        match &self.kind {
            TermKind::Compound(c) if c.functor == functor && c.args.len() == arity && c.notation != Notation::Chain => {
                Some(c)
            }
            _ => None,
        }
    }

    /// The operands of an xfy chain of `functor`, left to right, however it is written:
    /// `a, (b, c), d` gives `a`, `b`, `c`, `d` (the nesting to the right is the same term).
    /// A term that is no such chain is its own only operand.
    pub fn xfy_operands(&self, functor: Symbol) -> Vec<&Term> {
        let mut operands = Vec::new();
        let mut rest = self;
        loop {
            match &rest.kind {
                TermKind::Compound(c)
                    if c.functor == functor && (c.args.len() == 2 || c.notation == Notation::Chain) =>
                {
                    let (last, before) = c.args.split_last().expect("a chain has operands");
                    operands.extend(before);
                    rest = last;
                }
                _ => {
                    operands.push(rest);
                    return operands;
                }
            }
        }
    }

    /// The arguments if this is a compound, or none for an atom.
    pub fn args(&self) -> &[Term] {
        match &self.kind {
            TermKind::Compound(c) => &c.args,
            _ => &[],
        }
    }

    /// The span of the name for callable terms, else the whole span.
    pub fn name_span(&self) -> Span {
        match &self.kind {
            TermKind::Compound(c) => c.functor_span,
            _ => self.span,
        }
    }

    /// True if the term contains a recovered syntax error anywhere.
    pub fn has_error(&self) -> bool {
        match &self.kind {
            TermKind::Error => true,
            TermKind::Compound(c) => c.args.iter().any(Term::has_error),
            TermKind::List(l) => l.items.iter().any(Term::has_error) || l.tail.as_deref().is_some_and(Term::has_error),
            _ => false,
        }
    }

    /// Calls `f` on every variable occurrence, left to right.
    pub fn for_each_var(&self, f: &mut impl FnMut(Symbol, Span)) {
        match &self.kind {
            TermKind::Var(name) => f(*name, self.span),
            TermKind::Compound(c) => c.args.iter().for_each(|a| a.for_each_var(f)),
            TermKind::List(l) => {
                l.items.iter().for_each(|a| a.for_each_var(f));
                if let Some(tail) = &l.tail {
                    tail.for_each_var(f);
                }
            }
            _ => {}
        }
    }
}
