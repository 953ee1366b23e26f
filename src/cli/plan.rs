//! `kbc plan`: finds a total-order plan for one problem (or reads one), schedules it, and
//! prints it.
//!
//! The text output is itself a plan file: numbered snap actions, with figures and traces as
//! `%` comment lines, so `kbc plan ... > plan.txt` feeds `kbc validate`; with `--schedule` it
//! is a timed plan in the PDDL 2.1 format, which `kbc validate` reads too.

use std::io::{IsTerminal, Write};
use std::path::PathBuf;
use std::process::ExitCode;
use std::rc::Rc;
use std::time::{Duration, Instant};

use clap::ValueEnum;

use super::{MessageFormat, report};
use crate::ir::hir::{self, Kb, VarTable};
use crate::ir::plan::{self, Plan};
use crate::ir::pop::Achiever;
use crate::ir::schedule;
use crate::ir::stn::{UNITS, format_time};
use crate::planner::{Progress, SearchKind, Stats};
use crate::render;
use crate::session::{self, Pass, PlanSettings, Session};

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
    /// Give up when the stored states, or the heuristic's tables, exceed this many megabytes.
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
    /// As `--improve`, but for this many states expanded after the first plan instead of a
    /// time, so that every run gives the same plan (heuristic search; not with `--improve`)
    #[arg(long, value_name = "N", default_value_t = 0, conflicts_with = "improve")]
    pub(super) improve_states: u64,
    /// Keep the search's choice of arm for each job and its order of jobs, and its waiting
    /// starts (by default the heuristic search's plan is rearranged when that shortens its
    /// makespan: the `reassign` pass, which also sends a start that holds an arm waiting
    /// aside, such as a block moved to a free cell first).
    #[arg(long)]
    pub(super) no_reassign: bool,
    /// Expand every successor the heuristic search generates, even those that differ from
    /// another only by interchangeable constants, such as two idle arms (by default one of
    /// each such set is kept: the one whose arm is free soonest).
    #[arg(long)]
    pub(super) no_symmetry: bool,
    /// Jump ahead along relaxed plans: at each state with a better estimate than any before,
    /// the heuristic search also applies the actions of its relaxed plan as far as they apply
    /// and adds the state reached. Much faster on large problems; on some smaller ones the
    /// makespans get longer. `auto` turns it on when the initial state's estimate (landmarks
    /// plus h_FF, `-v` says whether it was on) is 400 or more, and once a search without it
    /// has expanded 1000 states without a plan. `--lookahead` alone means `on`; give a value
    /// as `--lookahead=off`.
    #[arg(long, value_enum, value_name = "WHEN", num_args = 0..=1, require_equals = true, default_value_t = LookaheadArg::Auto,
          default_missing_value = "on")]
    pub(super) lookahead: LookaheadArg,
    /// Which plan: the high-level actions, or the arm-level actions they refine into through
    /// `mapping/2` and `ll_action/6` (with its own achievers, schedule and tree).
    #[arg(long, value_enum, default_value_t = LevelArg::High)]
    pub(super) level: LevelArg,
    /// The least time between two ordered snap actions, an end and a start that depends on
    /// it included, in time units (kbc keeps thousandths). The default suits Kairos; VAL's
    /// default tolerance wants 0.01.
    #[arg(long, value_name = "TIME", default_value = "0.001", value_parser = parse_epsilon)]
    pub(super) epsilon: i64,
}

/// `--epsilon`: a time of at least 0.001 and at most 1000 time units, in STN time.
pub(super) fn parse_epsilon(text: &str) -> Result<i64, String> {
    let value: f64 = text.parse().map_err(|_| format!("`{text}` is not a number"))?;
    let thousandths = (value * crate::ir::stn::UNITS as f64).round();
    if !(1.0..=1_000_000.0).contains(&thousandths) {
        return Err("expected a time from 0.001 to 1000".to_string());
    }
    Ok(thousandths as i64)
}

/// When the heuristic search follows relaxed plans ahead (`--lookahead`).
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(super) enum LookaheadArg {
    /// On large problems (an initial estimate of 400 or more), and after 1000 expansions
    /// without a plan.
    Auto,
    /// Always.
    On,
    /// Never.
    Off,
}

