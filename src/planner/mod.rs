//! The planner: finds a total-order plan of snap actions for one problem.
//!
//! Two searches share the lifted action semantics of [`successors`]:
//!
//! - [`paper`]: the paper's Algorithm 1, faithfully: depth-first in clause order, a depth
//!   limit, the path's states as a been-list, the first plan found;
//! - [`best_first`]: greedy best-first search guided by a delete-relaxation heuristic
//!   ([`relaxed`]), with duplicate detection and a cost that counts the plan's makespan.
//!
//! Every search runs under a [`Budget`] (states, time, memory) and reports [`Stats`]. The
//! planner does no IO; progress reports go through a callback the CLI supplies.

pub mod analysis;
pub mod best_first;
pub mod detour;
mod ground;
mod landmarks;
pub mod paper;
pub mod relaxed;
pub mod successors;
pub mod symmetry;
pub mod timing;

use std::time::{Duration, Instant};

use crate::diag::{Diagnostic, codes};
use crate::engine::{Machine, Program};
use crate::ir::hir::Kb;
use crate::ir::plan::{Plan, Step};
use crate::ir::task::Task;
use successors::{Applicable, ConditionError, Successors};

/// Which search to run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SearchKind {
    /// The paper's depth-first search.
    Paper,
    /// Greedy best-first search with a delete-relaxation heuristic.
    Heuristic,
}

/// When the heuristic search follows relaxed plans ahead (`best_first`'s lookahead).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Lookahead {
    /// On large problems: when the search's estimate of the initial state (landmarks plus
    /// h_FF) is at least [`Lookahead::AUTO_ESTIMATE`], or once the plain search has expanded
    /// [`Lookahead::AUTO_STATES`] states without a plan.
    #[default]
    Auto,
    /// Always.
    On,
    /// Never.
    Off,
}

impl Lookahead {
    /// The initial estimate from which [`Lookahead::Auto`] turns the lookahead on. Measured
    /// on the ladder: the 30-block rungs start at 270-336 and the 50-block ones at 453-560;
    /// below, the plain search is fast and finds shorter makespans on the reverse and grid
    /// rungs; above, it needs thousands of evaluations of a few milliseconds each, and the
    /// lookahead solves rungs it cannot in the ladder's 30 s (reverse_b50 in 3.3 s, swap_b75
    /// in 3.2 s, build_b100_a10 in 14.8 s).
    pub const AUTO_ESTIMATE: u32 = 400;

    /// The expansions after which [`Lookahead::Auto`] turns the lookahead on in a plain
    /// search that has found no plan yet. Measured on the ladder's 20-30 block reverse rungs,
    /// seeds 1-3 (the only rungs of up to 30 blocks whose plain search expands more than
    /// about 2000 states): their plain searches took 2000-7941 expansions and up to 4.6 s;
    /// turned on after 1000, 1020-2092 expansions and at most 1.2 s for the whole run
    /// (`kbc bench`), and with the second search the same sum of makespans (426) over the
    /// nine.
    pub const AUTO_STATES: u64 = 1000;

    /// Whether a plain search turns the lookahead on, after `expanded` expansions without a
    /// plan.
    pub fn switches_on(self, expanded: u64) -> bool {
        self == Lookahead::Auto && expanded >= Lookahead::AUTO_STATES
    }

    /// Whether the search follows relaxed plans, given its estimate of the initial state.
    pub fn wanted(self, initial_estimate: u32) -> bool {
        match self {
            Lookahead::Auto => initial_estimate >= Lookahead::AUTO_ESTIMATE,
            Lookahead::On => true,
            Lookahead::Off => false,
        }
    }
}

/// Limits on a search.
#[derive(Clone, Copy, Debug)]
pub struct Budget {
    /// The most states to expand.
    pub max_states: u64,
    /// When to give up.
    pub deadline: Option<Instant>,
    /// The most bytes of stored states.
    pub max_bytes: usize,
    /// The most resolution steps for one OnKB query.
    pub engine_steps: u64,
    /// The most relaxed rule instantiations the heuristic search grounds; beyond it the
    /// heuristic is evaluated lifted, state by state (slower, same estimates without Invalid
    /// conditions and landmarks).
    pub max_ground_actions: usize,
    /// The most values one exploration of the delete relaxation may add to the task's before
    /// the relaxation counts as endless ([`BudgetKind::Constants`]).
    pub max_new_constants: usize,
}

