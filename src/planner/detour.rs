//! Detours: a plan step that holds a unit of a resource waiting is sent aside and finished
//! later.
//!
//! The search orders steps, not time, so it takes a block straight to its goal place even
//! where that place is ready only much later: the arm grips the block and starts the move,
//! and the move's end waits, the arm held, until the place is ready. On the ladder's larger
//! rungs most arms spend most of the plan like that (build_b50_a8: seven of eight arms held
//! about 140 time units each while one works). `reassign` cannot help: it keeps what happens
//! to the world and only remakes who does it.
//!
//! A detour remakes that one decision. For a *held* start (its end waits long after its
//! minimum duration; the caller picks them from the schedule) of a job (a unit's steps from
//! taking it to giving it back, see `passes::reassign`):
//!
//! - at the start's place in the plan, the same start with other values for its *chosen*
//!   variables ([`crate::ir::task::Schema::chosen_vars`], such as a move's destination) whose
//!   end applies at once, then that end and the job's steps after the original end (for
//!   std/blocks.pl: the block goes to a free cell and the arm lets it go);
//! - at the original end's place, the job's steps before the start again (the grip), the
//!   start with its original chosen values from where the first part left things (the move
//!   from the free cell to the goal place) and its end; the job's later steps follow as before.
//!
//! Every step is taken from the actions applicable in the state reached, under the search's
//! own semantics, so the result is a valid plan or no plan: a step of the original plan that
//! the detours make inapplicable (the free cell was another step's destination) fails the
//! rewrite and names the detour to blame, which the caller drops before trying again. Among
//! the alternatives for the chosen values, those no other step of the same action chooses
//! while this one is aside are tried first, cheapest first by `cost` (the least duration).
//! Nothing here is specific to the blocks world: the chosen variables, jobs and applicable
//! actions come from the KB.
//!
//! [`relocate`] remakes a different decision: where a unit is left for a while. The search
//! puts a block aside on the first free cell it lists (reverse_b100_a8, 82 free cells of 102:
//! its 208 moves took 5.4 time units at least on average, a move to a neighbouring cell 2,
//! and 108 of them were trips aside), and the arms pay for the distance twice, there and
//! back. Replayed with each such start
//! sent to the cheapest free place, measured on the ladder (`kbc bench --search heuristic`,
//! one run, relocating before and after the detours, against the detours alone):
//! reverse_b100_a8 240 -> 203, reverse_b75 131 -> 115, reverse_b50 97 -> 88, reverse_b20 57 ->
//! 49, build_b50 96 -> 78, swap_b15 41 -> 39; swap_b06 20 -> 21 (the detours found less to do
//! after relocating); the sum over the 52 rungs 2888 -> 2782, 17 -> 20 rungs within 1.3x of
//! the bound. On reverse_b100_a10 every replay failed (a place ran out where the plan had
//! one, taken by a relocated block) until the replays protected the plan's own places:
//! 239 -> 151. Replays also failed for reasons of their own: a block relocated on its way
//! aside and moved aside again later was looked for where the plan had left it, and a block
//! sent aside onto the place its next move takes it to stood on its goal place early. With
//! the later moves renamed and that place left out, every replay of swap_b25_a6_s1 succeeds
//! at once (most needed four bans or more, and the protection, before); the ladder's sums of
//! makespans (seeds 1/2/3) 2310/2235/2326 -> 2304/2231/2323, 8 rungs a unit or more shorter
//! (swap_b25_a6_s1 48 -> 46, reverse_b100_a8_s1 123 -> 120), 2 a unit longer.
//!
//! [`merge`] undoes a decision the other way: a block put aside (by the search or by a
//! detour) and taken on soon after by another job stays in the first job's arm and goes
//! straight to its second place, one grip, move and release fewer. On the ladder's small swap
//! rungs the search puts a block aside for a unit or two, its arm idle meanwhile
//! (measured before the reserving rule of `passes::reassign`: swap_b05_a3_s1 18 -> 13, nine
//! moves -> seven; the sum over the 52 rungs of seed 1 2684 -> 2647 with the cycles of
//! `session::temporal::reassign`, 25 -> 28 rungs within 1.3x of the bound).
//!
//! [`shortcut`] undoes a stop in time rather than in the arm: a block put down on its way
//! (by the search, which on build rungs moves blocks from one free cell to the next) and taken
//! on later by another job stays where it was, and that job takes it straight from there.
//! build_b100_a8 of seed 4 had 52 blocks moved twice, 39 of them from a cell no other block
//! ever needed; with shortcuts its makespan went 183 -> 155 against a bound of 136. Over the
//! 52 rungs of each of seeds 1-5 (260 in all) the makespans summed 11431 -> 11340, none longer.

use rustc_hash::FxHashMap;

use super::successors::{self, Applicable, Successors};
use super::{path_of, plan_from};
use crate::ir::hir::{Snap, Term};
use crate::ir::plan::Plan;
use crate::ir::task::{ConstId, Pattern, State, Task};

/// A held start to send aside: plan indices.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Held {
    /// The start that waits for its end.
    pub start: usize,
    /// Its end.
    pub end: usize,
    /// The job's steps before the start (taking the unit), repeated before the end.
    pub head: Vec<usize>,
    /// The job's steps after the end (giving the unit back), also taken right after the
    /// start's aside end.
    pub tail: Vec<usize>,
}

/// What a rewrite gave.
#[derive(Clone, Debug, PartialEq)]
pub struct Rewritten {
    /// The plan.
    pub plan: Plan,
    /// The indices (in the list given) of the detours it takes, in order; the others found
    /// no alternative and left their starts as they were.
    pub taken: Vec<usize>,
}

/// Why a rewrite gave no plan.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Failure {
    /// The detour at this index of the list given made a later step inapplicable, or could
    /// not be finished.
    Detour(usize),
    /// The plan is not one the search's semantics accept (before any detour).
    Plan,
}

/// How many alternatives of a held start are tried before it is left as it is.
const ALTERNATIVES: usize = 128;

/// `plan` with the detours `held` (each at its own start, distinct jobs); `cost` is the least
/// duration of a start's durative action, given the start's action (its index in
/// `Kb::actions`) and name. `successors` is the task's (its OnKB cache is kept from one
/// rewrite to the next).
pub fn rewrite(
    successors: &mut Successors<'_>,
    task: &mut Task,
    plan: &Plan,
    held: &[Held],
    cost: &mut dyn FnMut(usize, &Term) -> i64,
) -> Result<Rewritten, Failure> {
    let (mut rewriter, path) = Rewriter::for_plan(successors, task, plan)?;
    let start_of: FxHashMap<usize, usize> = held.iter().enumerate().map(|(d, h)| (h.start, d)).collect();
    let end_of: FxHashMap<usize, usize> = held.iter().enumerate().map(|(d, h)| (h.end, d)).collect();
    let mut state = task.init.clone();
    let mut out: Vec<Applicable> = Vec::with_capacity(path.len() + 6 * held.len());
    // The detours taken and not yet finished, in the order taken, with the chosen values they
    // took instead.
    let mut aside: Vec<(usize, Vec<Term>)> = Vec::new();
    let mut taken = Vec::new();
    for (k, action) in path.iter().enumerate() {
        if let Some(&d) = start_of.get(&k)
            && let Some((steps, next, values)) = rewriter.aside(task, &path, &held[d], &state, cost)
        {
            out.extend(steps);
            state = next;
            aside.push((d, values));
            taken.push(d);
            continue;
        }
        if let Some(&d) = end_of.get(&k)
            && let Some(position) = aside.iter().position(|(a, _)| *a == d)
        {
            let (steps, next) = rewriter.back(task, &path, &held[d], &state).ok_or(Failure::Detour(d))?;
            out.extend(steps);
            state = next;
            aside.remove(position);
            continue;
        }
        if !rewriter.applicable(task, &state, action) {
            return Err(blame(&aside, &rewriter.names[k]));
        }
        state = successors::apply(task, &state, action);
        out.push(action.clone());
    }
    if !successors::goal_reached(task, &state) {
        return Err(Failure::Plan);
    }
    Ok(Rewritten { plan: plan_from(task, &out), taken })
}

/// How many later actions an [`eliminate`] trial leaves out at most, besides its own.
/// Measured on `benches/other_domains/logistics_c5_t5_p2_k30.pl` (window 64): with 2, the
/// makespan went 662 -> 542; with 8, 662 -> 436. On the ladder's blocks, where nothing can
/// go, a trial that leaves out a needed grip cascades through that block's moves until this
/// limit stops it.
const ELIMINATION_CASCADE: usize = 8;

/// How many steps after the last one it left out an [`eliminate`] trial replays without
/// coming back to the plan's own state before it gives the trial up. Measured on the same
/// logistics KB with 8 actions a trial: 32, 662 -> 469 in 0.13 s; 64, -> 436 in 0.16 s (16,
/// before the limit of actions: 535 in 0.08 s). On reverse_b100_a8_s1, where nothing goes,
/// 55-71 ms, most of it the OnKB answers the later passes would have asked for anyway (the
/// whole run 1.14 s without the pass and 1.15 s with it, `perf stat -r 6`).
const ELIMINATION_WINDOW: usize = 64;

