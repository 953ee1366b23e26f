//! Running a compiled plan on the simulated arms and recovering from faults: the paper's
//! feedback loop of executing, observing the world and replanning.
//!
//! A round runs one program in the simulated world. It ends well when the tree succeeds and
//! the world read back satisfies the goal with every block on a cell. Otherwise the fault
//! was detected (an action failed or overran its duration, or the tree finished with the
//! world disagreeing with the goal) and, while recoveries are allowed, the world is brought
//! to rest ([`SimHost::recover`]), read back into facts, and a new problem is made of them:
//! the same goal, from the blocks where they really are and with the arms still working.
//! Its plan is compiled for the same host and run in the same world as the next round.
//!
//! Nothing here does IO: the caller prints the rounds.

use kbvm::Program;
use kbvm::sim::{Misplaced, SimHost};

use crate::stdlib::blocks::{self, AVAILABLE, GRIPPED};

use crate::diag::Diagnostics;
use crate::execute;
use crate::ir::hir::{Literal, Problem, Term};
use crate::planner;
use crate::session::{HostProfile, PlanError, PlanSettings, SearchFailed, Session};
use kbvm::run::{self as vm_run, HostEvent, Logged, Outcome, Run};

/// How to run and recover.
pub struct Settings<'a> {
    /// Replan after a fault (otherwise the first fault ends the run).
    pub replan: bool,
    /// The most recoveries before giving up.
    pub max_recoveries: u32,
    /// How each replan is found and scheduled, as `kbc plan` does (the timeout counts from
    /// each replan's start).
    pub plan: &'a PlanSettings,
    /// The host profile the replanned programs are checked against.
    pub profile: HostProfile<'a>,
    /// Each round's time budget, in program units.
    pub max_time: i64,
    /// Each round's tick budget.
    pub max_ticks: u64,
}

/// One program run in the world.
pub struct Round {
    /// The problem it was planned for (an index into the KB's problems).
    pub problem: usize,
    /// The program.
    pub program: Program,
    /// Its plan's makespan (program units).
    pub planned_makespan: i64,
    /// The world's time when it started.
    pub offset: i64,
    /// How the tree ended.
    pub run: Run,
    /// What the host did, in program time.
    pub log: Vec<(i64, kbvm::bytecode::EventId, HostEvent)>,
    /// Why the round did not reach the goal (`None` if it did).
    pub detected: Option<String>,
    /// What bringing the world to rest did after the round (empty if it was not needed).
    pub recovery: Vec<String>,
}

/// How an execution ended.
pub enum Verdict {
    /// The goal holds in the world read back and every block is on a cell.
    GoalReached,
    /// The last round did not reach the goal and no recovery is allowed or left.
    GaveUp {
        /// Why the last round failed, and why it was not recovered from.
        why: String,
        /// Whether recovering was considered: not for a budget that ran out or a malformed
        /// program, which are no faults of the world.
        considered: bool,
    },
    /// The world read back cannot reach the goal: a block it needs is lost, or held by a
    /// stopped arm, or no arm works.
    Unrecoverable {
        /// Why.
        why: String,
    },
    /// No plan from the world read back (the problem is the one replanned).
    NoPlan {
        /// The replanned problem.
        problem: usize,
        /// Why the search found none, and its figures.
        failed: std::rc::Rc<SearchFailed>,
    },
    /// A replanned plan could not be scheduled or compiled: the diagnostics say why.
    NotCompiled(Diagnostics),
    /// The executed timeline of a round breaks the KB: a compiler bug.
    InvalidTimeline(Diagnostics),
}

/// A finished execution: its rounds, the world, and how it ended.
pub struct Execution {
    /// The rounds, in order.
    pub rounds: Vec<Round>,
    /// The host, with the world as it ended.
    pub sim: SimHost,
    /// How it ended.
    pub verdict: Verdict,
}