impl Default for Budget {
    fn default() -> Self {
        Budget {
            max_states: 1_000_000,
            deadline: None,
            max_bytes: 2 << 30,
            engine_steps: 1_000_000,
            max_ground_actions: 1_000_000,
            max_new_constants: relaxed::MAX_NEW_CONSTANTS,
        }
    }
}

/// What a search should do.
#[derive(Clone, Copy, Debug)]
pub struct Options {
    /// The search.
    pub search: SearchKind,
    /// The depth limit of the paper's search; the problem's `go/5` value or 25 when `None`.
    pub max_depth: Option<u32>,
    /// Limits.
    pub budget: Budget,
    /// How many different plans to find before stopping (at least one): the search goes on
    /// after the first, within its budget, and reports the others as alternatives (for the
    /// heuristic search, each with a shorter makespan than the one before).
    pub plans: usize,
    /// For the heuristic search: how long to go on improving the makespan after the first
    /// plan (within the budget).
    pub improve: Option<Duration>,
    /// For the heuristic search: how many expansions to go on improving the makespan after
    /// the first plan (with `improve`, whichever limit comes first). Unlike a time, the same
    /// on every run (`kbc plan --improve-states`).
    pub improve_states: Option<u64>,
    /// The least separation of two ordered snap actions, in STN time, for the heuristic
    /// search's timing of plan prefixes (the same as the temporal network's).
    pub epsilon: i64,
    /// For the heuristic search: expand one of each set of successors that differ only by
    /// interchangeable constants, such as idle arms ([`symmetry`]).
    pub symmetry: bool,
    /// For the heuristic search: at each state better than any before, follow its relaxed
    /// plan as far as it applies and add the state reached (`best_first`'s lookahead).
    pub lookahead: Lookahead,
    /// For the heuristic search: break the last ties between states of equal rank by a hash
    /// of this seed rather than by depth, and add the hash's lowest bit to each state's
    /// estimate (states one apart taken in a seeded order), for a different plan of about the
    /// same quality (`kbc plan --improve` restarts the search with other seeds). The ties
    /// alone gave too little variety: over the ladder's 108 build, reverse and swap rungs of
    /// up to 30 blocks (seeds 1-3), six seeds' best plans were within 1.15x of the lower
    /// bound on 82 rungs with the ties alone and on 88 with the estimate's bit too (makespans
    /// summed 2576.6 -> 2563.6; 19 rungs shorter, 5 longer). Adding 0 to 2 instead of 0 or
    /// 1 gave 86; the hash ranked before the makespan instead of after, 86.
    pub tie_seed: Option<u64>,
    /// For the heuristic search: after how many expansions with no plan and no better
    /// estimate a third open list joins the two, ranked by the landmark count plus h_add
    /// instead of h_FF, the three taking turns (`u64::MAX`: never).
    ///
    /// h_FF counts what a relaxed plan does, and a relaxed plan takes a robot everywhere at
    /// once: where robots drive to their loads before carrying them, driving one towards a
    /// load seldom shortens that plan, and the search wanders through every drive of every
    /// robot on one estimate. h_add counts each goal's distance on its own, and such a drive
    /// shortens it. On `benches/other_domains` (`kbc plan --schedule`, one run each, the
    /// second search still starting as the first): warehouse_c20_r4_s48 had no plan in 227 s
    /// when its stored states passed 2 GB, and has one in 19.9 s (makespan 60);
    /// warehouse_c25_r3_s30 22.4 s -> 4.9 s (makespan 131 -> 137). Ranked by h_add alone after
    /// the stall (the search started over), those took 16.5 and 5.3 s (makespans 84 and 139),
    /// but sliding_b15_a3_c20 (moves to a neighbouring cell) went from 42.6 s to 46.7 s
    /// (makespan 38 -> 52), where with the turns it took 6.4 s (36). (With the second search
    /// starting with the list, `PlanSettings::stalled`: 18.9 s, 5.94 s with makespan 124, 3.39
    /// s with 27.) On the blocks world h_add alone is much worse: 18 of the ladder's 52 rungs
    /// of seed 1, all of 15 blocks or more, found no plan in 30 s.
    pub stalled_states: u64,
}

