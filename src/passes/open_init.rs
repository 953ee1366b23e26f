//! The `open_init` pass: the values the planner tries for the variables of a high-level
//! problem's initial facts (`go([available(A), ...], ...)`, warning W0015).
//!
//! Such a variable stands for one value for the whole plan. The candidates, in the order they
//! are tried: a value of the variable's own that equals nothing else in the KB (the variable
//! left unbound, as Prolog would leave it until something binds it), then every atom and
//! number the KB writes: the problem's own first (its initial facts and goal, in order), then
//! the action schemas', then the other clauses'. The groundings enumerate the candidates of
//! every variable, the last variable varying fastest, and stop at [`MAX_GROUNDINGS`]. Each
//! grounding is a ground problem; the session plans them in turn and keeps the first that
//! has a plan (docs/dsl.md, "Problems").

use rustc_hash::{FxHashMap, FxHashSet};

use crate::intern::{Interner, Symbol, sym};
use crate::ir::hir::{Kb, Literal, Problem, Term, VarId};
use crate::ir::unify::substitute;

/// The most groundings of one problem's initial variables that are tried.
pub const MAX_GROUNDINGS: usize = 256;

/// A problem's initial variables and the values each grounding gives them.
#[derive(Clone, Debug)]
pub struct Groundings {
    /// The variables, in order of first occurrence in the initial state.
    pub vars: Vec<VarId>,
    /// For each grounding, in the order they are tried, the value of each variable.
    pub values: Vec<Vec<Term>>,
    /// How many groundings there are in all (more than `values.len()` when capped).
    pub total: u128,
}

impl Groundings {
    /// The values grounding `index` gives the variables, as Prolog text (`'_A'`, `b1`).
    pub fn shown(&self, interner: &Interner, index: usize) -> Vec<String> {
        let no_vars = crate::ir::hir::VarTable::default();
        self.values[index].iter().map(|value| crate::ir::hir::term_to_string(interner, value, &no_vars)).collect()
    }
}

/// The initial facts of `problem` with variables that the high level reads: those not on an
/// arm-level predicate (`arm`, [`Kb::arm_level_preds`]), which the arm level binds by
/// unification.
pub fn high_level_open_facts<'a>(problem: &'a Problem, arm: &[(Symbol, usize)]) -> Vec<&'a Literal> {
    problem.open_init.iter().filter(|l| l.term.callable().is_none_or(|key| !arm.contains(&key))).collect()
}

/// The groundings of `problem`'s high-level initial variables, and the ground problem each one
/// makes, in the order they are tried; `None` when it has none. New names (the variables' own
/// values) are interned in `interner`.
pub fn groundings(kb: &Kb, interner: &mut Interner, problem: usize) -> Option<(Groundings, Vec<Problem>)> {
    let base = &kb.problems[problem];
    let arm = kb.arm_level_preds();
    let open = high_level_open_facts(base, &arm);
    let mut vars: Vec<VarId> = Vec::new();
    for fact in &open {
        fact.term.for_each_var(&mut |v| {
            if !vars.contains(&v) {
                vars.push(v);
            }
        });
    }
    if vars.is_empty() {
        return None;
    }
    let constants = constants(kb, base);
    let own: Vec<Term> = vars.iter().map(|&v| Term::Atom(own_name(interner, base, v, &constants, &vars))).collect();
    let candidates: Vec<Vec<Term>> =
        own.iter().map(|mine| std::iter::once(mine.clone()).chain(constants.iter().cloned()).collect()).collect();
    let total = candidates.iter().fold(1u128, |n, c| n.saturating_mul(c.len() as u128));
    let mut problems = Vec::new();
    let mut values = Vec::new();
    let mut digits = vec![0usize; vars.len()];
    loop {
        let chosen: Vec<Term> = digits.iter().zip(&candidates).map(|(&d, c)| c[d].clone()).collect();
        problems.push(ground(base, &arm, &vars, &chosen));
        values.push(chosen);
        if problems.len() == MAX_GROUNDINGS || !advance(&mut digits, &candidates) {
            break;
        }
    }
    Some((Groundings { vars, values, total }, problems))
}