/// Runs `program` (planned for `problem`, with makespan `planned`) in `sim`'s world, and
/// recovers from faults as `settings` allow.
pub fn execute(
    session: &mut Session,
    problem: usize,
    program: Program,
    planned: i64,
    mut sim: SimHost,
    settings: &Settings<'_>,
) -> Execution {
    let mut rounds: Vec<Round> = Vec::new();
    let mut current = (problem, program, planned);
    // The world each recovery left, to see when recovering gets nowhere.
    let mut recovered: Vec<Vec<String>> = Vec::new();
    loop {
        let (round_problem, program, planned_makespan) = current;
        sim.start_program();
        let offset = sim.time();
        let start_world = sorted_facts(sim.world());
        let mut host = Logged::new(sim);
        // The time budget counts on the world's clock, across rounds.
        let run = vm_run::run(&program, &mut host, (settings.max_time - offset).max(0), settings.max_ticks);
        let log = host.log;
        sim = host.host;
        // The tree may end on a wait that calls no host (a durative action's least duration
        // after its arm finished): bring the world to the program's end, where it is read back.
        sim.advance_to(run.end);
        // The goal, without what a stopped arm can no longer make true.
        let (goal, _) = waive(session, problem, &sim.world().stopped_arms());
        // When the tree says the plan was carried out, its timeline must satisfy the KB.
        let timeline = match run.outcome {
            Outcome::Success => execute::check_timeline(session, round_problem, &program, &run),
            _ => Diagnostics::new(),
        };
        let (facts, unaccounted) = execute::world_facts(sim.world(), session.interner_mut());
        let detected = match &run.outcome {
            Outcome::Success => {
                let unmet = execute::unmet_goals(&goal, &facts);
                if unmet.is_empty() && unaccounted.is_empty() {
                    None
                } else if unmet.is_empty() {
                    let lines: Vec<String> = unaccounted.iter().map(Misplaced::to_string).collect();
                    Some(format!("the tree succeeded, but {}", lines.join("; ")))
                } else {
                    let show = |t: &Term| crate::ir::hir::term_to_string(session.interner(), t, &Default::default());
                    let unmet: Vec<String> = unmet.iter().map(|t| format!("`{}`", show(t))).collect();
                    Some(format!("the tree succeeded, but the world lacks {}", unmet.join(", ")))
                }
            }
            Outcome::Failure(failure) => Some(failure.describe(&program)),
            Outcome::Stuck => Some("the tree is stuck: it waits for an event no node will record".to_string()),
            Outcome::Budget => Some("the round passed its time or tick budget".to_string()),
            Outcome::Unlinked(error) => Some(format!("the program does not link with the host: {error}")),
            _ => Some("the round ended without success".to_string()),
        };
        let mut round = Round {
            problem: round_problem,
            program,
            planned_makespan,
            offset,
            run,
            log,
            detected,
            recovery: Vec::new(),
        };
        if timeline.has_errors() {
            rounds.push(round);
            let verdict = Verdict::InvalidTimeline(timeline);
            return Execution { rounds, sim, verdict };
        }
        let Some(why) = round.detected.clone() else {
            rounds.push(round);
            return Execution { rounds, sim, verdict: Verdict::GoalReached };
        };
        let recoveries = rounds.len() as u32;
        if matches!(round.run.outcome, Outcome::Budget | Outcome::Stuck | Outcome::Unlinked(_)) {
            rounds.push(round);
            let verdict = Verdict::GaveUp { why, considered: false };
            return Execution { rounds, sim, verdict };
        }
        if !settings.replan || recoveries >= settings.max_recoveries {
            rounds.push(round);
            let why = if settings.replan {
                format!("{recoveries} recoveries were made, the most `--max-recoveries` allows")
            } else {
                why
            };
            let verdict = Verdict::GaveUp { why, considered: true };
            return Execution { rounds, sim, verdict };
        }
        // Recover: bring the world to rest, read it back, and plan from there; unless the
        // round changed nothing (the tree succeeded without moving a block as the goal
        // needs, so a replan would run the same plan again).
        round.recovery = sim.recover();
        let succeeded = round.run.outcome == Outcome::Success;
        rounds.push(round);
        if succeeded && sorted_facts(sim.world()) == start_world {
            let why = "the round changed nothing in the world, so a new plan would repeat it".to_string();
            let verdict = Verdict::GaveUp { why, considered: true };
            return Execution { rounds, sim, verdict };
        }
        let world = sorted_facts(sim.world());
        if recovered.contains(&world) {
            let why = format!(
                "after the fault, recovering led back to a world it had already planned from, and the new plan \
                 failed again: {why}"
            );
            return Execution { rounds, sim, verdict: Verdict::Unrecoverable { why } };
        }
        recovered.push(world);
        let (facts, unaccounted) = execute::world_facts(sim.world(), session.interner_mut());
        if let Some(why) = unreachable_goal(session, &goal, &facts, &unaccounted, &sim) {
            let verdict = Verdict::Unrecoverable { why };
            return Execution { rounds, sim, verdict };
        }
        let new_problem = replanned_problem(session, problem, &facts, &sim.world().stopped_arms());
        // What the replan reports is kept only when it fails.
        let _ = session.take_diagnostics();
        let planned = match session.plan(new_problem, settings.plan, &mut planner::Silent) {
            Ok(planned) => planned,
            Err(PlanError::Search(failed)) => {
                let verdict = Verdict::NoPlan { problem: new_problem, failed };
                return Execution { rounds, sim, verdict };
            }
            Err(PlanError::Unschedulable | PlanError::PlanFile | PlanError::Refinement) => {
                let verdict = Verdict::NotCompiled(session.take_diagnostics());
                return Execution { rounds, sim, verdict };
            }
        };
        match session.build(&planned, Some(settings.profile)) {
            Some(built) => current = (new_problem, built.program(), planned.timed.schedule.makespan),
            None => {
                let verdict = Verdict::NotCompiled(session.take_diagnostics());
                return Execution { rounds, sim, verdict };
            }
        }
    }
}

