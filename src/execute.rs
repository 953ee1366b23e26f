//! What the compiler adds to a run of a program (the run loop itself is `kbvm::run`): the
//! simulated world built for a KB's problem, the world read back as HIR terms, and the
//! executed timeline as a timed plan that the timed validator checks against the KB.

use kbvm::Program;
use kbvm::bytecode::Instr;
use kbvm::run::{Outcome, Run};

use crate::diag::{Diagnostic, codes};
#[cfg(feature = "sim")]
use kbvm::sim::{Arg, Misplaced, SimConfig, SimError, World, initial_facts, program_cells};

#[cfg(feature = "sim")]
use crate::intern::Interner;
use crate::ir::hir::Term;
use crate::ir::unify::unifiable;

/// The simulated world built from a program's initial state, laid out around the cells the
/// program mentions; its table also covers `cells` (where a recovery may put blocks down).
#[cfg(feature = "sim")]
pub fn sim_world(program: &Program, config: SimConfig, cells: &[(i64, i64)]) -> Result<World, SimError> {
    let mut world = World::new(config, &initial_facts(program), &program_cells(program))?;
    world.add_cells(cells);
    Ok(world)
}

/// The cells of the table a problem's KB declares: the answers to `pos(X, Y)` (std/blocks.pl's
/// cells: the `cell/2` facts, or the paper's 5 x 5 grid), at most 10,000 of them; none when
/// the KB has no `pos/2`. The simulated table covers them, and a recovery puts blocks down
/// on them.
pub fn kb_cells(session: &mut crate::session::Session, problem: usize) -> Vec<(i64, i64)> {
    use crate::engine::{Cell, Machine, Next};
    let Some(pos) = session.interner().get("pos") else { return Vec::new() };
    let program = session.program(problem);
    let mut machine = Machine::new(&program, 1_000_000);
    let (x, y) = (machine.new_var(), machine.new_var());
    let goal = machine.new_compound(pos, &[x, y]);
    let mut cells = Vec::new();
    let _ = machine.solve(goal, |m| {
        if let (Cell::Int(x), Cell::Int(y)) = (m.deref(x), m.deref(y)) {
            cells.push((x, y));
        }
        if cells.len() >= 10_000 { Next::Stop } else { Next::More }
    });
    cells.sort();
    cells.dedup();
    cells
}

/// The world read back as HIR terms, and the blocks it cannot place.
#[cfg(feature = "sim")]
pub fn world_facts(world: &World, interner: &mut Interner) -> (Vec<Term>, Vec<Misplaced>) {
    let (facts, unaccounted) = world.facts();
    let terms = facts
        .iter()
        .map(|f| {
            let args = f
                .args
                .iter()
                .map(|a| match a {
                    Arg::Atom(text) => Term::Atom(interner.intern(text)),
                    Arg::Int(i) => Term::Int(*i),
                })
                .collect();
            Term::Compound(interner.intern(&f.name), args)
        })
        .collect();
    (terms, unaccounted)
}

/// The goal literals no fact of the world unifies with.
pub fn unmet_goals<'g>(goal: &'g [Term], world: &[Term]) -> Vec<&'g Term> {
    goal.iter().filter(|g| !world.iter().any(|f| unifiable(g, f))).collect()
}

/// True if `text`, an atom of the bytecode, is the text of a term that is no atom: a
/// compound, a list, a number or a string, as codegen writes such an argument. The text is
/// read as Prolog reads it; anything that does not read as one such term is an atom's name.
fn term_text(text: &str) -> bool {
    use crate::syntax::ast::TermKind;
    if text.is_empty() || crate::syntax::ops::quote_free_atom(text) {
        return false;
    }
    let mut interner = crate::intern::Interner::new();
    let mut diags = crate::diag::Diagnostics::new();
    let source = format!("t({text}).");
    let ast = crate::syntax::parse_source(crate::source::FileId(0), &source, &mut interner, &mut diags);
    if !diags.is_empty() || ast.clauses.len() != 1 {
        return false;
    }
    match ast.clauses[0].term.args() {
        [arg] => !matches!(arg.kind, TermKind::Atom(_) | TermKind::Var(_)),
        _ => false,
    }
}

/// The executed timeline as a timed plan in the PDDL 2.1 format (`kbc validate` reads it):
/// each action at its start's recorded time, with the time to its end's.
pub fn timed_plan(program: &Program, run: &Run) -> String {
    let m = program.module();
    let mut lines: Vec<(i64, usize, String)> = Vec::new();
    let time = |t: i64| program.time_text(t);
    let call = |import: &kbvm::bytecode::ImportId, args: &[kbvm::bytecode::Value]| {
        let mut text = format!("({}", program.import_name(*import));
        for &a in args {
            text.push(' ');
            // Atoms as the KB writes them, so the line reads back (`'_A'` stays an atom). The
            // bytecode holds any other argument as an atom of its text (`loc(0, 0)`, `2.5`,
            // `[a, b]`): that text reads back as the term. (An atom of the KB's whose quoted
            // name is such a text, `'loc(0, 0)'`, would read back as the term too.)
            match a {
                kbvm::bytecode::Value::Atom(_) => {
                    let value = program.value_text(a);
                    if term_text(&value) {
                        // As the timed-plan printer writes a term: no layout between its tokens.
                        text.push_str(&crate::syntax::text::without_layout(&value));
                    } else {
                        crate::syntax::ops::write_atom_text(&mut text, &value)
                    }
                }
                kbvm::bytecode::Value::Int(_) => text.push_str(&program.value_text(a)),
            }
        }
        text.push(')');
        text
    };
    // The end event of each start event.
    let mut end_of = vec![None; m.events as usize];
    for node in &m.nodes {
        if let Instr::End { event, start, .. } = node {
            end_of[start.0 as usize] = Some(*event);
        }
    }
    for (i, node) in m.nodes.iter().enumerate() {
        match node {
            Instr::Start { event, import, args, .. } => {
                let Some(start) = run.events[event.0 as usize] else { continue };
                if let Some(end) = end_of[event.0 as usize].and_then(|e| run.events[e.0 as usize]) {
                    lines.push((start, i, format!("{}: {} [{}]", time(start), call(import, args), time(end - start))));
                }
            }
            Instr::Act { event, import, args, .. } => {
                if let Some(at) = run.events[event.0 as usize] {
                    lines.push((at, i, format!("{}: {}", time(at), call(import, args))));
                }
            }
            _ => {}
        }
    }
    lines.sort();
    let mut out = String::new();
    for (_, _, line) in lines {
        out.push_str(&line);
        out.push('\n');
    }
    out
}

