//! Greedy best-first search over snap actions, guided by h_FF.
//!
//! The search is lazy, as in Fast Downward: a state is evaluated when it is expanded, and its
//! successors enter the open lists with their parent's estimate. Successors reached through
//! FF's helpful actions go to a preferred open list, which is expanded from alternately with
//! the other and exclusively for a while after each improvement of the best estimate. States
//! are stored once and looked up for duplicate detection; a goal state is recognised when it
//! is generated. Among states with the same estimate, the one whose partial plan has the
//! shorter makespan comes first, then the older one, so the search leans towards plans that
//! keep several arms busy, and stays deterministic.

use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::hash::BuildHasher;

use hashbrown::HashTable;
use rustc_hash::FxBuildHasher;

use super::relaxed::{Helpful, Relaxation};
use super::successors::{self, Applicable, Successors};
use super::{Budget, Failure, Outcome, Progress, Stats, over_budget, plan_from};
use crate::ir::task::{State, Task};

/// How many expansions the preferred list gets to itself after the estimate improves.
const BOOST: u32 = 1000;

struct Node {
    state: State,
    parent: u32,
    action: Option<Applicable>,
    depth: u32,
    /// True once expanded: a node can sit in both open lists.
    expanded: bool,
}

/// An open-list entry: estimate, then depth (shallower first), then age.
type Entry = Reverse<(u32, u32, u32)>;

fn helpful(helpful: &[Helpful], action: &Applicable) -> bool {
    helpful.iter().any(|h| {
        h.schema == action.schema
            && h.bindings.iter().zip(action.bindings.iter()).all(|(wanted, got)| wanted.is_none() || wanted == got)
    })
}

/// Greedy best-first search.
pub fn search(
    task: &mut Task,
    mut successors: Successors<'_>,
    budget: &Budget,
    progress: &mut dyn Progress,
) -> Outcome {
    let mut stats = Stats::default();
    let mut relaxation = Relaxation::new(task);
    let init = task.init.clone();
    if successors::goal_reached(task, &init) {
        return Outcome { result: Ok(plan_from(task, &[])), stats };
    }
    let hasher = FxBuildHasher;
    let mut nodes: Vec<Node> = Vec::new();
    let mut seen: HashTable<u32> = HashTable::new();
    let mut bytes = init.footprint();
    seen.insert_unique(hasher.hash_one(&init), 0, |_| 0);
    nodes.push(Node { state: init, parent: u32::MAX, action: None, depth: 0, expanded: false });
    let mut preferred: BinaryHeap<Entry> = BinaryHeap::new();
    let mut regular: BinaryHeap<Entry> = BinaryHeap::new();
    regular.push(Reverse((u32::MAX, 0, 0)));
    let mut best = u32::MAX;
    let mut boost = 0u32;
    let mut turn = false;
    let mut applicable = Vec::new();
    loop {
        let from_preferred = !preferred.is_empty() && (boost > 0 || turn || regular.is_empty());
        turn = !turn;
        let Some(Reverse((_, _, id))) = (if from_preferred { preferred.pop() } else { regular.pop() }) else {
            return Outcome { result: Err(Failure::Exhausted { depth_limit: None }), stats };
        };
        if std::mem::replace(&mut nodes[id as usize].expanded, true) {
            continue;
        }
        boost = boost.saturating_sub(1);
        if let Some(kind) = over_budget(budget, &stats, bytes) {
            return Outcome { result: Err(Failure::Budget(kind)), stats };
        }
        let state = nodes[id as usize].state.clone();
        let estimate = {
            let (machine, cache) = successors.parts();
            match relaxation.evaluate(task, &state, machine, cache, true) {
                Ok(estimate) => estimate,
                Err(error) => return Outcome { result: Err(Failure::Condition(error)), stats },
            }
        };
        stats.evaluated += 1;
        let Some(h) = estimate.h_ff else { continue }; // a dead end: some goal is unreachable
        if h < best {
            best = h;
            boost = BOOST;
        }
        if let Err(error) = successors.applicable(task, &state, &mut applicable) {
            return Outcome { result: Err(Failure::Condition(error)), stats };
        }
        stats.expanded += 1;
        if stats.expanded % 1024 == 0 {
            progress.report(&stats);
        }
        let depth = nodes[id as usize].depth + 1;
        for action in applicable.drain(..) {
            let child = successors::apply(task, &state, &action);
            stats.generated += 1;
            let hash = hasher.hash_one(&child);
            if seen.find(hash, |&n| nodes[n as usize].state == child).is_some() {
                continue;
            }
            let is_helpful = helpful(&estimate.helpful, &action);
            let goal = successors::goal_reached(task, &child);
            let child_id = nodes.len() as u32;
            bytes += child.footprint() + std::mem::size_of::<Node>();
            stats.peak_bytes = stats.peak_bytes.max(bytes);
            nodes.push(Node { state: child, parent: id, action: Some(action), depth, expanded: false });
            seen.insert_unique(hash, child_id, |&n| hasher.hash_one(&nodes[n as usize].state));
            if goal {
                let mut path = Vec::new();
                let mut at = child_id;
                while let Some(action) = nodes[at as usize].action.clone() {
                    path.push(action);
                    at = nodes[at as usize].parent;
                }
                path.reverse();
                return Outcome { result: Ok(plan_from(task, &path)), stats };
            }
            let entry = Reverse((h, depth, child_id));
            if is_helpful {
                preferred.push(entry);
            }
            regular.push(entry);
        }
    }
}