/// The world read back, as sorted text, to compare two moments.
fn sorted_facts(world: &kbvm::sim::World) -> Vec<String> {
    let (facts, unaccounted) = world.facts();
    let mut text: Vec<String> =
        facts.iter().map(|f| f.to_string()).chain(unaccounted.iter().map(Misplaced::to_string)).collect();
    text.sort();
    text
}

/// The goal of `problem` split into the literals kept and those waived: a literal that names a
/// stopped arm (`available(a2)` once a2 has stopped) can never hold again, whatever the
/// other arms do.
pub fn waive(session: &Session, problem: usize, stopped: &[String]) -> (Vec<Term>, Vec<Term>) {
    let interner = session.interner();
    let names_stopped = |t: &Term| {
        t.args().iter().any(|a| matches!(a, Term::Atom(s) if stopped.iter().any(|n| n == interner.resolve(*s))))
    };
    session.kb().problems[problem].goal.iter().map(|l| l.term.clone()).partition(|t| !names_stopped(t))
}

/// Why the goal cannot be reached from the world read back, if that is plain without a
/// search: a goal block lost or held by a stopped arm, or no arm left.
fn unreachable_goal(
    session: &Session,
    goal: &[Term],
    facts: &[Term],
    unaccounted: &[Misplaced],
    sim: &SimHost,
) -> Option<String> {
    let interner = session.interner();
    let mut goal_atoms = Vec::new();
    for literal in goal {
        for arg in literal.args() {
            if let Term::Atom(a) = arg {
                goal_atoms.push(interner.resolve(*a).to_string());
            }
        }
    }
    for misplaced in unaccounted {
        let name = &misplaced.block;
        if goal_atoms.iter().any(|a| a == name) {
            return Some(format!("the goal needs `{name}`, which no arm can pick up: {misplaced}"));
        }
    }
    let stopped = sim.world().stopped_arms();
    for fact in facts {
        if let Term::Compound(name, args) = fact
            && let [Term::Atom(arm), Term::Atom(block)] = &args[..]
            && interner.resolve(*name) == GRIPPED.name
            && stopped.iter().any(|s| s == interner.resolve(*arm))
        {
            let (arm, block) = (interner.resolve(*arm), interner.resolve(*block));
            if goal_atoms.iter().any(|a| a == block) {
                return Some(format!("the goal needs `{block}`, which {arm} holds and {arm} has stopped"));
            }
        }
    }
    let available = facts.iter().any(|f| f.callable().is_some_and(|(n, _)| interner.resolve(n) == AVAILABLE.name));
    if !available {
        return Some(format!("no arm is left to work: {} stopped", stopped.join(", ")));
    }
    None
}