impl Options {
    /// The default of [`Options::stalled_states`]: above the longest run of expansions
    /// without a better estimate on the ladder (1,143, seeds 1-2, with the lookahead coming
    /// on after 1000 expansions), so that its rungs are searched as before, and below those of
    /// warehouse_c20_r4_s48 and warehouse_c25_r3_s30 (8,054 and 8,636 expansions, traced in
    /// runs of 20 s).
    pub const STALLED_STATES: u64 = 2000;
}

impl Default for Options {
    fn default() -> Self {
        Options {
            search: SearchKind::Heuristic,
            max_depth: None,
            budget: Budget::default(),
            plans: 1,
            improve: None,
            improve_states: None,
            epsilon: crate::ir::stn::EPSILON,
            symmetry: true,
            lookahead: Lookahead::Auto,
            tie_seed: None,
            stalled_states: Options::STALLED_STATES,
        }
    }
}

/// The paper's default depth limit.
pub const DEFAULT_MAX_DEPTH: u32 = 25;

/// Figures of a search.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stats {
    /// States whose successors were generated.
    pub expanded: u64,
    /// Successor states generated.
    pub generated: u64,
    /// Heuristic evaluations.
    pub evaluated: u64,
    /// Wall-clock time.
    pub elapsed: Duration,
    /// The part of `elapsed` spent before the first expansion: the analyses, the root check
    /// and the heuristic's grounding.
    pub setup: Duration,
    /// Whether the set-up was the one a search before kept ([`Prepared`]) rather than
    /// grounded again.
    pub setup_kept: bool,
    /// The most bytes of states stored at once.
    pub peak_bytes: usize,
    /// Plan prefixes pruned because no schedule fits their durations.
    pub unschedulable: u64,
    /// Successors not generated because another differs from them only by interchangeable
    /// constants ([`symmetry`]).
    pub symmetric: u64,
    /// Whether the heuristic search followed relaxed plans ([`Lookahead`], decided at the
    /// initial state, or turned on later by `Lookahead::Auto`).
    pub lookahead: bool,
    /// When the lookahead was turned on after the initial state: the states expanded before
    /// (0: from the start, or never).
    pub lookahead_from: u64,
    /// When the heuristic search's list ranked by h_add joined ([`Options::stalled_states`]):
    /// after how many expansions.
    pub summed_from: Option<u64>,
    /// When the heuristic search began again with patient lookahead chains
    /// (`best_first::PATIENT_STATES`): after how many expansions.
    pub patient_from: Option<u64>,
    /// States reached by following a relaxed plan (see `best_first`'s lookahead).
    pub looked_ahead: u64,
    /// States not evaluated because no action applies in them (every unit of a resource
    /// waits on another).
    pub stuck: u64,
    /// The states expanded until the first plan was found (all of them when the search
    /// stopped there; fewer when it went on to improve the plan).
    pub first_expanded: u64,
    /// How long the heuristic search took to its first plan, from the same start as
    /// `elapsed`: the rest of `elapsed` went to improving on it (`Options::improve`).
    pub first_found: Option<Duration>,
}

/// Which budget ran out.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BudgetKind {
    /// `--max-states`.
    States,
    /// `--timeout`.
    Time,
    /// The memory ceiling.
    Memory,
    /// The delete relaxation kept making values the problem does not have (OnKB arithmetic
    /// without a bound, `X1 is X + 1`): more than `Budget::max_new_constants` in one
    /// exploration, which then never ends.
    Constants,
}

impl From<relaxed::Stop> for Failure {
    fn from(stop: relaxed::Stop) -> Failure {
        match stop {
            relaxed::Stop::Condition(error) => Failure::Condition(error),
            relaxed::Stop::Budget(kind) => Failure::Budget(kind),
        }
    }
}

/// Why no plan came back.
#[derive(Clone, Debug, PartialEq)]
pub enum Failure {
    /// Every state the search may visit was visited: no plan exists (within the depth limit,
    /// for the paper's search).
    Exhausted {
        /// The depth limit, for the paper's search.
        depth_limit: Option<u32>,
    },
    /// A budget ran out first.
    Budget(BudgetKind),
    /// Proving an OnKB goal failed (an arithmetic error, say).
    Condition(ConditionError),
    /// The analysis proved the problem unsolvable; the diagnostic says why.
    Unsolvable(Box<crate::diag::Diagnostic>),
}

