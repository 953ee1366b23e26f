//! The paper's search (its Algorithm 1), faithfully.
//!
//! ```text
//! plan(State, Goal, Been, Actions, MaxDepth):
//!     if State satisfies Goal: return Actions
//!     if length(Actions) < MaxDepth:
//!         for each action applicable in State, in clause order:
//!             Child = apply(action, State)
//!             if Child satisfies Goal or Child is not in Been:
//!                 plan(Child, Goal, Been + Child, Actions + action, MaxDepth)
//! ```
//!
//! The been-list holds the states of the current path (Prolog discards it on backtracking), so
//! the search avoids cycles but revisits states reached along other paths: it is uninformed
//! and exponential, which is the point of comparing against it. It runs on an explicit stack,
//! so a deep search cannot overflow the native one.

use rustc_hash::FxHashSet;

use super::successors::{self, Applicable, PaperOrder, Successors};
use super::{Budget, Failure, Outcome, Progress, Stats, over_budget, plan_from};
use crate::ir::plan::Plan;
use crate::ir::task::{FactId, State, Task};

struct Frame {
    state: State,
    /// The state as the paper's lists: newest addition first, matched in this order.
    order: PaperOrder,
    actions: Vec<Applicable>,
    next: usize,
}

/// Depth-first search to depth `limit`, until `wanted` plans that `accept` takes are found
/// (backtracking after each, as Prolog would on a `fail` after printing one; a plan `accept`
/// refuses is backtracked over the same way).
#[allow(clippy::too_many_arguments)]
pub fn search(
    task: &mut Task,
    mut successors: Successors<'_>,
    limit: u32,
    budget: &Budget,
    wanted: usize,
    accept: &mut dyn FnMut(&mut Task, &Plan) -> bool,
    progress: &mut dyn Progress,
) -> Outcome {
    let mut stats = Stats::default();
    let init = task.init.clone();
    if successors::goal_reached(task, &init) {
        let plan = plan_from(task, &[]);
        let found = if accept(task, &plan) { vec![plan] } else { Vec::new() };
        return Outcome::ended(found, Failure::Exhausted { depth_limit: Some(limit) }, stats);
    }
    let mut found: Vec<Plan> = Vec::new();
    let mut path: Vec<Applicable> = Vec::new();
    let mut on_path: FxHashSet<State> = FxHashSet::default();
    let mut bytes = init.footprint();
    on_path.insert(init.clone());
    // The initial list is the problem's init list, in the order written (facts are interned
    // in that order).
    let mut facts: Vec<FactId> = init.facts().collect();
    facts.sort_unstable();
    let init_order = PaperOrder { facts, running: Vec::new() };
    let mut actions = Vec::new();
    if let Err(error) = successors.applicable_in_order(task, &init, &init_order, &mut actions) {
        return Outcome::failed(Failure::Condition(error), stats);
    }
    let mut stack = vec![Frame { state: init, order: init_order, actions, next: 0 }];
    stats.expanded = 1;
    loop {
        let Some(frame) = stack.last_mut() else {
            return Outcome::ended(found, Failure::Exhausted { depth_limit: Some(limit) }, stats);
        };
        let Some(action) = frame.actions.get(frame.next).cloned() else {
            let frame = stack.pop().expect("the stack is not empty here");
            on_path.remove(&frame.state);
            bytes -= frame.state.footprint();
            path.pop();
            continue;
        };
        frame.next += 1;
        // The paper's lists, and the state they hold (for the goal test and the path).
        let child_order = successors::apply_to_order(task, &frame.order, &action);
        let child = State::new(&task.facts, child_order.facts.iter().copied(), child_order.running.iter().copied());
        stats.generated += 1;
        if successors::goal_reached(task, &child) {
            path.push(action);
            let plan = plan_from(task, &path);
            path.pop();
            if !accept(task, &plan) {
                continue;
            }
            found.push(plan);
            if found.len() >= wanted {
                return Outcome::ended(found, Failure::Exhausted { depth_limit: Some(limit) }, stats);
            }
            continue;
        }
        if on_path.contains(&child) || stack.len() as u32 >= limit {
            // A state already on the path, or the depth limit: the paper backtracks.
            continue;
        }
        if let Some(kind) = over_budget(budget, &stats, bytes) {
            stats.peak_bytes = stats.peak_bytes.max(bytes);
            return Outcome::ended(found, Failure::Budget(kind), stats);
        }
        let mut actions = Vec::new();
        if let Err(error) = successors.applicable_in_order(task, &child, &child_order, &mut actions) {
            return Outcome::ended(found, Failure::Condition(error), stats);
        }
        stats.expanded += 1;
        if stats.expanded % 4096 == 0 {
            progress.report(&stats);
        }
        bytes += child.footprint();
        stats.peak_bytes = stats.peak_bytes.max(bytes);
        on_path.insert(child.clone());
        path.push(action);
        stack.push(Frame { state: child, order: child_order, actions, next: 0 });
    }
}
