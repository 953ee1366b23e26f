//! The built-in predicates and arithmetic functions of kbc's Prolog subset.
//!
//! This is the one list: the front end's name checks accept exactly these, docs/dsl.md
//! documents them, the language server completes and explains them, and the resolution engine
//! implements them, in one of three places ([`Imp`]): control constructs and tests inside the
//! engine's own dispatch, the other predicates written in Rust as [`Native`]s, and the list
//! library in Prolog (std/library.pl, loaded for a KB that calls it).
//!
//! Which predicates a KB may define itself follows SWI-Prolog 9 ([`Kind`]): the ISO built-ins
//! and control constructs are protected (SWI-Prolog refuses a clause for one, and so does kbc,
//! E0218); the library predicates are not (a KB's own `append/3` replaces the library's, as
//! SWI-Prolog's autoloader gives way to a user definition).

use crate::intern::{Interner, Symbol, sym};

/// Whether a KB may define the predicate itself.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A control construct or ISO built-in: a clause for it is an error (SWI-Prolog's
    /// permission error), E0218.
    Protected,
    /// A library predicate: the KB's own clauses, if it has any, replace kbc's.
    Library,
}

/// Where the engine implements a predicate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Imp {
    /// In the engine's dispatch (`engine::Machine::step`): control, unification, arithmetic;
    /// and `member/2`, whose two clauses the engine adds to every program that lacks it.
    Engine,
    /// In Rust, as one of the engine's natives.
    Native(Native),
    /// In Prolog, in std/library.pl.
    Prolog,
}

/// What the result of a predicate depends on besides the values it is given, for the
/// symmetry pruning of interchangeable constants (`planner::symmetry`), which may treat two
/// atoms as interchangeable only where nothing tells them apart.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reads {
    /// Nothing: atoms are treated alike, and the same solutions come whatever the order of the
    /// clauses that give them.
    Values,
    /// The order of solutions: a list of them (`findall/3`), or only the first (`once/1`).
    Order,
    /// The names of atoms: the standard order of terms (`compare/3`, `sort/2`).
    Names,
    /// Nothing, and it prints: kbc does not (W0016).
    Output,
}

/// An argument of a predicate that is called as a goal, with `extra` more arguments appended
/// (`maplist(P, L)` calls `P` with one more).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Called {
    /// The argument's position, from 0.
    pub arg: usize,
    /// How many arguments the call appends.
    pub extra: usize,
}

/// The predicates the engine implements in Rust.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[allow(missing_docs)]
pub enum Native {
    Var,
    Nonvar,
    Atom,
    Number,
    Integer,
    Float,
    Atomic,
    Compound,
    Callable,
    IsList,
    Ground,
    Compare,
    Before,
    After,
    NotAfter,
    NotBefore,
    Variant,
    NotVariant,
    /// `dif/2`: checked at once, and again after every unification while its terms could
    /// still become identical (`Machine::difs`).
    Dif,
    Functor,
    Arg,
    Univ,
    CopyTerm,
    TermVariables,
    Length,
    Between,
    Succ,
    Plus,
    MustBe,
    Msort,
    Sort,
    Sort4,
    Keysort,
    Findall,
    Findall4,
    Call,
    Once,
    Ignore,
    /// `V^Goal` called as a goal: calls `Goal`.
    Caret,
    Output,
    /// `'$bagof_split'(Template^Goal, Stripped, Witness)`: the goal without its `V^`
    /// prefixes, and the list of its free variables (bagof/3's witness).
    BagofSplit,
    /// `'$bagof_groups'(Pairs, Groups)`: `Witness-Item` pairs sorted on the witness and
    /// grouped by variant witnesses, as `Witness-Items` pairs.
    BagofGroups,
}