/// `plan` without the actions it can do without (greedy action elimination, as Fink and
/// Yang's "justified" plans and Nakhost and Müller's action elimination): in plan order,
/// each start (with its end) or instantaneous step is left out on trial, and so is every
/// later step that then no longer applies (a start with its end; an end whose start was
/// kept fails the trial); the trial is kept when the state it reaches equals the plan's own
/// state at the same point (the rest of the plan then applies as before and reaches the
/// goal), or when it replays to the end and reaches the goal. A trial that goes on
/// [`ELIMINATION_WINDOW`] steps after the last one it left out without meeting the plan's
/// state is given up, and so is every trial once `budget` steps have been replayed in all:
/// the search's plans are long where it wandered (a plane flown out and back with nothing
/// loaded), and most of their steps are needed. Every step kept applies in the state
/// reached, so the result is a valid plan; `Rewritten::taken` lists the plan indices of the
/// actions left out (their starts, with their ends left out too).
pub fn eliminate(
    successors: &mut Successors<'_>,
    task: &mut Task,
    plan: &Plan,
    budget: usize,
) -> Result<Rewritten, Failure> {
    let (mut rewriter, path) = Rewriter::for_plan(successors, task, plan)?;
    let n = path.len();
    // The plan's states before each step (and at the end), the plan as `kept`, from step
    // `from` on (`states[..=from]` as they were).
    let replay =
        |rewriter: &mut Rewriter<'_, '_>, task: &mut Task, kept: &[bool], states: &mut Vec<State>, from: usize| {
            states.truncate(from + 1);
            let mut state = states[from].clone();
            for k in from..n {
                if kept[k] {
                    if !rewriter.applicable(task, &state, &path[k]) {
                        return false;
                    }
                    state = successors::apply(task, &state, &path[k]);
                }
                states.push(state.clone());
            }
            true
        };
    let mut kept = vec![true; n];
    let mut before = vec![task.init.clone()];
    if !replay(&mut rewriter, task, &kept, &mut before, 0) {
        return Err(Failure::Plan);
    }
    if !successors::goal_reached(task, &before[n]) {
        return Err(Failure::Plan);
    }
    let mut replayed = 0usize;
    let mut taken = Vec::new();
    for k in 0..n {
        if !kept[k] || rewriter.start_index[k].is_some() || replayed >= budget {
            continue;
        }
        let mut trial = kept.clone();
        trial[k] = false;
        if let Some(end) = rewriter.end_index[k] {
            trial[end] = false;
        }
        let mut state = before[k].clone();
        // The last step left out, and the last plan index the trial differs at.
        let mut last_out = k;
        let mut horizon = rewriter.end_index[k].unwrap_or(k);
        let mut left_out = 0;
        let mut verdict = None;
        for j in k + 1..=n {
            if j > horizon && state == before[j] {
                verdict = Some(true);
                break;
            }
            if j == n {
                verdict = Some(successors::goal_reached(task, &state));
                break;
            }
            if !trial[j] {
                continue;
            }
            replayed += 1;
            if j - last_out > ELIMINATION_WINDOW || replayed >= budget {
                break;
            }
            if rewriter.applicable(task, &state, &path[j]) {
                state = successors::apply(task, &state, &path[j]);
                continue;
            }
            if rewriter.start_index[j].is_some() {
                break; // an end whose start was kept
            }
            trial[j] = false;
            if let Some(end) = rewriter.end_index[j] {
                trial[end] = false;
                horizon = horizon.max(end);
            }
            (last_out, horizon) = (j, horizon.max(j));
            left_out += 1;
            if left_out > ELIMINATION_CASCADE {
                break;
            }
        }
        if verdict == Some(true) {
            let mut states = before.clone();
            if !replay(&mut rewriter, task, &trial, &mut states, k) {
                continue;
            }
            taken.extend((0..n).filter(|&j| kept[j] && !trial[j] && rewriter.start_index[j].is_none()));
            (kept, before) = (trial, states);
        }
    }
    taken.sort_unstable();
    let steps: Vec<Applicable> = (0..n).filter(|&k| kept[k]).map(|k| path[k].clone()).collect();
    Ok(Rewritten { plan: plan_from(task, &steps), taken })
}

/// How many times [`relocate`] bans the alternative a failed replay blames and replays again.
const RELOCATION_RETRIES: usize = 16;

/// How many steps a [`relocate`] replay with the schedule may hold back at once before it
/// gives up (and blames the first).
const RELOCATION_PENDING: usize = 64;

/// How many failed replays of [`relocate`] only ban the choice blamed before the plan's
/// places are protected too.
const BANS_BEFORE_PROTECTING: usize = 4;

/// `plan` with its starts that leave a unit somewhere only for a while sent somewhere
/// cheaper: where the search put a block aside on a far cell, the nearest free one.
///
/// A start is *relocatable* when its chosen values ([`chosen_positions`]) are named, at
/// other positions, by a later start of the same action that also names what it moves (the
/// move that takes the same block off that cell again). Replaying the plan in order, each
/// such start is taken as the instance with the same other arguments whose least duration
/// (`cost`), with that of the later start named with its values (the move on from there), is
/// least (its own values first among equals, but costing also the wait `waits`
/// gives the start in the plan's schedule) among those whose chosen values no start running
/// then has taken and whose end could apply at once (its own values need not: they may
/// wait, as in the plan). (Without the wait, a block that the search sent onto a
/// neighbouring cell before the block there had left stayed there, its arm held for the
/// whole wait, whatever cell was free.) A place given to a relocated unit stays its own until the
/// unit leaves, since the plan's other starts may count on it. With the plan's schedule
/// (`times`, each step's earliest time; empty for none), a start may also be sent to a place
/// taken when it comes but left before its end, by a step of the plan (one not relocated) or
/// by a unit this replay relocated there: its end waits until the place is free, and the cost
/// counts that wait beyond its least duration (the leaving step's time less the start's).
/// With `hold_back` as well, the place may be left after the start's end in the plan's order,
/// and may be one a thing stands on from the initial state (the first start that leaves from
/// it frees it): the replay then holds back every step that does not apply yet (the end, the
/// unit's release and what needs it) and takes each as soon as it applies after a later step
/// (a block sent aside before the block on the nearer cell has started to leave). A step still
/// held back at the end, or more than [`RELOCATION_PENDING`] at once, fails the replay. A
/// later step that no longer applies is taken as the applicable instance named as it is (a grip where the block now
/// stands), or named with a relocation's new values instead of its old ones (the end of the
/// move, the move off the cell and its end). A step that still fails, or a relocatable start
/// with no instance left, blames the relocation whose new values it names (else the latest),
/// whose choice is banned before the plan is replayed again, up to [`RELOCATION_RETRIES`]
/// times. Where the plan needs most of its places, banning one choice at a time only moves
/// the conflict to the next relocation onto the same place; after [`BANS_BEFORE_PROTECTING`]
/// replays, no unit is relocated onto a place one of the plan's starts takes while that unit
/// would be there (reverse_b100_a10: every replay failed; 239 -> 151 with the places
/// protected). `Rewritten::taken` lists the plan indices of the starts relocated. Every step
/// comes from the applicable actions of the state reached, so the result is a valid plan;
/// nothing in it is specific to a domain.
///
/// With [`Placing::ByRegret`], each start first looks for the place [`Rewriter::by_regret`]
/// gives it, all starts considered at once; where that place is not to be had in the replay,
/// it takes the cheapest as above.
pub fn relocate(
    successors: &mut Successors<'_>,
    task: &mut Task,
    plan: &Plan,
    (waits, times, hold_back): (&[i64], &[i64], bool),
    placing: Placing,
    cost: &mut dyn FnMut(usize, &Term) -> i64,
) -> Result<Rewritten, Failure> {
    let (mut rewriter, path) = Rewriter::for_plan(successors, task, plan)?;
    let leaving = rewriter.leaving(task, &path);
    let mut banned: FxHashMap<usize, Vec<Vec<Term>>> = FxHashMap::default();
    let places: Vec<Place> = (0..path.len())
        .filter(|&k| task.schemas[path[k].schema].snap == Snap::Start)
        .map(|k| Place {
            family: rewriter.families[path[k].schema][0],
            values: rewriter.chosen_values(task, &path, k),
            from: k,
            until: leaving[k].unwrap_or(path.len()),
        })
        .filter(|place| !place.values.is_empty())
        .collect();
    // With the schedule: the places things stand on from the start and the plan's first
    // start to leave them (see `Timing::initial`).
    let initial = if hold_back { rewriter.initial_places(task, &path, &places) } else { Vec::new() };
    let preferred = match placing {
        Placing::InPlanOrder => FxHashMap::default(),
        Placing::ByRegret => rewriter.by_regret(task, &path, &leaving, &places, cost),
    };
    // (A replay renames the steps that name a place it relocates: each starts from the plan's.)
    let names = rewriter.names.clone();
    for attempt in 0..RELOCATION_RETRIES {
        // After a few conflicts over places (the plan needs most of its places), every
        // start's place is its own while its unit is there.
        let protected = if attempt < BANS_BEFORE_PROTECTING { &[][..] } else { &places[..] };
        let timing = Timing { waits, times, places: &places, initial: &initial, hold_back };
        rewriter.names.clone_from(&names);
        match rewriter.replay(task, &path, &leaving, (&banned, protected, &preferred), timing, cost) {
            Ok((steps, taken)) => return Ok(Rewritten { plan: plan_from(task, &steps), taken }),
            Err(Some((k, values))) => banned.entry(k).or_default().push(values),
            Err(None) => return Err(Failure::Plan),
        }
    }
    Err(Failure::Plan)
}

