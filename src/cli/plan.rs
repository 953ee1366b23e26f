//! `kbc plan`: finds a total-order plan for one problem (or reads one), schedules it, and
//! prints it.
//!
//! The text output is itself a plan file: numbered snap actions, with figures and traces as
//! `%` comment lines, so `kbc plan ... > plan.txt` feeds `kbc validate`; with `--schedule` it
//! is a timed plan in the PDDL 2.1 format, which `kbc validate` reads too.

use std::io::{IsTerminal, Write};
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::{Duration, Instant};

use clap::ValueEnum;

use super::{MessageFormat, report};
use crate::diag::{Diagnostic, Diagnostics};
use crate::driver;
use crate::ir::hir::{self, Kb, VarTable};
use crate::ir::plan::{self, Plan};
use crate::ir::pop::Achiever;
use crate::ir::schedule;
use crate::ir::stn::{UNITS, format_time};
use crate::passes;
use crate::planner::{self, Options, Progress, SearchKind, Stats};
use crate::render;
use crate::source::SourceDb;
use crate::validate;

/// What finding and scheduling a plan needs; `kbc plan` and `kbc build` share it.
#[derive(clap::Args)]
pub(super) struct PlanningArgs {
    /// KB and goal files (`kbc run` also takes a single bytecode file).
    #[arg(required = true, value_name = "FILE")]
    pub(super) files: Vec<PathBuf>,
    /// The problem to plan, when the files define several.
    #[arg(long, value_name = "NAME")]
    pub(super) problem: Option<String>,
    /// The search: the paper's depth-first search, or best-first with a heuristic.
    #[arg(long, value_enum, default_value_t = SearchArg::Heuristic)]
    pub(super) search: SearchArg,
    /// The paper's depth limit, in snap actions (default: the problem's go/5 value, else 25).
    #[arg(long, value_name = "N")]
    pub(super) max_depth: Option<u32>,
    /// Give up after expanding this many states.
    #[arg(long, value_name = "N", default_value_t = 1_000_000)]
    pub(super) max_states: u64,
    /// Give up after this many seconds.
    #[arg(long, value_name = "SECONDS")]
    pub(super) timeout: Option<f64>,
    /// Give up when the stored states exceed this many megabytes.
    #[arg(long, value_name = "MB", default_value_t = 2048)]
    pub(super) max_memory: u64,
    /// How to print diagnostics.
    #[arg(long, value_enum, default_value_t = MessageFormat::Human)]
    pub(super) message_format: MessageFormat,
    /// Schedule this total-order plan (a plan file, as `kbc plan` prints them) instead of
    /// searching for one.
    #[arg(long, value_name = "FILE")]
    pub(super) plan: Option<PathBuf>,
    /// When a plan cannot be scheduled (its durations and orderings contradict each other),
    /// ask the search for up to this many other plans.
    #[arg(long, value_name = "N", default_value_t = 0)]
    pub(super) retries: u32,
    /// After the first plan, go on searching for this many seconds for plans with a shorter
    /// makespan, and keep the best (heuristic search).
    #[arg(long, value_name = "SECONDS")]
    pub(super) improve: Option<f64>,
    /// Keep the search's choice of arm for each job and its order of jobs (by default the
    /// heuristic search's plan is rearranged when that shortens its makespan: the `reassign`
    /// pass).
    #[arg(long)]
    pub(super) no_reassign: bool,
}