/// One built-in predicate.
#[derive(Clone, Copy, Debug)]
pub struct Builtin {
    /// Its name.
    pub name: &'static str,
    /// Its arity.
    pub arity: usize,
    /// What it does, in a line.
    pub what: &'static str,
    /// Whether a KB may define it.
    pub kind: Kind,
    /// Where it is implemented.
    pub imp: Imp,
    /// What its result depends on.
    pub reads: Reads,
    /// The arguments it calls as goals.
    pub calls: &'static [Called],
}

const fn builtin(name: &'static str, arity: usize, kind: Kind, imp: Imp, reads: Reads, what: &'static str) -> Builtin {
    Builtin { name, arity, what, kind, imp, reads, calls: &[] }
}

const fn calling(mut b: Builtin, calls: &'static [Called]) -> Builtin {
    b.calls = calls;
    b
}

const fn goal(arg: usize) -> Called {
    Called { arg, extra: 0 }
}

const fn closure(arg: usize, extra: usize) -> Called {
    Called { arg, extra }
}

use Imp::{Engine, Native as N, Prolog};
use Kind::{Library, Protected};
use Reads::{Names, Order, Output, Values};

/// Built-in predicates, in the order docs/dsl.md lists them.
pub const PREDICATES: &[Builtin] = &[
    // Control.
    builtin("true", 0, Protected, Engine, Values, "succeeds"),
    builtin("fail", 0, Protected, Engine, Values, "fails"),
    builtin("false", 0, Protected, Engine, Values, "fails"),
    builtin("!", 0, Protected, Engine, Order, "cut: commits to the choices made since the clause was entered"),
    calling(builtin(",", 2, Protected, Engine, Values, "conjunction"), &[goal(0), goal(1)]),
    calling(builtin(";", 2, Protected, Engine, Values, "disjunction, or if-then-else with `->`"), &[goal(0), goal(1)]),
    calling(builtin("->", 2, Protected, Engine, Order, "if-then"), &[goal(0), goal(1)]),
    calling(builtin("\\+", 1, Protected, Engine, Values, "negation as failure"), &[goal(0)]),
    calling(builtin("not", 1, Library, Engine, Values, "negation as failure, as `\\+`"), &[goal(0)]),
    calling(
        builtin("call", 1, Protected, N(Native::Call), Values, "calls a goal (a cut inside is local to it)"),
        &[goal(0)],
    ),
    calling(
        builtin("call", 2, Protected, N(Native::Call), Values, "calls a goal with one more argument"),
        &[closure(0, 1)],
    ),
    calling(
        builtin("call", 3, Protected, N(Native::Call), Values, "calls a goal with 2 more arguments"),
        &[closure(0, 2)],
    ),
    calling(
        builtin("call", 4, Protected, N(Native::Call), Values, "calls a goal with 3 more arguments"),
        &[closure(0, 3)],
    ),
    calling(
        builtin("call", 5, Protected, N(Native::Call), Values, "calls a goal with 4 more arguments"),
        &[closure(0, 4)],
    ),
    calling(
        builtin("call", 6, Protected, N(Native::Call), Values, "calls a goal with 5 more arguments"),
        &[closure(0, 5)],
    ),
    calling(
        builtin("call", 7, Protected, N(Native::Call), Values, "calls a goal with 6 more arguments"),
        &[closure(0, 6)],
    ),
    calling(
        builtin("call", 8, Protected, N(Native::Call), Values, "calls a goal with 7 more arguments"),
        &[closure(0, 7)],
    ),
    calling(builtin("once", 1, Protected, N(Native::Once), Order, "the first solution of a goal"), &[goal(0)]),
    calling(
        builtin("ignore", 1, Library, N(Native::Ignore), Order, "calls a goal once, succeeding if it fails"),
        &[goal(0)],
    ),
    calling(
        builtin("forall", 2, Library, Prolog, Values, "every solution of the first goal satisfies the second"),
        &[goal(0), goal(1)],
    ),
    // Unification and comparison.
    builtin("=", 2, Protected, Engine, Values, "unify"),
    builtin("\\=", 2, Protected, Engine, Values, "do not unify"),
    builtin("unify_with_occurs_check", 2, Protected, Engine, Values, "unify (kbc always checks occurrences)"),
    builtin("==", 2, Protected, Engine, Values, "identical"),
    builtin("\\==", 2, Protected, Engine, Values, "not identical"),
    builtin("=@=", 2, Library, N(Native::Variant), Values, "variants: equal up to renaming variables"),
    builtin("\\=@=", 2, Library, N(Native::NotVariant), Values, "not variants"),
    builtin(
        "dif",
        2,
        Library,
        N(Native::Dif),
        Values,
        "different: fails if the terms are identical, and later as soon as bindings make them so",
    ),
    builtin("compare", 3, Protected, N(Native::Compare), Names, "the standard order of two terms: `<`, `=` or `>`"),
    builtin("@<", 2, Protected, N(Native::Before), Names, "before in the standard order of terms"),
    builtin("@>", 2, Protected, N(Native::After), Names, "after in the standard order of terms"),
    builtin("@=<", 2, Protected, N(Native::NotAfter), Names, "not after in the standard order of terms"),
    builtin("@>=", 2, Protected, N(Native::NotBefore), Names, "not before in the standard order of terms"),
    // Arithmetic.
    builtin("is", 2, Protected, Engine, Values, "evaluate arithmetic"),
    builtin("<", 2, Protected, Engine, Values, "arithmetic less than"),
    builtin(">", 2, Protected, Engine, Values, "arithmetic greater than"),
    builtin("=<", 2, Protected, Engine, Values, "arithmetic less or equal"),
    builtin(">=", 2, Protected, Engine, Values, "arithmetic greater or equal"),
    builtin("=:=", 2, Protected, Engine, Values, "arithmetic equal"),
    builtin("=\\=", 2, Protected, Engine, Values, "arithmetic not equal"),
    builtin("between", 3, Library, N(Native::Between), Values, "the integers from the first to the second (or `inf`)"),
    builtin("succ", 2, Library, N(Native::Succ), Values, "the second is the first plus one, both natural numbers"),
    builtin("plus", 3, Library, N(Native::Plus), Values, "the third is the sum of the first two"),
    // Types.
    builtin("var", 1, Protected, N(Native::Var), Values, "an unbound variable"),
    builtin("nonvar", 1, Protected, N(Native::Nonvar), Values, "not an unbound variable"),
    builtin("atom", 1, Protected, N(Native::Atom), Values, "an atom"),
    builtin("number", 1, Protected, N(Native::Number), Values, "a number"),
    builtin("integer", 1, Protected, N(Native::Integer), Values, "an integer"),
    builtin("float", 1, Protected, N(Native::Float), Values, "a float"),
    builtin("atomic", 1, Protected, N(Native::Atomic), Values, "an atom, number or string"),
    builtin("compound", 1, Protected, N(Native::Compound), Values, "a compound term"),
    builtin("callable", 1, Protected, N(Native::Callable), Values, "an atom or compound term"),
    builtin("is_list", 1, Library, N(Native::IsList), Values, "a proper list"),
    builtin("ground", 1, Protected, N(Native::Ground), Values, "a term without variables"),
    builtin(
        "must_be",
        2,
        Library,
        N(Native::MustBe),
        Values,
        "an error unless the second argument is of the type named",
    ),
    // Terms.
    builtin("functor", 3, Protected, N(Native::Functor), Values, "a term's name and arity"),
    builtin("arg", 3, Protected, N(Native::Arg), Values, "a compound's argument at a position"),
    builtin("=..", 2, Protected, N(Native::Univ), Values, "a term as a list: its name, then its arguments"),
    builtin("copy_term", 2, Protected, N(Native::CopyTerm), Values, "a copy with fresh variables"),
    builtin("term_variables", 2, Protected, N(Native::TermVariables), Values, "a term's variables, in order"),
    // Finding all solutions.
    calling(builtin("findall", 3, Protected, N(Native::Findall), Order, "the list of every solution"), &[goal(1)]),
    calling(
        builtin("findall", 4, Library, N(Native::Findall4), Order, "the list of every solution, ending in a tail"),
        &[goal(1)],
    ),
    calling(
        builtin("bagof", 3, Protected, Prolog, Order, "the solutions, grouped by the values of the free variables"),
        &[goal(1)],
    ),
    calling(builtin("setof", 3, Protected, Prolog, Names, "as bagof/3, each group sorted"), &[goal(1)]),
    calling(
        builtin("aggregate_all", 3, Library, Prolog, Order, "count, sum, max, min, bag or set of every solution"),
        &[goal(1)],
    ),
    calling(
        builtin("^", 2, Library, N(Native::Caret), Values, "calls the goal (`V^G` marks V in bagof/3 and setof/3)"),
        &[goal(1)],
    ),
    // Lists.
    builtin("member", 2, Library, Engine, Values, "list membership"),
    builtin("memberchk", 2, Library, Prolog, Order, "the first list member that unifies"),
    builtin("length", 2, Protected, N(Native::Length), Values, "a list's length"),
    builtin("append", 3, Library, Prolog, Values, "the concatenation of two lists"),
    builtin("append", 2, Library, Prolog, Values, "the concatenation of a list of lists"),
    builtin("nth0", 3, Library, Prolog, Values, "the element at an index from 0"),
    builtin("nth1", 3, Library, Prolog, Values, "the element at an index from 1"),
    builtin("last", 2, Library, Prolog, Values, "a list's last element"),
    builtin("reverse", 2, Library, Prolog, Values, "a list reversed"),
    builtin("nextto", 3, Library, Prolog, Values, "two elements next to each other in a list"),
    builtin("select", 3, Library, Prolog, Values, "a list without one element"),
    builtin("selectchk", 3, Library, Prolog, Order, "a list without the first element that unifies"),
    builtin("select", 4, Library, Prolog, Values, "a list with one element replaced"),
    builtin("subtract", 3, Library, Prolog, Order, "the elements of a list not in another"),
    builtin("intersection", 3, Library, Prolog, Order, "the elements of a list also in another"),
    builtin("union", 3, Library, Prolog, Order, "the elements of a list not in another, then the other"),
    builtin("delete", 3, Library, Prolog, Order, "a list without the elements that unify with one"),
    calling(builtin("exclude", 3, Library, Prolog, Order, "the elements for which a goal fails"), &[closure(0, 1)]),
    calling(builtin("include", 3, Library, Prolog, Order, "the elements for which a goal succeeds"), &[closure(0, 1)]),
    calling(
        builtin("partition", 4, Library, Prolog, Order, "the elements for which a goal succeeds, and the others"),
        &[closure(0, 1)],
    ),
    calling(builtin("maplist", 2, Library, Prolog, Values, "a goal holds for every element"), &[closure(0, 1)]),
    calling(
        builtin("maplist", 3, Library, Prolog, Values, "a goal holds for every pair of elements"),
        &[closure(0, 2)],
    ),
    calling(builtin("maplist", 4, Library, Prolog, Values, "a goal holds for every three elements"), &[closure(0, 3)]),
    calling(builtin("maplist", 5, Library, Prolog, Values, "a goal holds for every four elements"), &[closure(0, 4)]),
    calling(builtin("foldl", 4, Library, Prolog, Values, "a goal folded over a list"), &[closure(0, 3)]),
    calling(builtin("foldl", 5, Library, Prolog, Values, "a goal folded over two lists"), &[closure(0, 4)]),
    calling(builtin("foldl", 6, Library, Prolog, Values, "a goal folded over three lists"), &[closure(0, 5)]),
    builtin("sum_list", 2, Library, Prolog, Values, "the sum of a list of numbers"),
    builtin("sumlist", 2, Library, Prolog, Values, "the sum of a list of numbers, as sum_list/2"),
    builtin("max_list", 2, Library, Prolog, Values, "the largest of a list of numbers"),
    builtin("min_list", 2, Library, Prolog, Values, "the smallest of a list of numbers"),
    builtin("numlist", 3, Library, Prolog, Values, "the list of integers from the first to the second"),
    builtin("max_member", 2, Library, Prolog, Names, "the largest element in the standard order of terms"),
    builtin("min_member", 2, Library, Prolog, Names, "the smallest element in the standard order of terms"),
    builtin("list_to_set", 2, Library, Prolog, Order, "a list without repeated elements, first ones kept"),
    builtin("permutation", 2, Library, Prolog, Values, "a permutation of a list"),
    builtin("flatten", 2, Library, Prolog, Values, "a list of lists, flattened"),
    builtin("pairs_keys_values", 3, Library, Prolog, Values, "a list of `K-V` pairs, its keys and its values"),
    builtin("pairs_keys", 2, Library, Prolog, Values, "the keys of a list of `K-V` pairs"),
    builtin("pairs_values", 2, Library, Prolog, Values, "the values of a list of `K-V` pairs"),
    builtin("msort", 2, Library, N(Native::Msort), Names, "a list sorted in the standard order, duplicates kept"),
    builtin("sort", 2, Protected, N(Native::Sort), Names, "a list sorted in the standard order, duplicates removed"),
    builtin(
        "sort",
        4,
        Library,
        N(Native::Sort4),
        Names,
        "a list sorted on a key, in an order (`@<`, `@=<`, `@>`, `@>=`)",
    ),
    builtin("keysort", 2, Protected, N(Native::Keysort), Names, "a list of `K-V` pairs sorted on the keys, stably"),
    calling(builtin("predsort", 3, Library, Prolog, Order, "a list sorted by a comparison goal"), &[closure(0, 3)]),
    builtin("list_to_ord_set", 2, Library, Prolog, Names, "a list as an ordered set"),
    builtin("ord_union", 3, Library, Prolog, Names, "the union of two ordered sets"),
    builtin("ord_subtract", 3, Library, Prolog, Names, "the elements of an ordered set not in another"),
    builtin("ord_intersection", 3, Library, Prolog, Names, "the elements of an ordered set also in another"),
    builtin("ord_memberchk", 2, Library, Prolog, Names, "membership of an ordered set"),
    builtin("ord_subset", 2, Library, Prolog, Names, "every element of an ordered set is in another"),
    // Output, which kbc does not print (W0016).
    builtin("write", 1, Protected, N(Native::Output), Output, "prints a term (kbc does not print)"),
    builtin("print", 1, Library, N(Native::Output), Output, "prints a term (kbc does not print)"),
    builtin("writeln", 1, Library, N(Native::Output), Output, "prints a term and a new line (kbc does not print)"),
    builtin("writeq", 1, Protected, N(Native::Output), Output, "prints a term quoted (kbc does not print)"),
    builtin(
        "write_canonical",
        1,
        Protected,
        N(Native::Output),
        Output,
        "prints a term canonically (kbc does not print)",
    ),
    builtin("nl", 0, Protected, N(Native::Output), Output, "prints a new line (kbc does not print)"),
    builtin("tab", 1, Library, N(Native::Output), Output, "prints spaces (kbc does not print)"),
    builtin("format", 1, Library, N(Native::Output), Output, "prints formatted text (kbc does not print)"),
    builtin("format", 2, Library, N(Native::Output), Output, "prints formatted text (kbc does not print)"),
    // The list library's helpers, implemented in Rust.
    builtin("$bagof_split", 3, Protected, N(Native::BagofSplit), Values, "bagof/3's goal and witness"),
    builtin("$bagof_groups", 2, Protected, N(Native::BagofGroups), Names, "bagof/3's groups"),
];

