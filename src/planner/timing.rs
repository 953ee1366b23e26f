//! Achiever-based earliest times of snap actions, for the heuristic search's makespan cost.
//!
//! As a plan prefix grows one snap action at a time, each new action gets the earliest time it
//! could happen if every action waited only for its achievers, as the paper's partial order
//! does: the actions whose `add` made its Valid conditions true, the actions whose `del`
//! removed a fact its Invalid conditions forbid, and, for an end, its start plus the action's
//! minimum duration. The largest such time (with each start counted up to its earliest end) is
//! the prefix's makespan. Threat orderings and maximum durations belong to the temporal passes;
//! here the figure only steers the search towards plans that keep several arms busy.
//!
//! Durations come from the KB's `duration(Action, Min, Max)`, proven by the resolution engine
//! and remembered per action instance; an action without one takes [`DEFAULT_DURATION`].

use rustc_hash::FxHashMap;

use super::successors::{self, Applicable, ConditionError, const_to_cell};
use crate::engine::{Cell, Machine, Next};
use crate::intern::sym;
use crate::ir::hir::EffectKind;
use crate::ir::hir::Snap;
use crate::ir::task::{ConstId, Consts, FactId, Task};

/// The duration of a durative action that has no `duration/3`, in time units.
pub const DEFAULT_DURATION: u32 = 1;

/// Minimum durations of durative action instances, proven once each.
#[derive(Default)]
pub struct Durations {
    cache: FxHashMap<ConstId, u32>,
}

impl Durations {
    /// The minimum duration of the running instance `base(args)` started by a schema of index
    /// `schema`: the `Min` of the first solution of `duration(base(args), Min, _)`, rounded up
    /// to a whole time unit, or [`DEFAULT_DURATION`] when there is none or it is not a number.
    pub fn min(
        &mut self,
        consts: &Consts,
        machine: &mut Machine<'_>,
        schema: usize,
        instance: ConstId,
    ) -> Result<u32, ConditionError> {
        if let Some(&known) = self.cache.get(&instance) {
            return Ok(known);
        }
        machine.reset();
        let action = const_to_cell(machine, consts, instance);
        let min = machine.new_var();
        let max = machine.new_var();
        let goal = machine.new_compound(sym::DURATION, &[action, min, max]);
        let mut found = None;
        machine
            .solve(goal, |m| {
                found = Some(match m.deref(min) {
                    Cell::Int(i) => u32::try_from(i.max(0)).unwrap_or(u32::MAX),
                    Cell::Float(f) if f.is_finite() => f.max(0.0).ceil().min(u32::MAX as f64) as u32,
                    _ => DEFAULT_DURATION,
                });
                Next::Stop
            })
            .map_err(|error| ConditionError { schema, error })?;
        let duration = found.unwrap_or(DEFAULT_DURATION);
        self.cache.insert(instance, duration);
        Ok(duration)
    }
}

/// When the facts of a plan prefix were last added and deleted, and when its running actions
/// started. Facts of the initial state were added at time 0.
#[derive(Default)]
pub struct Timeline {
    added: FxHashMap<FactId, u32>,
    /// Per predicate, the facts deleted and when (the latest deletion of each).
    deleted: FxHashMap<u32, Vec<(FactId, u32)>>,
    started: FxHashMap<ConstId, u32>,
    /// The prefix's makespan so far.
    pub makespan: u32,
}

impl Timeline {
    /// Forgets everything, for reuse.
    pub fn clear(&mut self) {
        self.added.clear();
        self.deleted.clear();
        self.started.clear();
        self.makespan = 0;
    }

    /// The earliest time `action` can happen after the prefix recorded so far, and the time
    /// it occupies the plan until (its earliest end, for a start).
    pub fn earliest(
        &self,
        task: &mut Task,
        machine: &mut Machine<'_>,
        durations: &mut Durations,
        action: &Applicable,
    ) -> Result<(u32, u32), ConditionError> {
        let Task { consts, facts, schemas, .. } = task;
        let schema = &schemas[action.schema];
        let mut time = 0u32;
        for literal in schema.valid.iter() {
            let args: Option<Vec<ConstId>> =
                literal.args.iter().map(|a| successors::instantiate(a, consts, &action.bindings)).collect();
            if let Some(fact) = args.and_then(|args| facts.find(literal.pred, &args)) {
                time = time.max(self.added.get(&fact).copied().unwrap_or(0));
            }
        }
        let mut scratch = action.bindings.to_vec();
        let mut trail = Vec::new();
        for literal in schema.invalid.iter() {
            for &(fact, deleted_at) in self.deleted.get(&literal.pred.0).map(Vec::as_slice).unwrap_or(&[]) {
                if deleted_at > time
                    && successors::match_literal(literal, fact, consts, facts, &mut scratch, &mut trail)
                {
                    time = deleted_at;
                }
                successors::undo(&mut scratch, &mut trail, 0);
            }
        }
        let mut until = time;
        match schema.snap {
            Snap::End => {
                if let Some(instance) = action.ends {
                    let start = self.started.get(&instance).copied().unwrap_or(0);
                    let min = durations.min(consts, machine, action.schema, instance)?;
                    time = time.max(start.saturating_add(min));
                    until = time;
                }
            }
            Snap::Start => {
                if let Some(instance) = successors::running_instance(schema, consts, &action.bindings) {
                    until = time.saturating_add(durations.min(consts, machine, action.schema, instance)?);
                }
            }
            Snap::Instant => {}
        }
        Ok((time, until))
    }

    /// Records `action`, applied at `time` (occupying the plan until `until`).
    pub fn record(&mut self, task: &mut Task, action: &Applicable, time: u32, until: u32) {
        let Task { consts, facts, schemas, .. } = task;
        let schema = &schemas[action.schema];
        for (kind, literal) in schema.effects.iter() {
            let args: Option<Vec<ConstId>> =
                literal.args.iter().map(|a| successors::instantiate(a, consts, &action.bindings)).collect();
            let Some(fact) = args.and_then(|args| facts.find(literal.pred, &args)) else { continue };
            match kind {
                EffectKind::Add => {
                    self.added.insert(fact, time);
                }
                EffectKind::Del => {
                    let list = self.deleted.entry(literal.pred.0).or_default();
                    match list.iter_mut().find(|(f, _)| *f == fact) {
                        Some(entry) => entry.1 = time,
                        None => list.push((fact, time)),
                    }
                }
            }
        }
        match schema.snap {
            Snap::Start => {
                if let Some(instance) = successors::running_instance(schema, consts, &action.bindings) {
                    self.started.insert(instance, time);
                }
            }
            Snap::End => {
                if let Some(instance) = action.ends {
                    self.started.remove(&instance);
                }
            }
            Snap::Instant => {}
        }
        self.makespan = self.makespan.max(until);
    }
}

/// The makespan of a whole plan under achiever-based earliest times (no threat orderings).
pub fn makespan(task: &mut Task, machine: &mut Machine<'_>, path: &[Applicable]) -> Result<u32, ConditionError> {
    let mut durations = Durations::default();
    let mut timeline = Timeline::default();
    for action in path {
        let (time, until) = timeline.earliest(task, machine, &mut durations, action)?;
        timeline.record(task, action, time, until);
    }
    Ok(timeline.makespan)
}
