//! Writes terms back as Prolog text that reads back as the same term.
//!
//! One writer serves every IR: a term type implements [`TermView`] to show the printer what
//! it is, and [`write_term`] handles operators (with parentheses only where priorities need
//! them), lists, and atom quoting. The AST printer (`--dump-after=parse`), the HIR printer and
//! the messages of diagnostics all go through it, so a term looks the same everywhere.

use super::ast::{Clause, SourceAst, Term, TermKind};
use super::ops;
use crate::intern::{Interner, Symbol, sym};

/// How a term looks to the printer.
pub enum View<'a, T> {
    /// An atom.
    Atom(Symbol),
    /// A variable, by its printed name.
    Var(std::borrow::Cow<'a, str>),
    /// An integer.
    Int(i64),
    /// A float.
    Float(f64),
    /// A string's contents.
    Str(Symbol),
    /// A compound; `'[|]'(H, T)` prints as a list.
    Compound(Symbol, &'a [T]),
    /// A flat xfy chain `a op b op c` of three operands or more (see
    /// [`super::ast::Notation::Chain`]).
    Chain(Symbol, &'a [T]),
    /// A list written as one, with items and an optional tail.
    List(&'a [T], Option<&'a T>),
    /// A recovered syntax error.
    Error,
}

/// What the printer reads besides the term itself: the names of atoms, and whatever else a
/// term type needs to show its variables (a HIR term's variables are numbers, named in the
/// clause's variable table).
pub trait PrintContext {
    /// The names of atoms.
    fn interner(&self) -> &Interner;
}

impl PrintContext for Interner {
    fn interner(&self) -> &Interner {
        self
    }
}

/// Implemented by every term type that can be printed, for the context `C` it is printed in.
/// The printer walks the term itself, so printing builds no copy of it.
pub trait TermView<C: PrintContext + ?Sized>: Sized {
    /// What this term is.
    fn view<'a>(&'a self, context: &'a C) -> View<'a, Self>;
}

impl TermView<Interner> for Term {
    fn view<'a>(&'a self, interner: &'a Interner) -> View<'a, Term> {
        match &self.kind {
            TermKind::Atom(s) => View::Atom(*s),
            TermKind::Var(s) => View::Var(interner.resolve(*s).into()),
            TermKind::Int(i) => View::Int(*i),
            TermKind::Float(f) => View::Float(*f),
            TermKind::Str(s) => View::Str(*s),
            TermKind::Compound(c) if c.notation == super::ast::Notation::Chain => View::Chain(c.functor, &c.args),
            TermKind::Compound(c) => View::Compound(c.functor, &c.args),
            TermKind::List(l) => View::List(&l.items, l.tail.as_deref()),
            TermKind::Error => View::Error,
        }
    }
}

/// Prints `term` as a string, at the highest priority (no outer parentheses).
pub fn term_to_string<C: PrintContext + ?Sized, T: TermView<C>>(interner: &C, term: &T) -> String {
    let mut out = String::new();
    write_term(&mut out, interner, term, 1200);
    out
}

/// Writes `term` into `out`; `max_priority` is the highest operator priority allowed without
/// parentheses (999 for arguments, 1200 at the top).
pub fn write_term<C: PrintContext + ?Sized, T: TermView<C>>(
    out: &mut String,
    context: &C,
    term: &T,
    max_priority: u16,
) {
    let interner = context.interner();
    match term.view(context) {
        View::Atom(s) => {
            // An operator atom standing alone is parenthesised where it could be misread.
            if ops::is_operator(s) && max_priority < 1200 {
                out.push('(');
                ops::write_atom(out, interner, s);
                out.push(')');
            } else {
                ops::write_atom(out, interner, s);
            }
        }
        View::Var(name) => out.push_str(&name),
        View::Int(i) => {
            use std::fmt::Write;
            let _ = write!(out, "{i}");
        }
        View::Float(f) => {
            use std::fmt::Write;
            let _ = write!(out, "{f:?}");
        }
        View::Str(s) => {
            out.push('"');
            for c in interner.resolve(s).chars() {
                match c {
                    '"' => out.push_str("\\\""),
                    '\\' => out.push_str("\\\\"),
                    '\n' => out.push_str("\\n"),
                    c => out.push(c),
                }
            }
            out.push('"');
        }
        View::Error => out.push_str("<error>"),
        View::List(items, tail) => write_list(out, context, items.iter(), tail),
        View::Chain(functor, operands) => write_infix(out, context, functor, operands, max_priority),
        View::Compound(functor, args) => {
            if functor == sym::CONS && args.len() == 2 {
                write_cons_list(out, context, &args[0], &args[1]);
            } else if args.len() == 2 && ops::infix(functor).is_some() {
                write_infix(out, context, functor, args, max_priority);
            } else if args.len() == 1
                && let Some(op) = ops::prefix(functor)
            {
                let (_, arg_limit) = op.argument_limits();
                let parens = op.priority > max_priority;
                if parens {
                    out.push('(');
                }
                ops::write_atom(out, interner, functor);
                out.push(' ');
                write_term(out, context, &args[0], arg_limit);
                if parens {
                    out.push(')');
                }
            } else {
                ops::write_atom(out, interner, functor);
                out.push('(');
                for (i, arg) in args.iter().enumerate() {
                    if i > 0 {
                        out.push_str(", ");
                    }
                    write_term(out, context, arg, 999);
                }
                out.push(')');
            }
        }
    }
}

fn write_list<'a, C: PrintContext + ?Sized, T: TermView<C> + 'a>(
    out: &mut String,
    context: &C,
    items: impl Iterator<Item = &'a T>,
    tail: Option<&T>,
) {
    out.push('[');
    for (i, item) in items.enumerate() {
        if i > 0 {
            out.push_str(", ");
        }
        write_term(out, context, item, 999);
    }
    if let Some(tail) = tail {
        out.push('|');
        write_term(out, context, tail, 999);
    }
    out.push(']');
}

/// Writes `a op b op ... op z` for the infix operator `functor`: a binary term (two operands)
/// or a flat chain standing for the right-nested one. Every operand but the last is written at
/// the left argument's limit, the last at the right one's.
fn write_infix<C: PrintContext + ?Sized, T: TermView<C>>(
    out: &mut String,
    context: &C,
    functor: Symbol,
    operands: &[T],
    max_priority: u16,
) {
    let interner = context.interner();
    let op = ops::infix(functor).expect("only infix operators are written infix");
    let (left, right) = op.argument_limits();
    let parens = op.priority > max_priority;
    if parens {
        out.push('(');
    }
    for (i, operand) in operands.iter().enumerate() {
        if i > 0 {
            if functor == sym::COMMA {
                out.push_str(", ");
            } else {
                out.push(' ');
                ops::write_atom(out, interner, functor);
                out.push(' ');
            }
        }
        write_term(out, context, operand, if i + 1 == operands.len() { right } else { left });
    }
    if parens {
        out.push(')');
    }
}

fn write_cons_list<C: PrintContext + ?Sized, T: TermView<C>>(out: &mut String, context: &C, head: &T, tail: &T) {
    out.push('[');
    write_term(out, context, head, 999);
    let mut rest = tail;
    loop {
        match rest.view(context) {
            View::Atom(s) if s == sym::NIL => break,
            View::Compound(functor, args) if functor == sym::CONS && args.len() == 2 => {
                out.push_str(", ");
                write_term(out, context, &args[0], 999);
                rest = &args[1];
            }
            _ => {
                out.push('|');
                write_term(out, context, rest, 999);
                break;
            }
        }
    }
    out.push(']');
}

/// Prints a whole parsed file, one clause per line, for `--dump-after=parse`.
pub fn print_source(interner: &Interner, ast: &SourceAst) -> String {
    let mut out = String::new();
    for clause in &ast.clauses {
        print_clause(&mut out, interner, clause);
    }
    out
}

fn print_clause(out: &mut String, interner: &Interner, clause: &Clause) {
    write_term(out, interner, &clause.term, 1200);
    end_clause(out);
}

/// Ends a printed clause with `.`, after a space when the text ends in a symbol character:
/// `a :- b =..` followed directly by `.` would read as the atom `=...`.
pub fn end_clause(out: &mut String) {
    if out.ends_with(|c: char| "+-*/\\^<>=~:.?@#&$".contains(c)) {
        out.push(' ');
    }
    out.push_str(".\n");
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diag::Diagnostics;
    use crate::source::FileId;
    use crate::syntax::parser::parse_source;

    fn round_trip(text: &str) -> String {
        let mut interner = Interner::new();
        let mut diags = Diagnostics::new();
        let ast = parse_source(FileId(0), text, &mut interner, &mut diags);
        assert!(diags.is_empty(), "{text}: {diags:?}");
        print_source(&interner, &ast)
    }

    #[test]
    fn operators_print_with_minimal_parentheses() {
        assert_eq!(round_trip("a :- b, c ; d -> e."), "a :- b, c ; d -> e.\n");
        assert_eq!(round_trip("x(A) :- A is (1 + 2) * 3 - 4 / 5."), "x(A) :- A is (1 + 2) * 3 - 4 / 5.\n");
        assert_eq!(round_trip("y :- X = (a, b), \\+ p(X)."), "y :- X = (a, b), \\+ p(X).\n");
        assert_eq!(round_trip("z(1 - (2 - 3), (1 - 2) - 3)."), "z(1 - (2 - 3), 1 - 2 - 3).\n");
        assert_eq!(round_trip(":- dynamic foo/1, bar/2."), ":- dynamic foo / 1, bar / 2.\n");
    }

    #[test]
    fn swi_prolog_readings_of_operators_round_trip() {
        // An infix operator right after a term, directly followed by `(`, is the operator.
        assert_eq!(round_trip("p(2*(3+4), a-(b), X is(1))."), "p(2 * (3 + 4), a - b, X is 1).\n");
        // With nothing before it, it is the functor of a compound.
        assert_eq!(round_trip("p(-(1), =(a, b))."), "p(- 1, a = b).\n");
        // An operator alone as an operand is an atom.
        assert_eq!(round_trip("p(+, [-, mod, rem], (*))."), "p((+), [(-), (mod), (rem)], (*)).\n");
        // SWI-Prolog's other operators of the table, at their priorities.
        assert_eq!(
            round_trip("p(X @< Y, T =.. L, a^b^c, 2**3, 7 rem 2 xor 1)."),
            "p(X @< Y, T =.. L, a ^ b ^ c, 2 ** 3, 7 rem 2 xor 1).\n"
        );
        assert_eq!(
            round_trip("p(\\ 5 /\\ 3 \\/ 1, 1 << 2 >> 3, A =@= B, - a ^ b)."),
            "p(\\ 5 /\\ 3 \\/ 1, 1 << 2 >> 3, A =@= B, - a ^ b).\n"
        );
        // Arguments of priority above 999 where no `,` makes them ambiguous.
        assert_eq!(round_trip("p(a ; b, (c, d), e -> f, g :- h)."), "p((a ; b), (c, d), (e -> f), (g :- h)).\n");
    }

    #[test]
    fn symbolic_atoms_keep_their_own_period() {
        assert_eq!(round_trip("x :- \\+. ."), "x :- \\+. .\n");
        assert_eq!(round_trip("'/*'."), "'/*'.\n");
    }

    #[test]
    fn lists_and_quoting_round_trip() {
        assert_eq!(round_trip("p([a, 'B c', \"s\" | T], [], f())."), "p([a, 'B c', \"s\"|T], [], f()).\n");
        assert_eq!(round_trip("q(-1, - 1, -(1), 2.5e3)."), "q(-1, - 1, - 1, 2500.0).\n");
    }

    #[test]
    fn printing_is_a_fixed_point() {
        let text = "action(grip_start(A, B), [ontable(B, X, Y), available(A)], [gripped(_, B)], [], [X > 0, (X \\== 1 ; Y =:= 2)], [del(available(A)), add(gripping(A, B))]).\n";
        let once = round_trip(text);
        assert_eq!(round_trip(&once), once);
    }
}