/// The positions at which `args` name `values` in a row, the window touching none of `own`
/// (the step's own chosen positions): where a step names a place it leaves from.
fn place_windows<'a>(args: &'a [Term], values: &'a [Term], own: &'a [usize]) -> impl Iterator<Item = usize> + 'a {
    let len = values.len();
    (0..=args.len().saturating_sub(len)).filter(move |&p| {
        p + len <= args.len() && args[p..p + len] == *values && (p..p + len).all(|q| !own.contains(&q))
    })
}

/// The start that leaves a relocatable start's place (the later start of its action that
/// moves the same thing on), to cost a place as the way on from there.
struct Onward {
    /// The relocatable start's own chosen values, and those of the start that leaves.
    old: Vec<Term>,
    to: Vec<Term>,
    /// The leaving start's action and name.
    action: usize,
    name: Term,
}

impl Onward {
    /// The least duration of the start that leaves, named with `values` instead of the plan's
    /// place; `None` for the place it takes the unit to (unless the plan's own): not a place
    /// to leave the unit on meanwhile (the plan would take it from there to there; a block
    /// would stand on its goal place early, and its grip there be refused).
    fn cost(&self, values: &[Term], cost: &mut dyn FnMut(usize, &Term) -> i64) -> Option<i64> {
        if values == self.to && values != self.old {
            return None;
        }
        let (functor, _) = self.name.callable()?;
        let args = substituted(self.name.args(), &self.old, values).into_iter().next()?;
        Some(cost(self.action, &Term::Compound(functor, args.into())))
    }
}

/// A place by its family (the first member) and its interned values.
type PlaceKey = (usize, Vec<ConstId>);

/// The place of `family` named by `values`, interned (`None` when a value is not ground).
fn place_key(task: &mut Task, family: usize, values: &[Term]) -> Option<PlaceKey> {
    Some((family, values.iter().map(|v| task.consts.from_term(v)).collect::<Option<Vec<_>>>()?))
}

/// A relocatable start's choices for [`Rewriter::by_regret`]: over the plan indices
/// `start..until` its unit is on the place chosen.
struct Options {
    start: usize,
    until: usize,
    /// Cheapest first.
    candidates: Vec<Candidate>,
}

/// A place a relocatable start may take, and what its moves there and on from there cost.
struct Candidate {
    cost: i64,
    place: PlaceKey,
    values: Vec<Term>,
}

/// How [`relocate`] chooses places.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Placing {
    /// Each start in the plan's order takes the cheapest place free then: the first start
    /// to want a place gets it.
    InPlanOrder,
    /// Each start first looks for the place a choice over all of them gives it, the start
    /// that loses most by its second choice served first ([`Rewriter::by_regret`]).
    ByRegret,
}

/// What a [`relocate`] replay knows of the plan's schedule: for each step, how long its end
/// waits beyond its least duration (a start) and its time; and the plan's places.
#[derive(Clone, Copy)]
struct Timing<'a> {
    waits: &'a [i64],
    times: &'a [i64],
    places: &'a [Place],
    /// The places the plan's starts leave from before any of its starts took them (a
    /// block's cell at the start): a thing stands there until `Place::until`. Only when
    /// holding back.
    initial: &'a [Place],
    /// Whether a start may be sent to a place left after its end in the plan's order (its end
    /// and what follows from it held back until the place is free), or only before.
    hold_back: bool,
}

/// A place a plan's start leaves its unit on, and while.
struct Place {
    /// The start's family (its first member).
    family: usize,
    /// The start's chosen values.
    values: Vec<Term>,
    /// The plan indices over which the unit is there: from the start to the start that
    /// leaves again (else the plan's end).
    from: usize,
    until: usize,
}

/// A relocation in a replay: the start's plan index, its chosen values in the plan and the
/// ones taken instead, and the index of the last step that names it (the end of the move
/// that leaves from there).
struct Moved {
    start: usize,
    old: Vec<Term>,
    new: Vec<Term>,
    retire: usize,
}

/// `args` with each window equal to `old` replaced by `new`, one window at a time.
fn substituted(args: &[Term], old: &[Term], new: &[Term]) -> Vec<Vec<Term>> {
    if old.is_empty() || old.len() > args.len() {
        return Vec::new();
    }
    (0..=args.len() - old.len())
        .filter(|&p| args[p..p + old.len()] == *old)
        .map(|p| {
            let mut changed = args.to_vec();
            changed[p..p + old.len()].clone_from_slice(new);
            changed
        })
        .collect()
}

impl Rewriter<'_, '_> {
    /// For each step of `path`, if it is a relocatable start, the index of the later start
    /// of its action that leaves from its chosen values.
    fn leaving(&self, task: &Task, path: &[Applicable]) -> Vec<Option<usize>> {
        let mut found = vec![None; path.len()];
        for (k, action) in path.iter().enumerate() {
            if task.schemas[action.schema].snap != Snap::Start {
                continue;
            }
            let values = self.chosen_values(task, path, k);
            if values.is_empty() {
                continue;
            }
            let name = self.names[k].args();
            // What the start moves: its arguments neither chosen nor a unit of a resource.
            let moved = unit_free_positions(task, action.schema);
            found[k] = (k + 1..path.len()).find(|&l| {
                if !self.families[action.schema].contains(&path[l].schema) {
                    return false;
                }
                let args = self.names[l].args();
                let own = chosen_positions(task, path[l].schema);
                place_windows(args, &values, &own).any(|p| {
                    let window = p..p + values.len();
                    moved.iter().any(|&q| !window.contains(&q) && q < args.len() && args[q] == name[q])
                })
            });
        }
        found
    }

    /// One replay of [`relocate`] with the choices `banned`, relocating no unit onto a place
    /// `protected` while it is the plan's: the steps and the relocated starts, or the
    /// relocation to blame and the values to ban it (`None`: the plan itself fails).
    #[allow(clippy::type_complexity)]
    fn replay(
        &mut self,
        task: &mut Task,
        path: &[Applicable],
        leaving: &[Option<usize>],
        (banned, protected, preferred): (&FxHashMap<usize, Vec<Vec<Term>>>, &[Place], &FxHashMap<usize, Vec<Term>>),
        timing: Timing<'_>,
        cost: &mut dyn FnMut(usize, &Term) -> i64,
    ) -> Result<(Vec<Applicable>, Vec<usize>), Option<(usize, Vec<Term>)>> {
        let Timing { waits, times, places, initial, hold_back: holding } = timing;
        // The places of this replay's relocated starts, while their units are there.
        let mut relocated: Vec<Place> = Vec::new();
        let mut state = task.init.clone();
        let mut out: Vec<Applicable> = Vec::with_capacity(path.len());
        let mut active: Vec<Moved> = Vec::new();
        let mut taken = Vec::new();
        // The chosen values of the starts taken and not yet ended (relocated: not yet left):
        // the index in `path` of the step that frees them, their family, the values.
        let mut reserved: Vec<(usize, usize, Vec<Term>)> = Vec::new();
        // Steps held back, in plan order, each with the relocation to blame if it stays so.
        let mut pending: Vec<(usize, Option<(usize, Vec<Term>)>)> = Vec::new();
        let blame =
            |active: &[Moved], failed: &Term| to_blame(active, |m| &m.new, failed).map(|m| (m.start, m.new.clone()));
        for (k, action) in path.iter().enumerate() {
            if let Some(leaves) = leaving[k] {
                let own = self.chosen_values(task, path, k);
                // The plan's own values also cost the wait their end had in its schedule.
                let wait = waits.get(k).copied().unwrap_or(0).max(0);
                let end = self.end_index[k];
                let free = |family: usize, values: &[Term]| -> Option<(i64, Option<i64>)> {
                    let allowed = (values == own
                        || !protected.iter().any(|place| {
                            place.family == family && place.values == values && place.from < leaves && place.until > k
                        }))
                        && banned.get(&k).is_none_or(|b| !b.iter().any(|v| v == values));
                    if !allowed {
                        return None;
                    }
                    // (A place freed by step k itself is free for it.)
                    let reserved = reserved.iter().any(|(e, f, v)| *e != k && *f == family && v == values);
                    if values == own {
                        return (!reserved).then_some((wait, None));
                    }
                    // With the schedule's times: a place taken now (as the plan has it, as
                    // this replay relocated a unit there, or, holding back, from the start)
                    // but left before this start's end in the plan's order (holding back, at
                    // any later step: the end and what follows from it are held back until
                    // then). The move may head there and arrive once it is free, as a block
                    // in the air waits above a cell being cleared; ready when its units leave
                    // in the plan's schedule, after this start's time.
                    if let (false, Some(end)) = (times.is_empty(), end) {
                        let mut there = places
                            .iter()
                            .filter(|place| !taken.contains(&place.from))
                            .chain(&relocated)
                            .filter(|place| place.from < k)
                            .chain(initial)
                            .filter(|place| place.family == family && place.values == values && place.until > k)
                            .peekable();
                        if there.peek().is_some() {
                            let ready = there.try_fold(0, |ready, place| {
                                let (left, now) = (times.get(place.until)?, times.get(k)?);
                                (holding || place.until < end).then(|| ready.max(left - now))
                            });
                            if ready.is_some() {
                                return Some((0, ready));
                            }
                        }
                    }
                    (!reserved).then_some((0, None))
                };
                let prefer = preferred.get(&k).map(Vec::as_slice);
                let chosen = self.cheapest(task, path, (k, leaves), &state, (free, prefer), cost);
                if let Some((step, old, new)) = chosen {
                    // A unit sent elsewhere keeps the place until it leaves: the plan's other
                    // starts may have counted on it being free.
                    let until = if old == new { self.end_index[k] } else { Some(leaves) };
                    let family = self.families[action.schema][0];
                    if old != new {
                        self.rename_place(task, path, (k, leaves), &old, &new);
                        // (Kept until the move off the new place has ended too: its end names
                        // the place it left.)
                        let retire = self.end_index[leaves].unwrap_or(leaves);
                        relocated.push(Place { family, values: new.clone(), from: k, until: leaves });
                        active.push(Moved { start: k, old, new: new.clone(), retire });
                        taken.push(k);
                    }
                    let reserving = until.map(|until| (until, family, new));
                    Self::commit(task, k, step, reserving, (&mut state, &mut out), (&mut active, &mut reserved));
                } else if holding && !pending.is_empty() {
                    // (Its unit is not there yet: taken as the plan has it once it applies.)
                    pending.push((k, blame(&active, &self.names[k])));
                    continue;
                } else {
                    return Err(blame(&active, &self.names[k]));
                }
            } else if let Some(step) = self.take(task, path, k, &state, &active) {
                let reserving = self.reserving(task, path, k, &step);
                Self::commit(task, k, step, reserving, (&mut state, &mut out), (&mut active, &mut reserved));
            } else if holding {
                // A step that does not apply yet (the end of a move towards a place still
                // taken, and what follows from it) is held back and taken as soon as it
                // applies, after a later step; the result is valid either way, since every
                // step taken applies in the state reached.
                pending.push((k, blame(&active, &self.names[k])));
                if pending.len() > RELOCATION_PENDING {
                    return Err(pending.swap_remove(0).1);
                }
                continue;
            } else {
                return Err(blame(&active, &self.names[k]));
            }
            // What was held back, as soon as it applies (earlier ones first).
            let mut progress = !pending.is_empty();
            while progress {
                progress = false;
                let mut i = 0;
                while i < pending.len() {
                    let p = pending[i].0;
                    let Some(step) = self.take(task, path, p, &state, &active) else {
                        i += 1;
                        continue;
                    };
                    let reserving = self.reserving(task, path, p, &step);
                    Self::commit(task, p, step, reserving, (&mut state, &mut out), (&mut active, &mut reserved));
                    pending.remove(i);
                    progress = true;
                }
            }
        }
        if let Some((_, blamed)) = pending.into_iter().next() {
            return Err(blamed);
        }
        if !successors::goal_reached(task, &state) {
            return Err(active.last().map(|m| (m.start, m.new.clone())));
        }
        Ok((out, taken))
    }

