//! The temporal passes: achievers and the partial order, the STN with durations, consistency
//! and the schedule; and `reassign`, which keeps a rearranged plan when its schedule is shorter.

use crate::diag::{Diagnostic, Diagnostics};
use crate::intern::Interner;
use crate::ir::hir::{self, Kb};
use crate::passes::reassign::Rules;
use crate::planner::detour::Placing;

/// What the temporal passes produced for one plan.
#[derive(Clone)]
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

/// How many variants of its urgent rules ([`Rules::WithVariants`]) [`reassign`] simulates
/// besides the fixed rules when it first rearranges a plan. Measured on the ladder (`kbc
/// bench --search heuristic`, seeds 1/2/3, with [`polish`]) against none: the sums of
/// makespans 2332/2257/2357 -> 2312/2241/2329 (2310/2235/2326 with [`BOTH_WAYS_STEPS`]).
const REASSIGN_VARIANTS: u64 = 8;

/// How many times [`polish`] rearranges a finished plan, at most.
const POLISH_ROUNDS: usize = 4;

/// How many variants ([`Rules::Variants`]) [`polish`] simulates each time.
const POLISH_VARIANTS: u64 = 8;

/// How many times [`reassign`] rearranges a plan with detours (or merges, shortcuts, actions
/// left out: [`keep_shorter`]) before it is compared with the plan without them. (One round
/// gave the same makespans as four on the ladder's 30 to 100 block rungs, in three quarters
/// of the time, before the backward rules of `passes::reassign`; with them a second round
/// gains: `kbc bench --search heuristic`, seeds 1/5, makespans summed 2193/2210 ->
/// 2160/2186, 22 rungs shorter and 4 longer, in 8% more time; swap_b100_a8_s1 228 -> 208.)
const DETOUR_REASSIGN_ROUNDS: usize = 2;

/// How many times [`reassign`] rearranges a plan with relocations before it is compared with
/// the plan without them. (Two, as for the detours, gained less for more time: seeds 1/5
/// 2193/2210 -> 2184/2206, 18 rungs shorter and 5 longer; both at two, 2157/2180 in 16-21%
/// more time than one.)
const RELOCATION_REASSIGN_ROUNDS: usize = 1;

/// How many times [`reassign`] sends held starts aside in a plan it has just improved.
const DETOUR_ROUNDS: usize = 4;

/// How many times [`reassign`] runs its detours, relocations and merges in turn, while a
/// cycle shortens the plan by more than one part in [`CYCLE_GAIN`]: each pass's changes give
/// the others new material (a merge leaves an arm waiting that a detour sends aside, a
/// detour leaves a block aside briefly that a merge takes straight on). Measured on the
/// ladder's seed 1 (`kbc bench --search heuristic`) against one cycle, before the reserving
/// rule of `passes::reassign`: reverse_b25 52 -> 49, swap_b10 27 -> 24, swap_b25 51 -> 50,
/// nothing longer; the sum of makespans 2654 -> 2647.
const CYCLES: usize = 3;

/// See [`CYCLES`].
const CYCLE_GAIN: i64 = 100;

/// The waits (in multiples of the job's own length) from which a held start is sent aside:
/// one candidate plan each.
const DETOUR_FACTORS: [i64; 3] = [1, 2, 4];

/// How many times a rewrite that fails drops the detour it blames and tries again.
const DETOUR_RETRIES: usize = 16;

/// What [`reassign`] may change besides who does each job.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Moves {
    /// Nothing: each job given to a unit again.
    Jobs,
    /// Also shortcuts ([`shortcuts`]), and nothing else.
    Shortcuts,
    /// Also where starts that leave a unit somewhere for a while leave it (relocations).
    Relocations,
    /// Also relocations and detours, once each, without merges.
    Detours,
    /// Also relocations, detours and merges: everything `kbc plan` does.
    All,
}