/// Arithmetic functions `is/2` and the comparisons evaluate, as (name, arity).
pub const FUNCTIONS: &[(&str, usize)] = &[
    ("+", 2),
    ("-", 2),
    ("*", 2),
    ("/", 2),
    ("//", 2),
    ("mod", 2),
    ("rem", 2),
    ("div", 2),
    ("-", 1),
    ("+", 1),
    ("abs", 1),
    ("sign", 1),
    ("min", 2),
    ("max", 2),
    ("**", 2),
    ("^", 2),
    ("sqrt", 1),
    ("exp", 1),
    ("log", 1),
    ("sin", 1),
    ("cos", 1),
    ("tan", 1),
    ("asin", 1),
    ("acos", 1),
    ("atan", 1),
    ("atan", 2),
    ("atan2", 2),
    ("sinh", 1),
    ("cosh", 1),
    ("tanh", 1),
    ("floor", 1),
    ("ceiling", 1),
    ("round", 1),
    ("truncate", 1),
    ("integer", 1),
    ("float", 1),
    ("float_integer_part", 1),
    ("float_fractional_part", 1),
    ("gcd", 2),
    ("msb", 1),
    (">>", 2),
    ("<<", 2),
    ("/\\", 2),
    ("\\/", 2),
    ("xor", 2),
    ("\\", 1),
    ("pi", 0),
    ("e", 0),
    ("inf", 0),
    ("nan", 0),
    ("epsilon", 0),
];