/// A search's result and figures.
#[derive(Clone, Debug)]
pub struct Outcome {
    /// The first plan found, or why there is none.
    pub result: Result<Plan, Failure>,
    /// The other plans found, in the order found, when more than one was asked for.
    pub alternatives: Vec<Plan>,
    /// What the search did.
    pub stats: Stats,
}

impl Outcome {
    /// A search that ended with `found` plans (in order) or, with none, with `failure`.
    pub(crate) fn ended(mut found: Vec<Plan>, failure: Failure, stats: Stats) -> Outcome {
        if found.is_empty() {
            return Outcome { result: Err(failure), alternatives: Vec::new(), stats };
        }
        let first = found.remove(0);
        Outcome { result: Ok(first), alternatives: found, stats }
    }

    /// A search that failed before finding anything.
    pub(crate) fn failed(failure: Failure, stats: Stats) -> Outcome {
        Outcome { result: Err(failure), alternatives: Vec::new(), stats }
    }
}

/// Receives progress reports during long searches.
pub trait Progress {
    /// Called now and then with the figures so far.
    fn report(&mut self, stats: &Stats);
}

/// Scores a complete plan for the heuristic search's improvement phase: its makespan, in STN
/// units, after the passes that follow the search (for `kbc plan`, the temporal passes and
/// `reassign`), or `None` when it cannot be scheduled. A plan found while improving is kept
/// only if its score is shorter than the best so far. The paper's search takes only plans
/// that get a score and backtracks over the others (the refinement into arm-level actions
/// uses that to go on searching for a plan that refines).
pub trait Score {
    /// The score of `plan`, a plan for `task`.
    fn score(&mut self, task: &mut Task, plan: &Plan) -> Option<i64>;
}

/// A progress receiver that ignores everything.
pub struct Silent;

impl Progress for Silent {
    fn report(&mut self, _stats: &Stats) {}
}

/// The program a problem's OnKB goals are proven against: the KB plus the goal's facts.
pub fn program_for(kb: &Kb, interner: &crate::intern::Interner, problem: usize) -> Program {
    let problem = &kb.problems[problem];
    let goal_facts: Vec<_> = problem.goal.iter().map(|l| (l, &problem.vars)).collect();
    Program::new(kb, interner, &goal_facts)
}

/// The heuristic search's interchangeable constants, if it is to use them and there are any.
fn symmetry_for(
    kb: &Kb,
    interner: &crate::intern::Interner,
    task: &mut Task,
    options: &Options,
) -> Option<symmetry::Symmetry> {
    if options.search != SearchKind::Heuristic || !options.symmetry {
        return None;
    }
    Some(symmetry::Symmetry::new(kb, interner, task)).filter(|s| !s.is_empty())
}

/// Runs the chosen search on `task`.
///
/// Before searching, two analyses look for a proof that the problem has no solution: goal
/// literals an invariant forbids together, and goal literals the delete relaxation never
/// reaches. Either ends the search at once with a diagnostic that says why.
pub fn search(
    kb: &Kb,
    interner: &crate::intern::Interner,
    task: &mut Task,
    options: &Options,
    progress: &mut dyn Progress,
) -> Outcome {
    search_scored(kb, interner, task, options, None, progress)
}

/// [`search`], with the plans of the heuristic search's improvement phase (`Options::improve`)
/// judged by `scorer` instead of the search's own makespan estimate.
pub fn search_scored(
    kb: &Kb,
    interner: &crate::intern::Interner,
    task: &mut Task,
    options: &Options,
    scorer: Option<&mut dyn Score>,
    progress: &mut dyn Progress,
) -> Outcome {
    search_prepared(kb, interner, task, options, scorer, &mut None, progress)
}

