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
//!
//! A state in which nothing applies (every arm holds a block waiting for a place only another
//! arm could clear) has no successor and is not a goal: when one is taken from an open list,
//! it is dropped without being evaluated. Only states with no free unit of a resource are
//! checked, by trying ends first, which is much cheaper than an evaluation. On
//! build_b100_a10 a third of the evaluations had been of such states, every one a dead end;
//! the plans found are the same (checking states when they are generated instead cost more
//! than it saved on the swap rungs, whose stuck states are rarely taken).
//!
//! The optional lookahead ([`look_ahead`], YAHSP's) follows the relaxed plan of each state
//! whose estimate beats every earlier one and adds the state it ends in to the regular list.
//! Taken cheapest first, the relaxed plan's actions gave every arm a block whose place was not
//! ready (all grips cost nothing), and the chains ended with every arm waiting; and every
//! block moved aside went to the one free cell the relaxation found cheapest, landing on the
//! others there. The plan is now taken in the order its goals fall due
//! ([`super::relaxed::Estimate::plan`]), and a step whose loose values (a detour's cell) would
//! send it where a start of the chain is still headed takes others. Measured on the ladder
//! (`kbc bench --search heuristic --timeout 30 --lookahead`), against the cheapest-first
//! lookahead: build_b100_a10 solved in 15.7 s with makespan 162 (1.50x the bound; 33.9 s and
//! 386 before, with a 120 s budget), swap_b100_a10 in 8.9 s with 193 (1.55x; 75.5 s and 874),
//! swap_b75 in 3.0 s (1.87x; out of time), build_b50 3.32x (4.85x by default), reverse_b30
//! 4.73x -> 3.40x. The reverse and grid rungs still get longer makespans than without it
//! (reverse_b30 3.40x against 1.95x, grid_b20 2.62x against 1.47x: the chain follows the
//! shortest plan, a rotation of blocks through cells one after another, where the default
//! search finds more moves in parallel), so by default ([`Lookahead::Auto`]) it is on only
//! for problems whose initial estimate says they are large, where the plain search needs
//! thousands of evaluations of milliseconds each and the lookahead is faster and its
//! makespans shorter on every family (50 blocks and more on the ladder). Restricting the old
//! one (waiting starts skipped, the chain cut where an arm would wait, only after a plateau of
//! 10-100 expansions) had cost speed without giving the reverse rungs their makespans back.

use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::hash::BuildHasher;
use std::time::Instant;

use hashbrown::HashTable;
use rustc_hash::FxBuildHasher;

use super::landmarks::Accepted;
use super::relaxed::{Helpful, PlanAction, Relaxation};
use super::successors::{self, Applicable, ConditionError, Successors};
use super::symmetry::Symmetry;
use super::timing::{Durations, Placement, Timeline};
use super::{Budget, Failure, Lookahead, Outcome, Progress, Score, Stats, over_budget, plan_from};
use crate::ir::hir::Snap;
use crate::ir::plan::Plan;
use crate::ir::task::{ConstId, Pattern, State, Task};

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
    helpful.iter().any(|h| is_plan_action(task, h, action, &[]))
}

/// True if `action` is the relaxed plan's action `wanted`, up to the unit of a resource and
/// the values of the variables `free` (a plan step's loose ones, [`PlanAction::loose`]).
fn is_plan_action(task: &Task, wanted: &Helpful, action: &Applicable, free: &[u32]) -> bool {
    let resource_vars = &task.schemas[action.schema].resource_vars;
    wanted.schema == action.schema
        && wanted.bindings.iter().zip(action.bindings.iter()).enumerate().all(|(v, (want, got))| {
            want.is_none() || want == got || resource_vars.contains(&(v as u32)) || free.contains(&(v as u32))
        })
}

