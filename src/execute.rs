//! What the compiler adds to a run of a program (the run loop itself is `kbvm::run`): the
//! simulated world built for a KB's problem, the world read back as HIR terms, and the
//! executed timeline as a timed plan that the timed validator checks against the KB.

use std::fmt::Write;

use kbvm::Program;
use kbvm::bytecode::Instr;
use kbvm::run::Run;
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

/// The executed timeline as a timed plan in the PDDL 2.1 format (`kbc validate` reads it):
/// each action at its start's recorded time, with the time to its end's.
pub fn timed_plan(program: &Program, run: &Run) -> String {
    let m = program.module();
    let mut lines: Vec<(i64, usize, String)> = Vec::new();
    let time = |t: i64| program.time_text(t);
    let call = |import: &kbvm::bytecode::ImportId, args: &[kbvm::bytecode::Value]| {
        let mut text = format!("({}", program.import_name(*import));
        for &a in args {
            let _ = write!(text, " {}", program.value_text(a));
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
