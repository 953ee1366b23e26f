//! The temporal passes: achievers and the partial order, the STN with durations, consistency
//! and the schedule; and `reassign`, which keeps a rearranged plan when its schedule is shorter.

use crate::diag::{Diagnostic, Diagnostics};
use crate::intern::Interner;
use crate::ir::hir::{self, Kb};

/// What the temporal passes produced for one plan.
pub struct Timed {
    /// The partial-order plan.
    pub pop: crate::ir::pop::Pop,
    /// Its simple temporal network.
    pub stn: crate::ir::stn::Stn,
    /// The earliest-start schedule.
    pub schedule: crate::ir::schedule::Schedule,
}

/// What orders an arm-level plan beyond its own achievers.
#[derive(Clone, Copy)]
pub(crate) struct ArmOrder<'a> {
    /// The high-level step of each arm-level step.
    pub origin: &'a [usize],
    /// The high-level plan's partial order.
    pub high: &'a crate::ir::pop::Pop,
    /// The units of the resources (the arms), each doing one step at a time.
    pub units: &'a [hir::Term],
}

/// Runs the temporal passes on a valid plan: achievers and the partial order (for an
/// arm-level plan, also the refinement's order and one step at a time per arm: `arm`), the STN
/// with durations, consistency and the schedule. Warnings (default durations) and errors go to
/// `diags`; an inconsistent network is an error whose labels mark each constraint of the
/// negative cycle, and the result is `None`.
pub(crate) fn schedule(
    kb: &Kb,
    interner: &Interner,
    program: &crate::engine::Program,
    plan: &crate::ir::plan::Plan,
    arm: Option<ArmOrder<'_>>,
    epsilon: i64,
    diags: &mut Diagnostics,
) -> Option<Timed> {
    use crate::ir::{pop, schedule, stn};
    use crate::passes;
    let pop = super::timing::time(
        "pop",
        || {
            let mut pop = passes::pop::build(kb, interner, plan);
            if let Some(arm) = arm {
                passes::pop::order_by_refinement(&mut pop, arm.origin, arm.high);
                passes::pop::order_units(&mut pop, arm.units);
            }
            pop
        },
        |pop| format!("{} steps, {} orderings", pop.steps.len(), pop.orderings.len()),
    );
    super::verify_after("pop", || pop::verify(kb, &pop));
    let errors_before = diags.error_count();
    let stn = super::timing::time(
        "stn",
        || passes::stn::build(kb, interner, program, &pop, epsilon, diags),
        |stn| format!("{} time points, {} constraints", stn.graph.node_count(), stn.graph.edge_count()),
    );
    super::verify_after("stn", || stn::verify(&pop, &stn));
    if diags.error_count() > errors_before {
        return None;
    }
    let solved = super::timing::time(
        "schedule",
        || passes::schedule::solve(&stn),
        |solved| match solved {
            Ok(schedule) => format!("makespan {}", crate::ir::stn::format_time(schedule.makespan)),
            Err(_) => "a negative cycle".to_string(),
        },
    );
    match solved {
        Ok(schedule) => {
            super::verify_after("schedule", || schedule::verify(&pop, &schedule));
            Some(Timed { pop, stn, schedule })
        }
        Err(cycle) => {
            diags.push(negative_cycle_diagnostic(kb, interner, &pop, &stn, &cycle));
            None
        }
    }
}

/// How many times [`reassign`] rearranges a plan it has just improved.
const REASSIGN_ROUNDS: usize = 4;

/// Runs the `reassign` pass on a scheduled plan and keeps what it gains: each candidate, best
/// estimate first, is checked step by step under the search's semantics
/// ([`crate::planner::is_solution`]) and scheduled by the temporal passes; the first whose
/// makespan is shorter replaces the plan, and the pass runs again on it, up to
/// [`REASSIGN_ROUNDS`] times. Returns the plan and schedule kept (the given ones when nothing
/// was shorter).
pub(crate) fn reassign(
    kb: &Kb,
    interner: &Interner,
    program: &crate::engine::Program,
    task: &mut crate::ir::task::Task,
    plan: crate::ir::plan::Plan,
    timed: Timed,
) -> (crate::ir::plan::Plan, Timed) {
    let before = timed.schedule.makespan;
    let rounds = || {
        let (mut plan, mut timed) = (plan, timed);
        for _ in 0..REASSIGN_ROUNDS {
            let candidates = crate::passes::reassign::candidates(kb, &plan, &timed.pop, &timed.stn);
            let mut improved = false;
            for candidate in candidates {
                if candidate.estimate >= timed.schedule.makespan
                    || !crate::planner::is_solution(task, program, &candidate.plan)
                {
                    continue;
                }
                let mut diags = Diagnostics::new();
                if let Some(scheduled) =
                    schedule(kb, interner, program, &candidate.plan, None, timed.stn.epsilon, &mut diags)
                    && scheduled.schedule.makespan < timed.schedule.makespan
                {
                    (plan, timed) = (candidate.plan, scheduled);
                    improved = true;
                    break;
                }
            }
            if !improved {
                break;
            }
        }
        (plan, timed)
    };
    super::timing::time("reassign", rounds, |(_, timed)| {
        let (from, to) = (before, timed.schedule.makespan);
        format!("makespan {} -> {}", crate::ir::stn::format_time(from), crate::ir::stn::format_time(to))
    })
}

