//! The simple temporal network (STN): a time point per snap action of a partial-order plan,
//! plus the origin, and difference constraints between them, as a distance graph on petgraph.
//!
//! An edge `u -> v` of weight `w` says `t(v) - t(u) <= w`. Times are integers, in thousandths
//! of the KB's time unit ([`UNITS`]): floating-point weights make the zero-weight loops of
//! simultaneous starts and ends look like negative cycles, and a thousandth is the separation
//! that keeps ordered snap actions apart (the `epsilon` of PDDL 2.1 plans).
//!
//! Every edge remembers why it is there ([`EdgeKind`]), so a negative cycle can be reported
//! with a label on each constraint that closes it.

use std::fmt::Write;

use petgraph::graph::{DiGraph, EdgeIndex, NodeIndex};
use petgraph::visit::EdgeRef;

use crate::intern::Interner;
use crate::ir::hir::{self, VarTable};
use crate::ir::pop::{Pop, Reason};
use crate::source::Span;

/// Time points per unit of KB time: STN times are thousandths.
pub const UNITS: i64 = 1000;

/// The least duration of a durative action without `duration/3`, in KB time units; it has no
/// maximum, so the default never makes an order inconsistent: an end that must wait for
/// something simply comes later.
pub const DEFAULT_DURATION: i64 = 1;

/// The default least separation, in STN time (a thousandth of a time unit), between two
/// ordered snap actions, an end and a start that depends on it included: PDDL 2.1 asks for a positive ε
/// between an action and one that needs its effect, and validators (Kairos, for one) reject a
/// start at the very instant of the end it depends on.
pub const EPSILON: i64 = 1;

/// A time point: a step of the plan, or the origin.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TimePoint {
    /// Time zero: the plan starts here.
    Origin,
    /// The snap action at this index of the plan.
    Step(usize),
}

/// Where a durative action's bounds came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DurationSource {
    /// A `duration/3` clause (the first whose head matches the action).
    Clause(Span),
    /// No clause: at least [`DEFAULT_DURATION`], no maximum.
    Default,
}

/// Why an edge is there.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EdgeKind {
    /// Step `before` must happen before step `after` (an ordering of the partial-order plan).
    Precedence {
        /// The earlier step.
        before: usize,
        /// The later step.
        after: usize,
        /// The partial-order plan's reason.
        reason: Reason,
    },
    /// The end of the action started at `start` comes at least its minimum duration later.
    MinDuration {
        /// The start step.
        start: usize,
        /// Where the bound comes from.
        source: DurationSource,
    },
    /// The end of the action started at `start` comes at most its maximum duration later.
    MaxDuration {
        /// The start step.
        start: usize,
        /// Where the bound comes from.
        source: DurationSource,
    },
    /// Nothing happens before the origin.
    AfterOrigin,
}

/// An edge of the distance graph.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Edge {
    /// `t(target) - t(source) <= weight`.
    pub weight: i64,
    /// Why.
    pub kind: EdgeKind,
}

/// A durative action's bounds, in STN time.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Bounds {
    /// Minimum of end minus start.
    pub min: i64,
    /// Maximum of end minus start; `None` for `inf` (no upper bound).
    pub max: Option<i64>,
    /// Where they come from.
    pub source: DurationSource,
}

/// A simple temporal network over the steps of a partial-order plan.
#[derive(Clone, Debug)]
pub struct Stn {
    /// The distance graph.
    pub graph: DiGraph<TimePoint, Edge>,
    /// The origin's node.
    pub origin: NodeIndex,
    /// Each step's node, by plan index.
    pub nodes: Vec<NodeIndex>,
    /// For each start step, its action's bounds.
    pub durations: Vec<Option<Bounds>>,
    /// The least separation of two ordered snap actions in this network, in STN time
    /// ([`EPSILON`] unless asked otherwise: `--epsilon`).
    pub epsilon: i64,
}

impl TimePoint {
    /// The name dumps and pictures give the point: `origin`, or `aN` for step N (from 1), as
    /// the paper's table of achievers numbers actions.
    pub fn name(self) -> String {
        match self {
            TimePoint::Origin => "origin".to_string(),
            TimePoint::Step(i) => format!("a{}", i + 1),
        }
    }
}

impl Stn {
    /// The number of time points, the origin included.
    pub fn len(&self) -> usize {
        self.graph.node_count()
    }

    /// True if the network has no time point but the origin.
    pub fn is_empty(&self) -> bool {
        self.graph.node_count() <= 1
    }

    /// The network with every durative action's duration fixed to its minimum, as a planner
    /// reads `(= ?duration min)` (`kbc export pddl --durations min`): each minimum-duration
    /// constraint gets the maximum that matches it. `durations` keeps the KB's bounds.
    pub fn with_minimum_durations(&self) -> Stn {
        let mut fixed = self.clone();
        for edge in self.graph.edge_references() {
            if let EdgeKind::MinDuration { start, source } = edge.weight().kind {
                // The minimum is the edge end -> start of weight -min.
                let kind = EdgeKind::MaxDuration { start, source };
                fixed.graph.add_edge(edge.target(), edge.source(), Edge { weight: -edge.weight().weight, kind });
            }
        }
        fixed
    }

