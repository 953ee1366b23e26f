//! The built-in predicates and arithmetic functions of kbc's Prolog subset.
//!
//! This is the one list: the front end's name checks accept exactly these, docs/dsl.md
//! documents them, and the resolution engine implements them. A KB may call a built-in from a
//! rule body or an OnKB slot; it may not define the control constructs or ISO built-ins.

use crate::intern::{Symbol, sym};

/// Built-in predicates, as (name, arity) with a one-line description.
pub const PREDICATES: &[(&str, usize, &str)] = &[
    ("true", 0, "succeeds"),
    ("fail", 0, "fails"),
    ("false", 0, "fails"),
    ("!", 0, "cut: commits to the choices made since the clause was entered"),
    (",", 2, "conjunction"),
    (";", 2, "disjunction, or if-then-else with `->`"),
    ("->", 2, "if-then"),
    ("\\+", 1, "negation as failure"),
    ("not", 1, "negation as failure, as `\\+`"),
    ("=", 2, "unify"),
    ("\\=", 2, "do not unify"),
    ("==", 2, "identical"),
    ("\\==", 2, "not identical"),
    ("is", 2, "evaluate arithmetic"),
    ("<", 2, "arithmetic less than"),
    (">", 2, "arithmetic greater than"),
    ("=<", 2, "arithmetic less or equal"),
    (">=", 2, "arithmetic greater or equal"),
    ("=:=", 2, "arithmetic equal"),
    ("=\\=", 2, "arithmetic not equal"),
    ("member", 2, "list membership"),
];

/// Arithmetic functions `is/2` and the comparisons evaluate, as (name, arity).
pub const FUNCTIONS: &[(&str, usize)] =
    &[("+", 2), ("-", 2), ("*", 2), ("/", 2), ("//", 2), ("mod", 2), ("-", 1), ("abs", 1), ("min", 2), ("max", 2)];

/// True if `name/arity` is a built-in predicate.
pub fn is_builtin_predicate(name: Symbol, arity: usize) -> bool {
    matches!(
        (name, arity),
        (sym::TRUE | sym::FAIL | sym::FALSE | sym::CUT, 0)
            | (sym::COMMA | sym::SEMI | sym::ARROW, 2)
            | (sym::NOT_PROVABLE | sym::NOT, 1)
            | (
                sym::EQ
                    | sym::NOT_UNIFY
                    | sym::IDENTICAL
                    | sym::NOT_IDENTICAL
                    | sym::IS
                    | sym::LT
                    | sym::GT
                    | sym::LE
                    | sym::GE
                    | sym::ARITH_EQ
                    | sym::ARITH_NE
                    | sym::MEMBER,
                2
            )
    )
}

/// True if `name/arity` is a comparison or unification test (it reads no facts).
pub fn is_test(name: Symbol, arity: usize) -> bool {
    arity == 2
        && matches!(
            name,
            sym::EQ
                | sym::NOT_UNIFY
                | sym::IDENTICAL
                | sym::NOT_IDENTICAL
                | sym::IS
                | sym::LT
                | sym::GT
                | sym::LE
                | sym::GE
                | sym::ARITH_EQ
                | sym::ARITH_NE
        )
}

/// SWI-Prolog's debugger, as KBs for the paper's planner switch it on (`:- trace(action, all).`,
/// `leash(-all), trace`): nothing to do with planning, so kbc ignores it with a note.
pub const DEBUGGER: &[(&str, usize)] = &[
    ("leash", 1),
    ("trace", 0),
    ("trace", 1),
    ("trace", 2),
    ("notrace", 0),
    ("spy", 1),
    ("nospy", 1),
    ("debug", 0),
    ("nodebug", 0),
    ("visible", 1),
];

/// True if `name/arity` is one of the [`DEBUGGER`] predicates.
pub fn is_debugger(name: &str, arity: usize) -> bool {
    DEBUGGER.contains(&(name, arity))
}

/// Common SWI-Prolog library predicates that kbc does not provide; named in diagnostics so the
/// user learns it is a deliberate gap rather than a typo.
pub const NOT_PROVIDED: &[&str] = &[
    "format",
    "write",
    "writeln",
    "print",
    "nl",
    "length",
    "append",
    "findall",
    "bagof",
    "setof",
    "assert",
    "assertz",
    "asserta",
    "retract",
    "call",
    "nth0",
    "nth1",
    "msort",
    "sort",
    "between",
    "succ",
    "atom",
    "number",
    "var",
    "nonvar",
    "atom_codes",
    "atom_length",
    "sub_atom",
    "forall",
    "aggregate_all",
    "last",
    "sum_list",
    "max_list",
    "min_list",
    "exclude",
    "include",
    "maplist",
    "select",
    "subtract",
    "memberchk",
    "reverse",
    "nb_getval",
    "b_getval",
];

#[cfg(test)]
mod tests {
    use super::*;
    use crate::intern::Interner;

    #[test]
    fn the_table_and_the_predicate_agree() {
        let mut interner = Interner::new();
        for (name, arity, _) in PREDICATES {
            let symbol = interner.intern(name);
            assert!(is_builtin_predicate(symbol, *arity), "{name}/{arity}");
        }
        let member = interner.intern("member");
        assert!(!is_builtin_predicate(member, 3));
    }
}