/// The makespan `kbc plan` gives a plan the heuristic search found: scheduled by the temporal
/// passes, then rearranged by [`reassign`]. The search's improvement phase scores its plans
/// with it, since `reassign` can shorten a plan a lot more than the search can tell.
pub struct ReassignedMakespan<'a> {
    /// The KB.
    pub kb: &'a Kb,
    /// Its names.
    pub interner: &'a Interner,
    /// The problem's program (see [`crate::planner::program_for`]).
    pub program: &'a crate::engine::Program,
    /// The separation of ordered snap actions in the temporal network.
    pub epsilon: i64,
}

impl crate::planner::Score for ReassignedMakespan<'_> {
    fn score(&mut self, task: &mut crate::ir::task::Task, plan: &crate::ir::plan::Plan) -> Option<i64> {
        let timed = schedule(self.kb, self.interner, self.program, plan, None, self.epsilon, &mut Diagnostics::new())?;
        let (_, timed) = reassign(self.kb, self.interner, self.program, task, plan.clone(), timed);
        Some(timed.schedule.makespan)
    }
}

/// E0401, with a label on each constraint of the cycle.
fn negative_cycle_diagnostic(
    kb: &Kb,
    interner: &Interner,
    pop: &crate::ir::pop::Pop,
    stn: &crate::ir::stn::Stn,
    cycle: &crate::passes::schedule::NegativeCycle,
) -> Diagnostic {
    use crate::diag::codes;
    use crate::ir::pop::Reason;
    use crate::ir::stn::{DurationSource, EdgeKind, format_time};
    let no_vars = hir::VarTable::default();
    let step_name = |i: usize| format!("a{} `{}`", i + 1, hir::term_to_string(interner, &pop.steps[i].name, &no_vars));
    let action_span = |i: usize| kb.actions[pop.steps[i].action].name.span;
    let mut diagnostic = Diagnostic::error(
        codes::INCONSISTENT_STN,
        "no schedule satisfies the plan's durations and orderings".to_string(),
    );
    let mut chain = Vec::new();
    for (k, &edge) in cycle.edges.iter().enumerate() {
        let weight = stn.graph[edge];
        let (span, message) = match weight.kind {
            EdgeKind::Precedence { before, after, reason } => {
                let span = match reason {
                    Reason::Achiever { condition } => pop.steps[after].conditions.get(condition).map(|c| c.span),
                    Reason::Threat { consumer, condition } if consumer < pop.steps.len() => {
                        pop.steps[consumer].conditions.get(condition).map(|c| c.span)
                    }
                    Reason::Threat { condition, .. } => pop.goal.get(condition).map(|c| c.span),
                    Reason::StartEnd | Reason::Refinement | Reason::SameUnit => None,
                }
                .unwrap_or_else(|| action_span(after));
                chain.push(format!("{} after {}", step_name(after), step_name(before)));
                (span, format!("{} must wait for {}", step_name(after), step_name(before)))
            }
            EdgeKind::MinDuration { start, source } | EdgeKind::MaxDuration { start, source } => {
                let bounds = stn.durations[start].expect("a start has bounds");
                let is_max = matches!(weight.kind, EdgeKind::MaxDuration { .. });
                let what = if is_max {
                    format!("at most {}", bounds.max.map_or("inf".to_string(), format_time))
                } else {
                    format!("at least {}", format_time(bounds.min))
                };
                let running = crate::passes::stn::running_term(kb, &pop.steps[start]);
                let shown = hir::term_to_string(interner, &running, &no_vars);
                chain.push(format!("`{shown}` lasts {what}"));
                let span = match source {
                    DurationSource::Clause(span) => span,
                    DurationSource::Default => action_span(start),
                };
                (span, format!("`{shown}` lasts {what}"))
            }
            EdgeKind::AfterOrigin => {
                chain.push("nothing happens before time 0".to_string());
                continue;
            }
        };
        diagnostic = if k == 0 { diagnostic.primary(span, message) } else { diagnostic.secondary(span, message) };
    }
    diagnostic
        .with_note(format!("these constraints form a cycle: {}", chain.join("; ")))
        .with_note(format!(
            "together they ask a time point to come {} time units before itself",
            format_time(-cycle.weight)
        ))
        .with_help("correct the `duration/3` bounds, or ask for other plans with `--retries N`")
}