    /// Step `k` of `path` in `state` as a [`relocate`] replay takes it: as it is, else renamed
    /// after the relocations `active` ([`Rewriter::renamed`]).
    fn take(
        &mut self,
        task: &mut Task,
        path: &[Applicable],
        k: usize,
        state: &State,
        active: &[Moved],
    ) -> Option<Applicable> {
        if self.applicable(task, state, &path[k]) {
            return Some(path[k].clone());
        }
        self.renamed(task, path, k, state, active)
    }

    /// What step `k` (taken as `step`) reserves in a [`relocate`] replay: a start's chosen
    /// values, until its end.
    fn reserving(
        &self,
        task: &Task,
        path: &[Applicable],
        k: usize,
        step: &Applicable,
    ) -> Option<(usize, usize, Vec<Term>)> {
        let positions = chosen_positions(task, path[k].schema);
        if task.schemas[path[k].schema].snap != Snap::Start || positions.is_empty() {
            return None;
        }
        let end = self.end_index[k]?;
        let name = successors::action_name(task, step);
        let values = positions.iter().map(|&p| name.args()[p].clone()).collect();
        Some((end, self.families[path[k].schema][0], values))
    }

    /// Takes plan step `k` as `step` in a [`relocate`] replay: what it reserves, the state
    /// after it, and what it ends (the reservations it frees, the relocations it retires).
    #[allow(clippy::type_complexity)]
    fn commit(
        task: &mut Task,
        k: usize,
        step: Applicable,
        reserving: Option<(usize, usize, Vec<Term>)>,
        (state, out): (&mut State, &mut Vec<Applicable>),
        (active, reserved): (&mut Vec<Moved>, &mut Vec<(usize, usize, Vec<Term>)>),
    ) {
        reserved.retain(|(end, _, _)| *end != k);
        reserved.extend(reserving);
        *state = successors::apply(task, state, &step);
        out.push(step);
        active.retain(|m| m.retire != k);
    }

    /// The places starts of `path` leave from (named at a window away from their own chosen
    /// positions, of the length of those) before any start of their family took them: what
    /// stands there from the start (a block's first cell), until the first start that leaves
    /// (the first of them, if several). A window that names no place (a block and a cell
    /// together) gives a place no start ever chooses, and is never looked up.
    fn initial_places(&self, task: &Task, path: &[Applicable], places: &[Place]) -> Vec<Place> {
        let mut found: Vec<Place> = Vec::new();
        for (u, action) in path.iter().enumerate() {
            let own = chosen_positions(task, action.schema);
            if task.schemas[action.schema].snap != Snap::Start || own.is_empty() {
                continue;
            }
            let family = self.families[action.schema][0];
            let args = self.names[u].args();
            for p in
                (0..=args.len().saturating_sub(own.len())).filter(|&p| (p..p + own.len()).all(|q| !own.contains(&q)))
            {
                let values = &args[p..p + own.len()];
                let same = |place: &&Place| place.family == family && place.values == values;
                let arrived = places.iter().filter(same).any(|place| place.from < u);
                if !arrived && !found.iter().any(|place| same(&place)) {
                    found.push(Place { family, values: values.to_vec(), from: 0, until: u });
                }
            }
        }
        found
    }

    /// Where each relocatable start of the plan would best leave its unit, all of them at
    /// once: its alternatives in the plan's own states (costed as [`Rewriter::cheapest`]
    /// costs them, the move there and the move on from there, and kept when the start's end
    /// could apply at once), given out greatest regret first (the start that loses most by
    /// its second choice; the earliest among equals), no two starts of a family on the same
    /// values while both units would be there, nor on a place one of the plan's other starts
    /// takes meanwhile.
    fn by_regret(
        &mut self,
        task: &mut Task,
        path: &[Applicable],
        leaving: &[Option<usize>],
        places: &[Place],
        cost: &mut dyn FnMut(usize, &Term) -> i64,
    ) -> FxHashMap<usize, Vec<Term>> {
        let mut options: Vec<Options> = Vec::new();
        let mut state = task.init.clone();
        for (k, action) in path.iter().enumerate() {
            if let Some(leaves) = leaving[k]
                && let Some(end) = self.end_index[k].map(|e| path[e].clone())
            {
                let onward = self.onward(task, path, (k, leaves));
                let keep = |values: &[Term], cost: &mut dyn FnMut(usize, &Term) -> i64| onward.cost(values, cost);
                let family = self.families[action.schema][0];
                let mut candidates = Vec::new();
                for (cost, alternative, values) in self.alternatives(task, path, k, &state, keep, cost) {
                    let after = successors::apply(task, &state, &alternative);
                    if values != onward.old && self.end_of(task, &alternative, &end, &after).is_none() {
                        continue;
                    }
                    if let Some(place) = place_key(task, family, &values) {
                        candidates.push(Candidate { cost, place, values });
                    }
                }
                options.push(Options { start: k, until: leaves, candidates });
            }
            state = successors::apply(task, &state, action);
        }
        // The places taken: first those of the plan's starts that are not relocatable, while
        // their units are there.
        let mut taken: FxHashMap<PlaceKey, Vec<(usize, usize)>> = FxHashMap::default();
        for place in places.iter().filter(|place| leaving[place.from].is_none()) {
            if let Some(key) = place_key(task, place.family, &place.values) {
                taken.entry(key).or_default().push((place.from, place.until));
            }
        }
        let free = |taken: &FxHashMap<PlaceKey, Vec<(usize, usize)>>, option: &Options, candidate: &Candidate| {
            taken
                .get(&candidate.place)
                .is_none_or(|spans| spans.iter().all(|&(from, until)| until <= option.start || from >= option.until))
        };
        let mut preferred = FxHashMap::default();
        let mut open: Vec<usize> = (0..options.len()).collect();
        loop {
            // The open option with the greatest regret.
            let mut pick: Option<(i64, usize)> = None;
            for (i, &o) in open.iter().enumerate() {
                let option = &options[o];
                let mut costs = option.candidates.iter().filter(|c| free(&taken, option, c)).map(|c| c.cost);
                let Some(best) = costs.next() else { continue };
                let regret = costs.next().map_or(i64::MAX, |second| second - best);
                if pick.is_none_or(|(most, _)| regret > most) {
                    pick = Some((regret, i));
                }
            }
            let Some((_, i)) = pick else { break };
            let option = &options[open.remove(i)];
            if let Some(best) = option.candidates.iter().find(|c| free(&taken, option, c)) {
                taken.entry(best.place.clone()).or_default().push((option.start, option.until));
                preferred.insert(option.start, best.values.clone());
            }
        }
        preferred
    }