/// The heuristic search's set-up of a task, kept so that another search of the same task
/// (the lookahead's second search, `--improve`'s restarts) starts from it instead of
/// grounding the relaxation again, which is most of a search's time on the grid rungs
/// (grid_b20_a3_s3: 0.45 s of the second search's 0.51). It is the set-up exactly as the
/// first search had it when it began: the task with what grounding interned (the values
/// OnKB goals computed), the grounded relaxation after its estimate of the initial state
/// (the root check), that estimate, and the OnKB answers proven so far. A search started
/// from it expands the same states in the same order as one that grounds again.
pub struct Prepared {
    /// What it was grounded for: the problem, the limit on ground actions and the memory
    /// budget (a search with other limits grounds again).
    key: (usize, usize, usize),
    task: Task,
    relaxation: relaxed::Relaxation,
    cache: successors::OnKbCache,
    /// The relaxation's estimate of the initial state (the root check's).
    root: relaxed::Estimate,
}

impl Prepared {
    fn key(task: &Task, budget: &Budget) -> (usize, usize, usize) {
        (task.problem, budget.max_ground_actions, budget.max_bytes)
    }

    /// Whether a search with `options` keeps its set-up (the grounded `relaxation`, whose
    /// estimate of the initial state is `root`): copying it takes about a tenth of grounding
    /// (build_b100_a8: 0.16 s of 1.1), wasted where no search follows. One follows where
    /// `--improve` restarts, and where the lookahead is automatic and the search starts
    /// without it (the lookahead's second search, see `Session::plan`); that start is
    /// predicted from the root estimate with every landmark counted (the search decides on
    /// the landmarks not yet reached). A wrong guess costs time, never a different plan.
    fn wanted(options: &Options, root: &relaxed::Estimate, relaxation: &relaxed::Relaxation) -> bool {
        let estimate = root.h_ff.unwrap_or(0) + relaxation.landmark_count().unwrap_or(0) as u32;
        relaxation.ground_actions().is_some()
            && (options.improve.is_some()
                || (options.lookahead == Lookahead::Auto && !options.lookahead.wanted(estimate)))
    }
}