    /// The edge's endpoints.
    pub fn endpoints(&self, edge: EdgeIndex) -> (TimePoint, TimePoint) {
        let (a, b) = self.graph.edge_endpoints(edge).expect("an edge of this graph");
        (self.graph[a], self.graph[b])
    }
}

/// Formats STN time as KB time with three decimals: `1500` is `1.500`.
pub fn format_time(t: i64) -> String {
    let sign = if t < 0 { "-" } else { "" };
    let t = t.unsigned_abs();
    format!("{sign}{}.{:03}", t / UNITS as u64, t % UNITS as u64)
}

/// The text form (`--dump-after stn`): each constraint as a difference bound.
pub fn print(interner: &Interner, pop: &Pop, stn: &Stn) -> String {
    let mut out = String::new();
    let no_vars = VarTable::default();
    let _ = writeln!(
        out,
        "% STN: {} time points, {} constraints (times in thousandths)",
        stn.len(),
        stn.graph.edge_count()
    );
    for (i, step) in pop.steps.iter().enumerate() {
        let _ = write!(out, "a{:<3} {}", i + 1, hir::term_to_string(interner, &step.name, &no_vars));
        if let Some(Some(bounds)) = stn.durations.get(i) {
            let source = match bounds.source {
                DurationSource::Clause(_) => "duration/3",
                DurationSource::Default => "default",
            };
            let max = bounds.max.map_or("inf".to_string(), format_time);
            let _ = write!(out, "  duration [{}, {max}] ({source})", format_time(bounds.min));
        }
        out.push('\n');
    }
    for edge in stn.graph.edge_references() {
        let (from, to) = (stn.graph[edge.source()], stn.graph[edge.target()]);
        if edge.weight().kind == EdgeKind::AfterOrigin {
            continue;
        }
        let _ = writeln!(out, "{} - {} <= {}", to.name(), from.name(), edge.weight().weight);
    }
    out
}

/// Checks the invariants: one node per step plus the origin, every edge between existing
/// points and consistent with its kind, durations only on starts. A failure is a compiler bug.
pub fn verify(pop: &Pop, stn: &Stn) -> Result<(), String> {
    if stn.nodes.len() != pop.steps.len() || stn.len() != pop.steps.len() + 1 {
        return Err(format!("{} nodes for {} steps", stn.len(), pop.steps.len()));
    }
    if stn.graph[stn.origin] != TimePoint::Origin {
        return Err("the origin node is not the origin".to_string());
    }
    for (i, &node) in stn.nodes.iter().enumerate() {
        if stn.graph[node] != TimePoint::Step(i) {
            return Err(format!("node of step {} is {:?}", i + 1, stn.graph[node]));
        }
    }
    for edge in stn.graph.edge_references() {
        let (from, to) = (stn.graph[edge.source()], stn.graph[edge.target()]);
        let ok = match edge.weight().kind {
            EdgeKind::Precedence { before, after, .. } => {
                from == TimePoint::Step(after) && to == TimePoint::Step(before) && edge.weight().weight <= 0
            }
            EdgeKind::MinDuration { start, .. } => to == TimePoint::Step(start),
            EdgeKind::MaxDuration { start, .. } => from == TimePoint::Step(start),
            EdgeKind::AfterOrigin => to == TimePoint::Origin && edge.weight().weight == 0,
        };
        if !ok {
            return Err(format!("edge {from:?} -> {to:?} does not match its kind {:?}", edge.weight().kind));
        }
    }
    Ok(())
}

/// The text form of the minimal network (`--dump-after minimal`), written as it is computed:
/// for every pair of time points, the tightest bounds on the later minus the earlier, in
/// thousandths (`inf` where nothing bounds it). `row(node)` gives, by node index, how much
/// later every point can be than `node` and how much earlier (see
/// `passes::schedule::MinimalNetwork::row`).
pub fn print_minimal(
    stn: &Stn,
    mut row: impl FnMut(usize) -> (Vec<Option<i64>>, Vec<Option<i64>>),
    out: &mut dyn std::io::Write,
) -> std::io::Result<()> {
    // Origin first, then the steps in plan order, as `--dump-after stn` names them.
    let order: Vec<NodeIndex> = std::iter::once(stn.origin).chain(stn.nodes.iter().copied()).collect();
    writeln!(
        out,
        "% minimal network: {} time points; `x y [lo, hi]` is lo <= y - x <= hi (times in thousandths)",
        stn.len()
    )?;
    for (k, &x) in order.iter().enumerate() {
        let (later, earlier) = row(x.index());
        for &y in &order[k + 1..] {
            let lo = earlier[y.index()].map_or("-inf".to_string(), |d| (-d).to_string());
            let hi = later[y.index()].map_or("inf".to_string(), |d| d.to_string());
            writeln!(out, "{} {} [{lo}, {hi}]", stn.graph[x].name(), stn.graph[y].name())?;
        }
    }
    Ok(())
}