impl From<LookaheadArg> for crate::planner::Lookahead {
    fn from(arg: LookaheadArg) -> Self {
        match arg {
            LookaheadArg::Auto => crate::planner::Lookahead::Auto,
            LookaheadArg::On => crate::planner::Lookahead::On,
            LookaheadArg::Off => crate::planner::Lookahead::Off,
        }
    }
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(super) enum LevelArg {
    /// The plan of `action/6`s.
    High,
    /// The plan of `ll_action/6`s the high-level plan refines into.
    Arm,
}

#[derive(clap::Args)]
pub(super) struct PlanArgs {
    #[command(flatten)]
    planning: PlanningArgs,
    /// Print the state after each step (of the high-level plan).
    #[arg(long, conflicts_with = "level")]
    trace: bool,
    /// The output format.
    #[arg(long, value_enum, default_value_t = OutputFormat::Text)]
    format: OutputFormat,
    /// Print the intermediate representation after this pass on stdout first: the syntax
    /// tree, the resolved KB, the planning task, the partial-order plan (with the achievers
    /// of every step), the STN, the schedule, the minimal network or the behaviour tree.
    #[arg(long, value_enum, value_name = "PASS")]
    dump_after: Option<Pass>,
    /// Print the timed plan, in the PDDL 2.1 plan format, instead of the total order.
    #[arg(long)]
    schedule: bool,
    /// Write a picture instead: the partial order or the STN as Graphviz, or the schedule as
    /// an SVG Gantt chart with one lane per arm.
    #[arg(long, value_enum, value_name = "KIND")]
    emit: Option<Emit>,
    /// Where `--emit` writes (default, or `-`: stdout); the plan itself is not printed then.
    #[arg(short, long, value_name = "FILE", requires = "emit")]
    output: Option<PathBuf>,
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

impl PlanningArgs {
    /// The session's settings for these arguments.
    pub(super) fn settings(&self) -> PlanSettings {
        PlanSettings {
            search: match self.search {
                SearchArg::Paper => SearchKind::Paper,
                SearchArg::Heuristic => SearchKind::Heuristic,
            },
            max_depth: self.max_depth,
            max_states: self.max_states,
            timeout: self.timeout.map(|s| Duration::from_secs_f64(s.max(0.0))),
            max_bytes: (self.max_memory as usize).saturating_mul(1 << 20),
            retries: self.retries as usize,
            improve: self.improve.map(|s| Duration::from_secs_f64(s.max(0.0))),
            improve_states: self.improve_states,
            reassign: !self.no_reassign,
            plan_file: None,
            epsilon: self.epsilon,
            symmetry: !self.no_symmetry,
            lookahead: self.lookahead.into(),
            tie_seed: None,
            stalled: false,
            thorough: false,
        }
    }
}

/// Opens a session on the files, finds (or reads and checks) a plan and schedules it; prints
/// the IR after `dump` when it comes before the plan (the task, or a front-end pass). On
/// failure the diagnostics are already printed and the exit status is returned.
pub(super) fn plan_and_schedule(
    args: &PlanningArgs,
    color: bool,
    dump: Option<Pass>,
) -> Result<(Session, Rc<session::Planned>), ExitCode> {
    let (mut session, problem) = super::open_for_problem(&args.files, args.problem.as_deref());
    let fail = |session: &Session| super::fail(session.db(), session.diagnostics(), args.message_format, color);
    if let Some(pass) = dump.filter(|p| p.is_frontend()) {
        let _ = session.dump_frontend(pass, &mut std::io::stdout().lock());
    }
    let Some(problem) = problem else { return Err(fail(&session)) };
    let mut settings = args.settings();
    if let Some(path) = &args.plan {
        let Some(file) = session.read_file(path) else { return Err(fail(&session)) };
        settings.plan_file = Some(file);
    } else if dump == Some(Pass::Task) {
        let _ = session.dump_task(problem, &mut std::io::stdout().lock());
    }
    let mut progress = TerminalProgress {
        started: Instant::now(),
        enabled: std::io::stderr().is_terminal(),
        shown: false,
        drawn: None,
    };
    let mut planned = session.plan(problem, &settings, &mut progress);
    if args.level == LevelArg::Arm
        && let Ok(high) = planned
    {
        planned = session.refine(high, &settings, &mut progress);
    }
    if progress.shown {
        eprint!("\r{:60}\r", "");
    }
    match planned {
        Ok(planned) => Ok((session, planned)),
        Err(_) => Err(fail(&session)),
    }
}

pub(super) fn run(args: PlanArgs, color: bool) -> ExitCode {
    let dump = args.dump_after;
    let (mut session, planned) = match plan_and_schedule(&args.planning, color, dump) {
        Ok(planned) => planned,
        Err(status) => return status,
    };
    if let Some(pass) = dump.filter(|p| *p > Pass::Task) {
        let mut out = std::io::BufWriter::new(std::io::stdout().lock());
        let _ = session.dump_planned(pass, &planned, &mut out);
        let _ = out.flush();
    }
    report(session.db(), session.diagnostics(), args.planning.message_format, color);
    let (kb, interner) = (session.kb(), session.interner());
    let timed = &planned.timed;
    if let Some(emit) = args.emit {
        let text = match emit {
            Emit::PopDot => render::dot::pop(interner, &timed.pop),
            Emit::StnDot => render::dot::stn(interner, &timed.pop, &timed.stn),
            Emit::GanttSvg => render::gantt::svg(interner, kb, &timed.pop, &timed.schedule),
        };
        // The picture is the output: the plan is not printed as well.
        return match &args.output {
            Some(path) => super::write_output(path, text.as_bytes()).err().unwrap_or(ExitCode::SUCCESS),
            None => {
                print_out(&text);
                ExitCode::SUCCESS
            }
        };
    }
    let problem_name = interner.resolve(kb.problems[planned.problem].name).to_string();
    let figures = Figures::of(timed, planned.stats.as_ref(), planned.index, planned.plans.len());
    let schedule_text =
        args.schedule.then(|| schedule_text(interner, kb, timed, &problem_name, &planned.origin, &figures));
    let origin = &planned.origin;
    let text = match args.format {
        OutputFormat::Text if args.schedule => schedule_text.unwrap_or_default(),
        OutputFormat::Text => {
            let states = args.trace.then(|| session.states(planned.plan()));
            let (kb, interner) = (session.kb(), session.interner());
            match &planned.refinement {
                Some(refinement) => arm_plan_text(interner, kb, &planned, refinement, &problem_name, &figures),
                None => plan_text(interner, kb, planned.plan(), states.as_deref(), &problem_name, origin, &figures),
            }
        }
        OutputFormat::Json => {
            let mut value = plan_json(kb, interner, planned.plan(), timed, &problem_name, origin, &figures);
            if let Some(refinement) = &planned.refinement {
                // Each arm-level step says which high-level step it refines (1-based).
                value["level"] = "arm".into();
                if let Some(steps) = value["steps"].as_array_mut() {
                    for (step, origin) in steps.iter_mut().zip(&refinement.origin) {
                        step["high_level_step"] = (origin + 1).into();
                    }
                }
                let high = refinement.high.plan();
                value["high_level_steps"] = high
                    .steps
                    .iter()
                    .map(|s| hir::term_to_string(interner, &s.name, &VarTable::default()))
                    .collect::<Vec<_>>()
                    .into();
            } else {
                value["level"] = "high".into();
            }
            format!("{value}\n")
        }
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
    fn of(timed: &session::Timed, stats: Option<&Stats>, index: usize, found: usize) -> Figures {
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
            line.push_str(&session::stats_line(stats));
        }
        line
    }
}

/// The plan as a plan file; with `states` (the initial state, then the state after each
/// step), each state as a comment line.
fn plan_text(
    interner: &crate::intern::Interner,
    kb: &Kb,
    plan: &Plan,
    states: Option<&[Vec<hir::Term>]>,
    problem: &str,
    origin: &str,
    figures: &Figures,
) -> String {
    let mut out = format!("% plan for {problem} ({origin}): {} snap actions\n", plan.steps.len());
    match states {
        Some(states) => {
            let no_vars = VarTable::default();
            let width = plan.steps.len().to_string().len();
            let show = |facts: &[hir::Term]| {
                let mut facts: Vec<String> = facts.iter().map(|f| hir::term_to_string(interner, f, &no_vars)).collect();
                facts.sort();
                format!("[{}]", facts.join(", "))
            };
            out.push_str(&format!("% {:>width$}  state: {}\n", "", show(&states[0])));
            for (i, (step, state)) in plan.steps.iter().zip(&states[1..]).enumerate() {
                out.push_str(&format!("{:>width$}  {}\n", i + 1, hir::term_to_string(interner, &step.name, &no_vars)));
                out.push_str(&format!("% {:>width$}  state: {}\n", "", show(state)));
            }
        }
        None => out.push_str(&plan::print(interner, kb, plan)),
    }
    out.push_str(&format!("% {}\n", figures.line()));
    out
}

/// An arm-level plan as a plan file: its steps under the high-level step each comes from.
fn arm_plan_text(
    interner: &crate::intern::Interner,
    kb: &Kb,
    planned: &session::Planned,
    refinement: &session::Refinement,
    problem: &str,
    figures: &Figures,
) -> String {
    let high = refinement.high.plan();
    let mut out = format!(
        "% arm-level plan for {problem} ({}): {} arm-level snap actions for {} high-level ones\n",
        planned.origin,
        planned.plan().steps.len(),
        high.steps.len()
    );
    out.push_str(&plan::print_arm(interner, kb, high, planned.plan(), &refinement.origin));
    out.push_str(&format!("% {}\n", figures.line()));
    out
}

fn schedule_text(
    interner: &crate::intern::Interner,
    kb: &Kb,
    timed: &session::Timed,
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
    timed: &session::Timed,
    problem: &str,
    origin: &str,
    figures: &Figures,
) -> serde_json::Value {
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
        "type": "plan",
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
            "process_peak_bytes": crate::source::fs::process_peak_bytes(),
        });
    }
    value
}
