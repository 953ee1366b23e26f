//! Times of the snap actions of a plan prefix, for the heuristic search: a makespan to prefer
//! plans that keep several arms busy, and a check that the prefix can be scheduled at all.
//!
//! As a prefix grows one snap action at a time, each new action is *placed*: its achievers are
//! the actions whose `add` made its Valid conditions true and those whose `del` removed a fact
//! its Invalid conditions forbid (the links of the paper's partial order), and, for an end,
//! its start; its earliest time is the latest achiever's time plus a separation (a thousandth,
//! `ir::stn::EPSILON`), and an end comes at least its minimum duration after its
//! start. Times are in STN units (thousandths of a KB time unit), as in `ir::stn`.
//!
//! Maximum durations are what makes a prefix unschedulable: an arm that holds a block in the
//! air waiting for its destination overruns the move's maximum, and delaying the move's start
//! does not help when other actions needed it early. [`Timeline::consistent`] runs the
//! prefix's difference constraints (achiever links, minimum and maximum durations) through a
//! Bellman-Ford relaxation and finds out; the search prunes such prefixes rather than hand
//! the scheduler a plan it must reject. Threat orderings are left to the temporal passes.
//!
//! Beside its time, each step gets a *resource-free* time: the same rule without the achievers
//! of Valid conditions on a renewable resource (`available(A)` under `resources(available(_))`).
//! It is when the step could happen if a unit were always free, and the resource-free makespan
//! is a lower bound for any plan that does the same steps with the units given out again (the
//! `reassign` pass), which the improvement phase of the search prunes with.
//!
//! Durations come from the KB's `duration(Action, Min, Max)`, proven by the resolution engine
//! and remembered per action instance; an action without one takes the documented default.

use rustc_hash::FxHashMap;

use super::successors::{self, Applicable, ConditionError, const_to_cell};
use crate::engine::{Cell, Machine, Next};
use crate::intern::sym;
use crate::ir::hir::{EffectKind, Snap};
use crate::ir::stn::{DEFAULT_DURATION, EPSILON, UNITS};
use crate::ir::task::{ConstId, Consts, FactId, Task};

/// Bounds of durative action instances, proven once each.
#[derive(Default)]
pub struct Durations {
    cache: FxHashMap<ConstId, (i64, i64)>,
}

fn to_units(cell: Cell) -> Option<i64> {
    match cell {
        Cell::Atom(sym::INF) => Some(i64::MAX),
        Cell::Int(i) => i.checked_mul(UNITS),
        Cell::Float(f) if f.is_finite() && f.abs() < 1e12 => Some((f * UNITS as f64).round() as i64),
        _ => None,
    }
}

impl Durations {
    /// The bounds (in STN units) of the running instance `base(args)` started by the schema of
    /// index `schema`: the first solution of `duration(base(args), Min, Max)`, or the default
    /// when there is none or it is not a pair of numbers; a maximum of `inf` is `i64::MAX`.
    pub fn bounds(
        &mut self,
        consts: &Consts,
        machine: &mut Machine<'_>,
        schema: usize,
        instance: ConstId,
    ) -> Result<(i64, i64), ConditionError> {
        if let Some(&known) = self.cache.get(&instance) {
            return Ok(known);
        }
        machine.reset();
        let action = const_to_cell(machine, consts, instance);
        let min = machine.new_var();
        let max = machine.new_var();
        let goal = machine.new_compound(sym::DURATION, &[action, min, max]);
        // No answer: at least the default, no maximum (as the STN pass has it).
        let default = (DEFAULT_DURATION * UNITS, i64::MAX);
        let mut found = None;
        machine
            .solve(goal, |m| {
                found = Some(match (to_units(m.deref(min)), to_units(m.deref(max))) {
                    (Some(min), Some(max)) if min < i64::MAX => (min.max(0), max),
                    _ => default,
                });
                Next::Stop
            })
            .map_err(|error| ConditionError { schema, error, duration: true })?;
        let bounds = found.unwrap_or(default);
        self.cache.insert(instance, bounds);
        Ok(bounds)
    }
}

/// Where a new action goes in the timeline.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Placement {
    /// Its earliest time.
    pub time: i64,
    /// The time it occupies the plan until: its earliest end, for a start.
    pub until: i64,
    /// Its resource-free time.
    pub free: i64,
    /// Its resource-free `until`.
    pub free_until: i64,
    /// The earlier steps it waits for, with the separation from each.
    achievers: Vec<(usize, i64)>,
    /// For an end: its start step and the action's bounds.
    end_of: Option<(usize, i64, i64)>,
    /// For a start: the instance it begins.
    starts: Option<ConstId>,
}