/// True if `action` is a start whose action cannot end in `child`, the state it leads to: it
/// would hold its resources (an arm) idle until it can.
fn idles(
    task: &mut Task,
    successors: &mut Successors<'_>,
    child: &State,
    action: &Applicable,
    scratch: &mut Vec<Applicable>,
) -> Result<bool, ConditionError> {
    if task.schemas[action.schema].snap != Snap::Start {
        return Ok(false);
    }
    let Some(instance) = successors::running_instance(&task.schemas[action.schema], &mut task.consts, &action.bindings)
    else {
        return Ok(false);
    };
    scratch.clear();
    let base = task.schemas[action.schema].base;
    for index in 0..task.schemas.len() {
        if task.schemas[index].snap == Snap::End && task.schemas[index].base == base {
            successors.ending(task, index, child, instance, scratch)?;
        }
    }
    Ok(!scratch.iter().any(|a| a.ends == Some(instance)))
}

/// True if one of the goal's resource units (`available(a1)`, `resource_goals` are their goal
/// literals) is free in `state`.
fn any_unit_free(task: &Task, resource_goals: &[usize], state: &State) -> bool {
    let mut bindings = vec![None; task.goal_vars];
    let mut trail = Vec::new();
    resource_goals.iter().any(|&g| {
        let literal = &task.goal[g];
        state.facts_of(literal.pred).any(|fact| {
            let holds = successors::match_literal(literal, fact, &task.consts, &task.facts, &mut bindings, &mut trail);
            successors::undo(&mut bindings, &mut trail, 0);
            holds
        })
    })
}

/// True if no action applies in `state`: ends (of the few running actions) are tried first,
/// then starts and instantaneous actions, and the first applicable instance answers.
fn stuck(
    task: &mut Task,
    successors: &mut Successors<'_>,
    state: &State,
    scratch: &mut Vec<Applicable>,
) -> Result<bool, ConditionError> {
    for snap in [Snap::End, Snap::Start, Snap::Instant] {
        for index in 0..task.schemas.len() {
            if task.schemas[index].snap == snap {
                scratch.clear();
                successors.schema(task, index, state, scratch)?;
                if !scratch.is_empty() {
                    return Ok(false);
                }
            }
        }
    }
    Ok(true)
}

/// A run of steps [`look_ahead`] took: each action with the prefix's makespan after it and
/// its own time, and the state it ends in.
struct Chain {
    steps: Vec<(Applicable, i64, i64)>,
    end: State,
}

/// A start the lookahead took with loose variables, until its end: its running instance, its
/// durative action, and the values of its loose name arguments (see [`loose_values`]).
type Headed = (ConstId, crate::intern::Symbol, Vec<(usize, ConstId)>);

/// The values a start gives the name arguments that are its loose variables: two running
/// actions of one durative action with the same ones are headed for the same place.
fn loose_values(task: &Task, wanted: &PlanAction, action: &Applicable) -> Vec<(usize, ConstId)> {
    let Pattern::Compound(_, args) = &task.schemas[action.schema].name else { return Vec::new() };
    args.iter()
        .enumerate()
        .filter_map(|(position, arg)| match arg {
            Pattern::Var(v) if wanted.loose.contains(v) => Some((position, action.bindings[*v as usize]?)),
            _ => None,
        })
        .collect()
}