    /// After relocatable start `k` took the chosen values `new` instead of `old`, the steps
    /// that name its place by them named with `new`: its end (at its chosen positions) and
    /// the start `leaves` that leaves from there and that one's end (elsewhere than at its
    /// own chosen positions, as [`Rewriter::leaving`] found it). Without this, a start that
    /// leaves from a relocated place and is relocatable itself (a block moved from one place
    /// aside to another) would look for its unit where the plan had put it, and fail.
    fn rename_place(
        &mut self,
        task: &Task,
        path: &[Applicable],
        (k, leaves): (usize, usize),
        old: &[Term],
        new: &[Term],
    ) {
        let rename = |name: &Term, at: usize| -> Option<Term> {
            let (functor, _) = name.callable()?;
            let mut args = name.args().to_vec();
            let window = args.get_mut(at..at + old.len())?;
            if window != old {
                return None;
            }
            window.clone_from_slice(new);
            Some(Term::Compound(functor, args.into()))
        };
        if let (Some(end), Some(&at)) = (self.end_index[k], chosen_positions(task, path[k].schema).first())
            && let Some(renamed) = rename(&self.names[end], at)
        {
            self.names[end] = renamed;
        }
        let own = chosen_positions(task, path[leaves].schema);
        let Some(at) = place_windows(self.names[leaves].args(), old, &own).next() else { return };
        for step in std::iter::once(leaves).chain(self.end_index[leaves]) {
            if let Some(renamed) = rename(&self.names[step], at) {
                self.names[step] = renamed;
            }
        }
    }

    /// Step `k` where it no longer applies as it is, after the relocations `active`: the
    /// applicable instance named as it is (other values outside its name: the grip of a block
    /// that stands elsewhere), else one named with a relocation's new values for its old ones
    /// (the end of the move, the move off the new place), the latest relocation first.
    fn renamed(
        &mut self,
        task: &mut Task,
        path: &[Applicable],
        k: usize,
        state: &State,
        active: &[Moved],
    ) -> Option<Applicable> {
        if let Some(step) = self.same(task, path, k, state) {
            return Some(step);
        }
        let name = self.names[k].clone();
        let (functor, _) = name.callable()?;
        for moved in active.iter().rev() {
            for args in substituted(name.args(), &moved.old, &moved.new) {
                let wanted = Term::Compound(functor, args.into());
                if let Some(step) = self.named(task, path[k].schema, state, &wanted) {
                    return Some(step);
                }
            }
        }
        None
    }

    /// The least costly way to take relocatable start `k` in `state`: the instance of its
    /// action with the same other arguments and any chosen values `free` accepts (given the
    /// family, it answers what they cost beyond the least duration; the plan's own among
    /// them, first among equals), costed with the start `leaves` that leaves from there named
    /// with them, whose end could apply at once (the plan's own values need not); with the
    /// plan's chosen values and the ones taken.
    fn cheapest(
        &mut self,
        task: &mut Task,
        path: &[Applicable],
        (k, leaves): (usize, usize),
        state: &State,
        (free, prefer): (impl Fn(usize, &[Term]) -> Option<(i64, Option<i64>)>, Option<&[Term]>),
        cost: &mut dyn FnMut(usize, &Term) -> i64,
    ) -> Option<(Applicable, Vec<Term>, Vec<Term>)> {
        let family = self.families[path[k].schema][0];
        // The start that leaves from there, named with the values instead of the plan's.
        let onward = self.onward(task, path, (k, leaves));
        let old = &onward.old;
        let (own_action, own) = (task.schemas[path[k].schema].action, self.names[k].clone());
        let keep = |values: &[Term], cost: &mut dyn FnMut(usize, &Term) -> i64| -> Option<i64> {
            let (mut extra, ready) = free(family, values)?;
            if let Some(ready) = ready {
                // A place still taken: the time it is free after the start, beyond the
                // start's own least duration, is spent waiting.
                let (functor, _) = own.callable()?;
                let args = substituted(own.args(), old, values).into_iter().next()?;
                extra = (ready - cost(own_action, &Term::Compound(functor, args.into()))).max(0);
            }
            Some(extra.saturating_add(onward.cost(values, cost)?))
        };
        let mut ranked = self.alternatives(task, path, k, state, keep, cost);
        if let Some(at) = prefer.and_then(|p| ranked.iter().position(|(_, _, values)| values[..] == *p)) {
            ranked[..=at].rotate_right(1);
        }
        let end = self.end_index[k].map(|e| path[e].clone())?;
        for (_, alternative, values) in ranked {
            // (The plan's own values may wait for their end, as they did in the plan.)
            let next = successors::apply(task, state, &alternative);
            let later = free(family, &values).is_some_and(|(_, ready)| ready.is_some());
            if values == *old || later || self.end_of(task, &alternative, &end, &next).is_some() {
                return Some((alternative, old.clone(), values));
            }
        }
        None
    }
}

/// Two jobs that move one thing, made one: `first` leaves the thing somewhere for a while (a
/// relocatable start, see [`relocate`]) and `second`, in another job, takes it on from there.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Merge {
    /// The first job's start.
    pub first: usize,
    /// The second job's start, which leaves from where `first` went.
    pub second: usize,
}

/// The merges `plan` offers ([`merge`]): each relocatable start with the start that takes
/// what it moved on from there, when each is its job's only step between its start and end
/// (`jobs` are the plan's, see [`crate::passes::reassign::jobs`]), and the merged start (the
/// first named with the second's chosen values) could apply where the first start is in the
/// plan, but for its Invalid conditions (which a later state may lift: the merge holds it
/// back until then). A block put aside and brought back to the cell it left cannot go
/// straight there (a move must change the cell, an OnKB condition of std/blocks.pl);
/// offered anyway, such a merge failed every set it was in (and, once blamed and dropped one
/// replay at a time, took reverse_b100_a10_s1 from 3.7 s to 7.3 s).
pub fn merges(
    successors: &mut Successors<'_>,
    task: &mut Task,
    plan: &Plan,
    jobs: &crate::passes::reassign::Jobs,
) -> Result<Vec<Merge>, Failure> {
    let (rewriter, path) = Rewriter::for_plan(successors, task, plan)?;
    let leaving = rewriter.leaving(task, &path);
    let mut offered = Vec::new();
    let mut state = task.init.clone();
    for (first, action) in path.iter().enumerate() {
        if let Some(second) = leaving[first]
            && rewriter.in_two_jobs(jobs, first, second)
            && let Some(merged) = merged_start(task, action, &rewriter.names[second])
            && rewriter.successors.applies_but_for_invalid(task, &merged, &state) == Ok(true)
        {
            offered.push(Merge { first, second });
        }
        state = successors::apply(task, &state, action);
    }
    Ok(offered)
}

/// Start `first` with the chosen values of the start named `second` (see [`merge`]); None
/// when its schema's chosen positions are not variables or `second` has no value there.
fn merged_start(task: &mut Task, first: &Applicable, second: &Term) -> Option<Applicable> {
    let Pattern::Compound(_, args) = &task.schemas[first.schema].name else { return None };
    let mut step = first.clone();
    for p in chosen_positions(task, first.schema) {
        let (Pattern::Var(v), Some(value)) = (&args[p], second.args().get(p)) else { return None };
        step.bindings[*v as usize] = task.consts.from_term(value);
    }
    Some(step)
}

/// How many steps a [`merge`] replay may hold back at once before it gives up.
const MERGE_PENDING: usize = 64;