/// One recorded step.
#[derive(Clone, Debug)]
struct Placed {
    time: i64,
    free: i64,
    achievers: Vec<(usize, i64)>,
    end_of: Option<(usize, i64, i64)>,
}

/// What recording a step changed in a [`Timeline`], to be undone by [`Timeline::truncate`].
#[derive(Clone, Debug)]
enum Undo {
    /// `added[fact]` was this before.
    Added(FactId, Option<usize>),
    /// `deleted[pred][index]` had this step before; `None`: the entry was pushed.
    Deleted(u32, usize, Option<usize>),
    /// `started[instance]` was this before.
    Started(ConstId, Option<usize>),
}

/// The steps of a plan prefix and, for each fact, the last step that added or deleted it.
///
/// The search places the prefix of every state it expands; consecutive states mostly share
/// a long prefix, so the timeline can be cut back to a shorter prefix ([`Timeline::truncate`],
/// from a log of what each step changed) and only the rest placed again.
#[derive(Clone)]
pub struct Timeline {
    /// The least separation of two ordered snap actions.
    epsilon: i64,
    added: FxHashMap<FactId, usize>,
    /// Per predicate, the facts deleted and by which step (the latest deletion of each).
    deleted: FxHashMap<u32, Vec<(FactId, usize)>>,
    started: FxHashMap<ConstId, usize>,
    steps: Vec<Placed>,
    /// The prefix's makespan so far.
    pub makespan: i64,
    /// The prefix's resource-free makespan so far.
    pub free_makespan: i64,
    /// What the recorded steps changed, in order.
    undo: Vec<Undo>,
    /// Per recorded step: the length of `undo` and the two makespans before it.
    marks: Vec<(usize, i64, i64)>,
}

impl Default for Timeline {
    fn default() -> Timeline {
        Timeline::new(EPSILON)
    }
}

impl Timeline {
    /// An empty timeline whose ordered snap actions are at least `epsilon` apart.
    pub fn new(epsilon: i64) -> Timeline {
        Timeline {
            epsilon,
            added: FxHashMap::default(),
            deleted: FxHashMap::default(),
            started: FxHashMap::default(),
            steps: Vec::new(),
            makespan: 0,
            free_makespan: 0,
            undo: Vec::new(),
            marks: Vec::new(),
        }
    }

    /// Forgets every step after the first `len`: the timeline is as it was when they were
    /// recorded.
    pub fn truncate(&mut self, len: usize) {
        while self.steps.len() > len {
            self.steps.pop();
            let (undo, makespan, free_makespan) = self.marks.pop().expect("a mark per step");
            for change in self.undo.drain(undo..).rev() {
                match change {
                    Undo::Added(fact, before) => match before {
                        Some(step) => {
                            self.added.insert(fact, step);
                        }
                        None => {
                            self.added.remove(&fact);
                        }
                    },
                    Undo::Deleted(pred, index, before) => {
                        let list = self.deleted.get_mut(&pred).expect("logged when changed");
                        match before {
                            Some(step) => list[index].1 = step,
                            None => {
                                list.pop();
                            }
                        }
                    }
                    Undo::Started(instance, before) => match before {
                        Some(step) => {
                            self.started.insert(instance, step);
                        }
                        None => {
                            self.started.remove(&instance);
                        }
                    },
                }
            }
            self.makespan = makespan;
            self.free_makespan = free_makespan;
        }
    }