/// [`search_scored`], for the heuristic search starting from `prepared` where it holds the
/// set-up of the same task (see [`Prepared`]), and leaving its own set-up there otherwise.
pub fn search_prepared(
    kb: &Kb,
    interner: &crate::intern::Interner,
    task: &mut Task,
    options: &Options,
    mut scorer: Option<&mut dyn Score>,
    prepared: &mut Option<Prepared>,
    progress: &mut dyn Progress,
) -> Outcome {
    let started = Instant::now();
    // The figures of a search that ends before its first expansion.
    let before_search = |evaluated: u64| {
        let elapsed = started.elapsed();
        Stats { elapsed, setup: elapsed, evaluated, ..Stats::default() }
    };
    let program = program_for(kb, interner, task.problem);
    let unsolvable =
        analysis::exclusive_goals(kb, task, interner).or_else(|| analysis::missing_units(kb, task, interner));
    if let Some(diagnostic) = unsolvable {
        return Outcome::failed(Failure::Unsolvable(Box::new(diagnostic)), before_search(0));
    }
    let key = Prepared::key(task, &options.budget);
    let reused = prepared.as_ref().filter(|p| options.search == SearchKind::Heuristic && p.key == key);
    let kept = reused.is_some();
    let mut successors = match reused {
        Some(reused) => {
            *task = reused.task.clone();
            Successors::with_cache(Machine::new(&program, options.budget.engine_steps), reused.cache.clone())
        }
        None => Successors::new(task, Machine::new(&program, options.budget.engine_steps)),
    };
    let init = task.init.clone();
    // The root check: a goal no relaxed plan reaches can never be reached. The heuristic
    // search's relaxation, grounded by one full exploration from the initial state, answers it
    // (and is then handed to the search); the paper's search only needs the answer.
    let mut relaxation = None;
    let root = match (options.search, reused) {
        (SearchKind::Heuristic, Some(reused)) => {
            let mut reused_relaxation = reused.relaxation.clone();
            reused_relaxation.limit(&options.budget);
            relaxation = Some(reused_relaxation);
            Ok(reused.root.clone())
        }
        (SearchKind::Heuristic, None) => match ground_relaxation(task, &mut successors, &options.budget) {
            Ok(mut grounded) => {
                let (machine, cache) = successors.parts();
                let estimate = grounded.evaluate(task, &init, machine, cache, false);
                if let Ok(root) = &estimate
                    && Prepared::wanted(options, root, &grounded)
                {
                    let (task, relaxation, cache, root) = (task.clone(), grounded.clone(), cache.clone(), root.clone());
                    *prepared = Some(Prepared { key, task, relaxation, cache, root });
                }
                relaxation = Some(grounded);
                estimate
            }
            Err(stop) => Err(stop),
        },
        (SearchKind::Paper, _) => {
            let mut lifted = relaxed::Relaxation::new(task);
            lifted.limit(&options.budget);
            let (machine, cache) = successors.parts();
            let estimate = lifted.evaluate(task, &init, machine, cache, false);
            lifted.discard();
            estimate
        }
    };
    match root {
        // The root check only looks for a goal that can never be reached; the paper's search
        // does not need it, so one too big for the budget is skipped rather than fatal.
        Err(relaxed::Stop::Budget(_)) if options.search == SearchKind::Paper => {}
        Ok(estimate) if estimate.h_add.is_some() => {}
        failed => {
            if let Some(relaxation) = relaxation {
                relaxation.discard();
            }
            let result = match failed {
                Err(stop) => return Outcome::failed(stop.into(), before_search(0)),
                Ok(_) => match analysis::explain_unreachable(kb, task, &program, interner, &options.budget) {
                    Some(diagnostic) => Failure::Unsolvable(Box::new(diagnostic)),
                    None => Failure::Exhausted { depth_limit: None },
                },
            };
            return Outcome::failed(result, before_search(1));
        }
    }
    let symmetry = symmetry_for(kb, interner, task, options);
    let setup = started.elapsed();
    let mut outcome = match options.search {
        SearchKind::Paper => {
            let limit = options.max_depth.or(task.max_depth).unwrap_or(DEFAULT_MAX_DEPTH);
            // A scorer that gives a plan no score refuses it, and the search goes on.
            let mut accept =
                |task: &mut Task, plan: &Plan| scorer.as_deref_mut().is_none_or(|s| s.score(task, plan).is_some());
            paper::search(task, successors, limit, &options.budget, options.plans.max(1), &mut accept, progress)
        }
        SearchKind::Heuristic => {
            let until = options.improve.map(|time| Instant::now() + time);
            let (wanted, until) = match (until, options.improve_states) {
                (None, None) => (options.plans.max(1), None),
                (until, expansions) => (usize::MAX, Some(best_first::Improving { until, expansions })),
            };
            let relaxation = relaxation.expect("grounded for the root check");
            let outcome = best_first::search(
                task,
                successors,
                relaxation,
                symmetry,
                options.lookahead,
                &options.budget,
                wanted,
                until,
                true,
                options.epsilon,
                options.tie_seed,
                options.stalled_states,
                scorer.as_mut().map(|s| &mut **s as &mut dyn Score),
                progress,
            );
            if matches!(outcome.result, Err(Failure::Exhausted { .. })) && outcome.stats.unschedulable > 0 {
                // Every plan the search could reach was pruned for its durations. Plan once
                // more without the temporal check: the scheduler then rejects that plan with
                // a diagnostic naming the constraints that cannot be met, which says far more
                // than "no plan".
                let mut successors = Successors::new(task, Machine::new(&program, options.budget.engine_steps));
                let relaxation = match ground_relaxation(task, &mut successors, &options.budget) {
                    Ok(relaxation) => relaxation,
                    Err(stop) => return Outcome::failed(stop.into(), outcome.stats),
                };
                let symmetry = symmetry_for(kb, interner, task, options);
                let mut retry = best_first::search(
                    task,
                    successors,
                    relaxation,
                    symmetry,
                    options.lookahead,
                    &options.budget,
                    wanted,
                    until,
                    false,
                    options.epsilon,
                    options.tie_seed,
                    options.stalled_states,
                    scorer,
                    progress,
                );
                retry.stats.unschedulable += outcome.stats.unschedulable;
                retry
            } else {
                outcome
            }
        }
    };
    outcome.stats.elapsed = started.elapsed();
    outcome.stats.first_found = outcome.stats.first_found.map(|searching| setup + searching);
    outcome.stats.setup = setup;
    outcome.stats.setup_kept = kept;
    outcome
}