/// Runs the `reassign` pass on a scheduled plan (its fixed rules and [`REASSIGN_VARIANTS`]
/// variants) and keeps what it gains; then, as `moves` asks, relocates starts, sends held
/// starts aside and merges jobs ([`crate::planner::detour`]) where that shortens the plan
/// further.
///
/// Reassigning: each candidate, best estimate first, is checked step by step under the
/// search's semantics ([`crate::planner::is_solution`]) and scheduled by the temporal passes;
/// the first whose makespan is shorter replaces the plan, and the pass runs again on it, up
/// to [`REASSIGN_ROUNDS`] times.
///
/// Detours: a start whose end waits, beyond its minimum duration, longer than its job takes
/// without the wait (see [`held`]) holds a unit idle; the plan with every such start sent
/// aside (and those waiting two and four times as long, as two more candidates) is
/// rewritten, scheduled and reassigned, and the shortest replaces the plan when it is shorter
/// than the plan, up to [`DETOUR_ROUNDS`] times.
///
/// Merges ([`merges`]): two jobs that move one thing in a row (a block put aside and taken
/// on soon after) made one, the unit holding the thing in between; each set of merges whose
/// thing stays put at most a quarter, one or four times the first job's length is a candidate,
/// kept when shorter, up to [`MERGE_ROUNDS`] times.
///
/// Shortcuts ([`shortcuts`]): a thing put down on its way and taken on later by another job
/// stays where it was and goes straight on then; every shortcut the plan offers at once, kept
/// when shorter, up to [`SHORTCUT_ROUNDS`] times. Not on the way without the variants
/// ([`BOTH_WAYS_STEPS`]): the two ways then differ, and the shorter is kept.
///
/// Relocations ([`relocations`]) run before the detours and again after them, the merges
/// after those and the shortcuts last; detours, relocations, merges and shortcuts run again,
/// up to [`CYCLES`] times, while they gain; with `Moves::All`, a last relocation onto places being cleared
/// ([`relocations_onto_cleared`]) and a [`polish`]. Returns the plan and schedule kept (the
/// given ones when nothing was shorter).
///
/// A plan of at most [`BOTH_WAYS_STEPS`] steps, or of any size when `thorough` (while
/// improving), goes through all of this twice, the second time without the variants
/// ([`Rules::Fixed`], pass `fixed rules` in `-v`), and the shorter result is kept.
#[allow(clippy::too_many_arguments)]
pub(crate) fn reassign(
    kb: &Kb,
    interner: &Interner,
    program: &crate::engine::Program,
    task: &mut crate::ir::task::Task,
    (plan, timed): (crate::ir::plan::Plan, Timed),
    moves: Moves,
    thorough: bool,
    memo: &mut Memo,
) -> Rearranged {
    let both_ways = thorough || plan.steps.len() <= BOTH_WAYS_STEPS;
    let again = both_ways.then(|| (plan.clone(), timed.clone()));
    // One generator for every plan checked (both ways), so that OnKB goals are proven once.
    let engine = crate::engine::Machine::new(program, crate::planner::Budget::default().engine_steps);
    let successors = crate::planner::successors::Successors::new(task, engine);
    let mut cx = Rearranging { kb, interner, program, successors, task, memo };
    // The actions the plan can do without, left out first, before anything is rearranged.
    let (plan, timed, eliminated) = match moves {
        Moves::All => pass(&mut cx, ("eliminate", "actions left out", eliminations), (plan, timed)),
        _ => (plan, timed, 0),
    };
    let varied = reassign_with(&mut cx, (plan, timed), moves, Rules::WithVariants(REASSIGN_VARIANTS));
    let with_eliminated = |kept: Rearranged| Rearranged { changes: Changes { eliminated, ..kept.changes }, ..kept };
    let Some((plan, timed)) = again else { return with_eliminated(varied) };
    let before = varied.timed.schedule.makespan;
    let fixed = super::timing::time(
        "fixed rules",
        || reassign_with(&mut cx, (plan, timed), moves, Rules::Fixed),
        |fixed| change(before, before.min(fixed.timed.schedule.makespan)),
    );
    let kept = if fixed.timed.schedule.makespan < varied.timed.schedule.makespan { fixed } else { varied };
    with_eliminated(kept)
}

/// Plans of at most so many steps [`reassign`] rearranges both with and without the variants
/// of [`REASSIGN_VARIANTS`]: the variants change the path the later passes take, on some
/// plans for the worse (on the ladder, 11 of 156 rungs were longer with them alone; on a
/// random 40-block problem, 79 -> 89). Larger plans are not, for time: with 1200 (every
/// ladder rung both ways), the sums of makespans over seeds 1/2/3 went 2300/2231/2322 ->
/// 2299/2220/2318 (build_b100_a10_s2 137 -> 129, none longer), but the nine rungs it
/// shortened took 1.3-1.65 times as long, some longer than before the speed-ups of the same
/// session (swap_b75_a10_s1: 0.84 s at cd2accf, 1.11 s so). While improving, where the time
/// is the user's, every plan goes both ways (`kbc bench --improve 1`, seeds 1/2: makespans
/// summed 2260/2199 -> 2253/2192, within 1.15x of the bound 39/37 -> 40/38; swap_b100_a8_s1
/// 222 -> 216, build_b100_a10_s2 135 -> 128; swap_b75_a10_s2 95 -> 96, its restarts
/// fewer in the time; the slowest rung 2.18/2.25 -> 2.08/2.55 s).
const BOTH_WAYS_STEPS: usize = 400;

/// [`reassign`] once, with `first` the rules of the first rearrangement.
fn reassign_with(
    cx: &mut Rearranging<'_, '_>,
    (plan, timed): (crate::ir::plan::Plan, Timed),
    moves: Moves,
    first: Rules,
) -> Rearranged {
    let (plan, timed, _) = Memo::run(cx, ("reassign", Some(first)), (plan, timed), |cx, (plan, timed)| {
        let before = timed.schedule.makespan;
        let (plan, timed) = super::timing::time(
            "reassign",
            || rearrange(cx, (plan, timed), REASSIGN_ROUNDS, first),
            |(_, timed)| change(before, timed.schedule.makespan),
        );
        (plan, timed, 0)
    });
    if moves == Moves::Jobs {
        return Rearranged { plan, timed, changes: Changes::default() };
    }
    if moves == Moves::Shortcuts {
        let (plan, timed, cut) = pass(cx, ("shortcut", "shortcuts taken", shortcuts), (plan, timed));
        return Rearranged { plan, timed, changes: Changes { shortcuts: cut, ..Changes::default() } };
    }
    // Relocating before the detours gives them shorter moves to work from; after them, the
    // places they chose are relocated in turn.
    let relocation = ("relocate", "starts relocated", relocations as Step);
    let (plan, timed, relocated) = pass(cx, relocation, (plan, timed));
    if moves == Moves::Relocations {
        return Rearranged { plan, timed, changes: Changes { relocated, ..Changes::default() } };
    }
    let (mut plan, mut timed) = (plan, timed);
    let mut changes = Changes { relocated, ..Changes::default() };
    for _ in 0..CYCLES {
        let start = timed.schedule.makespan;
        let (aside, again, joined, taken);
        (plan, timed, aside) = pass(cx, ("detour", "starts sent aside", detours), (plan, timed));
        changes.detours += aside;
        (plan, timed, again) = pass(cx, relocation, (plan, timed));
        changes.relocated += again;
        if moves == Moves::Detours {
            break;
        }
        (plan, timed, joined) = pass(cx, ("merge", "jobs merged", merges), (plan, timed));
        changes.merged += joined;
        // (Only one way: a shortcut kept early can leave the later passes less to do, and
        // the way without them keeps their path. Measured with shortcuts both ways:
        // build_b50_a8_s3 60 -> 66, where `cleared` found nothing after them.)
        if first != Rules::Fixed {
            (plan, timed, taken) = pass(cx, ("shortcut", "shortcuts taken", shortcuts), (plan, timed));
            changes.shortcuts += taken;
        }
        if start - timed.schedule.makespan <= start / CYCLE_GAIN {
            break;
        }
    }
    if moves == Moves::All {
        let cleared = ("cleared", "starts relocated onto places being cleared", relocations_onto_cleared as Step);
        let again;
        (plan, timed, again) = pass(cx, cleared, (plan, timed));
        changes.relocated += again;
        (plan, timed, _) = pass(cx, ("polish", "rounds kept", polish), (plan, timed));
    }
    Rearranged { plan, timed, changes }
}