    /// Where `action` goes after the prefix recorded so far.
    pub fn place(
        &self,
        task: &mut Task,
        machine: &mut Machine<'_>,
        durations: &mut Durations,
        action: &Applicable,
    ) -> Result<Placement, ConditionError> {
        let Task { consts, facts, schemas, .. } = task;
        let schema = &schemas[action.schema];
        let mut achievers: Vec<(usize, i64)> = Vec::new();
        let mut free = 0;
        for (literal, &resource) in schema.valid.iter().zip(schema.resource_valid.iter()) {
            let args: Option<Vec<ConstId>> =
                literal.args.iter().map(|a| successors::instantiate(a, consts, &action.bindings)).collect();
            if let Some(step) = args.and_then(|args| facts.find(literal.pred, &args)).and_then(|f| self.added.get(&f)) {
                let separation = self.epsilon;
                achievers.push((*step, separation));
                if !resource {
                    free = free.max(self.steps[*step].free + separation);
                }
            }
        }
        let mut scratch = action.bindings.to_vec();
        let mut trail = Vec::new();
        for literal in schema.invalid.iter() {
            for &(fact, step) in self.deleted.get(&literal.pred.0).map(Vec::as_slice).unwrap_or(&[]) {
                if successors::match_literal(literal, fact, consts, facts, &mut scratch, &mut trail) {
                    let separation = self.epsilon;
                    achievers.push((step, separation));
                    free = free.max(self.steps[step].free + separation);
                }
                successors::undo(&mut scratch, &mut trail, 0);
            }
        }
        let mut time = achievers.iter().map(|&(step, sep)| self.steps[step].time + sep).max().unwrap_or(0);
        let mut until = time;
        let mut free_until = free;
        let mut end_of = None;
        let mut starts = None;
        match schema.snap {
            Snap::End => {
                if let Some(&start) = action.ends.as_ref().and_then(|instance| self.started.get(instance)) {
                    let instance = action.ends.expect("checked above");
                    let (min, max) = durations.bounds(consts, machine, action.schema, instance)?;
                    time = time.max(self.steps[start].time + min.max(self.epsilon));
                    until = time;
                    free = free.max(self.steps[start].free + min.max(self.epsilon));
                    free_until = free;
                    end_of = Some((start, min.max(self.epsilon), max));
                }
            }
            Snap::Start => {
                if let Some(instance) = successors::running_instance(schema, consts, &action.bindings) {
                    let (min, _) = durations.bounds(consts, machine, action.schema, instance)?;
                    until = time.saturating_add(min.max(self.epsilon));
                    free_until = free.saturating_add(min.max(self.epsilon));
                    starts = Some(instance);
                }
            }
            Snap::Instant => {}
        }
        Ok(Placement { time, until, free, free_until, achievers, end_of, starts })
    }

    /// Records `action`, placed at `placement`, as the next step.
    pub fn record(&mut self, task: &mut Task, action: &Applicable, placement: Placement) {
        let index = self.steps.len();
        self.marks.push((self.undo.len(), self.makespan, self.free_makespan));
        let Task { consts, facts, schemas, .. } = task;
        let schema = &schemas[action.schema];
        for (kind, literal) in schema.effects.iter() {
            let args: Option<Vec<ConstId>> =
                literal.args.iter().map(|a| successors::instantiate(a, consts, &action.bindings)).collect();
            let Some(fact) = args.and_then(|args| facts.find(literal.pred, &args)) else { continue };
            match kind {
                EffectKind::Add => {
                    let before = self.added.insert(fact, index);
                    self.undo.push(Undo::Added(fact, before));
                }
                EffectKind::Del => {
                    let list = self.deleted.entry(literal.pred.0).or_default();
                    match list.iter().position(|(f, _)| *f == fact) {
                        Some(at) => {
                            self.undo.push(Undo::Deleted(literal.pred.0, at, Some(list[at].1)));
                            list[at].1 = index;
                        }
                        None => {
                            self.undo.push(Undo::Deleted(literal.pred.0, list.len(), None));
                            list.push((fact, index));
                        }
                    }
                }
            }
        }
        if let Some(instance) = placement.starts {
            let before = self.started.insert(instance, index);
            self.undo.push(Undo::Started(instance, before));
        }
        if let Some(instance) = action.ends
            && let Some(before) = self.started.remove(&instance)
        {
            self.undo.push(Undo::Started(instance, Some(before)));
        }
        self.makespan = self.makespan.max(placement.until);
        self.free_makespan = self.free_makespan.max(placement.free_until);
        self.steps.push(Placed {
            time: placement.time,
            free: placement.free,
            achievers: placement.achievers,
            end_of: placement.end_of,
        });
    }