/// The heuristic's relaxation of `task`, grounded by one full exploration from the initial
/// state ([`relaxed::Relaxation::ground`]) under the search's deadline and memory budget: a
/// task too big to ground in half the memory keeps the lifted relaxation.
fn ground_relaxation(
    task: &mut Task,
    successors: &mut Successors<'_>,
    budget: &Budget,
) -> Result<relaxed::Relaxation, relaxed::Stop> {
    let mut relaxation = relaxed::Relaxation::new(task);
    relaxation.limit(budget);
    let (machine, cache) = successors.parts();
    match relaxation.ground(task, machine, cache, budget.max_ground_actions, true) {
        Ok(_) => Ok(relaxation),
        Err(stop) => {
            relaxation.discard();
            Err(stop)
        }
    }
}

/// The diagnostic that says why a search for `problem` found no plan; `figures` describes
/// what the search did (the CLI adds the process's peak memory to `stats`).
#[allow(clippy::too_many_arguments)]
pub fn failure_diagnostic(
    kb: &Kb,
    interner: &crate::intern::Interner,
    task: &crate::ir::task::Task,
    problem: &str,
    failure: &Failure,
    stats: &Stats,
    figures: &str,
    options: &Options,
) -> Diagnostic {
    match failure {
        Failure::Exhausted { depth_limit: Some(limit) } => Diagnostic::error(
            codes::NO_PLAN,
            format!("no plan for `{problem}` within the depth limit of {limit} snap actions"),
        )
        .with_note(format!("the paper's search tried every plan up to that length: {}", figures))
        .with_help("raise the limit with `--max-depth`, or use the heuristic search, which has no depth limit"),
        Failure::Exhausted { depth_limit: None } => {
            Diagnostic::error(codes::NO_PLAN, format!("no plan exists for `{problem}`"))
                .with_note(format!("every state reachable from the initial state was explored: {}", figures))
        }
        Failure::Budget(kind) => {
            let (what, help) = match kind {
                BudgetKind::States => {
                    (format!("its budget of {} states", options.budget.max_states), "raise `--max-states`")
                }
                BudgetKind::Time => (format!("time after {:.1} s", stats.elapsed.as_secs_f64()), "raise `--timeout`"),
                BudgetKind::Memory => {
                    (format!("its budget of {} MB of memory", options.budget.max_bytes >> 20), "raise `--max-memory`")
                }
                BudgetKind::Constants => {
                    return Diagnostic::error(
                        codes::SEARCH_BUDGET,
                        format!("the search for `{problem}` stopped: its relaxation makes new values without end"),
                    )
                    .with_note(format!(
                        "ignoring deletions (as the heuristic does), the actions' OnKB goals computed more than {} \
                         values the problem does not have, and would go on: a counter such as `X1 is X + 1` that \
                         nothing bounds",
                        options.budget.max_new_constants
                    ))
                    .with_note(format!("no plan found so far: {}", figures))
                    .with_help(
                        "bound the value in the OnKB goals of the action that computes it (`X1 is X + 1, X1 =< 10`), \
                         or try `--search paper`, which uses no heuristic",
                    );
                }
            };
            let diagnostic =
                Diagnostic::error(codes::SEARCH_BUDGET, format!("the search for `{problem}` ran out of {what}"))
                    .with_note(format!("no plan found so far: {}", figures));
            if stats.expanded == 0 && options.search == SearchKind::Heuristic && *kind != BudgetKind::States {
                diagnostic
                    .with_note(
                        "it ran out in the heuristic's set-up, which explores everything the initial state can \
                         reach when deletions are ignored",
                    )
                    .with_help(format!("{help}, or try `--search paper`, which uses no heuristic"))
            } else {
                diagnostic.with_help(help)
            }
        }
        Failure::Unsolvable(diagnostic) => (**diagnostic).clone(),
        Failure::Condition(error) if error.duration => {
            let action = &kb.actions[task.schemas[error.schema].action];
            let base = interner.resolve(action.base);
            // The `duration/3` clause for this action, if it has one, else the action.
            let clause = kb.clauses.iter().find(|c| {
                c.head.term.callable() == Some((crate::intern::sym::DURATION, 3))
                    && c.head.term.args()[0].callable().is_some_and(|(name, _)| name == action.base)
            });
            let diagnostic = Diagnostic::error(
                codes::CONDITION_ERROR,
                format!("proving the duration of `{base}` failed: {}", error.error.message(interner)),
            );
            match clause {
                Some(clause) => diagnostic.primary(clause.head.span, "this `duration/3` clause"),
                None => diagnostic.primary(action.name.span, "this durative action"),
            }
            .with_note("the search asks `duration/3` for the least time of each action it places")
            .with_note("the search stops, as SWI-Prolog would on an uncaught error")
        }
        Failure::Condition(error) => {
            let action = &kb.actions[task.schemas[error.schema].action];
            let name = interner.resolve(action.name.name());
            Diagnostic::error(
                codes::CONDITION_ERROR,
                format!("proving the OnKB goals of `{name}` failed: {}", error.error.message(interner)),
            )
            .primary(action.slots[4], "these goals")
            .with_note("the search stops, as SWI-Prolog would on an uncaught error")
        }
    }
}

