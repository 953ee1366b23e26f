//! Greedy best-first search over snap actions, guided by landmarks and h_FF.
//!
//! The search is lazy, as in Fast Downward: a state is evaluated when it is expanded, and its
//! successors enter the open lists with their parent's estimate. The estimate is the landmark
//! count (LAMA's, see [`super::landmarks`]) plus h_FF: the landmark count keeps going down
//! where h_FF sits on a plateau, such as while blocks are moved aside to a free cell, and h_FF
//! sees the work a landmark count cannot. Successors reached through helpful actions (FF's:
//! those that achieve a subgoal of the relaxed plan's first layer) also go to a preferred open
//! list, and the two lists take turns. States are stored once and looked up for duplicate
//! detection; a goal state is recognised when it is generated.
//!
//! Among states with the same estimate, those reached by a start whose action cannot end yet
//! (an arm that would hold its block in the air, waiting) come last; then the one whose plan
//! prefix has the shorter makespan comes first (achiever-based earliest times,
//! [`super::timing`]), then the lower h_FF, then the one whose last action can happen
//! earliest, then the shallower, then the older one: the search leans towards plans that keep
//! several arms busy, and stays deterministic. (Measured on the ladder, the first tie-break
//! took the sum of the 36 rungs' makespans from 1846 to 1684 for 1.7 times the search time;
//! ranking such starts one step behind instead, as the improvement phase does, took it to
//! 1356 but for 6 times the time, 16 on the 30-block tower.)
//!
//! Choices measured on the ladder (`kbc bench`): h_FF alone left the swap problems beyond six
//! blocks unsolved in 10 s; LAMA's alternation between a landmark list and an h_FF list, and
//! the lexicographic pair (landmarks, h_FF), solved everything but with longer plans than the
//! sum; FF-style boosting of the preferred list (1000 expansions after each improvement) cost
//! up to ten times more expansions on the swap problems, whose helpful actions lead into states
//! where every arm holds a block, so the lists simply alternate.

use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::hash::BuildHasher;
use std::time::Instant;

use hashbrown::HashTable;
use rustc_hash::FxBuildHasher;

use super::landmarks::Accepted;
use super::relaxed::{Helpful, Relaxation};
use super::successors::{self, Applicable, Successors};
use super::symmetry::Symmetry;
use super::timing::{Durations, Placement, Timeline};
use super::{Budget, Failure, Outcome, Progress, Score, Stats, over_budget, plan_from};
use crate::ir::hir::Snap;
use crate::ir::plan::Plan;
use crate::ir::task::{State, Task};

struct Node {
    /// The state, kept once the node is expanded (its children are made from it); a node
    /// only generated is its parent and action, its state made again when it is expanded.
    state: Option<State>,
    /// The state's fingerprint, for duplicate detection without keeping every state.
    fingerprint: Fingerprint,
    parent: u32,
    action: Option<Applicable>,
    depth: u32,
    /// The landmarks accepted on the path here; set when the node is expanded (a node can
    /// sit in both open lists, and is expanded once).
    accepted: Option<Accepted>,
    /// The makespan of the prefix that leads here (achiever-based, see [`Timeline`]).
    makespan: i64,
}

/// A state's 128-bit fingerprint: two independent 64-bit hashes (FxHash for the table,
/// SipHash with fixed keys for the rest). Two different states share one with a probability
/// near 2^-128 per pair, so the search can recognise a state it has seen without storing it:
/// at 10^7 states the odds of any collision are below 10^-24.
type Fingerprint = (u64, u64);

fn fingerprint(state: &State) -> Fingerprint {
    use std::hash::{Hash, Hasher};
    let mut sip = std::hash::DefaultHasher::new();
    state.hash(&mut sip);
    (FxBuildHasher.hash_one(state), sip.finish())
}

/// An open-list entry: landmark count plus h_FF, whether the last action is a start that
/// holds its arm idle (see [`search`]), the prefix's makespan, h_FF, the time of the last
/// action, depth, age.
type Entry = Reverse<(u32, u32, i64, u32, i64, u32, u32)>;

/// True if `action` is one of the relaxed plan's helpful actions, up to the unit of a resource
/// it uses: the relaxed plan picks one arm for a step where any idle arm would do, and the
/// makespan tie-break then prefers an idle one.
fn in_relaxed_plan(task: &Task, helpful: &[Helpful], action: &Applicable) -> bool {
    let resource_vars = &task.schemas[action.schema].resource_vars;
    helpful.iter().any(|h| {
        h.schema == action.schema
            && h.bindings
                .iter()
                .zip(action.bindings.iter())
                .enumerate()
                .all(|(v, (wanted, got))| wanted.is_none() || wanted == got || resource_vars.contains(&(v as u32)))
    })
}