/// The next combination, last digit fastest; false after the last one.
fn advance(digits: &mut [usize], candidates: &[Vec<Term>]) -> bool {
    for i in (0..digits.len()).rev() {
        digits[i] += 1;
        if digits[i] < candidates[i].len() {
            return true;
        }
        digits[i] = 0;
    }
    false
}

/// The variable's own value: an atom named like it (`'_A'` for `A`, `'_G2'` for the third
/// variable when it is `_`) that no term of the KB uses.
fn own_name(interner: &mut Interner, problem: &Problem, v: VarId, taken: &[Term], vars: &[VarId]) -> Symbol {
    let info = problem.vars.get(v);
    let written = interner.resolve(info.name).to_string();
    let stem = if info.name == sym::ANON || written.starts_with('_') {
        let index = vars.iter().position(|&w| w == v).unwrap_or(0);
        if info.name == sym::ANON { format!("_G{index}") } else { written }
    } else {
        format!("_{written}")
    };
    let mut name = stem.clone();
    let mut n = 1;
    while taken.iter().any(|t| matches!(t, Term::Atom(s) if interner.resolve(*s) == name)) {
        name = format!("{stem}_{n}");
        n += 1;
    }
    interner.intern(&name)
}

/// `base` with `vars` replaced by `values` in its initial facts, goal and arm-level facts; the
/// initial facts stay in the order they are written.
fn ground(base: &Problem, arm: &[(Symbol, usize)], vars: &[VarId], values: &[Term]) -> Problem {
    let bindings: FxHashMap<VarId, Term> = vars.iter().copied().zip(values.iter().cloned()).collect();
    let apply = |l: &Literal| Literal { term: substitute(&l.term, &bindings), ..l.clone() };
    let high: Vec<Literal> = high_level_open_facts(base, arm).into_iter().map(apply).collect();
    let mut init = base.init.clone();
    let (now_ground, still_open): (Vec<Literal>, Vec<Literal>) = high.into_iter().partition(|l| l.term.is_ground());
    init.extend(now_ground);
    init.sort_by_key(|l| (l.span.file, l.span.start));
    let mut open_init: Vec<Literal> =
        base.open_init.iter().filter(|l| l.term.callable().is_some_and(|key| arm.contains(&key))).map(apply).collect();
    open_init.extend(still_open);
    Problem { init, goal: base.goal.iter().map(apply).collect(), open_init, ..base.clone() }
}

/// Every atom and integer the KB writes, each once: the problem's, then the action schemas',
/// then the other clauses'.
fn constants(kb: &Kb, problem: &Problem) -> Vec<Term> {
    let mut found: Vec<Term> = Vec::new();
    let mut seen = FxHashSet::default();
    // The arguments of each literal: its name is a predicate, not a value.
    let mut add = |t: &Term| t.args().iter().for_each(|a| collect(a, &mut found, &mut seen));
    for literal in problem.init.iter().chain(&problem.open_init).chain(&problem.goal) {
        add(&literal.term);
    }
    for action in kb.high_level_actions() {
        let literals = action.valid.iter().chain(&action.invalid).chain(&action.invalid_at_end);
        add(&action.name.term);
        for literal in literals.chain(action.effects.iter().map(|e| &e.literal)) {
            add(&literal.term);
        }
    }
    for clause in &kb.clauses {
        add(&clause.head.term);
    }
    found
}

/// A constant's identity: an atom's name or an integer.
#[derive(PartialEq, Eq, Hash)]
enum Key {
    Atom(Symbol),
    Int(i64),
}

/// Adds the atoms (but `[]`) and integers of `term` not seen yet to `found`, left to right.
fn collect(term: &Term, found: &mut Vec<Term>, seen: &mut FxHashSet<Key>) {
    let mut stack = vec![term];
    while let Some(t) = stack.pop() {
        let key = match t {
            Term::Compound(_, args) => {
                stack.extend(args.iter().rev());
                continue;
            }
            Term::Atom(s) if *s != sym::NIL => Key::Atom(*s),
            Term::Int(i) => Key::Int(*i),
            _ => continue,
        };
        if seen.insert(key) {
            found.push(t.clone());
        }
    }
}