/// Turns the applicable actions along a path into a plan.
pub(crate) fn plan_from(task: &Task, path: &[Applicable]) -> Plan {
    let steps = path
        .iter()
        .map(|a| Step {
            action: task.schemas[a.schema].action,
            name: successors::action_name(task, a),
            bindings: successors::action_bindings(task, a),
        })
        .collect();
    Plan { problem: task.problem, steps }
}

/// Checks the time and memory budgets; the states budget is checked by each search.
pub(crate) fn over_budget(budget: &Budget, stats: &Stats, bytes: usize) -> Option<BudgetKind> {
    if bytes > budget.max_bytes {
        return Some(BudgetKind::Memory);
    }
    if stats.expanded >= budget.max_states {
        return Some(BudgetKind::States);
    }
    if budget.deadline.is_some_and(|d| Instant::now() >= d) {
        return Some(BudgetKind::Time);
    }
    None
}

/// The applicable actions a plan's steps stand for, with the search's own semantics. Stops
/// early at a step that names no schema or a value the task does not know.
pub fn path_of(task: &mut Task, plan: &Plan) -> Vec<Applicable> {
    let mut path = Vec::new();
    for step in &plan.steps {
        let Some(schema) = task.schemas.iter().position(|s| s.action == step.action) else { break };
        let bindings: Option<Box<[Option<crate::ir::task::ConstId>]>> = step
            .bindings
            .iter()
            .map(|b| match b {
                Some(term) => task.consts.from_term(term).map(Some),
                None => Some(None),
            })
            .collect();
        let Some(bindings) = bindings else { break };
        let ends = match task.schemas[schema].snap {
            crate::ir::hir::Snap::End => {
                let Task { schemas, consts, .. } = task;
                successors::running_instance(&schemas[schema], consts, &bindings)
            }
            _ => None,
        };
        path.push(Applicable { schema, bindings, ends });
    }
    path
}

/// The states a plan passes through, after each of its steps, replayed with the search's own
/// semantics (for `--trace`). Stops early at a step that names no applicable action.
pub fn replay(task: &mut Task, plan: &Plan) -> Vec<crate::ir::task::State> {
    let mut states = Vec::new();
    let mut state = task.init.clone();
    for action in path_of(task, plan) {
        state = successors::apply(task, &state, &action);
        states.push(state.clone());
    }
    states
}

/// True if `plan` solves its task under the search's own semantics: each step applicable in
/// turn (its Valid, Invalid, InvalidAtEnd and OnKB conditions, as [`Successors`] decides
/// them) and the last state a goal state with nothing left running. Plans the planner did not
/// find itself (rearranged by `passes::reassign`) are checked with it before they are used.
pub fn is_solution(task: &mut Task, program: &Program, plan: &Plan) -> bool {
    let mut successors = Successors::new(task, Machine::new(program, Budget::default().engine_steps));
    is_solution_with(&mut successors, task, plan)
}

/// [`is_solution`] with the task's `successors` (whose OnKB cache a caller that checks many
/// plans keeps from one to the next).
pub fn is_solution_with(successors: &mut Successors<'_>, task: &mut Task, plan: &Plan) -> bool {
    let path = path_of(task, plan);
    if path.len() != plan.steps.len() {
        return false;
    }
    let mut state = task.init.clone();
    for action in &path {
        if successors.applies(task, action, &state) != Ok(true) {
            return false;
        }
        state = successors::apply(task, &state, action);
    }
    successors::goal_reached(task, &state)
}