/// The executed timeline of a run checked on the KB of `problem` by the timed validator; an
/// error here is a compiler bug, and a note says so.
pub fn check_timeline(
    session: &mut crate::session::Session,
    problem: usize,
    program: &Program,
    run: &Run,
) -> crate::diag::Diagnostics {
    let mut diagnostics = crate::diag::Diagnostics::new();
    let text = timed_plan(program, run);
    let file = session.add_text("<executed timeline>", text.clone());
    let steps = crate::validate::read_plan(file, &text, session.interner_mut(), &mut diagnostics);
    let kb_program = session.program(problem);
    let verdict = crate::validate::validate_timed(session.kb(), session.interner(), &kb_program, problem, &steps);
    diagnostics.extend(verdict.diagnostics);
    if diagnostics.has_errors() {
        diagnostics.push(crate::diag::Diagnostic::note("the executed timeline breaks the KB: this is a compiler bug"));
    }
    diagnostics
}

/// A run's budget as the user gave it (`--max-time` in KB time units, `--max-ticks`), for
/// the diagnostic that says it ran out.
#[derive(Clone, Copy, Debug)]
pub struct RunBudget {
    /// The most time, in KB time units.
    pub max_time: f64,
    /// The most ticks.
    pub max_ticks: u64,
}

/// A run's failure as a diagnostic (E0502): the tree failed, got stuck, ran out of budget or
/// did not link with the host; `None` when it succeeded. `end` is the time it stopped.
pub fn outcome_diagnostic(program: &Program, outcome: &Outcome, end: &str, budget: RunBudget) -> Option<Diagnostic> {
    match outcome {
        Outcome::Success => None,
        Outcome::Failure(failure) => Some(Diagnostic::error(codes::RUN_FAILED, failure.describe(program))),
        Outcome::Stuck => Some(
            Diagnostic::error(
                codes::RUN_FAILED,
                format!("the tree is stuck at time {end}: it waits for an event no node will record"),
            )
            .with_help("the program is malformed; rebuild it with `kbc build`"),
        ),
        Outcome::Budget => Some(
            Diagnostic::error(
                codes::RUN_FAILED,
                format!("the run stopped at time {end} without finishing: it passed its budget"),
            )
            .with_note(format!(
                "the budget: {} time units (`--max-time`), {} ticks (`--max-ticks`)",
                budget.max_time, budget.max_ticks
            ))
            .with_help("raise `--max-time` if the plan is meant to take longer"),
        ),
        Outcome::Unlinked(error) => Some(
            Diagnostic::error(codes::RUN_FAILED, format!("the program does not link with the host: {error}"))
                .with_note("the program's actions were checked against the host before the first tick")
                .with_help(
                    "build for the host you run on (`kbc build --host sim` names each action the arms cannot run), \
                     or run on `--host trace`",
                ),
        ),
        _ => Some(Diagnostic::error(codes::RUN_FAILED, format!("the run ended at time {end} without success"))),
    }
}

/// E0505: the goal literals the world lacks, the blocks not on a cell, the world.
#[cfg(feature = "sim")]
pub fn goal_diagnostic(
    interner: &Interner,
    tree_succeeded: bool,
    unmet: &[&Term],
    facts: &[Term],
    unaccounted: &[Misplaced],
) -> Diagnostic {
    let show = |t: &Term| crate::ir::hir::term_to_string(interner, t, &Default::default());
    let head = if tree_succeeded { "the tree succeeded, but " } else { "" };
    let mut diagnostic = Diagnostic::error(
        codes::GOAL_NOT_REACHED,
        match unmet.len() {
            0 => format!("{head}some blocks are not on a cell of the table"),
            1 => format!("{head}a goal literal does not hold in the world"),
            n => format!("{head}{n} goal literals do not hold in the world"),
        },
    );
    for g in unmet {
        diagnostic = diagnostic.with_note(format!("not in the world: `{}`", show(g)));
    }
    for u in unaccounted {
        diagnostic = diagnostic.with_note(format!("unaccounted: {u}"));
    }
    diagnostic.with_note(world_note(interner, facts, &[]))
}

/// The world read back, for a note.
#[cfg(feature = "sim")]
pub fn world_note(interner: &Interner, facts: &[Term], unaccounted: &[Misplaced]) -> String {
    let show = |t: &Term| crate::ir::hir::term_to_string(interner, t, &Default::default());
    let mut world: Vec<String> = facts.iter().map(show).collect();
    world.extend(unaccounted.iter().map(|u| format!("unaccounted: {u}")));
    format!("the world read back: {}", world.join(", "))
}