/// `plan` with the jobs of each of `merges` made one: at the first start's place, the start
/// named as it is but with the second start's chosen values (the block goes straight to
/// where its second move took it); the first job's end and later steps, and the second job's
/// steps up to its start, are left out; at the second start's end's place, the end of the
/// merged start, and the second job's later steps then name the first job's unit (the arm
/// holds the block all along). Merges must not share a job.
///
/// The merged job holds its unit longer, so a later job may find every unit taken, or a step
/// may find what it needs not there yet: such a step is held back, with the later steps of its
/// job, and taken as soon as it applies after a later step (held-back steps first, in plan
/// order). A job whose own unit is taken when its first step comes takes the first other
/// unit of its resource free then, and names it in all its steps. Every step comes from the
/// actions applicable in the state reached, so the result is a valid plan or none: a step
/// still held back at the end (or more than [`MERGE_PENDING`] at once) blames the latest merge
/// under way when it was held back (`Failure::Detour` with its index). The inverse of a detour;
/// nothing in it is specific to a domain.
pub fn merge(
    successors: &mut Successors<'_>,
    task: &mut Task,
    plan: &Plan,
    jobs: &crate::passes::reassign::Jobs,
    merges: &[Merge],
) -> Result<Rewritten, Failure> {
    let (rewriter, path) = Rewriter::for_plan(successors, task, plan)?;
    let mut replay = MergeReplay {
        rewriter,
        jobs,
        merges,
        path: &path,
        skip: vec![false; path.len()],
        at_first: FxHashMap::default(),
        at_end: FxHashMap::default(),
        started: FxHashMap::default(),
        renamed: FxHashMap::default(),
        active: Vec::new(),
        state: task.init.clone(),
        out: Vec::with_capacity(path.len()),
    };
    for (m, merge) in merges.iter().enumerate() {
        let ends = (replay.rewriter.end_index[merge.first], replay.rewriter.end_index[merge.second]);
        let jobs_of = (jobs.job_of(merge.first), jobs.job_of(merge.second));
        let ((Some(end1), Some(end2)), (Some(j1), Some(j2))) = (ends, jobs_of) else {
            return Err(Failure::Detour(m));
        };
        if j1 == j2 {
            return Err(Failure::Detour(m));
        }
        for &k in jobs.job(j1).iter().filter(|&&k| k >= end1) {
            replay.skip[k] = true;
        }
        for &k in jobs.job(j2).iter().filter(|&&k| k <= merge.second) {
            replay.skip[k] = true;
        }
        replay.at_first.insert(merge.first, m);
        replay.at_end.insert(end2, m);
    }
    // Steps held back, in plan order, each with the merge to blame if it stays so.
    let mut pending: Vec<(usize, Failure)> = Vec::new();
    let mut taken = Vec::new();
    for k in 0..path.len() {
        if replay.skip[k] {
            continue;
        }
        let job = jobs.job_of(k);
        let behind = job.is_some() && pending.iter().any(|&(p, _)| jobs.job_of(p) == job);
        if behind || !replay.take(task, k, &mut taken)? {
            let blame = match replay.at_end.get(&k) {
                Some(&m) => Failure::Detour(m),
                None => replay.active.last().map_or(Failure::Plan, |(m, _)| Failure::Detour(*m)),
            };
            pending.push((k, blame));
            if pending.len() > MERGE_PENDING {
                return Err(pending[0].1);
            }
            continue;
        }
        // What was held back, as soon as it applies.
        let mut progress = true;
        while progress {
            progress = false;
            let mut i = 0;
            while i < pending.len() {
                let (p, _) = pending[i];
                let job = jobs.job_of(p);
                let first_of_job = job.is_none() || !pending[..i].iter().any(|&(q, _)| jobs.job_of(q) == job);
                if first_of_job && replay.take(task, p, &mut taken)? {
                    pending.remove(i);
                    progress = true;
                } else {
                    i += 1;
                }
            }
        }
    }
    if let Some(&(_, blame)) = pending.first() {
        return Err(blame);
    }
    if !successors::goal_reached(task, &replay.state) {
        return Err(replay.active.last().map_or(Failure::Plan, |(m, _)| Failure::Detour(*m)));
    }
    Ok(Rewritten { plan: plan_from(task, &replay.out), taken })
}

/// The shortcuts `plan` offers ([`shortcut`]): the pairs [`merges`] would look at (a
/// relocatable start, the start of another job that takes what it moved on from there, each
/// its job's only step between its start and end) where the second start names the place
/// the thing left in a row, at the positions where the first start names where it took it
/// from (in std/blocks.pl, the move's source cell), so the second can be named with the
/// first's source instead.
pub fn shortcuts(
    successors: &mut Successors<'_>,
    task: &mut Task,
    plan: &Plan,
    jobs: &crate::passes::reassign::Jobs,
) -> Result<Vec<Merge>, Failure> {
    let (rewriter, path) = Rewriter::for_plan(successors, task, plan)?;
    let leaving = rewriter.leaving(task, &path);
    let mut offered = Vec::new();
    for (first, second) in leaving.iter().enumerate().filter_map(|(k, l)| l.map(|l| (k, l))) {
        if rewriter.in_two_jobs(jobs, first, second) && rewriter.shortened_name(task, &path, first, second).is_some() {
            offered.push(Merge { first, second });
        }
    }
    Ok(offered)
}

/// `plan` with each of `shortcuts` taken, the inverse of a [`detour`](rewrite) in time: the
/// first job's steps are left out, so the thing stays where it was, and the second job takes
/// it from there, its start named with the first start's source in place of the place it no
/// longer visits and its end the one that start's running instance takes (the block waits on
/// its cell and goes straight to its next place later: one grip, move and release fewer, and
/// the first job's unit free for other work). A second job that would take the thing back to where it already stands is left
/// out too. Shortcuts must not share a job.
///
/// Every step comes from the actions applicable in the state reached, so the result is a
/// valid plan or none: a step that no longer applies (the place the thing now keeps was
/// another step's destination, or something beneath it had to be cleared) blames the latest
/// shortcut under way whose source the step names, else the latest under way
/// (`Failure::Detour` with its index). Nothing in it is specific to a domain.
pub fn shortcut(
    successors: &mut Successors<'_>,
    task: &mut Task,
    plan: &Plan,
    jobs: &crate::passes::reassign::Jobs,
    shortcuts: &[Merge],
) -> Result<Rewritten, Failure> {
    let (mut rewriter, path) = Rewriter::for_plan(successors, task, plan)?;
    let mut skip = vec![false; path.len()];
    // The second starts, named with their shortcut's source.
    let mut renamed = vec![false; path.len()];
    // Each shortcut's (source values, the step that ends it: the second start's end).
    let mut under: Vec<(Vec<Term>, usize)> = Vec::with_capacity(shortcuts.len());
    let mut first_of: FxHashMap<usize, usize> = FxHashMap::default();
    for (s, cut) in shortcuts.iter().enumerate() {
        let (j1, j2) = (jobs.job_of(cut.first), jobs.job_of(cut.second));
        let (Some(j1), Some(j2), Some(end)) = (j1, j2, rewriter.end_index[cut.second]) else {
            return Err(Failure::Detour(s));
        };
        let Some((name, source)) = rewriter.shortened_name(task, &path, cut.first, cut.second) else {
            return Err(Failure::Detour(s));
        };
        if j1 == j2 || jobs.job(j1).iter().chain(jobs.job(j2)).any(|&k| skip[k]) {
            return Err(Failure::Detour(s));
        }
        for &k in jobs.job(j1) {
            skip[k] = true;
        }
        // Back to where it stands: nothing to do.
        if rewriter.chosen_values(task, &path, cut.second) == source {
            for &k in jobs.job(j2) {
                skip[k] = true;
            }
        }
        rewriter.names[cut.second] = name;
        renamed[cut.second] = true;
        under.push((source, end));
        first_of.insert(cut.first, s);
    }
    // Starts taken otherwise than the plan has them, by index.
    let mut started: FxHashMap<usize, Applicable> = FxHashMap::default();
    let mut active: Vec<(usize, Vec<Term>)> = Vec::new();
    let mut taken = Vec::new();
    let mut state = task.init.clone();
    let mut out: Vec<Applicable> = Vec::with_capacity(path.len());
    for (k, action) in path.iter().enumerate() {
        active.retain(|(s, _)| under[*s].1 >= k);
        if let Some(&s) = first_of.get(&k) {
            active.push((s, under[s].0.clone()));
            taken.push(s);
        }
        if skip[k] {
            continue;
        }
        let step = match rewriter.start_index[k].and_then(|s| started.get(&s)) {
            Some(start) => {
                let start = start.clone();
                rewriter.end_of(task, &start, action, &state)
            }
            None if !renamed[k] && rewriter.applicable(task, &state, action) => Some(action.clone()),
            None => {
                let name = rewriter.names[k].clone();
                rewriter.named(task, action.schema, &state, &name)
            }
        };
        let Some(step) = step else {
            let failed = rewriter.names[k].clone();
            return Err(
                to_blame(&active, |(_, values)| values, &failed).map_or(Failure::Plan, |(s, _)| Failure::Detour(*s))
            );
        };
        if step != *action && task.schemas[step.schema].snap == Snap::Start {
            started.insert(k, step.clone());
        }
        state = successors::apply(task, &state, &step);
        out.push(step);
    }
    if !successors::goal_reached(task, &state) {
        return Err(active.last().map_or(Failure::Plan, |(s, _)| Failure::Detour(*s)));
    }
    Ok(Rewritten { plan: plan_from(task, &out), taken })
}

/// The state of a [`merge`] replay.
struct MergeReplay<'s, 'p, 'a> {
    rewriter: Rewriter<'s, 'p>,
    jobs: &'a crate::passes::reassign::Jobs,
    merges: &'a [Merge],
    path: &'a [Applicable],
    /// The steps the merges leave out.
    skip: Vec<bool>,
    /// The merge whose first start each step is.
    at_first: FxHashMap<usize, usize>,
    /// The merge whose second start's end each step is.
    at_end: FxHashMap<usize, usize>,
    /// The starts taken otherwise than the plan has them (renamed or merged), as taken.
    started: FxHashMap<usize, Applicable>,
    /// The unit each renamed job names instead of its own.
    renamed: FxHashMap<usize, (ConstId, ConstId)>,
    /// The merges under way, with their merged starts.
    active: Vec<(usize, Applicable)>,
    state: State,
    out: Vec<Applicable>,
}

/// `action` with every binding to `from` bound to `to` instead.
fn rebound(action: &Applicable, from: ConstId, to: ConstId) -> Applicable {
    let bindings = action.bindings.iter().map(|&b| if b == Some(from) { Some(to) } else { b }).collect();
    Applicable { bindings, ..action.clone() }
}