/// A pass's makespan before and after, for `-v`.
fn change(from: i64, to: i64) -> String {
    format!("makespan {} -> {}", crate::ir::stn::format_time(from), crate::ir::stn::format_time(to))
}

/// How [`reassign`] moves a plan on: the plan and schedule to the ones kept and how many
/// changes they made ([`relocations`], [`detours`], [`merges`]).
type Step = fn(&mut Rearranging<'_, '_>, (crate::ir::plan::Plan, Timed)) -> (crate::ir::plan::Plan, Timed, usize);

/// What the rearranging passes of [`reassign`] made of the plans they were given, by pass:
/// they are deterministic, so given a plan again a pass would make the same of it, and it is
/// not run again. A plan goes through the same passes more than once: `reassign` runs them
/// with and without the variants of its rules ([`BOTH_WAYS_STEPS`]) and the two ways often
/// meet (whenever the first reassigning keeps the plan), the second search often finds the
/// first one's plan, and a pass that left a plan as it was meets it again in the next cycle.
/// Measured on swap_b05_a3_s1 (`kbc plan --schedule`): 40 passes run, on 20 distinct plans.
/// One memo serves a [`crate::session::Session`]'s whole `plan` (scorer, both searches,
/// restarts); it keeps at most [`MEMO_STEPS`] steps of plans, the oldest forgotten first.
#[derive(Default)]
pub(crate) struct Memo {
    entries: std::collections::VecDeque<Remembered>,
    /// The steps of the plans held (given and made).
    steps: usize,
}

/// One result in a [`Memo`].
struct Remembered {
    /// The pass (its name in `-v`) and, for the first reassigning, its rules.
    pass: (&'static str, Option<Rules>),
    /// The separation of the schedules (the passes schedule with it).
    epsilon: i64,
    given: crate::ir::plan::Plan,
    /// The plan the pass made of it (`None`: the plan given) and how many changes it made.
    /// (Not its schedule: the plan is scheduled again on a hit, which costs less than keeping
    /// every schedule: cloning them cost `kbc plan` of reverse_b08_a3_s1 2% more instructions,
    /// 797 -> 815 M under callgrind.)
    made: (Option<crate::ir::plan::Plan>, usize),
}

impl Remembered {
    /// The steps of the plans it holds, given and made.
    fn steps(&self) -> usize {
        self.given.steps.len() + self.made.0.as_ref().map_or(0, |p| p.steps.len())
    }
}

/// How many plan steps a [`Memo`] holds at most (about 30 results on a 100-block problem:
/// its plans have 600-800 steps).
const MEMO_STEPS: usize = 25_000;

impl Memo {
    fn remember(&mut self, remembered: Remembered) {
        self.steps += remembered.steps();
        self.entries.push_back(remembered);
        while self.steps > MEMO_STEPS && self.entries.len() > 1 {
            let Some(old) = self.entries.pop_front() else { break };
            self.steps -= old.steps();
        }
    }