#[derive(clap::Args)]
pub(super) struct PlanArgs {
    #[command(flatten)]
    planning: PlanningArgs,
    /// Print the state after each step.
    #[arg(long)]
    trace: bool,
    /// The output format.
    #[arg(long, value_enum, default_value_t = OutputFormat::Text)]
    format: OutputFormat,
    /// Print an intermediate representation on stdout first: the planning task, the
    /// partial-order plan (with the achievers of every step), the STN, or the schedule.
    #[arg(long, value_enum, value_name = "PASS")]
    dump_after: Option<PlanDump>,
    /// Print the timed plan, in the PDDL 2.1 plan format, instead of the total order.
    #[arg(long)]
    schedule: bool,
    /// Write a picture instead: the partial order or the STN as Graphviz, or the schedule as
    /// an SVG Gantt chart with one lane per arm.
    #[arg(long, value_enum, value_name = "KIND")]
    emit: Option<Emit>,
    /// Where `--emit` writes (default: stdout).
    #[arg(short, long, value_name = "FILE", requires = "emit")]
    output: Option<PathBuf>,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum PlanDump {
    /// The planning task the search runs on.
    Task,
    /// The partial-order plan: achievers and orderings.
    Pop,
    /// The simple temporal network.
    Stn,
    /// The schedule: each snap action's earliest and latest time and its slack.
    Schedule,
    /// The minimal network: the tightest bounds the STN implies between every pair of time
    /// points (all-pairs shortest paths; its size grows with the square of the plan's).
    Minimal,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum Emit {
    /// The partial-order plan as Graphviz DOT.
    PopDot,
    /// The STN's distance graph as Graphviz DOT.
    StnDot,
    /// The schedule as an SVG Gantt chart, one lane per arm.
    GanttSvg,
}

#[derive(Clone, Copy, ValueEnum)]
pub(super) enum SearchArg {
    /// The paper's Algorithm 1: depth-first in clause order with a depth limit.
    Paper,
    /// Greedy best-first search guided by h_FF.
    Heuristic,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum OutputFormat {
    Text,
    Json,
}

/// Prints a progress line on a terminal once a search has run for a second.
struct TerminalProgress {
    started: Instant,
    enabled: bool,
    shown: bool,
    /// When the line was last drawn: it is redrawn at most ten times a second.
    drawn: Option<Instant>,
}

impl Progress for TerminalProgress {
    fn report(&mut self, stats: &Stats) {
        let elapsed = self.started.elapsed();
        let due = self.drawn.is_none_or(|d| d.elapsed() >= Duration::from_millis(100));
        if self.enabled && elapsed > Duration::from_secs(1) && due {
            self.drawn = Some(Instant::now());
            eprint!(
                "\r  searching: {} states expanded, {} generated, {:.1} s ",
                stats.expanded,
                stats.generated,
                elapsed.as_secs_f64()
            );
            self.shown = true;
        }
    }
}

/// A plan found (or read), checked and scheduled, with everything that made it.
pub(super) struct Planned {
    pub(super) db: SourceDb,
    pub(super) diagnostics: Diagnostics,
    pub(super) frontend: driver::Frontend,
    pub(super) problem: usize,
    /// Every plan found; `index` is the one kept.
    pub(super) plans: Vec<Plan>,
    pub(super) index: usize,
    pub(super) timed: driver::Timed,
    /// Where the plan came from, for the output's first line.
    pub(super) origin: String,
    pub(super) stats: Option<Stats>,
    pub(super) task: crate::ir::task::Task,
}

/// The search options the arguments ask for; a timeout counts from now.
pub(super) fn search_options(args: &PlanningArgs) -> Options {
    let search = match args.search {
        SearchArg::Paper => SearchKind::Paper,
        SearchArg::Heuristic => SearchKind::Heuristic,
    };
    Options {
        search,
        max_depth: args.max_depth,
        budget: planner::Budget {
            max_states: args.max_states,
            deadline: args.timeout.map(|s| Instant::now() + Duration::from_secs_f64(s.max(0.0))),
            max_bytes: (args.max_memory as usize).saturating_mul(1 << 20),
            ..planner::Budget::default()
        },
        plans: args.retries as usize + 1,
        improve: args.improve.map(|s| Duration::from_secs_f64(s.max(0.0))),
    }
}

/// Whether the plans the search finds go through the `reassign` pass: the heuristic search's,
/// unless `--no-reassign` (for `kbc run`, its replans after a fault too).
pub(super) fn reassigns_search_plans(args: &PlanningArgs) -> bool {
    matches!(args.search, SearchArg::Heuristic) && !args.no_reassign
}

/// Whether the search scores its plans by their makespan after `reassign` (while improving).
fn scored(args: &PlanningArgs) -> bool {
    args.plan.is_none() && args.improve.is_some() && reassigns_search_plans(args)
}

/// Runs the front end, finds (or reads and checks) a plan and schedules it; on failure the
/// diagnostics are already printed and the exit status is returned.
pub(super) fn plan_and_schedule(args: &PlanningArgs, color: bool, dump_task: bool) -> Result<Planned, ExitCode> {
    let mut db = SourceDb::new();
    let mut diagnostics = Diagnostics::new();
    let fail = |db: &SourceDb, diagnostics: &Diagnostics| super::fail(db, diagnostics, args.message_format, color);
    let found = super::frontend_for_problem(&args.files, args.problem.as_deref(), &mut db, &mut diagnostics);
    let Some((mut frontend, problem)) = found else {
        return Err(fail(&db, &diagnostics));
    };
    let program = planner::program_for(&frontend.kb, problem);
    // The total-order plans to schedule: read from a file, or found by the search.
    let (mut plans, mut origin, stats, mut task) = match &args.plan {
        Some(path) => {
            let plan_file = super::read_roots(std::slice::from_ref(path), &mut db, &mut diagnostics);
            let Some(&file) = plan_file.first() else { return Err(fail(&db, &diagnostics)) };
            let text = db.file(file).text_arc();
            let steps = validate::read_plan(file, &text, &mut frontend.interner, &mut diagnostics);
            if diagnostics.has_errors() {
                return Err(fail(&db, &diagnostics));
            }
            let verdict = validate::validate(&frontend.kb, &frontend.interner, &program, problem, &steps);
            diagnostics.extend(verdict.diagnostics);
            if diagnostics.has_errors() {
                return Err(fail(&db, &diagnostics));
            }
            let task = passes::task::build(&frontend.kb, problem);
            (vec![verdict.plan], format!("plan file {}", path.display()), None, task)
        }
        None => {
            let mut task = passes::task::build(&frontend.kb, problem);
            if cfg!(debug_assertions) {
                crate::ir::task::verify(&task)
                    .unwrap_or_else(|e| panic!("internal compiler error: the task verifier failed: {e}"));
            }
            if dump_task {
                let text = crate::ir::task::print(&frontend.interner, &frontend.kb, &task);
                let _ = std::io::stdout().lock().write_all(text.as_bytes());
            }
            let options = search_options(args);
            let search = options.search;
            let mut progress = TerminalProgress {
                started: Instant::now(),
                enabled: std::io::stderr().is_terminal(),
                shown: false,
                drawn: None,
            };
            // While improving, plans are judged by the makespan they end up with.
            let mut scorer =
                driver::ReassignedMakespan { kb: &frontend.kb, interner: &frontend.interner, program: &program };
            let scorer = scored(args).then_some(&mut scorer as &mut dyn planner::Score);
            let outcome =
                planner::search_scored(&frontend.kb, &frontend.interner, &mut task, &options, scorer, &mut progress);
            if progress.shown {
                eprint!("\r{:60}\r", "");
            }
            let name = frontend.interner.resolve(frontend.kb.problems[problem].name).to_string();
            match outcome.result {
                Ok(first) => {
                    let mut plans = vec![first];
                    plans.extend(outcome.alternatives);
                    let origin = match search {
                        SearchKind::Paper => "paper search",
                        SearchKind::Heuristic => "heuristic search",
                    };
                    (plans, origin.to_string(), Some(outcome.stats), task)
                }
                Err(failure) => {
                    let (kb, interner) = (&frontend.kb, &frontend.interner);
                    diagnostics.push(planner::failure_diagnostic(
                        kb,
                        interner,
                        &task,
                        &name,
                        &failure,
                        &outcome.stats,
                        &stats_line(&outcome.stats),
                        &options,
                    ));
                    return Err(fail(&db, &diagnostics));
                }
            }
        }
    };
    let (kb, interner) = (&frontend.kb, &frontend.interner);
    // Schedule the plans: with `--improve`, each plan found has a shorter estimated makespan
    // than the one before, so the best schedule is sought among all of them; otherwise the
    // first that can be scheduled is kept (`--retries` asks for more when it cannot). The
    // heuristic search's plans go through the `reassign` pass, which remakes its choice of
    // arms and order of jobs where that is shorter; the paper's search and plan files are
    // scheduled as they are.
    let reassign = args.plan.is_none() && reassigns_search_plans(args);
    // Plans the search scored come shortest last: the last one that can be scheduled is the one.
    let order: Vec<usize> = if scored(args) { (0..plans.len()).rev().collect() } else { (0..plans.len()).collect() };
    // (index, schedule, makespan before `reassign`)
    let mut chosen: Option<(usize, driver::Timed, i64)> = None;
    let mut first_failure: Option<Diagnostics> = None;
    for index in order {
        let plan = &mut plans[index];
        if cfg!(debug_assertions) {
            plan::verify(kb, plan).unwrap_or_else(|e| panic!("internal compiler error: the plan verifier failed: {e}"));
        }
        let mut attempt = Diagnostics::new();
        match driver::schedule(kb, interner, &program, plan, &mut attempt) {
            Some(timed) => {
                let searched = timed.schedule.makespan;
                let timed = if reassign {
                    let (rearranged, timed) =
                        driver::reassign(kb, interner, &program, &mut task, std::mem::take(plan), timed);
                    *plan = rearranged;
                    timed
                } else {
                    timed
                };
                let better =
                    chosen.as_ref().is_none_or(|(_, best, _)| timed.schedule.makespan < best.schedule.makespan);
                if better {
                    if chosen.is_none() {
                        diagnostics.extend(attempt); // warnings, once
                    }
                    chosen = Some((index, timed, searched));
                }
                if args.improve.is_none() || scored(args) {
                    break;
                }
            }
            None => {
                first_failure.get_or_insert(attempt);
                if !scored(args) && chosen.is_none() && index >= args.retries as usize {
                    break;
                }
            }
        }
    }
    let Some((index, timed, searched)) = chosen else {
        diagnostics.extend(first_failure.unwrap_or_default());
        if plans.len() > 1 {
            diagnostics.push(Diagnostic::note(format!(
                "the search found {} plans and none of them can be scheduled",
                plans.len()
            )));
        }
        return Err(fail(&db, &diagnostics));
    };
    if timed.schedule.makespan < searched {
        origin = format!("{origin}, jobs reassigned from a makespan of {}", format_time(searched));
    }
    Ok(Planned { db, diagnostics, frontend, problem, plans, index, timed, origin, stats, task })
}

pub(super) fn run(args: PlanArgs, color: bool) -> ExitCode {
    let dump_task = args.dump_after == Some(PlanDump::Task);
    let planned = match plan_and_schedule(&args.planning, color, dump_task) {
        Ok(planned) => planned,
        Err(status) => return status,
    };
    let Planned { db, diagnostics, frontend, problem, plans, index, timed, origin, stats, mut task } = planned;
    let (kb, interner) = (&frontend.kb, &frontend.interner);
    let plan = &plans[index];
    match args.dump_after {
        Some(PlanDump::Pop) => print_out(&crate::ir::pop::print(interner, &timed.pop)),
        Some(PlanDump::Stn) => print_out(&crate::ir::stn::print(interner, &timed.pop, &timed.stn)),
        Some(PlanDump::Schedule) => print_out(&schedule::dump(interner, &timed.pop, &timed.schedule)),
        Some(PlanDump::Minimal) => {
            let network = passes::schedule::MinimalNetwork::new(&timed.stn, &timed.schedule);
            let mut out = std::io::BufWriter::new(std::io::stdout().lock());
            let _ = crate::ir::stn::print_minimal(&timed.stn, |node| network.row(node), &mut out);
            let _ = out.flush();
        }
        _ => {}
    }
    report(&db, &diagnostics, args.planning.message_format, color);
    if let Some(emit) = args.emit {
        let text = match emit {
            Emit::PopDot => render::dot::pop(interner, &timed.pop),
            Emit::StnDot => render::dot::stn(interner, &timed.pop, &timed.stn),
            Emit::GanttSvg => render::gantt::svg(interner, kb, &timed.pop, &timed.schedule),
        };
        match &args.output {
            Some(path) => {
                if let Err(error) = super::write_atomically(path, text.as_bytes()) {
                    eprintln!("error: cannot write `{}`: {error}", path.display());
                    return ExitCode::from(1);
                }
            }
            None => print_out(&text),
        }
        if args.output.is_none() {
            return ExitCode::SUCCESS;
        }
    }
    let problem_name = interner.resolve(kb.problems[problem].name).to_string();
    let figures = Figures::of(&timed, stats.as_ref(), index, plans.len());
    let text = match args.format {
        OutputFormat::Text if args.schedule => schedule_text(interner, kb, &timed, &problem_name, &origin, &figures),
        OutputFormat::Text => plan_text(interner, kb, &mut task, plan, &problem_name, &origin, &figures, args.trace),
        OutputFormat::Json => plan_json(kb, interner, plan, &timed, &problem_name, &origin, &figures),
    };
    print_out(&text);
    ExitCode::SUCCESS
}

fn print_out(text: &str) {
    let _ = std::io::stdout().lock().write_all(text.as_bytes());
}

/// What the output says about the plan and the search.
struct Figures {
    makespan: i64,
    /// The makespan if one action ran at a time, each taking its minimum duration.
    sequential: i64,
    stats: Option<Stats>,
    /// Which of how many plans found was kept.
    kept: (usize, usize),
}

impl Figures {
    fn of(timed: &driver::Timed, stats: Option<&Stats>, index: usize, found: usize) -> Figures {
        let sequential = timed.stn.durations.iter().flatten().map(|b| b.min).sum::<i64>();
        Figures { makespan: timed.schedule.makespan, sequential, stats: stats.copied(), kept: (index, found) }
    }

    fn line(&self) -> String {
        let speedup = if self.makespan > 0 { self.sequential as f64 / self.makespan as f64 } else { 1.0 };
        let mut line = format!(
            "makespan {} time units; one action at a time: {} ({speedup:.2}x)",
            format_time(self.makespan),
            format_time(self.sequential)
        );
        if self.kept.1 > 1 {
            line.push_str(&format!("; plan {} of {} found", self.kept.0 + 1, self.kept.1));
        }
        if let Some(stats) = &self.stats {
            line.push_str("; ");
            line.push_str(&stats_line(stats));
        }
        line
    }
}

/// The process's peak resident memory in bytes (`VmHWM`), where the system reports it.
fn process_peak_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kilobytes: u64 = line.trim_start_matches("VmHWM:").trim().trim_end_matches("kB").trim().parse().ok()?;
    Some(kilobytes * 1024)
}

pub(super) fn stats_line(stats: &Stats) -> String {
    format!(
        "expanded {} {}, generated {}, evaluated {}; {:.3} s; states stored {:.1} MB{}",
        stats.expanded,
        if stats.expanded == 1 { "state" } else { "states" },
        stats.generated,
        stats.evaluated,
        stats.elapsed.as_secs_f64(),
        stats.peak_bytes as f64 / 1e6,
        process_peak_bytes().map_or(String::new(), |b| format!(", process peak {:.1} MB", b as f64 / 1e6))
    )
}

#[allow(clippy::too_many_arguments)]
fn plan_text(
    interner: &crate::intern::Interner,
    kb: &Kb,
    task: &mut crate::ir::task::Task,
    plan: &Plan,
    problem: &str,
    origin: &str,
    figures: &Figures,
    trace: bool,
) -> String {
    let mut out = format!("% plan for {problem} ({origin}): {} snap actions\n", plan.steps.len());
    if trace {
        let no_vars = VarTable::default();
        let states = planner::replay(task, plan);
        let width = plan.steps.len().to_string().len();
        let show = |state: &crate::ir::task::State, task: &crate::ir::task::Task| {
            let mut facts: Vec<String> = state
                .facts()
                .map(|f| hir::term_to_string(interner, &task.facts.to_term(&task.consts, f), &no_vars))
                .collect();
            facts.sort();
            format!("[{}]", facts.join(", "))
        };
        out.push_str(&format!("% {:>width$}  state: {}\n", "", show(&task.init, task)));
        for (i, (step, state)) in plan.steps.iter().zip(&states).enumerate() {
            out.push_str(&format!("{:>width$}  {}\n", i + 1, hir::term_to_string(interner, &step.name, &no_vars)));
            out.push_str(&format!("% {:>width$}  state: {}\n", "", show(state, task)));
        }
    } else {
        out.push_str(&plan::print(interner, kb, plan));
    }
    out.push_str(&format!("% {}\n", figures.line()));
    out
}

fn schedule_text(
    interner: &crate::intern::Interner,
    kb: &Kb,
    timed: &driver::Timed,
    problem: &str,
    origin: &str,
    figures: &Figures,
) -> String {
    let actions = schedule::timed_actions(kb, &timed.pop, &timed.schedule).len();
    let mut out = format!("% schedule for {problem} ({origin}): {actions} actions, earliest start times\n");
    out.push_str(&schedule::print(interner, kb, &timed.pop, &timed.schedule));
    out.push_str(&format!("% {}\n", figures.line()));
    out
}

fn plan_json(
    kb: &Kb,
    interner: &crate::intern::Interner,
    plan: &Plan,
    timed: &driver::Timed,
    problem: &str,
    origin: &str,
    figures: &Figures,
) -> String {
    let no_vars = VarTable::default();
    let steps: Vec<serde_json::Value> = plan
        .steps
        .iter()
        .enumerate()
        .map(|(i, step)| {
            let action = &kb.actions[step.action];
            serde_json::json!({
                "index": i + 1,
                "action": hir::term_to_string(interner, &step.name, &no_vars),
                "snap": match action.snap { hir::Snap::Start => "start", hir::Snap::End => "end", hir::Snap::Instant => "instant" },
                "durative_action": interner.resolve(action.base),
                "achievers": timed.pop.achievers(i).iter().map(|a| match a {
                    Achiever::Init => 0,
                    Achiever::Step(j) => j + 1,
                }).collect::<Vec<_>>(),
                "time": timed.schedule.earliest[i] as f64 / UNITS as f64,
                "latest": timed.schedule.latest[i] as f64 / UNITS as f64,
            })
        })
        .collect();
    let schedule: Vec<serde_json::Value> = schedule::timed_actions(kb, &timed.pop, &timed.schedule)
        .iter()
        .map(|a| {
            serde_json::json!({
                "time": a.time as f64 / UNITS as f64,
                "action": hir::term_to_string(interner, &a.name, &no_vars),
                "duration": a.duration.map(|d| d as f64 / UNITS as f64),
            })
        })
        .collect();
    let mut value = serde_json::json!({
        "problem": problem,
        "origin": origin,
        "steps": steps,
        "schedule": schedule,
        "makespan": figures.makespan as f64 / UNITS as f64,
        "sequential": figures.sequential as f64 / UNITS as f64,
    });
    if let Some(stats) = &figures.stats {
        value["stats"] = serde_json::json!({
            "expanded": stats.expanded,
            "generated": stats.generated,
            "evaluated": stats.evaluated,
            "seconds": stats.elapsed.as_secs_f64(),
            "stored_bytes": stats.peak_bytes,
            "process_peak_bytes": process_peak_bytes(),
        });
    }
    format!("{value}\n")
}
