//! A schedule: a time for every snap action of a plan, the earliest the STN allows, with the
//! latest times that keep the makespan and the slack between them.

use std::fmt::Write;

use crate::intern::Interner;
use crate::ir::hir::{self, Kb, Snap, Term, VarTable};
use crate::ir::pop::Pop;
use crate::ir::stn::format_time;

/// Times of the snap actions of a plan, in STN time (thousandths of a time unit).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Schedule {
    /// The earliest time of each step, by plan index.
    pub earliest: Vec<i64>,
    /// The latest time of each step that keeps the makespan.
    pub latest: Vec<i64>,
    /// The time of the last snap action.
    pub makespan: i64,
}

impl Schedule {
    /// How much step `i` may slip without delaying the plan.
    pub fn slack(&self, i: usize) -> i64 {
        self.latest[i] - self.earliest[i]
    }
}

/// One action of a timed plan: a durative action (start and end steps) or an instantaneous one.
#[derive(Clone, Debug, PartialEq)]
pub struct TimedAction {
    /// The step that starts it (or the instant step).
    pub step: usize,
    /// Its name: `X(args)` for a durative action `X_start`/`X_end`, the step's name otherwise.
    pub name: Term,
    /// When it starts.
    pub time: i64,
    /// For a durative action, end minus start.
    pub duration: Option<i64>,
    /// For a durative action, the step that ends it.
    pub end: Option<usize>,
}

/// The actions of a scheduled plan, by start time (then plan order).
pub fn timed_actions(kb: &Kb, pop: &Pop, schedule: &Schedule) -> Vec<TimedAction> {
    let mut ends = vec![None; pop.steps.len()];
    for (i, step) in pop.steps.iter().enumerate() {
        if let Some(start) = step.start {
            ends[start] = Some(i);
        }
    }
    let mut actions: Vec<TimedAction> = pop
        .steps
        .iter()
        .enumerate()
        .filter(|(_, step)| step.snap != Snap::End)
        .map(|(i, step)| {
            let base = kb.actions[step.action].base;
            let name = match (step.snap, &step.name) {
                (Snap::Start, Term::Compound(_, args)) => Term::Compound(base, args.clone()),
                (Snap::Start, _) => Term::Atom(base),
                _ => step.name.clone(),
            };
            let duration = ends[i].map(|e| schedule.earliest[e] - schedule.earliest[i]);
            TimedAction { step: i, name, time: schedule.earliest[i], duration, end: ends[i] }
        })
        .collect();
    actions.sort_by_key(|a| (a.time, a.step));
    actions
}

/// `name(a, b)` as PDDL writes an action: `(name a b)`.
pub fn pddl_action(interner: &Interner, name: &Term) -> String {
    let no_vars = VarTable::default();
    match name {
        Term::Compound(f, args) => {
            let args: Vec<String> = args
                .iter()
                .map(|a| crate::syntax::text::without_layout(&hir::term_to_string(interner, a, &no_vars)))
                .collect();
            format!("({} {})", interner.resolve(*f), args.join(" "))
        }
        other => format!("({})", hir::term_to_string(interner, other, &no_vars)),
    }
}

/// The schedule in the PDDL 2.1 plan format: `0.000: (grip a1 b2) [1.000]`, one action a line.
pub fn print(interner: &Interner, kb: &Kb, pop: &Pop, schedule: &Schedule) -> String {
    let mut out = String::new();
    for action in timed_actions(kb, pop, schedule) {
        let _ = write!(out, "{}: {}", format_time(action.time), pddl_action(interner, &action.name));
        if let Some(duration) = action.duration {
            let _ = write!(out, " [{}]", format_time(duration));
        }
        out.push('\n');
    }
    out
}

/// The text form (`--dump-after schedule`): every snap action with its earliest and latest
/// time and its slack, in plan order.
pub fn dump(interner: &Interner, pop: &Pop, schedule: &Schedule) -> String {
    let no_vars = VarTable::default();
    let names: Vec<String> = pop.steps.iter().map(|s| hir::term_to_string(interner, &s.name, &no_vars)).collect();
    let width = names.iter().map(String::len).max().unwrap_or(0);
    let mut out = format!(
        "% schedule: makespan {}; each snap action's earliest time, latest time that keeps the makespan, slack\n",
        format_time(schedule.makespan)
    );
    for (i, name) in names.iter().enumerate() {
        let _ = writeln!(
            out,
            "a{:<3} {name:<width$}  {:>9} {:>9}  slack {}",
            i + 1,
            format_time(schedule.earliest[i]),
            format_time(schedule.latest[i]),
            format_time(schedule.slack(i))
        );
    }
    out
}

/// Checks the invariants: a time per step, earliest <= latest, nothing before zero, the
/// makespan the largest time, every ordering respected. A failure is a compiler bug.
pub fn verify(pop: &Pop, schedule: &Schedule) -> Result<(), String> {
    let n = pop.steps.len();
    if schedule.earliest.len() != n || schedule.latest.len() != n {
        return Err(format!("{} and {} times for {n} steps", schedule.earliest.len(), schedule.latest.len()));
    }
    for i in 0..n {
        if schedule.earliest[i] < 0 || schedule.earliest[i] > schedule.latest[i] {
            return Err(format!("step {}: earliest {} latest {}", i + 1, schedule.earliest[i], schedule.latest[i]));
        }
    }
    if schedule.makespan != schedule.earliest.iter().copied().max().unwrap_or(0) {
        return Err("the makespan is not the last time".to_string());
    }
    for o in &pop.orderings {
        if schedule.earliest[o.before] > schedule.earliest[o.after] {
            return Err(format!("a{} is scheduled after a{}", o.before + 1, o.after + 1));
        }
    }
    Ok(())
}
