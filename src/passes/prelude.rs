//! The `prelude` pass: the states of tests whose `go` call follows other goals
//! (`test :- start_state(I), end_state(G), go(I, G).`).
//!
//! Prolog runs a test's goals in order, so `go` receives whatever the goals before it bound.
//! This pass runs those goals with the engine, against the KB's clauses and the library
//! predicates it calls (as OnKB goals are run, without the problem's goal facts, which the
//! goals are computing), and reads `go`'s first two arguments from the first solution: a list
//! of facts and a list of goal literals, which become the problem's initial state and goal as
//! if they had been written in the call. Prolog would backtrack into the goals for another
//! solution if `go` found no plan; kbc plans the first solution's problem (docs/dsl.md,
//! "Problems").

use crate::diag::{Diagnostic, Diagnostics, codes};
use crate::engine::{Machine, Next, Program};
use crate::intern::Interner;
use crate::ir::hir::{Kb, Literal, Prelude, Term, VarInfo, VarTable, term_to_string};
use crate::source::Span;

/// The resolution steps the goals before one `go` call may take (as an OnKB query may, by
/// default: `crate::planner::Budget::engine_steps`).
pub const PRELUDE_STEPS: u64 = 1_000_000;

/// Gives every problem with a prelude its initial state, goal and variables, from the first
/// solution of the prelude's goals; E0215 where they fail, stop with an error, or leave `go`
/// something other than two lists of callable terms. Problems whose prelude does not resolve
/// keep empty states (the diagnostic is an error, so nothing plans them).
pub fn resolve(kb: &mut Kb, interner: &mut Interner, diags: &mut Diagnostics) {
    if kb.problems.iter().all(|p| p.prelude.is_none()) {
        return;
    }
    let program = Program::new(kb, interner, &[]);
    let mut machine = Machine::new(&program, PRELUDE_STEPS);
    let mut resolved = Vec::new();
    for (index, problem) in kb.problems.iter().enumerate() {
        let Some(prelude) = &problem.prelude else { continue };
        machine.reset();
        match first_solution(&mut machine, prelude, problem.vars.len(), interner) {
            Ok((init, goal, count)) => resolved.push((index, init, goal, count)),
            // (Failing for want of a built-in kbc does not provide says nothing of Prolog's
            // run, where it may succeed: the check's E0210 on the call says why.)
            Err(_) if calls_missing_builtin(kb, &program, interner, &prelude.goals) => {}
            Err(diagnostic) => diags.push(*diagnostic),
        }
    }
    for (index, init, goal, count) in resolved {
        let prelude = kb.problems[index].prelude.clone().expect("resolved from a prelude");
        let vars = VarTable {
            vars: (0..count)
                .map(|v| VarInfo { name: interner.intern(&format!("_G{}", v + 1)), occurrences: vec![prelude.span] })
                .collect(),
        };
        let shown = |term: &Term| term_to_string(interner, term, &vars);
        let init = literals(&init, &prelude.init_spans, "initial state", "facts", &shown);
        let goal = literals(&goal, &prelude.goal_spans, "goal", "goal literals", &shown);
        let (init, goal) = match (init, goal) {
            (Ok(init), Ok(goal)) => (init, goal),
            (init, goal) => {
                for diagnostic in init.err().into_iter().chain(goal.err()) {
                    diags.push(*diagnostic);
                }
                continue;
            }
        };
        for fact in init.iter().filter(|l| !l.term.is_ground()) {
            diags.push(
                crate::passes::lower::with_open_init_notes(
                    Diagnostic::warning(codes::OPEN_INIT, "an initial state fact with a variable")
                        .primary(fact.span, format!("the goals before `go` leave `{}` here", shown(&fact.term))),
                    "it",
                )
                .with_help("bind every argument in the goals before `go`"),
            );
        }
        let problem = &mut kb.problems[index];
        if let Some(prelude) = problem.prelude.as_mut() {
            prelude.resolved = true;
        }
        let (ground, open): (Vec<Literal>, Vec<Literal>) = init.into_iter().partition(|l| l.term.is_ground());
        problem.init = ground;
        problem.open_init = open;
        problem.goal = goal;
        problem.vars = vars;
    }
}