/// Adds the problem "the original goal, from the world read back" to the KB: the facts read
/// back, plus the original initial facts of predicates the world does not observe.
fn replanned_problem(session: &mut Session, original: usize, facts: &[Term], stopped: &[String]) -> usize {
    let (_, waived) = waive(session, original, stopped);
    // The world observes these; an initial fact of any other predicate is carried over into
    // the replanned problem unchanged.
    let observed: Vec<(crate::intern::Symbol, usize)> =
        blocks::OBSERVED.iter().map(|p| (session.intern(p.name), p.arity)).collect();
    let base = &session.kb().problems[original];
    let span = base.name_span;
    let literal = |term: Term| Literal { term, span, name_span: span };
    let mut init: Vec<Literal> = facts.iter().cloned().map(literal).collect();
    init.extend(base.init.iter().filter(|l| !observed.iter().any(|&(n, a)| l.name() == n && l.arity() == a)).cloned());
    let round = session.kb().problems.len();
    let name = format!("{}_from_world_{round}", session.interner().resolve(base.name));
    let goal = base.goal.iter().filter(|l| !waived.contains(&l.term)).cloned().collect();
    let base = base.clone();
    let name = session.intern(&name);
    session.add_problem(Problem { name, init, goal, ..base })
}

impl Execution {
    /// Why the execution did not reach the goal, as diagnostics (none when it did): the
    /// last round's failure or the goal literals the world lacks, why it was not recovered
    /// from, or why recovering was impossible (E0502, E0505, E0506).
    pub fn diagnostics(
        &self,
        session: &mut Session,
        problem: usize,
        settings: &Settings<'_>,
        budget: execute::RunBudget,
    ) -> Diagnostics {
        use crate::diag::{Diagnostic, codes};
        let mut diagnostics = Diagnostics::new();
        let (facts, unaccounted) = &execute::world_facts(self.sim.world(), session.interner_mut());
        let (goal, _) = waive(session, problem, &self.sim.world().stopped_arms());
        let after = match self.rounds.len() - 1 {
            0 => String::new(),
            1 => " after 1 recovery".to_string(),
            n => format!(" after {n} recoveries"),
        };
        let last = self.rounds.last().expect("at least one round");
        match &self.verdict {
            Verdict::GoalReached => {}
            Verdict::GaveUp { why, considered } => {
                let program = &last.program;
                let end_round = program.time_text(last.run.end);
                match execute::outcome_diagnostic(program, &last.run.outcome, &end_round, budget) {
                    Some(d) => diagnostics.push(d),
                    None => {
                        let unmet = execute::unmet_goals(&goal, facts);
                        diagnostics.push(execute::goal_diagnostic(
                            session.interner(),
                            true,
                            &unmet,
                            facts,
                            unaccounted,
                        ));
                    }
                }
                if !settings.replan {
                    diagnostics.push(Diagnostic::note("not replanned: replanning is off (`--no-replan`)"));
                } else if *considered {
                    diagnostics.push(Diagnostic::note(format!("not replanned: {why}")));
                }
            }
            Verdict::Unrecoverable { why } => {
                diagnostics.push(
                    Diagnostic::error(codes::CANNOT_RECOVER, format!("the goal cannot be reached{after}: {why}"))
                        .with_note(execute::world_note(session.interner(), facts, unaccounted)),
                );
            }
            Verdict::NoPlan { problem: replanned, failed } => {
                let figures = crate::session::stats_line(&failed.stats);
                let search = session.search_failure(*replanned, failed, &figures, settings.plan);
                diagnostics.push(
                    Diagnostic::error(
                        codes::CANNOT_RECOVER,
                        format!("the goal cannot be reached{after}: no plan from the world read back"),
                    )
                    .with_note(format!("the search: {}", search.message))
                    .with_note(execute::world_note(session.interner(), facts, unaccounted)),
                );
            }
            Verdict::NotCompiled(found) => {
                diagnostics.extend(found.clone());
                diagnostics.push(Diagnostic::error(
                    codes::CANNOT_RECOVER,
                    format!("the goal cannot be reached{after}: the plan from the world read back does not compile"),
                ));
            }
            Verdict::InvalidTimeline(found) => diagnostics.extend(found.clone()),
        }
        diagnostics
    }
}