impl MergeReplay<'_, '_, '_> {
    /// Job `j`'s unit.
    fn unit(&self, task: &mut Task, j: usize) -> Option<ConstId> {
        task.consts.from_term(self.jobs.unit(j))
    }

    /// Takes step `k` (as the merges make it) if it applies in the state reached: `Ok(false)`
    /// if it does not yet, an error when it never will. Merges whose first start it is go onto
    /// `taken`.
    fn take(&mut self, task: &mut Task, k: usize, taken: &mut Vec<usize>) -> Result<bool, Failure> {
        let original = &self.path[k];
        let job = self.jobs.job_of(k);
        let mut step = match job.and_then(|j| self.renamed.get(&j)) {
            Some(&(from, to)) => rebound(original, from, to),
            None => original.clone(),
        };
        // An end names the running start: as taken.
        if let Some(start) = self.rewriter.start_index[k].and_then(|s| self.started.get(&s)) {
            let Task { schemas, consts, .. } = task;
            step.ends = successors::running_instance(&schemas[start.schema], consts, &start.bindings);
        }
        if let Some(&m) = self.at_first.get(&k) {
            // The start with the second start's chosen values.
            let second = &self.rewriter.names[self.merges[m].second];
            step = merged_start(task, &step, second).ok_or(Failure::Detour(m))?;
            if !self.rewriter.applicable(task, &self.state, &step) {
                match self.rewriter.named_as(task, &self.state, &step) {
                    Some(found) => step = found,
                    None => return Ok(false),
                }
            }
            self.active.push((m, step.clone()));
            taken.push(m);
        } else if let Some(&m) = self.at_end.get(&k) {
            // (Its merged start still held back: blame the merge.)
            let Some(position) = self.active.iter().position(|(a, _)| *a == m) else { return Err(Failure::Detour(m)) };
            let start = self.active[position].1.clone();
            let Some(end) = self.rewriter.end_of(task, &start, original, &self.state) else { return Ok(false) };
            step = end;
            self.active.remove(position);
            // The second job's later steps name the first job's unit.
            let (j1, j2) = (self.jobs.job_of(self.merges[m].first), self.jobs.job_of(self.merges[m].second));
            if let (Some(j1), Some(j2)) = (j1, j2) {
                let unit = match self.renamed.get(&j1) {
                    Some(&(_, to)) => Some(to),
                    None => self.unit(task, j1),
                };
                if let (Some(own), Some(unit)) = (self.unit(task, j2), unit) {
                    self.renamed.insert(j2, (own, unit));
                }
            }
        } else if !self.rewriter.applicable(task, &self.state, &step) {
            // Named as it is (with its job's unit), other values outside its name; else, a
            // job's first step whose unit is taken: the first other unit free.
            if let Some(found) = self.rewriter.named_as(task, &self.state, &step) {
                step = found;
            } else {
                let Some(j) = job.filter(|&j| self.jobs.job(j).first() == Some(&k) && !self.renamed.contains_key(&j))
                else {
                    return Ok(false);
                };
                let Some(own) = self.unit(task, j) else { return Ok(false) };
                let others: Vec<ConstId> =
                    self.jobs.units_like(j).filter_map(|u| task.consts.from_term(u)).filter(|&u| u != own).collect();
                let Some((unit, other)) = others
                    .into_iter()
                    .map(|u| (u, rebound(original, own, u)))
                    .find(|(_, other)| self.rewriter.applicable(task, &self.state, other))
                else {
                    return Ok(false);
                };
                self.renamed.insert(j, (own, unit));
                step = other;
            }
        }
        if step != *original && task.schemas[step.schema].snap == Snap::Start {
            self.started.insert(k, step.clone());
        }
        self.state = successors::apply(task, &self.state, &step);
        self.out.push(step);
        Ok(true)
    }
}

/// The detour to blame for the step named `failed` no longer applying: the latest of those
/// aside whose values the step's name holds, in a row (it goes where the detour left
/// something), or else the latest aside.
fn blame(aside: &[(usize, Vec<Term>)], failed: &Term) -> Failure {
    to_blame(aside, |(_, values)| values, failed).map_or(Failure::Plan, |(d, _)| Failure::Detour(*d))
}

/// Of `changes` (detours or relocations, in the order made), the one to blame for the step
/// named `failed` failing: the latest whose `values` the name holds in a row, else the latest.
fn to_blame<'a, T>(changes: &'a [T], values: impl Fn(&T) -> &[Term], failed: &Term) -> Option<&'a T> {
    let args = failed.args();
    let holds = |values: &[Term]| !values.is_empty() && args.windows(values.len()).any(|w| w == values);
    changes.iter().rev().find(|c| holds(values(c))).or(changes.last())
}

/// For each start of `path`, the index of the end that ends it (the first after it that ends
/// its running instance).
fn end_index(task: &mut Task, path: &[Applicable]) -> Vec<Option<usize>> {
    let mut found = vec![None; path.len()];
    let mut open: FxHashMap<crate::ir::task::ConstId, Vec<usize>> = FxHashMap::default();
    for (k, action) in path.iter().enumerate() {
        match task.schemas[action.schema].snap {
            Snap::Start => {
                let Task { schemas, consts, .. } = task;
                if let Some(running) = successors::running_instance(&schemas[action.schema], consts, &action.bindings) {
                    open.entry(running).or_default().push(k);
                }
            }
            Snap::End => {
                if let Some(starts) = action.ends.and_then(|r| open.get_mut(&r))
                    && !starts.is_empty()
                {
                    found[starts.remove(0)] = Some(k);
                }
            }
            Snap::Instant => {}
        }
    }
    found
}

/// For each schema, the schemas of the same snap whose names have its functor and arity (the
/// clauses of one action).
fn families(task: &Task) -> Vec<Vec<usize>> {
    let key = |i: usize| {
        let schema = &task.schemas[i];
        let functor = match &schema.name {
            Pattern::Compound(f, args) => Some((*f, args.len())),
            Pattern::Const(_) | Pattern::Var(_) => None,
        };
        (schema.snap, functor, schema.base)
    };
    (0..task.schemas.len()).map(|i| (0..task.schemas.len()).filter(|&j| key(j) == key(i)).collect()).collect()
}

struct Rewriter<'s, 'p> {
    successors: &'s mut Successors<'p>,
    /// The name of each step of the original plan.
    names: Vec<Term>,
    /// For each start of the original plan, the index of its end.
    end_index: Vec<Option<usize>>,
    /// For each end of the original plan, the index of its start (`end_index` inverted).
    start_index: Vec<Option<usize>>,
    families: Vec<Vec<usize>>,
    scratch: Vec<Applicable>,
}

impl<'s, 'p> Rewriter<'s, 'p> {
    /// A rewriter of `plan`, with its steps as applicable actions; `Failure::Plan` when the
    /// search's semantics do not accept it.
    fn for_plan(
        successors: &'s mut Successors<'p>,
        task: &mut Task,
        plan: &Plan,
    ) -> Result<(Self, Vec<Applicable>), Failure> {
        let path = path_of(task, plan);
        if path.len() != plan.steps.len() {
            return Err(Failure::Plan);
        }
        let end_index = end_index(task, &path);
        let mut start_index = vec![None; path.len()];
        for (start, end) in end_index.iter().enumerate() {
            if let Some(end) = *end {
                start_index[end] = Some(start);
            }
        }
        let rewriter = Rewriter {
            successors,
            names: path.iter().map(|a| successors::action_name(task, a)).collect(),
            end_index,
            start_index,
            families: families(task),
            scratch: Vec::new(),
        };
        Ok((rewriter, path))
    }

    fn applicable(&mut self, task: &mut Task, state: &State, action: &Applicable) -> bool {
        self.successors.applies(task, action, state) == Ok(true)
    }

    /// The applicable actions of `schema`'s family in `state` whose names satisfy `keep`.
    fn family(
        &mut self,
        task: &mut Task,
        schema: usize,
        state: &State,
        keep: impl Fn(&Term) -> bool,
    ) -> Vec<Applicable> {
        let mut found = Vec::new();
        for member in self.families[schema].clone() {
            self.scratch.clear();
            if self.successors.schema(task, member, state, &mut self.scratch).is_err() {
                continue;
            }
            found.extend(self.scratch.drain(..).filter(|a| keep(&successors::action_name(task, a))));
        }
        found
    }

    /// The applicable action of step `k`'s family named as step `k` is.
    fn same(&mut self, task: &mut Task, path: &[Applicable], k: usize, state: &State) -> Option<Applicable> {
        let name = self.names[k].clone();
        self.named(task, path[k].schema, state, &name)
    }

    /// The applicable action of `schema`'s family named `name` (whatever its values outside
    /// its name).
    fn named(&mut self, task: &mut Task, schema: usize, state: &State, name: &Term) -> Option<Applicable> {
        // Every applicable action has a ground name.
        let wanted = task.consts.from_term(name)?;
        for member in self.families[schema].clone() {
            self.scratch.clear();
            if self.successors.named(task, member, state, wanted, &mut self.scratch).is_err() {
                continue;
            }
            if let Some(found) = self.scratch.drain(..).find(|a| successors::action_name(task, a) == *name) {
                return Some(found);
            }
        }
        None
    }

    /// The applicable action of `step`'s family named as `step` is, in `state`.
    fn named_as(&mut self, task: &mut Task, state: &State, step: &Applicable) -> Option<Applicable> {
        let name = successors::action_name(task, step);
        self.named(task, step.schema, state, &name)
    }

