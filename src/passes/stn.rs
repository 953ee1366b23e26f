//! Pass `stn`: a partial-order plan becomes a simple temporal network ([`Stn`]).
//!
//! Each ordering of the plan becomes a precedence `t(after) - t(before) >= epsilon` (zero for
//! an end followed by a start, since at equal times ends come first); each durative action
//! gets `min <= t(end) - t(start) <= max` from `duration/3`, proven by the resolution engine
//! on its instance (`duration(grip(a1, b2), Min, Max)`), or the documented default with a
//! warning naming the action; every point is at or after the origin.

use petgraph::graph::DiGraph;

use crate::diag::{Diagnostic, Diagnostics, codes};
use crate::engine::{Cell, Machine, Next, Program};
use crate::intern::{Interner, sym};
use crate::ir::hir::{self, Kb, Term, VarId, VarTable};
use crate::ir::pop::{Pop, PopStep};
use crate::ir::stn::{Bounds, DEFAULT_DURATION, DurationSource, Edge, EdgeKind, Stn, TimePoint, UNITS};
use crate::ir::unify::unifiable;

/// The durative action `base(args)` a start or end step stands for.
pub fn running_term(kb: &Kb, step: &PopStep) -> Term {
    kb.actions[step.action].instance(&step.name)
}

/// The default bounds: at least [`DEFAULT_DURATION`], no maximum.
fn default_bounds() -> Bounds {
    Bounds { min: DEFAULT_DURATION * UNITS, max: None, source: DurationSource::Default }
}

/// A number of KB time units as STN time, rounded to the nearest thousandth.
pub(crate) fn to_stn_time(value: f64) -> Option<i64> {
    let scaled = (value * UNITS as f64).round();
    (scaled.is_finite() && scaled.abs() < 1e15).then_some(scaled as i64)
}

/// The bounds `duration/3` gave, `min` and `max` (`None`: `inf`), in STN time; `None` when
/// one is out of range (the least negative, or either too large).
pub(crate) fn to_stn_bounds(min: f64, max: Option<f64>) -> Option<(i64, Option<i64>)> {
    let min = to_stn_time(min).filter(|&m| m >= 0)?;
    match max {
        None => Some((min, None)),
        Some(max) => Some((min, Some(to_stn_time(max)?))),
    }
}

/// The bounds `duration(instance, Min, Max)` gives (a maximum of `None` for `inf`), or why
/// not: `Ok(None)` when no clause answers.
pub(crate) fn query_duration(machine: &mut Machine<'_>, instance: &Term) -> Result<Option<(f64, Option<f64>)>, String> {
    machine.reset();
    let mut vars = [None, None];
    let query =
        Term::Compound(sym::DURATION, hir::Args::from([instance.clone(), Term::Var(VarId(0)), Term::Var(VarId(1))]));
    let goal = machine.put_term(&query, &mut vars);
    let (Some(min), Some(max)) = (vars[0], vars[1]) else { return Err("internal: query variables".into()) };
    let mut found: Option<Result<(f64, Option<f64>), String>> = None;
    let number = |m: &Machine<'_>, cell: Cell| match m.deref(cell) {
        Cell::Int(i) => Some(Some(i as f64)),
        Cell::Float(f) => Some(Some(f)),
        Cell::Atom(sym::INF) => Some(None),
        _ => None,
    };
    machine
        .solve(goal, |m| {
            found = Some(match (number(m, min), number(m, max)) {
                (Some(Some(a)), Some(b)) => Ok((a, b)),
                _ => Err("its bounds are not numbers (the maximum may be `inf`)".to_string()),
            });
            Next::Stop
        })
        .map_err(|e| format!("proving it failed: {e:?}"))?;
    found.transpose()
}