    /// `step` on a plan as pass `pass`, or what it made of that plan before.
    fn run(
        cx: &mut Rearranging<'_, '_>,
        pass: (&'static str, Option<Rules>),
        (plan, timed): (crate::ir::plan::Plan, Timed),
        step: impl FnOnce(&mut Rearranging<'_, '_>, (crate::ir::plan::Plan, Timed)) -> (crate::ir::plan::Plan, Timed, usize),
    ) -> (crate::ir::plan::Plan, Timed, usize) {
        let epsilon = timed.stn.epsilon;
        let seen = cx.memo.entries.iter().find(|r| r.pass == pass && r.epsilon == epsilon && r.given == plan);
        match seen.map(|r| r.made.clone()) {
            Some((None, count)) => return (plan, timed, count),
            Some((Some(made), count)) => {
                let mut diags = Diagnostics::new();
                if let Some(timed) = schedule(cx.kb, cx.interner, cx.program, &made, None, epsilon, &mut diags) {
                    return (made, timed, count);
                }
            }
            None => {}
        }
        let given = plan.clone();
        let (made, timed, count) = step(cx, (plan, timed));
        let kept = (made != given).then(|| made.clone());
        cx.memo.remember(Remembered { pass, epsilon, given, made: (kept, count) });
        (made, timed, count)
    }
}

/// A step of [`reassign`] as a pass of its own in `-v`'s list, named `name`, its line saying
/// the makespan before and after and how many changes it made (`what`: "starts relocated");
/// not run on a plan the memo has its result for.
fn pass(
    cx: &mut Rearranging<'_, '_>,
    (name, what, step): (&'static str, &str, Step),
    planned: (crate::ir::plan::Plan, Timed),
) -> (crate::ir::plan::Plan, Timed, usize) {
    Memo::run(cx, (name, None), planned, |cx, (plan, timed)| {
        let before = timed.schedule.makespan;
        super::timing::time(
            name,
            || step(cx, (plan, timed)),
            |(_, timed, made)| format!("{}, {made} {what}", change(before, timed.schedule.makespan)),
        )
    })
}

/// What [`reassign`] kept.
pub(crate) struct Rearranged {
    /// The plan.
    pub plan: crate::ir::plan::Plan,
    /// Its schedule.
    pub timed: Timed,
    /// What the passes changed to get there.
    pub changes: Changes,
}

/// What [`reassign`]'s passes changed in the plan it kept, for the schedule's header.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Changes {
    /// How many actions it left out ([`crate::planner::detour::eliminate`]).
    pub eliminated: usize,
    /// How many held starts it sent aside.
    pub detours: usize,
    /// How many starts it sent somewhere cheaper ([`crate::planner::detour::relocate`]).
    pub relocated: usize,
    /// How many pairs of jobs it made one ([`crate::planner::detour::merge`]).
    pub merged: usize,
    /// How many stops on the way it left out ([`crate::planner::detour::shortcut`]).
    pub shortcuts: usize,
}

/// What [`rearrange`], [`relocations`] and [`detours`] work with: the KB, its names, the
/// problem's program, one generator of applicable actions for every plan checked (OnKB goals
/// proven once), the task and what the passes made of the plans they were given before.
struct Rearranging<'a, 'p> {
    kb: &'a Kb,
    interner: &'a Interner,
    program: &'p crate::engine::Program,
    successors: crate::planner::successors::Successors<'p>,
    task: &'a mut crate::ir::task::Task,
    memo: &'a mut Memo,
}

/// The reassigning rounds of [`reassign`], at most `rounds`.
fn rearrange(
    cx: &mut Rearranging<'_, '_>,
    (mut plan, mut timed): (crate::ir::plan::Plan, Timed),
    rounds: usize,
    rules: Rules,
) -> (crate::ir::plan::Plan, Timed) {
    let kb = cx.kb;
    for _ in 0..rounds {
        let candidates = crate::passes::reassign::candidates(kb, &plan, &timed.pop, &timed.stn, rules);
        let mut improved = None;
        for candidate in candidates.iter() {
            if candidate.estimate >= timed.schedule.makespan {
                continue;
            }
            let rearranged = candidate.plan();
            if let Some(scheduled) = checked(cx, &rearranged, timed.stn.epsilon)
                && scheduled.schedule.makespan < timed.schedule.makespan
            {
                improved = Some((rearranged, scheduled));
                break;
            }
        }
        let Some(found) = improved else { break };
        (plan, timed) = found;
    }
    (plan, timed)
}

/// The schedule of a candidate plan of [`rearrange`] or [`polish`], if the search's semantics
/// accept it step by step ([`crate::planner::is_solution`]).
fn checked(cx: &mut Rearranging<'_, '_>, plan: &crate::ir::plan::Plan, epsilon: i64) -> Option<Timed> {
    if !crate::planner::is_solution_with(&mut cx.successors, cx.task, plan) {
        return None;
    }
    schedule(cx.kb, cx.interner, cx.program, plan, None, epsilon, &mut Diagnostics::new())
}

/// The last pass of [`reassign`] with `Moves::All`: the finished plan rearranged by variants
/// of the urgent rules ([`Rules::Variants`]), all of them scheduled and the shortest kept if
/// shorter than the plan, while that gains, up to [`POLISH_ROUNDS`] times. Unlike
/// [`rearrange`], which takes the first candidate with a shorter schedule in the order of
/// their estimates, every candidate whose estimate is less than one part in [`POLISH_SLACK`]
/// above the plan's makespan is scheduled: the estimate is the simulation's, not the STN's,
/// and the variants differ by little. With how many rounds kept a plan.
fn polish(
    cx: &mut Rearranging<'_, '_>,
    (mut plan, mut timed): (crate::ir::plan::Plan, Timed),
) -> (crate::ir::plan::Plan, Timed, usize) {
    let kb = cx.kb;
    let mut kept = 0;
    for _ in 0..POLISH_ROUNDS {
        let makespan = timed.schedule.makespan;
        let mut best: Option<(crate::ir::plan::Plan, Timed)> = None;
        let candidates =
            crate::passes::reassign::candidates(kb, &plan, &timed.pop, &timed.stn, Rules::Variants(POLISH_VARIANTS));
        for candidate in candidates.iter() {
            if candidate.estimate >= makespan + makespan / POLISH_SLACK {
                continue;
            }
            let shortest = best.as_ref().map_or(makespan, |(_, t)| t.schedule.makespan);
            let rearranged = candidate.plan();
            if let Some(scheduled) = checked(cx, &rearranged, timed.stn.epsilon)
                && scheduled.schedule.makespan < shortest
            {
                best = Some((rearranged, scheduled));
            }
        }
        let Some(found) = best else { break };
        (plan, timed) = found;
        kept += 1;
    }
    (plan, timed, kept)
}

/// How far above the plan's makespan (less than one part in so many) the estimate of a
/// candidate [`polish`] schedules may be.
const POLISH_SLACK: i64 = 20;

/// The detour rounds of [`reassign`], with how many starts the plans kept sent aside.
fn detours(
    cx: &mut Rearranging<'_, '_>,
    (plan, timed): (crate::ir::plan::Plan, Timed),
) -> (crate::ir::plan::Plan, Timed, usize) {
    use crate::planner::detour;
    let (kb, program) = (cx.kb, cx.program);
    let mut cost = least_duration(kb, program);
    rounds(cx, (plan, timed), DETOUR_ROUNDS, |cx, plan, timed, best| {
        let waiting = held(kb, plan, timed);
        let mut tried: Vec<Vec<detour::Held>> = Vec::new();
        // The starts sent aside by each rewrite made.
        let mut taken: Vec<Vec<usize>> = Vec::new();
        for factor in DETOUR_FACTORS {
            let mut set: Vec<detour::Held> = waiting
                .iter()
                .filter(|(wait, length, _)| *wait > factor * *length)
                .map(|(_, _, h)| h.clone())
                .collect();
            if set.is_empty() || tried.contains(&set) {
                continue;
            }
            tried.push(set.clone());
            let rewritten = retried(cx, &mut set, |cx, set| {
                let found = detour::rewrite(&mut cx.successors, cx.task, plan, set, &mut cost)?;
                // (The same detours as a candidate tried already: the same plan.)
                let starts: Vec<usize> = found.taken.iter().map(|&d| set[d].start).collect();
                if starts.is_empty() || taken.contains(&starts) {
                    return Ok(None);
                }
                let count = starts.len();
                taken.push(starts);
                Ok(Some((found.plan, count)))
            });
            if let Some(rewritten) = rewritten {
                keep_shorter(cx, timed, rewritten, best, DETOUR_REASSIGN_ROUNDS);
            }
        }
    })
}

/// Up to `count` rounds of `round`, which offers plans rewritten from the plan it is given to
/// [`keep_shorter`] (with the schedule it is given and the best so far): the shortest offered
/// replaces the plan, and the rounds stop when none is shorter. With the sum of the changes the
/// plans kept made.
fn rounds(
    cx: &mut Rearranging<'_, '_>,
    (mut plan, mut timed): (crate::ir::plan::Plan, Timed),
    count: usize,
    mut round: impl FnMut(
        &mut Rearranging<'_, '_>,
        &crate::ir::plan::Plan,
        &Timed,
        &mut Option<(crate::ir::plan::Plan, Timed, usize)>,
    ),
) -> (crate::ir::plan::Plan, Timed, usize) {
    let mut changes = 0;
    for _ in 0..count {
        let mut best = None;
        round(cx, &plan, &timed, &mut best);
        let Some((found, scheduled, made)) = best else { break };
        (plan, timed) = (found, scheduled);
        changes += made;
    }
    (plan, timed, changes)
}

/// `rewrite` of the changes `set`, each failure's blamed change dropped before trying again,
/// up to [`DETOUR_RETRIES`] times: the plan rewritten and how many changes it made (`None`:
/// no plan, or none worth trying).
fn retried<C>(
    cx: &mut Rearranging<'_, '_>,
    set: &mut Vec<C>,
    mut rewrite: impl FnMut(
        &mut Rearranging<'_, '_>,
        &[C],
    ) -> Result<Option<(crate::ir::plan::Plan, usize)>, crate::planner::detour::Failure>,
) -> Option<(crate::ir::plan::Plan, usize)> {
    use crate::planner::detour::Failure;
    for _ in 0..DETOUR_RETRIES {
        if set.is_empty() {
            return None;
        }
        match rewrite(cx, set) {
            Ok(found) => return found,
            Err(Failure::Detour(d)) => {
                set.remove(d);
            }
            Err(Failure::Plan) => return None,
        }
    }
    None
}

/// A rewritten plan (with how many changes it made), scheduled and reassigned (`rounds` at
/// most), kept in `best` when shorter than `best` (else than `timed`, the plan's).
fn keep_shorter(
    cx: &mut Rearranging<'_, '_>,
    timed: &Timed,
    (rewritten, count): (crate::ir::plan::Plan, usize),
    best: &mut Option<(crate::ir::plan::Plan, Timed, usize)>,
    rounds: usize,
) {
    let mut diags = Diagnostics::new();
    let Some(scheduled) = schedule(cx.kb, cx.interner, cx.program, &rewritten, None, timed.stn.epsilon, &mut diags)
    else {
        return;
    };
    let (rewritten, scheduled) = rearrange(cx, (rewritten, scheduled), rounds, Rules::Fixed);
    let shortest = best.as_ref().map_or(timed.schedule.makespan, |(_, t, _)| t.schedule.makespan);
    if scheduled.schedule.makespan < shortest {
        *best = Some((rewritten, scheduled, count));
    }
}

/// How many times [`reassign`] merges jobs in a plan it has just improved.
const MERGE_ROUNDS: usize = 4;

/// The longest stays, in quarters of the first job's length, of the merges tried together:
/// one candidate plan each ("the thing sat where the first job left it at most so long").
const MERGE_STAYS: [i64; 3] = [1, 4, 16];

/// The merging rounds of [`reassign`]: jobs that move one thing twice in a row made one
/// ([`crate::planner::detour::merge`]), those whose thing stays put briefly first; kept when
/// the rewritten plan, scheduled and reassigned, is shorter. With how many merges it kept.
fn merges(
    cx: &mut Rearranging<'_, '_>,
    (plan, timed): (crate::ir::plan::Plan, Timed),
) -> (crate::ir::plan::Plan, Timed, usize) {
    use crate::planner::detour;
    let kb = cx.kb;
    rounds(cx, (plan, timed), MERGE_ROUNDS, |cx, plan, timed, best| {
        let Some(jobs) = crate::passes::reassign::jobs(kb, plan) else { return };
        let Ok(offered) = detour::merges(&mut cx.successors, cx.task, plan, &jobs) else { return };
        let earliest = &timed.schedule.earliest;
        // (stay, first job's length, merge)
        let mut ranked: Vec<(i64, i64, detour::Merge)> = Vec::new();
        for merge in offered {
            let (Some(j1), Some(j2)) = (jobs.job_of(merge.first), jobs.job_of(merge.second)) else { continue };
            let (first, second) = (jobs.job(j1), jobs.job(j2));
            let (Some(&begin), Some(&end), Some(&next)) = (first.first(), first.last(), second.first()) else {
                continue;
            };
            let stay = earliest[next] - earliest[end];
            ranked.push((stay, (earliest[end] - earliest[begin]).max(1), merge));
        }
        ranked.sort_by_key(|(stay, _, m)| (*stay, m.first));
        let mut tried: Vec<Vec<detour::Merge>> = Vec::new();
        for quarters in MERGE_STAYS {
            // Merges that share no job, the briefest stays first.
            let brief = ranked.iter().filter(|(stay, length, _)| 4 * stay <= quarters.saturating_mul(*length));
            let mut set = sharing_no_job(&jobs, brief.map(|(_, _, merge)| *merge));
            if set.is_empty() || tried.contains(&set) {
                continue;
            }
            tried.push(set.clone());
            let rewritten = retried(cx, &mut set, |cx, set| {
                let found = detour::merge(&mut cx.successors, cx.task, plan, &jobs, set)?;
                let count = found.taken.len();
                Ok((count > 0).then_some((found.plan, count)))
            });
            if let Some(rewritten) = rewritten {
                keep_shorter(cx, timed, rewritten, best, DETOUR_REASSIGN_ROUNDS);
            }
        }
    })
}

/// Of `pairs` (merges or shortcuts), in their order, each that shares no job with one taken
/// before it.
fn sharing_no_job(
    jobs: &crate::passes::reassign::Jobs,
    pairs: impl IntoIterator<Item = crate::planner::detour::Merge>,
) -> Vec<crate::planner::detour::Merge> {
    let mut used: Vec<usize> = Vec::new();
    let mut set = Vec::new();
    for pair in pairs {
        let js = [jobs.job_of(pair.first), jobs.job_of(pair.second)];
        if js.iter().flatten().any(|j| used.contains(j)) {
            continue;
        }
        used.extend(js.iter().flatten());
        set.push(pair);
    }
    set
}

/// How many times [`reassign`] takes shortcuts in a plan it has just improved.
const SHORTCUT_ROUNDS: usize = 4;

/// The shortcut rounds of [`reassign`]: a thing put down on its way and taken on later by
/// another job is left where it was and taken straight on by that job instead
/// ([`crate::planner::detour::shortcut`]), all the shortcuts the plan offers at once (no two
/// sharing a job), those a replay blames dropped; kept when the rewritten plan, scheduled
/// and reassigned, is shorter. With how many shortcuts it kept.
fn shortcuts(
    cx: &mut Rearranging<'_, '_>,
    (plan, timed): (crate::ir::plan::Plan, Timed),
) -> (crate::ir::plan::Plan, Timed, usize) {
    use crate::planner::detour;
    let kb = cx.kb;
    rounds(cx, (plan, timed), SHORTCUT_ROUNDS, |cx, plan, timed, best| {
        let Some(jobs) = crate::passes::reassign::jobs(kb, plan) else { return };
        let Ok(offered) = detour::shortcuts(&mut cx.successors, cx.task, plan, &jobs) else { return };
        let mut set = sharing_no_job(&jobs, offered);
        let rewritten = retried(cx, &mut set, |cx, set| {
            let found = detour::shortcut(&mut cx.successors, cx.task, plan, &jobs, set)?;
            let count = found.taken.len();
            Ok((count > 0).then_some((found.plan, count)))
        });
        if let Some(rewritten) = rewritten {
            keep_shorter(cx, timed, rewritten, best, DETOUR_REASSIGN_ROUNDS);
        }
    })
}

/// The least duration (STN time) of the durative action of index `action` (in
/// `Kb::actions`) that a start named `name` begins; `i64::MAX` when the KB gives none.
fn least_duration<'p>(kb: &'p Kb, program: &'p crate::engine::Program) -> impl FnMut(usize, &hir::Term) -> i64 + 'p {
    let mut machine = crate::engine::Machine::new(program, crate::planner::Budget::default().engine_steps);
    move |action: usize, name: &hir::Term| -> i64 {
        let running = hir::Term::Compound(kb.actions[action].base, name.args().iter().cloned().collect());
        match crate::passes::stn::query_duration(&mut machine, &running) {
            Ok(Some((min, _))) => crate::passes::stn::to_stn_time(min).unwrap_or(i64::MAX),
            _ => i64::MAX,
        }
    }
}

/// How many steps [`eliminations`] replays at most, in all its trials (reverse_b100_a8_s1,
/// 1200 steps: 14,886 replayed, nothing left out; logistics_c5_t5_p2_k30, 1784 steps: 32,619,
/// 557 actions left out).
const ELIMINATION_BUDGET: usize = 400_000;

/// The eliminating step of [`reassign`]: the plan without the actions it can do without
/// ([`crate::planner::detour::eliminate`]), scheduled, kept when its makespan is no longer
/// (it does less work); with how many actions were left out.
fn eliminations(
    cx: &mut Rearranging<'_, '_>,
    (plan, timed): (crate::ir::plan::Plan, Timed),
) -> (crate::ir::plan::Plan, Timed, usize) {
    let found = crate::planner::detour::eliminate(&mut cx.successors, cx.task, &plan, ELIMINATION_BUDGET);
    let Some(found) = found.ok().filter(|found| !found.taken.is_empty()) else { return (plan, timed, 0) };
    let mut diags = Diagnostics::new();
    match schedule(cx.kb, cx.interner, cx.program, &found.plan, None, timed.stn.epsilon, &mut diags) {
        Some(scheduled) if scheduled.schedule.makespan <= timed.schedule.makespan => {
            (found.plan, scheduled, found.taken.len())
        }
        _ => (plan, timed, 0),
    }
}

/// The relocating step of [`reassign`]: the plan with its starts that leave a unit somewhere
/// for a while sent somewhere cheaper ([`crate::planner::detour::relocate`]), scheduled and
/// reassigned, kept when its schedule is shorter; with how many starts it relocated.
fn relocations(
    cx: &mut Rearranging<'_, '_>,
    planned: (crate::ir::plan::Plan, Timed),
) -> (crate::ir::plan::Plan, Timed, usize) {
    relocated(cx, planned, false)
}

/// [`relocations`] where a start may also be sent to a place still taken when it starts but
/// left before its end (the unit waits there, as a block in the air over a cell being
/// cleared). Run once, after the cycles of [`reassign`]: as their relocation pass, it made the
/// plans that followed longer as often as shorter (seeds 1-3 of the ladder, sums of makespans
/// 2355 -> 2387, 2283 -> 2303, 2376 -> 2392). Last, it shortens 29 of the 156 rungs and
/// lengthens none (2355 -> 2344, 2283 -> 2263, 2376 -> 2362; reverse_b03_a3_s3 14 -> 12, the
/// optimum `tests/optimum.rs` finds; reverse_b10_a4_s1 27 -> 24). On plans of at most
/// [`REGRET_STEPS`] steps it also relocates by regret and keeps the shorter result.
///
/// A third candidate holds back (`hold_back` of [`crate::planner::detour::relocate`]): in
/// plan order, onto places left later than the start's end in the plan's order, or taken from
/// the initial state. The search sends a block aside onto a free cell before the block on a
/// nearer one has started to leave it (build_b02_a3_s5: 10 units, its optimum 8). Measured on
/// the ladder (`kbc bench --search heuristic`, seeds 1/2/3, one run each): makespans summed
/// 2294/2228/2309 -> 2276/2221/2301, 24 rungs shorter (build_b100_a8_s1 180 -> 174,
/// reverse_b25_a6_s1 44 -> 42) and none longer, the time within this VM's noise (seed 1
/// 15.5 -> 15.1 s, run in turn); on the unseen seeds 4-8, 2201/2307/2263/2227/2244 ->
/// 2187/2302/2256/2222/2237, one rung longer (reverse_b30_a6_s6 47 -> 48). As the only
/// candidate with the schedule it made 7 rungs a unit or two longer (reverse_b10_a4_s3 28 ->
/// 30): the greedy replay takes the places held back where the plan's own order did better.
/// Holding back by regret too found nothing more.
fn relocations_onto_cleared(
    cx: &mut Rearranging<'_, '_>,
    planned: (crate::ir::plan::Plan, Timed),
) -> (crate::ir::plan::Plan, Timed, usize) {
    relocated(cx, planned, true)
}

/// [`relocations`], or with `onto_cleared` [`relocations_onto_cleared`]: the relocated plan
/// (each placing's, see [`REGRET_STEPS`]) rescheduled and reassigned, the shortest kept when
/// shorter than the plan.
fn relocated(
    cx: &mut Rearranging<'_, '_>,
    (plan, timed): (crate::ir::plan::Plan, Timed),
    onto_cleared: bool,
) -> (crate::ir::plan::Plan, Timed, usize) {
    let (kb, program) = (cx.kb, cx.program);
    let mut cost = least_duration(kb, program);
    let waits = waits(&plan, &timed);
    let times: &[i64] = match onto_cleared {
        true => &timed.schedule.earliest[..plan.steps.len().min(timed.schedule.earliest.len())],
        false => &[],
    };
    let placings: &[Placing] = match onto_cleared && plan.steps.len() <= REGRET_STEPS {
        true => &[Placing::InPlanOrder, Placing::ByRegret],
        false => &[Placing::InPlanOrder],
    };
    // Onto places being cleared, a third candidate: in plan order, holding back.
    let holding = onto_cleared.then_some((true, Placing::InPlanOrder));
    let mut best: Option<(crate::ir::plan::Plan, Timed, usize)> = None;
    // The candidates' plans so far: one that is the same plan again is not scheduled again.
    let mut seen: Vec<crate::ir::plan::Plan> = Vec::new();
    for (hold_back, placing) in placings.iter().map(|&placing| (false, placing)).chain(holding) {
        let found = crate::planner::detour::relocate(
            &mut cx.successors,
            cx.task,
            &plan,
            (&waits, times, hold_back),
            placing,
            &mut cost,
        );
        let Some(found) = found.ok().filter(|found| !found.taken.is_empty()) else { continue };
        if seen.contains(&found.plan) {
            continue;
        }
        seen.push(found.plan.clone());
        let count = found.taken.len();
        keep_shorter(cx, &timed, (found.plan, count), &mut best, RELOCATION_REASSIGN_ROUNDS);
    }
    best.unwrap_or((plan, timed, 0))
}

/// Plans of at most so many steps [`relocations_onto_cleared`] also relocates by regret
/// ([`Placing::ByRegret`]), and keeps the shorter of that and the relocation in plan order.
/// Measured on the ladder (`kbc bench --search heuristic`, seeds 1/2/3, one run each):
/// - instead of the plan order, in every relocation: as often longer as shorter (sums of
///   makespans 2304/2231/2323 -> 2285/2248/2337; build_b08_a3_s3 21 -> 19, reverse_b10_a4_s3
///   28 -> 30), and up to twice as slow on the largest rungs (reverse_b100_a8_s1 1.8 ->
///   4.8 s);
/// - besides it, in every relocation of plans up to this size: 13 rungs shorter by a unit or
///   two and none longer (2304/2231/2323 -> 2299/2225/2318), but a quarter more time on the
///   25- to 50-block rungs (swap_b25_a6_s1 0.8 -> 1.0 s), more than the gain is worth;
/// - besides it, in the last relocation alone (this): 3 rungs shorter (swap_b25_a6_s1 46 ->
///   43, reverse_b05_a3_s1 and build_b50_a8_s3 a unit), none longer (-> 2300/2231/2322), in
///   0.98 times the time (rungs over 0.3 s, run in turn with the build before).
const REGRET_STEPS: usize = 400;

/// For each step of `plan`, how long its end waits beyond its minimum duration in the
/// schedule when it is a start (else 0).
fn waits(plan: &crate::ir::plan::Plan, timed: &Timed) -> Vec<i64> {
    let earliest = &timed.schedule.earliest;
    let mut waits = vec![0; plan.steps.len()];
    for (end, step) in timed.pop.steps.iter().enumerate() {
        let Some(start) = step.start else { continue };
        let min = timed.stn.durations[start].map_or(0, |b| b.min);
        if let Some(wait) = waits.get_mut(start) {
            *wait = (earliest[end] - earliest[start] - min).max(0);
        }
    }
    waits
}

/// The starts of `plan` whose ends wait: for each job (see [`crate::passes::reassign::jobs`])
/// the start in it whose end comes latest after its minimum duration, with that wait and the
/// time the job takes without it, when the wait is positive.
fn held(kb: &Kb, plan: &crate::ir::plan::Plan, timed: &Timed) -> Vec<(i64, i64, crate::planner::detour::Held)> {
    let Some(jobs) = crate::passes::reassign::jobs(kb, plan) else { return Vec::new() };
    let earliest = &timed.schedule.earliest;
    let waits = waits(plan, timed);
    let mut found = Vec::new();
    for steps in jobs.steps() {
        let (Some(&first), Some(&last)) = (steps.first(), steps.last()) else { continue };
        let mut longest: Option<(i64, usize, usize)> = None;
        for &end in steps {
            let Some(start) = timed.pop.steps[end].start else { continue };
            if !steps.contains(&start) {
                continue;
            }
            let wait = waits[start];
            if wait > 0 && longest.is_none_or(|(w, _, _)| wait > w) {
                longest = Some((wait, start, end));
            }
        }
        let Some((wait, start, end)) = longest else { continue };
        let length = earliest[last] - earliest[first] - wait;
        let head = steps.iter().copied().filter(|&k| k < start).collect();
        let tail = steps.iter().copied().filter(|&k| k > end).collect();
        found.push((wait, length.max(1), crate::planner::detour::Held { start, end, head, tail }));
    }
    found
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
    /// The shortest so far: the plan scored and what `reassign` made of it (the first among
    /// equals, as the search keeps).
    pub(crate) best: Option<(crate::ir::plan::Plan, Rearranged)>,
    /// What the passes made of the plans given them so far.
    pub(crate) memo: Memo,
    /// The longest one scoring took (a restart's passes take about as long).
    pub(crate) longest: std::time::Duration,
}

impl<'a> ReassignedMakespan<'a> {
    /// A scorer for plans of the problem whose `program` is given, with nothing scored yet.
    pub fn new(kb: &'a Kb, interner: &'a Interner, program: &'a crate::engine::Program, epsilon: i64) -> Self {
        ReassignedMakespan {
            kb,
            interner,
            program,
            epsilon,
            best: None,
            memo: Memo::default(),
            longest: std::time::Duration::ZERO,
        }
    }
}

impl crate::planner::Score for ReassignedMakespan<'_> {
    fn score(&mut self, task: &mut crate::ir::task::Task, plan: &crate::ir::plan::Plan) -> Option<i64> {
        let begun = std::time::Instant::now();
        let timed = schedule(self.kb, self.interner, self.program, plan, None, self.epsilon, &mut Diagnostics::new())?;
        let (kb, interner, program) = (self.kb, self.interner, self.program);
        // (The scorer runs while improving: thorough.)
        let rearranged = reassign(kb, interner, program, task, (plan.clone(), timed), Moves::All, true, &mut self.memo);
        self.longest = self.longest.max(begun.elapsed());
        let makespan = rearranged.timed.schedule.makespan;
        if self.best.as_ref().is_none_or(|(_, best)| makespan < best.timed.schedule.makespan) {
            self.best = Some((plan.clone(), rearranged));
        }
        Some(makespan)
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