    /// True if the prefix can be scheduled: the earliest times that respect every achiever
    /// link and every minimum duration also respect every maximum duration, once starts that
    /// overrun are moved later (a longest-path relaxation, which fails exactly when a cycle of
    /// constraints is positive).
    pub fn consistent(&self) -> bool {
        let n = self.steps.len();
        let mut time: Vec<i64> = self.steps.iter().map(|s| s.time).collect();
        // Forward edges (a step after its achievers) in plan order; backward edges (a start
        // no earlier than its end minus the maximum) only where an end overruns.
        for _round in 0..=n {
            let mut changed = false;
            for (i, step) in self.steps.iter().enumerate() {
                let mut t = time[i];
                for &(j, sep) in &step.achievers {
                    t = t.max(time[j] + sep);
                }
                if let Some((start, min, _)) = step.end_of {
                    t = t.max(time[start] + min);
                }
                if t != time[i] {
                    time[i] = t;
                    changed = true;
                }
            }
            for (i, step) in self.steps.iter().enumerate() {
                if let Some((start, _, max)) = step.end_of
                    && time[i].saturating_sub(time[start]) > max
                {
                    time[start] = time[i] - max;
                    changed = true;
                }
            }
            if !changed {
                return true;
            }
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ladder::{Family, Rung};
    use crate::planner::successors::{Successors, apply};

    /// A timeline cut back to a prefix of the path it recorded places every action as a
    /// timeline that recorded only that prefix, at every length, and taken on from there
    /// along another path, as one that recorded that path from the start: the undo log puts
    /// back the last adder and deleter of each fact, the started instances and the makespans.
    #[test]
    fn a_truncated_timeline_places_as_one_built_from_the_start() {
        let rung = Rung { family: Family::Swap, blocks: 6, arms: 3, seed: 2 };
        let (_, frontend, _) = crate::session::Session::from_text(&rung.name(), rung.source()).into_parts();
        let problem = frontend.kb.problems.len() - 1;
        let mut task = crate::passes::task::build(&frontend.kb, problem);
        let program = crate::planner::program_for(&frontend.kb, &frontend.interner, problem);
        let mut successors = Successors::new(&task, Machine::new(&program, 1_000_000));
        // A walk of up to 40 steps, each the applicable action of index `pick(step)` (modulo
        // how many apply): the actions and the states before each and after the last.
        let mut walk = |task: &mut Task, pick: &dyn Fn(usize) -> usize| {
            let (mut states, mut actions, mut applicable) = (vec![task.init.clone()], Vec::new(), Vec::new());
            for step in 0..40 {
                let state = states.last().expect("the initial state");
                successors.applicable(task, state, &mut applicable).expect("no engine error");
                let Some(action) = applicable.get(pick(step) % applicable.len().max(1)).cloned() else { break };
                states.push(apply(task, state, &action));
                actions.push(action);
            }
            (actions, states)
        };
        let (first, states) = walk(&mut task, &|step| step * 5 + 1);
        // (The first other walk that agrees on 12 steps and goes on for 30.)
        let (second, _) = (2..40)
            .map(|other| walk(&mut task, &|step| if step < 12 { step * 5 + 1 } else { step * 5 + other }))
            .find(|(second, _)| second.len() >= 30 && second[12] != first[12])
            .expect("a walk of 30 steps");
        assert!(first.len() >= 30 && first[..12] == second[..12]);
        let mut machine = Machine::new(&program, 1_000_000);
        let mut checker = Successors::new(&task, Machine::new(&program, 1_000_000));
        let mut durations = Durations::default();
        let mut record = |timeline: &mut Timeline, task: &mut Task, actions: &[Applicable]| {
            for action in actions {
                let placement = timeline.place(task, &mut machine, &mut durations, action).expect("no engine error");
                timeline.record(task, action, placement);
            }
        };
        let mut cut = Timeline::default();
        record(&mut cut, &mut task, &first);
        // Cut back one step at a time: the same placements as a timeline of the prefix alone,
        // for the prefix's next step and every action that applies after it.
        let mut machine = Machine::new(&program, 1_000_000);
        let mut durations = Durations::default();
        let mut applicable = Vec::new();
        for k in (0..=first.len()).rev() {
            cut.truncate(k);
            let mut fresh = Timeline::default();
            record(&mut fresh, &mut task, &first[..k]);
            assert_eq!(cut.steps.len(), k);
            assert_eq!((cut.makespan, cut.free_makespan), (fresh.makespan, fresh.free_makespan), "after {k} steps");
            assert_eq!(cut.consistent(), fresh.consistent());
            checker.applicable(&mut task, &states[k], &mut applicable).expect("no engine error");
            for action in first.get(k).into_iter().chain(&applicable) {
                let mut at = |timeline: &Timeline| {
                    timeline.place(&mut task, &mut machine, &mut durations, action).expect("no engine error")
                };
                assert_eq!(at(&cut), at(&fresh), "after {k} steps: {action:?}");
            }
        }
        assert!(cut.steps.is_empty() && cut.makespan == 0 && cut.added.is_empty() && cut.started.is_empty());
        assert!(cut.deleted.values().all(Vec::is_empty));
        // Taken on along the other path from its 12 shared steps.
        record(&mut cut, &mut task, &first[..20]);
        cut.truncate(12);
        record(&mut cut, &mut task, &second[12..]);
        let mut fresh = Timeline::default();
        record(&mut fresh, &mut task, &second);
        assert_eq!(
            (cut.makespan, cut.free_makespan, cut.consistent()),
            (fresh.makespan, fresh.free_makespan, fresh.consistent())
        );
    }
}