/// True if `goals`, or a rule they reach, call an SWI-Prolog built-in that kbc does not
/// provide (`atom_concat/3`, [`crate::builtins::not_provided`]) and the KB does not define.
fn calls_missing_builtin(kb: &Kb, program: &Program, interner: &Interner, goals: &[crate::ir::hir::Goal]) -> bool {
    let mut seen: Vec<(crate::intern::Symbol, usize)> = Vec::new();
    let mut pending: Vec<&crate::ir::hir::Goal> = goals.iter().collect();
    while let Some(goal) = pending.pop() {
        let mut called = Vec::new();
        goal.for_each_called(&mut |literal, extra| called.push((literal.name(), literal.arity() + extra)));
        for key in called {
            if seen.contains(&key) {
                continue;
            }
            seen.push(key);
            if program.defines(key.0, key.1) {
                let bodies = kb.clauses.iter().chain(&kb.library).filter(|c| (c.head.name(), c.head.arity()) == key);
                pending.extend(bodies.filter_map(|c| c.body.as_deref()));
            } else if crate::builtins::lookup(interner, key.0, key.1).is_none()
                && crate::builtins::not_provided(interner.resolve(key.0)).is_some()
            {
                return true;
            }
        }
    }
    false
}

/// The first solution of `prelude`'s goals (whose terms have `vars` variables, the
/// problem's as lowered): `go`'s two arguments, and how many variables they share (numbered
/// from 0 by first occurrence, the initial state's first).
fn first_solution(
    machine: &mut Machine<'_>,
    prelude: &Prelude,
    vars: usize,
    interner: &Interner,
) -> Result<(Term, Term, usize), Box<Diagnostic>> {
    let mut cells = vec![None; vars];
    let query = machine.put_conjunction(&prelude.goals, &mut cells);
    let init = machine.put_term(&prelude.init, &mut cells);
    let goal = machine.put_term(&prelude.goal, &mut cells);
    let mut found = None;
    let outcome = machine.solve(query, |m| {
        let mut vars = Vec::new();
        let init = m.read(init, &mut vars);
        let goal = m.read(goal, &mut vars);
        found = Some((init, goal, vars.len()));
        Next::Stop
    });
    let failed = |message: String, label: &str| {
        Diagnostic::error(codes::BAD_PROBLEM, message)
            .primary(prelude.span, label.to_string())
            .secondary(prelude.init_spans.0.to(prelude.goal_spans.0), "the states `go` is given")
            .with_note("kbc runs the goals before a test's `go` call, as Prolog does, to find its states")
    };
    match (outcome, found) {
        (Ok(_), Some(found)) => Ok(found),
        (Ok(_), None) => Err(Box::new(failed("the goals before `go` fail".into(), "no solution").with_help(
            "in Prolog this test fails before planning; check the facts these goals read \
             (`swipl kb.pl`, then ask them)",
        ))),
        (Err(error), _) => {
            let stopped = failed(
                format!("the goals before `go` stop with an error: {}", error.message(interner)),
                "while running these",
            );
            Err(Box::new(match error {
                crate::engine::EngineError::Budget { .. } => stopped.with_help(
                    "these goals loop, or compute more than kbc allows a test; write the states out in the `go` call",
                ),
                _ => stopped,
            }))
        }
    }
}

/// A list term read back from the engine as literals, spanned where `spans` says (each item
/// its own span when the list was written out in the call with as many items).
fn literals(
    list: &Term,
    spans: &(Span, Vec<Span>),
    what: &str,
    items: &str,
    shown: &dyn Fn(&Term) -> String,
) -> Result<Vec<Literal>, Box<Diagnostic>> {
    let (whole, each) = spans;
    let not_a_list = || {
        Box::new(
            Diagnostic::error(codes::BAD_PROBLEM, format!("`go`'s {what} is `{}`, not a list of {items}", shown(list)))
                .primary(*whole, "the goals before `go` give it this value")
                .with_help(format!("give `go` a proper list of {items}, such as `[clear(b1), available(a1)]`")),
        )
    };
    let Some(terms) = list.list_items() else { return Err(not_a_list()) };
    let mut literals = Vec::with_capacity(terms.len());
    for (position, term) in terms.iter().enumerate() {
        let span = if each.len() == terms.len() { each[position] } else { *whole };
        if term.callable().is_none() {
            return Err(Box::new(
                Diagnostic::error(
                    codes::NOT_CALLABLE,
                    format!("item {} of `go`'s {what} is `{}`, not an atom or a compound", position + 1, shown(term)),
                )
                .primary(span, format!("the goals before `go` give the {what} this item"))
                .with_help(format!("{items} are atoms or compounds such as `clear(b1)`")),
            ));
        }
        literals.push(Literal { term: (*term).clone(), span, name_span: span });
    }
    Ok(literals)
}