    /// The end of the running start `start` applicable in `state`, in the family of `end`.
    fn end_of(&mut self, task: &mut Task, start: &Applicable, end: &Applicable, state: &State) -> Option<Applicable> {
        let Task { schemas, consts, .. } = task;
        let running = successors::running_instance(&schemas[start.schema], consts, &start.bindings)?;
        for member in self.families[end.schema].clone() {
            self.scratch.clear();
            if self.successors.ending(task, member, state, running, &mut self.scratch).is_ok()
                && let Some(found) = self.scratch.first()
            {
                return Some(found.clone());
            }
        }
        None
    }

    /// The first part of detour `h` in `state`: the start with other chosen values, its end
    /// and the job's tail, and the state after them; `None` when no alternative works.
    fn aside(
        &mut self,
        task: &mut Task,
        path: &[Applicable],
        h: &Held,
        state: &State,
        cost: &mut dyn FnMut(usize, &Term) -> i64,
    ) -> Option<(Vec<Applicable>, State, Vec<Term>)> {
        let start = &path[h.start];
        let positions = chosen_positions(task, start.schema);
        if positions.is_empty() {
            return None;
        }
        let old = self.chosen_values(task, path, h.start);
        // The chosen values other steps of this family take while this one would be aside
        // (starts between the held start and its end, and starts running across the start).
        let taken: Vec<Vec<Term>> = (0..self.names.len())
            .filter(|&k| k != h.start && self.families[start.schema].contains(&path[k].schema))
            .filter(|&k| k < h.end && (k > h.start || self.end_index[k].is_some_and(|e| e > h.start)))
            .map(|k| positions.iter().map(|&p| self.names[k].args()[p].clone()).collect())
            .collect();
        let ranked = self.alternatives(
            task,
            path,
            h.start,
            state,
            |v, _| (*v != old[..] && !taken.iter().any(|t| t == v)).then_some(0),
            cost,
        );
        let end = &path[h.end];
        for (_, alternative, values) in ranked {
            let mut next = successors::apply(task, state, &alternative);
            let Some(finish) = self.end_of(task, &alternative, end, &next) else { continue };
            next = successors::apply(task, &next, &finish);
            let mut steps = vec![alternative, finish];
            if self.again(task, path, &h.tail, &mut next, &mut steps) {
                return Some((steps, next, values));
            }
        }
        None
    }

    /// The start `leaves` that leaves relocatable start `k`'s place, for costing places.
    fn onward(&self, task: &Task, path: &[Applicable], (k, leaves): (usize, usize)) -> Onward {
        Onward {
            old: self.chosen_values(task, path, k),
            to: self.chosen_values(task, path, leaves),
            action: task.schemas[path[leaves].schema].action,
            name: self.names[leaves].clone(),
        }
    }

    /// The chosen values of step `k` (at [`chosen_positions`]).
    fn chosen_values(&self, task: &Task, path: &[Applicable], k: usize) -> Vec<Term> {
        let name = self.names[k].args();
        chosen_positions(task, path[k].schema).iter().map(|&p| name[p].clone()).collect()
    }

    /// Whether starts `first` and `second` are in two different jobs, each its job's only step
    /// between the start and its end.
    fn in_two_jobs(&self, jobs: &crate::passes::reassign::Jobs, first: usize, second: usize) -> bool {
        let alone = |start: usize| -> Option<usize> {
            let end = self.end_index[start]?;
            let job = jobs.job_of(start)?;
            (jobs.job_of(end) == Some(job) && !jobs.job(job).iter().any(|&k| k > start && k < end)).then_some(job)
        };
        alone(first).zip(alone(second)).is_some_and(|(j1, j2)| j1 != j2)
    }

    /// Start `second`'s name with start `first`'s source where it names the place `first`
    /// took the thing to (the values `first`'s name holds at the positions where `second`'s
    /// holds `first`'s chosen values in a row, outside the chosen positions of either), and
    /// that source; `None` when `second` names no such place or the source is the place.
    fn shortened_name(
        &self,
        task: &Task,
        path: &[Applicable],
        first: usize,
        second: usize,
    ) -> Option<(Term, Vec<Term>)> {
        let old = self.chosen_values(task, path, first);
        if old.is_empty() {
            return None;
        }
        let own = chosen_positions(task, path[second].schema);
        let at = place_windows(self.names[second].args(), &old, &own).next()?;
        let window = at..at + old.len();
        let first_own = chosen_positions(task, path[first].schema);
        if window.clone().any(|q| first_own.contains(&q)) {
            return None;
        }
        let source = self.names[first].args().get(window.clone())?.to_vec();
        if source == old {
            return None;
        }
        let (functor, _) = self.names[second].callable()?;
        let mut args = self.names[second].args().to_vec();
        args[window].clone_from_slice(&source);
        Some((Term::Compound(functor, args.into()), source))
    }

    /// The applicable instances of start `k`'s action in `state` named as it is but at its
    /// chosen positions, whose chosen values `keep` accepts (it answers what they cost
    /// beyond the least duration, with `cost` at hand), with those values: at most
    /// [`ALTERNATIVES`], cheapest first by `cost` plus that (the plan's own values first
    /// among equals, then in the order found).
    fn alternatives(
        &mut self,
        task: &mut Task,
        path: &[Applicable],
        k: usize,
        state: &State,
        keep: impl Fn(&[Term], &mut dyn FnMut(usize, &Term) -> i64) -> Option<i64>,
        cost: &mut dyn FnMut(usize, &Term) -> i64,
    ) -> Vec<(i64, Applicable, Vec<Term>)> {
        let schema = path[k].schema;
        let positions = chosen_positions(task, schema);
        let wanted = self.names[k].args().to_vec();
        let old: Vec<Term> = positions.iter().map(|&p| wanted[p].clone()).collect();
        let instances = self.family(task, schema, state, |name| {
            let a = name.args();
            a.len() == wanted.len() && (0..a.len()).all(|p| positions.contains(&p) || a[p] == wanted[p])
        });
        let mut ranked: Vec<(i64, bool, usize, Applicable, Vec<Term>)> = instances
            .into_iter()
            .enumerate()
            .filter_map(|(i, a)| {
                let name = successors::action_name(task, &a);
                let values: Vec<Term> = positions.iter().map(|&p| name.args()[p].clone()).collect();
                let extra = keep(&values, cost)?;
                let cost = cost(task.schemas[a.schema].action, &name).saturating_add(extra);
                Some((cost, values != old, i, a, values))
            })
            .collect();
        ranked.sort_by_key(|(c, other, i, _, _)| (*c, *other, *i));
        ranked.into_iter().take(ALTERNATIVES).map(|(cost, _, _, a, values)| (cost, a, values)).collect()
    }

    /// Takes the plan's steps `ks` again from `state`, each the applicable action named as
    /// it is, onto `steps`; false when one does not apply.
    fn again(
        &mut self,
        task: &mut Task,
        path: &[Applicable],
        ks: &[usize],
        state: &mut State,
        steps: &mut Vec<Applicable>,
    ) -> bool {
        for &k in ks {
            let Some(step) = self.same(task, path, k, state) else { return false };
            *state = successors::apply(task, state, &step);
            steps.push(step);
        }
        true
    }

    /// The second part of detour `h` in `state`, at the original end's place: the job's head
    /// again, the start with its original chosen values, and its end.
    fn back(
        &mut self,
        task: &mut Task,
        path: &[Applicable],
        h: &Held,
        state: &State,
    ) -> Option<(Vec<Applicable>, State)> {
        let mut next = state.clone();
        let mut steps = Vec::new();
        if !self.again(task, path, &h.head, &mut next, &mut steps) {
            return None;
        }
        let start = &path[h.start];
        let positions = chosen_positions(task, start.schema);
        let wanted = self.names[h.start].args().to_vec();
        let candidates = self.family(task, start.schema, &next, |name| {
            let a = name.args();
            a.len() == wanted.len() && positions.iter().all(|&p| a[p] == wanted[p])
        });
        // The most positions alike, the first found among equals.
        let (_, again) = candidates.into_iter().enumerate().max_by_key(|(i, a)| {
            let name = successors::action_name(task, a);
            (name.args().iter().zip(&wanted).filter(|(x, y)| x == y).count(), std::cmp::Reverse(*i))
        })?;
        next = successors::apply(task, &next, &again);
        let finish = self.end_of(task, &again, &path[h.end], &next)?;
        next = successors::apply(task, &next, &finish);
        steps.push(again);
        steps.push(finish);
        Some((steps, next))
    }
}

/// The argument positions of schema `index`'s name that hold a variable neither chosen nor
/// a unit of a resource (what a move moves, and from where).
fn unit_free_positions(task: &Task, index: usize) -> Vec<usize> {
    let schema = &task.schemas[index];
    let chosen = schema.chosen_vars();
    match &schema.name {
        Pattern::Compound(_, args) => (0..args.len())
            .filter(
                |&p| matches!(args[p], Pattern::Var(v) if !chosen.contains(&v) && !schema.resource_vars.contains(&v)),
            )
            .collect(),
        Pattern::Const(_) | Pattern::Var(_) => Vec::new(),
    }
}

/// The argument positions of schema `index`'s name that are its chosen variables.
fn chosen_positions(task: &Task, index: usize) -> Vec<usize> {
    let schema = &task.schemas[index];
    let chosen = schema.chosen_vars();
    match &schema.name {
        Pattern::Compound(_, args) => {
            (0..args.len()).filter(|&p| matches!(args[p], Pattern::Var(v) if chosen.contains(&v))).collect()
        }
        Pattern::Const(_) | Pattern::Var(_) => Vec::new(),
    }
}