/// The path from the root to node `id`, as node indices, root excluded.
fn path_to(nodes: &[Node], id: u32, path: &mut Vec<u32>) {
    path.clear();
    let mut at = id;
    while at != 0 {
        path.push(at);
        at = nodes[at as usize].parent;
    }
    path.reverse();
}

/// Greedy best-first search.
///
/// After the first plan the search may go on (anytime, as LAMA does), each further plan with
/// a shorter makespan than the last. With `improve_until`, the first plan restarts the search
/// from the initial state (LAMA restarts too): the open lists then hold what was ordered for
/// finding any plan, and searching on from them rarely finds a better one. From there,
/// prefixes that cannot beat the best makespan are pruned, a state reached again by a prefix
/// with a shorter makespan is searched again, and a start whose action could not end in the
/// state it leads to (it would hold its arm idle while waiting, the main waste in first plans)
/// is neither preferred nor ranked with the others but one step behind. Measured on the
/// ladder with `--improve 1`: build_b15 68.0 -> 31.0, swap_b20 174.0 -> 74.0, where going on
/// with the first search's open lists had left build_b15 at 68.0 (and swap_b20 at 174.0
/// with `--improve 0.3`). It stops
/// when `wanted` plans are found, `improve_until` has passed, the open lists are empty, or the
/// budget runs out. With `temporal`, plan prefixes
/// whose durations cannot be met are pruned ([`Timeline::consistent`]).
///
/// With a `scorer` (the makespan a plan gets after the passes that follow the search, such as
/// `reassign`), each plan found while improving is scored by it: the plans kept are those
/// with a shorter score than the one before, and prefixes are pruned by their resource-free
/// makespan (a lower bound for the rearranged plan) rather than by their own, which those
/// passes can shorten a lot.
///
/// `relaxation` is the heuristic, grounded by the caller (who also used it to check that the
/// initial state is not a dead end). With `symmetry`, of the successors of a state that differ
/// only by constants interchangeable there (idle arms), the one placed earliest in the
/// prefix's timeline is kept (the arm free soonest), the others are not generated.
#[allow(clippy::too_many_arguments)]
pub fn search(
    task: &mut Task,
    mut successors: Successors<'_>,
    mut relaxation: Relaxation,
    mut symmetry: Option<Symmetry>,
    budget: &Budget,
    wanted: usize,
    improve_until: Option<Instant>,
    temporal: bool,
    epsilon: i64,
    mut scorer: Option<&mut dyn Score>,
    progress: &mut dyn Progress,
) -> Outcome {
    let mut stats = Stats::default();
    let init = task.init.clone();
    if successors::goal_reached(task, &init) {
        return Outcome::ended(vec![plan_from(task, &[])], Failure::Exhausted { depth_limit: None }, stats);
    }
    let mut found: Vec<Plan> = Vec::new();
    let mut nodes: Vec<Node> = Vec::new();
    let mut seen: HashTable<u32> = HashTable::new();
    let mut bytes = init.footprint() + std::mem::size_of::<Node>();
    let root_print = fingerprint(&init);
    seen.insert_unique(root_print.0, 0, |_| 0);
    nodes.push(Node {
        state: Some(init),
        fingerprint: root_print,
        parent: u32::MAX,
        action: None,
        depth: 0,
        accepted: None,
        makespan: 0,
    });
    // Once a plan is found: the makespan to beat.
    let mut best: Option<i64> = None;
    let mut regular: BinaryHeap<Entry> = BinaryHeap::new();
    let mut preferred: BinaryHeap<Entry> = BinaryHeap::new();
    regular.push(Reverse((0, 0, 0, 0, 0, 0, 0)));
    let mut durations = Durations::default();
    let mut timeline = Timeline::new(epsilon);
    let mut path: Vec<u32> = Vec::new();
    let mut from_preferred = false;
    let mut applicable = Vec::new();
    let mut placements: Vec<Placement> = Vec::new();
    let mut ends_scratch = Vec::new();
    let mut restart = false;
    loop {
        from_preferred = !from_preferred;
        let entry = match (from_preferred, preferred.is_empty()) {
            (true, false) => preferred.pop(),
            _ => regular.pop().or_else(|| preferred.pop()),
        };
        let Some(Reverse((_, _, _, _, _, _, id))) = entry else {
            return Outcome::ended(found, Failure::Exhausted { depth_limit: None }, stats);
        };
        if nodes[id as usize].accepted.is_some() {
            continue; // already expanded, from the other list
        }
        if let Some(kind) = over_budget(budget, &stats, bytes) {
            return Outcome::ended(found, Failure::Budget(kind), stats);
        }
        if !found.is_empty() && improve_until.is_some_and(|until| Instant::now() >= until) {
            return Outcome::ended(found, Failure::Exhausted { depth_limit: None }, stats);
        }
        // The timeline of the plan prefix that leads here, replayed from the root; a prefix
        // that cannot be scheduled (an action overruns its maximum duration) is a dead end.
        // (A later, schedulable path to the same state is then lost to duplicate detection:
        // the price of checking time only on the states the search keeps.)
        path_to(&nodes, id, &mut path);
        timeline.clear();
        for &n in &path {
            let Some(action) = nodes[n as usize].action.clone() else { continue };
            let (machine, _) = successors.parts();
            match timeline.place(task, machine, &mut durations, &action) {
                Ok(placement) => timeline.record(task, &action, placement),
                Err(error) => return Outcome::ended(found, Failure::Condition(error), stats),
            }
        }
        if temporal && !timeline.consistent() {
            nodes[id as usize].accepted = Some(Box::default());
            stats.unschedulable += 1;
            continue;
        }
        // The state: kept if the node was expanded before, else made from its parent's.
        let state = match &nodes[id as usize].state {
            Some(state) => state.clone(),
            None => {
                let node = &nodes[id as usize];
                let (parent, action) = (node.parent as usize, node.action.as_ref().expect("a child has an action"));
                let parent_state = nodes[parent].state.as_ref().expect("a parent is expanded before its children");
                let state = successors::apply(task, parent_state, action);
                bytes += state.footprint();
                nodes[id as usize].state = Some(state.clone());
                state
            }
        };
        let parent_accepted = match nodes[id as usize].parent {
            u32::MAX => None,
            parent => nodes[parent as usize].accepted.clone(),
        };
        let (estimate, landmarks) = {
            let (machine, cache) = successors.parts();
            match relaxation.evaluate_for_search(task, &state, machine, cache, parent_accepted.as_deref()) {
                Ok(evaluated) => evaluated,
                Err(stop) => return Outcome::ended(found, stop.into(), stats),
            }
        };
        stats.evaluated += 1;
        let (accepted, h_lm) = landmarks.unwrap_or_default();
        bytes += accepted.len() * 8;
        nodes[id as usize].accepted = Some(accepted);
        let Some(h_ff) = estimate.h_ff else { continue }; // a dead end: some goal is unreachable
        if let Err(error) = successors.applicable(task, &state, &mut applicable) {
            return Outcome::ended(found, Failure::Condition(error), stats);
        }
        stats.expanded += 1;
        if stats.expanded % 256 == 0 {
            progress.report(&stats);
        }
        let depth = nodes[id as usize].depth + 1;
        placements.clear();
        for action in &applicable {
            let (machine, _) = successors.parts();
            match timeline.place(task, machine, &mut durations, action) {
                Ok(placement) => placements.push(placement),
                Err(error) => return Outcome::ended(found, Failure::Condition(error), stats),
            }
        }
        let keep = match symmetry.as_mut() {
            Some(symmetry) => {
                let classes = symmetry.classes(task, &state);
                symmetry.keep(&classes, &applicable, |i| placements[i].time)
            }
            None => Vec::new(),
        };
        for (i, (action, placement)) in applicable.drain(..).zip(placements.drain(..)).enumerate() {
            if !keep.get(i).copied().unwrap_or(true) {
                stats.symmetric += 1;
                continue;
            }
            let child = successors::apply(task, &state, &action);
            stats.generated += 1;
            let (time, makespan) = (placement.time, timeline.makespan.max(placement.until));
            let bound = match scorer {
                Some(_) => timeline.free_makespan.max(placement.free_until),
                None => makespan,
            };
            if best.is_some_and(|best| bound >= best) {
                continue; // cannot improve on the plan already found
            }
            if successors::goal_reached(task, &child) {
                if temporal {
                    // The last steps must fit their durations too.
                    let mut complete = timeline.clone();
                    complete.record(task, &action, placement);
                    if !complete.consistent() {
                        stats.unschedulable += 1;
                        continue;
                    }
                }
                let mut actions: Vec<Applicable> =
                    path.iter().filter_map(|&n| nodes[n as usize].action.clone()).collect();
                actions.push(action);
                let plan = plan_from(task, &actions);
                let first = found.is_empty();
                match scorer.as_deref_mut() {
                    Some(scorer) => match scorer.score(task, &plan) {
                        Some(score) if best.is_none_or(|best| score < best) => best = Some(score),
                        // (The first plan is kept whatever its score, for the caller to report.)
                        _ if first => {}
                        _ => continue,
                    },
                    None => best = Some(makespan),
                }
                found.push(plan);
                if found.len() >= wanted || improve_until.is_some_and(|until| Instant::now() >= until) {
                    return Outcome::ended(found, Failure::Exhausted { depth_limit: None }, stats);
                }
                if first && improve_until.is_some() && best.is_some() {
                    restart = true;
                    break;
                }
                continue; // a goal state is not expanded
            }
            let print = fingerprint(&child);
            if let Some(&other) = seen.find(print.0, |&n| nodes[n as usize].fingerprint == print) {
                // Once improving, a state reached by a prefix with a shorter makespan is
                // searched again from there.
                let better = best.is_some() && makespan < nodes[other as usize].makespan;
                // (Never below one of its own descendants: the parents must stay a tree.)
                if better && nodes[other as usize].parent != u32::MAX && !path.contains(&other) {
                    let node = &mut nodes[other as usize];
                    node.parent = id;
                    node.action = Some(action);
                    node.depth = depth;
                    node.makespan = makespan;
                    node.accepted = None;
                    regular.push(Reverse((h_lm + h_ff, 0, makespan, h_ff, time, depth, other)));
                }
                continue;
            }
            let mut helpful = in_relaxed_plan(task, &estimate.helpful, &action)
                || relaxation.achieves_subgoal(task, &action, &estimate.subgoals);
            // A start whose action cannot end yet holds its resources (an arm) idle until it
            // can. Among successors with the same estimate, such a start comes after the
            // others; while improving a makespan, it is neither preferred nor ranked with
            // the others but one step behind.
            let mut idles = false;
            if task.schemas[action.schema].snap == Snap::Start {
                let instance =
                    successors::running_instance(&task.schemas[action.schema], &mut task.consts, &action.bindings);
                let can_end = match instance {
                    Some(instance) => {
                        ends_scratch.clear();
                        let base = task.schemas[action.schema].base;
                        for index in 0..task.schemas.len() {
                            if task.schemas[index].snap == Snap::End
                                && task.schemas[index].base == base
                                && let Err(error) = successors.ending(task, index, &child, instance, &mut ends_scratch)
                            {
                                return Outcome::ended(found, Failure::Condition(error), stats);
                            }
                        }
                        ends_scratch.iter().any(|a| a.ends == Some(instance))
                    }
                    None => true,
                };
                idles = !can_end;
            }
            let improving = best.is_some();
            if idles && improving {
                helpful = false;
            }
            let child_id = nodes.len() as u32;
            bytes += std::mem::size_of::<Node>() + std::mem::size_of_val(&*action.bindings);
            stats.peak_bytes = stats.peak_bytes.max(bytes);
            nodes.push(Node {
                state: None,
                fingerprint: print,
                parent: id,
                action: Some(action),
                depth,
                accepted: None,
                makespan,
            });
            seen.insert_unique(print.0, child_id, |&n| nodes[n as usize].fingerprint.0);
            let entry = if improving {
                Reverse((h_lm + h_ff + idles as u32, 0, makespan, h_ff, time, depth, child_id))
            } else {
                Reverse((h_lm + h_ff, idles as u32, makespan, h_ff, time, depth, child_id))
            };
            if helpful {
                preferred.push(entry);
            }
            regular.push(entry);
        }
        if std::mem::take(&mut restart) {
            // The first plan is found: search again from the start with its makespan as the
            // bound and starts that would idle their arm ranked last, instead of going on
            // from open lists ordered for finding any plan.
            let root = nodes.swap_remove(0);
            nodes.clear();
            nodes.push(Node { accepted: None, ..root });
            seen.clear();
            seen.insert_unique(nodes[0].fingerprint.0, 0, |_| 0);
            regular.clear();
            preferred.clear();
            regular.push(Reverse((0, 0, 0, 0, 0, 0, 0)));
            bytes = nodes[0].state.as_ref().map_or(0, State::footprint) + std::mem::size_of::<Node>();
        }
    }
}