/// Builds the STN of `pop`. Durations come from `program` (the KB's clauses); warnings for
/// actions without one, and errors for unusable ones, go to `diags`.
pub fn build(kb: &Kb, interner: &Interner, program: &Program, pop: &Pop, epsilon: i64, diags: &mut Diagnostics) -> Stn {
    let mut graph: DiGraph<TimePoint, Edge> = DiGraph::new();
    let origin = graph.add_node(TimePoint::Origin);
    let nodes: Vec<_> = (0..pop.steps.len()).map(|i| graph.add_node(TimePoint::Step(i))).collect();
    for &node in &nodes {
        graph.add_edge(node, origin, Edge { weight: 0, kind: EdgeKind::AfterOrigin });
    }
    for ordering in &pop.orderings {
        let separation = epsilon;
        graph.add_edge(
            nodes[ordering.after],
            nodes[ordering.before],
            Edge {
                weight: -separation,
                kind: EdgeKind::Precedence { before: ordering.before, after: ordering.after, reason: ordering.reason },
            },
        );
    }
    let mut machine = Machine::new(program, 1_000_000);
    let mut durations: Vec<Option<Bounds>> = vec![None; pop.steps.len()];
    let mut warned: Vec<crate::intern::Symbol> = Vec::new();
    let no_vars = VarTable::default();
    for (end, step) in pop.steps.iter().enumerate() {
        let Some(start) = step.start else { continue };
        let instance = running_term(kb, step);
        let shown = hir::term_to_string(interner, &instance, &no_vars);
        let clause_span = kb
            .clauses
            .iter()
            .find(|c| {
                c.head.name() == sym::DURATION && c.head.arity() == 3 && unifiable(&c.head.term.args()[0], &instance)
            })
            .map(|c| c.span);
        let bounds = match query_duration(&mut machine, &instance) {
            Ok(Some((min, max))) => match to_stn_bounds(min, max) {
                Some((min, max)) => {
                    Bounds { min, max, source: clause_span.map_or(DurationSource::Default, DurationSource::Clause) }
                }
                None => {
                    let mut diagnostic = Diagnostic::error(
                        codes::BAD_DURATION_VALUE,
                        format!("the duration of `{shown}` is out of range"),
                    )
                    .with_note(format!(
                        "`duration/3` gave [{min}, {}] time units",
                        max.map_or("inf".to_string(), |m| m.to_string())
                    ));
                    if let Some(span) = clause_span {
                        diagnostic = diagnostic.primary(span, "this clause");
                    }
                    diags.push(diagnostic);
                    default_bounds()
                }
            },
            Ok(None) => {
                let action = &kb.actions[pop.steps[start].action];
                if !warned.contains(&action.base) {
                    warned.push(action.base);
                    let base = interner.resolve(action.base);
                    diags.push(
                        Diagnostic::warning(
                            codes::DEFAULT_DURATION,
                            format!("`{base}` has no duration: it takes at least {DEFAULT_DURATION} time unit"),
                        )
                        .primary(action.name.span, "this durative action")
                        .with_note(format!("no `duration/3` clause answers `duration({shown}, Min, Max)`"))
                        .with_help(format!("add a fact such as `duration({base}(...), 1, 2).`")),
                    );
                }
                default_bounds()
            }
            Err(why) => {
                let mut diagnostic = Diagnostic::error(
                    codes::BAD_DURATION_VALUE,
                    format!("cannot read the duration of `{shown}`: {why}"),
                );
                if let Some(span) = clause_span {
                    diagnostic = diagnostic.primary(span, "this clause");
                }
                diags.push(diagnostic.with_help("`duration(Action, Min, Max)` must bind Min and Max to numbers"));
                default_bounds()
            }
        };
        durations[start] = Some(bounds);
        if let Some(max) = bounds.max {
            graph.add_edge(
                nodes[start],
                nodes[end],
                Edge { weight: max, kind: EdgeKind::MaxDuration { start, source: bounds.source } },
            );
        }
        graph.add_edge(
            nodes[end],
            nodes[start],
            Edge { weight: -bounds.min, kind: EdgeKind::MinDuration { start, source: bounds.source } },
        );
    }
    Stn { graph, origin, nodes, durations, epsilon }
}