/// Follows the relaxed plan from `state`, as YAHSP's lookahead does (Vidal, ICAPS 2004): of
/// the plan's actions not yet taken, the first (in the plan's order: see [`Estimate::plan`])
/// that has an applicable instance is applied, the instance the prefix's timeline places
/// earliest (the unit of a resource free soonest), and again, until none of the plan's
/// remaining actions applies. A step whose loose variables ([`PlanAction::loose`]) would
/// send it where a start the lookahead took is still headed (the relaxed plan sends every
/// block it moves aside to the one cheapest free cell) takes other values for them, and
/// so does one that has no applicable instance with the plan's values. It stops short of a
/// goal state, which the search recognises when it generates it, and at `deadline`.
#[allow(clippy::too_many_arguments)]
fn look_ahead(
    task: &mut Task,
    successors: &mut Successors<'_>,
    timeline: &Timeline,
    durations: &mut Durations,
    state: &State,
    plan: &[PlanAction],
    deadline: Option<Instant>,
) -> Result<Chain, ConditionError> {
    let mut taken = vec![false; plan.len()];
    let mut timeline = timeline.clone();
    let mut state = state.clone();
    let mut steps = Vec::new();
    let mut applicable = Vec::new();
    // Starts taken with loose variables and not yet ended.
    let mut headed: Vec<Headed> = Vec::new();
    'step: loop {
        if deadline.is_some_and(|deadline| Instant::now() >= deadline) {
            break;
        }
        successors.applicable(task, &state, &mut applicable)?;
        for (i, wanted) in plan.iter().enumerate() {
            if taken[i] {
                continue;
            }
            // (whether it goes where a taken start is headed, whether it differs from the
            // plan's values, its time, its index)
            let mut best: Option<((bool, bool, i64, usize), Placement)> = None;
            for (k, action) in applicable.iter().enumerate() {
                let loosely = !wanted.loose.is_empty();
                if !is_plan_action(task, &wanted.action, action, &wanted.loose) {
                    continue;
                }
                let exact = !loosely || is_plan_action(task, &wanted.action, action, &[]);
                let crowded = loosely && {
                    let base = task.schemas[action.schema].base;
                    let values = loose_values(task, wanted, action);
                    headed.iter().any(|(_, b, v)| *b == base && *v == values)
                };
                let (machine, _) = successors.parts();
                let placement = timeline.place(task, machine, durations, action)?;
                let key = (crowded, !exact, placement.time, k);
                if best.as_ref().is_none_or(|(first, _)| key < *first) {
                    best = Some((key, placement));
                }
            }
            let Some(((_, _, _, k), placement)) = best else { continue };
            let action = applicable.swap_remove(k);
            let next = successors::apply(task, &state, &action);
            if successors::goal_reached(task, &next) {
                break 'step;
            }
            taken[i] = true;
            if let Some(instance) = action.ends {
                headed.retain(|(running, _, _)| *running != instance);
            } else if !wanted.loose.is_empty() {
                let schema = &task.schemas[action.schema];
                let base = schema.base;
                if let Some(instance) = successors::running_instance(schema, &mut task.consts, &action.bindings) {
                    let values = loose_values(task, wanted, &action);
                    headed.push((instance, base, values));
                }
            }
            let time = placement.time;
            timeline.record(task, &action, placement);
            steps.push((action, timeline.makespan, time));
            state = next;
            continue 'step;
        }
        break;
    }
    Ok(Chain { steps, end: state })
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
    mode: Lookahead,
    budget: &Budget,
    wanted: usize,
    improve_until: Option<Instant>,
    temporal: bool,
    epsilon: i64,
    mut scorer: Option<&mut dyn Score>,
    progress: &mut dyn Progress,
) -> Outcome {
    let mut stats = Stats::default();
    // Decided at the initial state's estimate (relaxed plans are kept until then).
    let mut lookahead = mode != Lookahead::Off;
    let mut decided = false;
    relaxation.keep_relaxed_plans(lookahead);
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
    let resource_goals: Vec<usize> = (0..task.goal.len()).filter(|&g| task.resource_goal[g]).collect();
    // The lowest estimate of any state evaluated so far.
    let mut best_h = u32::MAX;
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
        // Every unit of a resource taken, each waiting for a place only another could clear:
        // a state where nothing applies is a dead end, found here without evaluating it.
        if !resource_goals.is_empty() && !any_unit_free(task, &resource_goals, &state) {
            match stuck(task, &mut successors, &state, &mut ends_scratch) {
                Ok(true) => {
                    nodes[id as usize].accepted = Some(Box::default());
                    stats.stuck += 1;
                    continue;
                }
                Ok(false) => {}
                Err(error) => return Outcome::ended(found, Failure::Condition(error), stats),
            }
        }
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
        let progressed = h_lm + h_ff < best_h;
        if !std::mem::replace(&mut decided, true) {
            lookahead = mode.wanted(h_lm + h_ff);
            stats.lookahead = lookahead;
            relaxation.keep_relaxed_plans(lookahead);
        }
        best_h = best_h.min(h_lm + h_ff);
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
            let idles = match idles(task, &mut successors, &child, &action, &mut ends_scratch) {
                Ok(idles) => idles,
                Err(error) => return Outcome::ended(found, Failure::Condition(error), stats),
            };
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
        // At a state better than any before, a jump along its relaxed plan: the state the
        // lookahead ends in joins the regular list with its own estimate.
        if lookahead && progressed && best.is_none() && !restart {
            let plan = &estimate.plan;
            let chain =
                match look_ahead(task, &mut successors, &timeline, &mut durations, &state, plan, budget.deadline) {
                    Ok(chain) => chain,
                    Err(error) => return Outcome::ended(found, Failure::Condition(error), stats),
                };
            let print = fingerprint(&chain.end);
            // (One step is a successor like any other.)
            if chain.steps.len() >= 2 && seen.find(print.0, |&n| nodes[n as usize].fingerprint == print).is_none() {
                let accepted = nodes[id as usize].accepted.clone();
                let (end_estimate, end_landmarks) = {
                    let (machine, cache) = successors.parts();
                    match relaxation.evaluate_for_search(task, &chain.end, machine, cache, accepted.as_deref()) {
                        Ok(evaluated) => evaluated,
                        Err(stop) => return Outcome::ended(found, stop.into(), stats),
                    }
                };
                stats.evaluated += 1;
                if let Some(end_ff) = end_estimate.h_ff {
                    let end_h = end_ff + end_landmarks.map_or(0, |(_, count)| count);
                    best_h = best_h.min(end_h);
                    // The steps become a path of nodes; only its last is a state the search
                    // knows (the ones between are neither stored nor looked up).
                    let mut parent = id;
                    let count = chain.steps.len();
                    let mut entry_time = 0;
                    for (k, (action, makespan, time)) in chain.steps.into_iter().enumerate() {
                        let last = k + 1 == count;
                        bytes += std::mem::size_of::<Node>() + std::mem::size_of_val(&*action.bindings);
                        nodes.push(Node {
                            state: if last { Some(chain.end.clone()) } else { None },
                            fingerprint: if last { print } else { (0, 0) },
                            parent,
                            action: Some(action),
                            depth: nodes[parent as usize].depth + 1,
                            // (Never expanded, so marked as if they were.)
                            accepted: if last { None } else { accepted.clone() },
                            makespan,
                        });
                        parent = nodes.len() as u32 - 1;
                        entry_time = time;
                    }
                    bytes += chain.end.footprint();
                    stats.peak_bytes = stats.peak_bytes.max(bytes);
                    seen.insert_unique(print.0, parent, |&n| nodes[n as usize].fingerprint.0);
                    let node = &nodes[parent as usize];
                    regular.push(Reverse((end_h, 0, node.makespan, end_ff, entry_time, node.depth, parent)));
                    stats.looked_ahead += 1;
                }
            }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::engine::Machine;
    use crate::ladder::{Family, Rung};

    /// Runs the lookahead from the initial state of `rung` (the standard blocks world) and
    /// hands its chain to `check`, with the task.
    fn chain_from_start(rung: Rung, check: impl FnOnce(&mut Task, &mut Successors<'_>, &Chain)) {
        let (_, frontend, _) = crate::session::Session::from_text(&rung.name(), rung.source()).into_parts();
        let problem = frontend.kb.problems.len() - 1;
        let mut task = crate::passes::task::build(&frontend.kb, problem);
        let program = super::super::program_for(&frontend.kb, problem);
        let mut successors = Successors::new(&task, Machine::new(&program, 1_000_000));
        let mut relaxation = Relaxation::new(&task);
        let init = task.init.clone();
        let estimate = {
            let (machine, cache) = successors.parts();
            assert!(relaxation.ground(&mut task, machine, cache, 1_000_000, true).expect("no engine error"));
            relaxation.keep_relaxed_plans(true);
            let (estimate, _) =
                relaxation.evaluate_for_search(&mut task, &init, machine, cache, None).expect("no engine error");
            estimate
        };
        assert!(!estimate.plan.is_empty(), "{}: no relaxed plan", rung.name());
        let chain = look_ahead(
            &mut task,
            &mut successors,
            &Timeline::default(),
            &mut Durations::default(),
            &init,
            &estimate.plan,
            None,
        )
        .expect("no engine error");
        check(&mut task, &mut successors, &chain);
    }

    #[test]
    fn the_lookahead_gives_arms_to_blocks_whose_place_is_ready_first() {
        // Taken cheapest first, the relaxed plan's grips all cost nothing, and the chain gave
        // every arm a block whose place was not ready (the top of a tower whose base still
        // stood elsewhere, a base whose cell another block held): a state where nothing
        // applies. Taken in the order their goals fall due, the arms go to the blocks that
        // ready those places, and the chain goes on (on build_b30_a6 it had ended stuck).
        for (blocks, arms) in [(12, 4), (20, 4), (30, 6)] {
            let rung = Rung { family: Family::Build, blocks, arms, seed: 1 };
            chain_from_start(rung, |task, successors, chain| {
                let mut scratch = Vec::new();
                let stuck = stuck(task, successors, &chain.end, &mut scratch).expect("no engine error");
                assert!(!stuck, "{}: the lookahead ends where nothing applies", rung.name());
                assert!(chain.steps.len() >= 2 * arms, "{}: a chain of {} steps", rung.name(), chain.steps.len());
            });
        }
    }

    #[test]
    fn the_lookahead_sends_blocks_it_moves_aside_to_different_cells() {
        // Reversing a stack in place takes every block aside first; the relaxed plan sends
        // them all to the one cheapest free cell, where they would land on one another. The
        // lookahead sends each block moved aside while another is on its way to a free cell
        // of its own (there are more free cells than arms here).
        for (blocks, arms) in [(10, 4), (20, 4)] {
            let rung = Rung { family: Family::Reverse, blocks, arms, seed: 1 };
            chain_from_start(rung, |task, _, chain| {
                // The cells some goal literal names (the last two arguments of `ontable/3`
                // and `on/4`): moves there are not moves aside.
                let goal_cells: Vec<(ConstId, ConstId)> = task
                    .goal
                    .iter()
                    .filter(|l| l.args.len() >= 3)
                    .filter_map(|l| match &l.args[l.args.len() - 2..] {
                        [Pattern::Const(x), Pattern::Const(y)] => Some((*x, *y)),
                        _ => None,
                    })
                    .collect();
                let mut headed: Vec<(ConstId, (ConstId, ConstId))> = Vec::new();
                let mut aside = 0;
                for (action, _, _) in &chain.steps {
                    if let Some(instance) = action.ends {
                        headed.retain(|(running, _)| *running != instance);
                        continue;
                    }
                    let schema = &task.schemas[action.schema];
                    let Pattern::Compound(_, args) = &schema.name else { continue };
                    let cell = match &args[..] {
                        [_, _, _, _, Pattern::Var(x), Pattern::Var(y)] if schema.snap == Snap::Start => {
                            (action.bindings[*x as usize], action.bindings[*y as usize])
                        }
                        _ => continue,
                    };
                    let (Some(x), Some(y)) = cell else { continue };
                    if goal_cells.contains(&(x, y)) {
                        continue;
                    }
                    aside += 1;
                    assert!(
                        headed.iter().all(|(_, other)| *other != (x, y)),
                        "{}: two blocks on their way to the same free cell",
                        rung.name()
                    );
                    let schema = &task.schemas[action.schema];
                    let instance = successors::running_instance(schema, &mut task.consts, &action.bindings)
                        .expect("a start has a running instance");
                    headed.push((instance, (x, y)));
                }
                assert!(aside >= 2, "{}: {aside} moves aside", rung.name());
            });
        }
    }
}