/// The built-in `name/arity`, if there is one.
pub fn find(name: &str, arity: usize) -> Option<&'static Builtin> {
    PREDICATES.iter().find(|b| b.name == name && b.arity == arity)
}

/// The built-in `name/arity` named by a symbol.
pub fn lookup(interner: &Interner, name: Symbol, arity: usize) -> Option<&'static Builtin> {
    find(interner.resolve(name), arity)
}

/// True if `name/arity` is a control construct or one of the tests the engine dispatches on
/// itself (unification, identity, arithmetic comparison, `member/2`): the names that can never
/// stand for a state fact, as a slip of writing a test among the state conditions shows.
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

/// True if `name/arity` is built in and implemented in Rust, by the engine's dispatch or as a
/// native: it is never a clause of the program, and a call of it needs no clause.
pub fn is_engine_predicate(interner: &Interner, name: Symbol, arity: usize) -> bool {
    is_builtin_predicate(name, arity)
        || lookup(interner, name, arity).is_some_and(|b| matches!(b.imp, Imp::Engine | Imp::Native(_)))
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

/// True if `literal`, called with `extra` more arguments, is a built-in (other than the
/// engine's control constructs) one of whose goal arguments is a variable: a goal known only
/// at run time, which may call any predicate (`call(G)`, `findall(X, G, L)`).
pub fn calls_run_time_goal(interner: &Interner, literal: &crate::ir::hir::Literal, extra: usize) -> bool {
    extra == 0
        && lookup(interner, literal.name(), literal.arity()).is_some_and(|builtin| {
            builtin.imp != Imp::Engine
                && builtin
                    .calls
                    .iter()
                    .any(|c| matches!(literal.term.args().get(c.arg), Some(crate::ir::hir::Term::Var(_))))
        })
}

/// True if `name/arity` is one of the [`DEBUGGER`] predicates.
pub fn is_debugger(name: &str, arity: usize) -> bool {
    DEBUGGER.contains(&(name, arity))
}

/// Common SWI-Prolog predicates that kbc does not provide, with the reason; named in
/// diagnostics so the user learns it is a deliberate gap rather than a typo.
pub const NOT_PROVIDED: &[(&str, &str)] = &[
    ("assert", "kbc's KB is static: a plan must not depend on a program that changes while it runs"),
    ("asserta", "kbc's KB is static: a plan must not depend on a program that changes while it runs"),
    ("assertz", "kbc's KB is static: a plan must not depend on a program that changes while it runs"),
    ("retract", "kbc's KB is static: a plan must not depend on a program that changes while it runs"),
    ("retractall", "kbc's KB is static: a plan must not depend on a program that changes while it runs"),
    ("nb_getval", "global variables change while the program runs, and kbc's KB is static"),
    ("b_getval", "global variables change while the program runs, and kbc's KB is static"),
    ("nb_setval", "global variables change while the program runs, and kbc's KB is static"),
    ("b_setval", "global variables change while the program runs, and kbc's KB is static"),
    ("random", "a plan must not depend on chance: the same KB always gives the same plan"),
    ("random_between", "a plan must not depend on chance: the same KB always gives the same plan"),
    ("random_member", "a plan must not depend on chance: the same KB always gives the same plan"),
    ("catch", "kbc's engine reports an error as a diagnostic rather than raising it in the program"),
    ("throw", "kbc's engine reports an error as a diagnostic rather than raising it in the program"),
    ("atom_length", "kbc's engine does not take atoms apart into their characters"),
    ("atom_chars", "kbc's engine does not take atoms apart into their characters"),
    ("atom_codes", "kbc's engine does not take atoms apart into their characters"),
    ("char_code", "kbc's engine does not take atoms apart into their characters"),
    ("atom_concat", "kbc's engine does not make new atoms while it runs"),
    ("atomic_list_concat", "kbc's engine does not make new atoms while it runs"),
    ("atom_number", "kbc's engine does not take atoms apart into their characters"),
    ("atom_string", "kbc's engine does not take atoms apart into their characters"),
    ("sub_atom", "kbc's engine does not take atoms apart into their characters"),
    ("upcase_atom", "kbc's engine does not make new atoms while it runs"),
    ("downcase_atom", "kbc's engine does not make new atoms while it runs"),
    ("term_to_atom", "kbc's engine does not make new atoms while it runs"),
    ("number_codes", "kbc's engine does not take atoms apart into their characters"),
    (
        "format",
        "kbc's engine does not make new atoms while it runs (format/1 and format/2 are provided, without printing)",
    ),
    ("string_concat", "kbc's engine has no string operations"),
    ("string_chars", "kbc's engine has no string operations"),
    ("string_codes", "kbc's engine has no string operations"),
    ("split_string", "kbc's engine has no string operations"),
    ("sub_string", "kbc's engine has no string operations"),
    ("string_length", "kbc's engine has no string operations"),
    ("number_string", "kbc's engine has no string operations"),
    (
        "aggregate_all",
        "aggregate_all/3 is provided: count, sum(E), max(E), min(E), max(E, W), min(E, W), bag(T), set(T)",
    ),
    ("tab", "tab/1 is provided, without printing"),
    ("halt", "kbc plans the KB's problems; it does not run the KB as a program that could stop"),
];

/// Why kbc does not provide `name`, if it is one of [`NOT_PROVIDED`].
pub fn not_provided(name: &str) -> Option<&'static str> {
    NOT_PROVIDED.iter().find(|(n, _)| *n == name).map(|(_, why)| *why)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_and_the_dispatch_agree() {
        let mut interner = Interner::new();
        // Every name the dispatch recognises is in the table.
        for name in ["true", "fail", "false", "!"] {
            let symbol = interner.intern(name);
            assert!(is_builtin_predicate(symbol, 0) && find(name, 0).is_some(), "{name}/0");
        }
        for name in [",", ";", "->", "=", "\\=", "==", "\\==", "is", "<", ">", "=<", ">=", "=:=", "=\\=", "member"] {
            let symbol = interner.intern(name);
            assert!(is_builtin_predicate(symbol, 2) && find(name, 2).is_some(), "{name}/2");
        }
        let member = interner.intern("member");
        assert!(!is_builtin_predicate(member, 3));
        // No name/arity twice.
        for (i, b) in PREDICATES.iter().enumerate() {
            assert!(
                !PREDICATES[..i].iter().any(|a| a.name == b.name && a.arity == b.arity),
                "{}/{} twice",
                b.name,
                b.arity
            );
        }
    }

    #[test]
    fn a_called_argument_is_an_argument() {
        for b in PREDICATES {
            assert!(b.calls.iter().all(|c| c.arg < b.arity), "{}/{}", b.name, b.arity);
        }
    }
}
