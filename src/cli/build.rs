//! `kbc build`, `kbc run` and `kbc disasm`: the back end and the VM from the command line.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::ValueEnum;
use kbvm::Program;
use kbvm::bytecode::MAGIC;

use super::plan::{PlanningArgs, plan_and_schedule};
use super::{MessageFormat, report, write_output};
use crate::diag::{Diagnostic, Diagnostics, codes};
use crate::execute;
use crate::recover;
use crate::render;
use crate::session::{self, HostProfile, Pass, Session};
use crate::source::SourceDb;
use kbvm::bytecode::Instr;
use kbvm::run::{self as vm_run, HostEvent, Logged, Outcome, TraceHost};
use kbvm::sim::{FaultSpec, Rng, SimConfig};

#[derive(clap::Args)]
pub(super) struct BuildArgs {
    #[command(flatten)]
    planning: PlanningArgs,
    /// Where to write the output (required for bytecode; other kinds default to stdout).
    #[arg(short, long, value_name = "FILE")]
    output: Option<PathBuf>,
    /// What to write: the bytecode, the tree as BehaviorTree.CPP v4 XML, or as Graphviz.
    #[arg(long, value_enum, value_name = "KIND", default_value_t = BuildEmit::Bytecode)]
    emit: BuildEmit,
    /// Print the intermediate representation after this pass on stdout first (any pass up to
    /// `bt`, the behaviour tree).
    #[arg(long, value_enum, value_name = "PASS")]
    dump_after: Option<Pass>,
    /// Check that the host can run every action of the plan (directly or through its
    /// `mapping/2` refinement).
    #[arg(long, value_enum, value_name = "HOST")]
    host: Option<HostKind>,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum BuildEmit {
    /// The VM's bytecode (`.kbb`).
    Bytecode,
    /// BehaviorTree.CPP v4 XML, for ROS tools and Groot2.
    BtXml,
    /// Graphviz DOT.
    BtDot,
}

#[derive(clap::Args)]
pub(super) struct RunArgs {
    /// The files, and how to plan them when they are KB files.
    #[command(flatten)]
    planning: PlanningArgs,
    /// The host that runs the actions.
    /// (Default: the simulated arms when they can run every action of the plan, else the trace
    /// host, with a note; a bytecode file runs on the simulated arms.)
    #[arg(long, value_enum)]
    host: Option<HostKind>,
    /// Give up when the virtual clock passes this many KB time units.
    #[arg(long, value_name = "UNITS", default_value_t = 100_000.0)]
    max_time: f64,
    /// Give up after this many ticks (of each round, when replanning).
    #[arg(long, value_name = "N", default_value_t = 10_000_000)]
    max_ticks: u64,
    /// Inject a fault into the simulated world: `drop[:ARM]`, `stall[:ARM[:SECONDS]]`,
    /// `stop[:ARM]` or `nudge[:BLOCK[:X:Y]]`, at `@SECONDS` or `@ACTION` (the start of the
    /// first action whose text begins so); open parts are drawn from `--seed`. Repeatable.
    #[arg(long, value_name = "FAULT")]
    fault: Vec<FaultSpec>,
    /// The seed the faults' open parts are drawn from.
    #[arg(long, value_name = "N", default_value_t = 0)]
    seed: u64,
    /// After a fault, read the world back, replan from it and go on (the default).
    #[arg(long, overrides_with = "no_replan")]
    replan: bool,
    /// Stop at the first fault instead of replanning.
    #[arg(long, overrides_with = "replan")]
    no_replan: bool,
    /// Give up after this many recoveries.
    #[arg(long, value_name = "N", default_value_t = 5)]
    max_recoveries: u32,
    /// Save the poses of the blocks and grippers over time as JSON (simulated arms).
    #[arg(long, value_name = "FILE")]
    record: Option<PathBuf>,
    /// Draw the planned and the executed timeline per arm as an SVG Gantt chart (simulated
    /// arms, KB files).
    #[arg(long, value_name = "FILE")]
    gantt_svg: Option<PathBuf>,
    /// Write a page that replays the run (simulated arms): one self-contained HTML file with
    /// a top and a side view, a time slider, play and pause, and the planned-versus-executed
    /// chart. Open it in any browser; `FILE#t=end` opens it at the end.
    #[arg(long, value_name = "FILE")]
    view: Option<PathBuf>,
}

impl RunArgs {
    /// The run's budget as given.
    fn budget(&self) -> execute::RunBudget {
        execute::RunBudget { max_time: self.max_time, max_ticks: self.max_ticks }
    }

    /// `--max-time` in the program's time units.
    fn max_time_units(&self, program: &Program) -> i64 {
        (self.max_time * program.module().time_scale as f64).min(i64::MAX as f64 / 2.0) as i64
    }
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum HostKind {
    /// Simulated arms in a rigid-body world: actions run as their arm-level steps.
    Sim,
    /// A scripted host: every action succeeds after its least duration.
    Trace,
}

impl HostKind {
    /// The host profile the compiler checks the plan against.
    fn profile(self) -> Option<HostProfile<'static>> {
        match self {
            HostKind::Sim => Some(HostProfile::SIMULATED_ARMS),
            HostKind::Trace => None,
        }
    }
}

#[derive(clap::Args)]
pub(super) struct DisasmArgs {
    /// The bytecode file.
    #[arg(value_name = "FILE")]
    file: PathBuf,
}

pub(super) fn build(args: BuildArgs, color: bool) -> ExitCode {
    if args.emit == BuildEmit::Bytecode && args.output.is_none() {
        eprintln!("error: bytecode is binary: give the file to write with `-o FILE` (or `--emit bt-xml` for text)");
        return ExitCode::from(2);
    }
    let dump = args.dump_after;
    let (mut session, planned) = match plan_and_schedule(&args.planning, color, dump) {
        Ok(planned) => planned,
        Err(status) => return status,
    };
    let Some(built) = session.build(&planned, args.host.and_then(HostKind::profile)) else {
        return super::fail(session.db(), session.diagnostics(), args.planning.message_format, color);
    };
    report(session.db(), session.diagnostics(), args.planning.message_format, color);
    if let Some(pass) = dump.filter(|p| *p > Pass::Task) {
        let mut out = std::io::BufWriter::new(std::io::stdout().lock());
        let _ = session.dump_planned(pass, &planned, &mut out);
        let _ = out.flush();
    }
    let module = built.module;
    let bytes = match args.emit {
        BuildEmit::Bytecode => module.encode(),
        BuildEmit::BtXml => render::bt::xml(&module).into_bytes(),
        BuildEmit::BtDot => render::bt::dot(&module).into_bytes(),
    };
    match &args.output {
        Some(path) => {
            if let Err(status) = write_output(path, &bytes) {
                return status;
            }
        }
        None => {
            let _ = std::io::stdout().lock().write_all(&bytes);
        }
    }
    ExitCode::SUCCESS
}

/// Reads and verifies a bytecode file; a refusal is E0501 with the byte offset.
fn load(path: &Path, diagnostics: &mut Diagnostics) -> Option<Program> {
    let bytes = match std::fs::read(path) {
        Ok(bytes) => bytes,
        Err(error) => {
            diagnostics
                .push(Diagnostic::error(codes::BAD_BYTECODE, format!("cannot read `{}`: {error}", path.display())));
            return None;
        }
    };
    match Program::load(&bytes) {
        Ok(program) => Some(program),
        Err(error) => {
            diagnostics.push(
                Diagnostic::error(codes::BAD_BYTECODE, format!("`{}` is not a valid kbc program", path.display()))
                    .with_note(error.to_string())
                    .with_help("rebuild it with `kbc build`; a file from another kbc version must be rebuilt too"),
            );
            None
        }
    }
}

fn is_bytecode(path: &Path) -> bool {
    let mut head = [0u8; 4];
    std::fs::File::open(path).and_then(|mut f| std::io::Read::read_exact(&mut f, &mut head)).is_ok() && head == MAGIC
}

pub(super) fn run(args: RunArgs, color: bool) -> ExitCode {
    let format = args.planning.message_format;
    let sim_only = [
        (!args.fault.is_empty(), "--fault"),
        (args.record.is_some(), "--record"),
        (args.gantt_svg.is_some(), "--gantt-svg"),
        (args.view.is_some(), "--view"),
    ];
    if let Some((_, option)) = sim_only.iter().find(|(given, _)| *given && args.host == Some(HostKind::Trace)) {
        eprintln!("error: `{option}` needs the simulated arms (`--host sim`)");
        return ExitCode::from(2);
    }
    let arm_level = args.planning.level == super::plan::LevelArg::Arm;
    if arm_level && (args.host == Some(HostKind::Sim) || sim_only.iter().any(|(given, _)| *given)) {
        eprintln!(
            "error: `--level arm` runs on the trace host: the simulated arms run the high-level plan through \
             their own steps (std/arms.pl)"
        );
        return ExitCode::from(2);
    }
    // The host that runs it: as asked, else the simulated arms (unless they cannot run the
    // plan); an arm-level plan runs on the trace host.
    let mut host = args.host.unwrap_or(if arm_level { HostKind::Trace } else { HostKind::Sim });
    // The program: loaded, or planned and built here (keeping the session to check the
    // timeline and the goal, and to replan).
    let files = &args.planning.files;
    let (program, session, planned) = if files.len() == 1 && is_bytecode(&files[0]) {
        let mut diagnostics = Diagnostics::new();
        match load(&files[0], &mut diagnostics) {
            Some(program) => (program, None, None),
            None => return super::fail(&SourceDb::new(), &diagnostics, format, color),
        }
    } else {
        let (mut session, planned) = match plan_and_schedule(&args.planning, color, None) {
            Ok(planned) => planned,
            Err(status) => return status,
        };
        let sim_options = sim_only.iter().any(|(given, _)| *given);
        let mut built = session.build(&planned, host.profile());
        let not_provided = session.diagnostics().iter().any(|d| d.code == Some(codes::NOT_PROVIDED));
        if built.is_none() && not_provided && args.host.is_none() && !sim_options {
            // No host asked for, and the arms cannot run the plan: the trace host can.
            let refused = session.take_diagnostics();
            let why = refused.iter().find(|d| d.is_error()).map(|d| d.message.clone()).unwrap_or_default();
            for diagnostic in refused.into_iter().filter(|d| !d.is_error()) {
                session.push(diagnostic);
            }
            session.push(
                Diagnostic::note("the simulated arms cannot run this plan, so it runs on the trace host")
                    .with_note(why)
                    .with_help(
                        "`--host sim` insists on the arms (E0503 says what they lack); `--host trace` chooses this",
                    ),
            );
            host = HostKind::Trace;
            built = session.build(&planned, None);
        }
        let Some(built) = built else {
            return super::fail(session.db(), session.diagnostics(), format, color);
        };
        report(session.db(), session.diagnostics(), format, color);
        let _ = session.take_diagnostics();
        (built.program(), Some(session), Some(planned))
    };
    let problem = planned.as_ref().map_or(0, |p| p.problem);
    let mut diagnostics = Diagnostics::new();
    let scale = program.module().time_scale as f64;
    let makespan = planned.as_ref().map(|p| p.timed.schedule.makespan);
    let mut session = session;
    let sim = match host {
        HostKind::Trace => None,
        HostKind::Sim => {
            let config = SimConfig { units_per_second: program.module().time_scale as i64, ..SimConfig::default() };
            let cells = session.as_mut().map(|s| execute::kb_cells(s, problem)).unwrap_or_default();
            match execute::sim_world(&program, config, &cells) {
                Ok(world) => {
                    let horizon = makespan.unwrap_or(program.module().time_scale as i64 * 10) as f64 / scale;
                    let mut sim = with_faults(world, &args.fault, args.seed, horizon);
                    if args.record.is_some() || args.view.is_some() {
                        sim.record(RECORD_SECONDS);
                    }
                    Some(sim)
                }
                Err(error) => {
                    diagnostics.push(
                        Diagnostic::error(codes::RUN_FAILED, format!("cannot build the simulated world: {error}"))
                            .with_help("the initial state must place every block with `ontable/3` or `on/4` and name the arms with `available/1`"),
                    );
                    let empty = SourceDb::new();
                    let db = session.as_ref().map_or(&empty, |s| s.db());
                    return super::fail(db, &diagnostics, format, color);
                }
            }
        }
    };
    match (sim, session) {
        (Some(sim), Some(session)) => {
            let planned = planned.expect("planned with the session");
            run_with_recovery(&args, color, session, program, &planned, sim)
        }
        (sim, session) => {
            if args.gantt_svg.is_some() {
                eprintln!("error: `--gantt-svg` needs KB files: a bytecode file carries no plan to compare with");
                return ExitCode::from(2);
            }
            run_once(&args, color, session, problem, program, makespan, sim)
        }
    }
}

/// How often `--record` samples the poses, in simulated seconds.
const RECORD_SECONDS: f64 = 0.05;

/// The recorded poses as JSON (the `kbc-sim-record` format of docs/json.md): the world's
/// geometry and names, then one frame per sample.
fn record_value(sim: &kbvm::sim::SimHost) -> serde_json::Value {
    let world = sim.world();
    let config = world.config();
    let frames: Vec<serde_json::Value> = sim
        .frames()
        .iter()
        .map(|f| serde_json::json!({"t": f.time, "blocks": f.blocks, "grippers": f.grippers, "elbows": f.elbows}))
        .collect();
    let faults: Vec<serde_json::Value> = sim
        .injected()
        .iter()
        .map(|(t, what)| serde_json::json!({"t": *t as f64 / config.units_per_second as f64, "what": what}))
        .collect();
    serde_json::json!({
        "format": "kbc-sim-record",
        "version": 1,
        "units": {"length": "m", "time": "s", "rotation": "quaternion x y z w"},
        "units_per_second": config.units_per_second,
        "cell_size": config.cell_size,
        "block_size": config.block_size,
        "cells": world.cells(),
        "blocks": world.block_names(),
        "arms": world.arm_names(),
        "shoulders": world.arm_shoulders(),
        "frames": frames,
        "faults": faults,
    })
}

/// [`record_value`] as one line of JSON.
fn record_json(sim: &kbvm::sim::SimHost) -> String {
    let mut text = serde_json::to_string(&record_value(sim)).expect("JSON of plain values");
    text.push('\n');
    text
}

/// An action as it ran: its text, the arm its name names (an index into the world's arms),
/// its start and end in program time units from the world's start, and how it ended.
struct Ran {
    text: String,
    arm: Option<usize>,
    start: i64,
    end: i64,
    ending: render::gantt::Ending,
}

/// The actions of one round's log, each from its start to its end (or failure, or halt);
/// `offset` is the round's start on the world's clock.
fn ran_actions(program: &Program, arms: &[String], offset: i64, log: &Log) -> Vec<Ran> {
    use render::gantt::Ending;
    let mut open: Vec<(kbvm::bytecode::EventId, i64)> = Vec::new();
    let mut ran = Vec::new();
    for (t, id, event) in log {
        let t = offset + t;
        let ending = match event {
            HostEvent::Start => {
                open.push((*id, t));
                continue;
            }
            HostEvent::Failed(_) => Ending::Failed,
            HostEvent::Halted => Ending::Halted,
            _ => Ending::Done,
        };
        let start = open.iter().position(|(o, _)| o == id).map(|i| open.remove(i).1).unwrap_or(t);
        let text = program.action_text(*id);
        let arm = text.split(['(', ',', ')']).skip(1).find_map(|a| arms.iter().position(|n| n == a.trim()));
        ran.push(Ran { text, arm, start, end: t, ending });
    }
    ran
}

/// The `% ` lines of a run's timeline after its last event (how it ended, the makespans), as
/// one line for the `--view` page.
fn summary_of(timeline: &str) -> String {
    let lines: Vec<&str> = timeline.lines().filter_map(|l| l.strip_prefix("% ")).skip(1).collect();
    lines.join("; ")
}

/// Writes the `--view` page of a run of `rounds` (program, its start on the world's clock,
/// its log).
fn write_view(
    path: &Path,
    title: &str,
    summary: &str,
    sim: &kbvm::sim::SimHost,
    rounds: &[(&Program, i64, &Log)],
    gantt_svg: Option<&str>,
) -> Result<(), ExitCode> {
    let arms = sim.world().arm_names();
    let mut actions = Vec::new();
    for (program, offset, log) in rounds {
        let seconds = |t: i64| t as f64 / program.module().time_scale as f64;
        actions.extend(ran_actions(program, &arms, *offset, log).into_iter().map(|r| render::view::RanAction {
            arm: r.arm.map(|a| arms[a].clone()),
            start: seconds(r.start),
            end: seconds(r.end),
            ending: r.ending,
            text: r.text,
        }));
    }
    let actions = actions.as_slice();
    let record = record_value(sim);
    let page = render::view::html(&render::view::RunView { title, summary, record: &record, actions, gantt_svg });
    write_output(path, page.as_bytes())?;
    if path.as_os_str() != "-" {
        super::status(&format!("wrote {}: open it in a browser to watch the run", path.display()));
    }
    Ok(())
}

/// A host over `world` with the faults asked for, their open parts drawn from `seed`.
fn with_faults(world: kbvm::sim::World, specs: &[FaultSpec], seed: u64, horizon: f64) -> kbvm::sim::SimHost {
    let (arms, blocks) = (world.arm_names(), world.block_names());
    let mut rng = Rng::new(seed);
    let faults = specs.iter().map(|spec| spec.resolve(&arms, &blocks, horizon, &mut rng)).collect();
    kbvm::sim::SimHost::with_faults(world, faults, seed)
}

/// One timeline entry: the world's time, then the line.
type Entry = (i64, String);

/// A run's log: each event's time (program units), action and what happened.
type Log = [(i64, kbvm::bytecode::EventId, HostEvent)];

fn timeline_entries(program: &Program, offset: i64, log: &Log) -> Vec<Entry> {
    let time = |t: i64| program.time_text(t);
    log.iter()
        .map(|(t, id, event)| {
            let text = program.action_text(*id);
            let (what, why) = match event {
                HostEvent::Start => ("start", String::new()),
                HostEvent::Done => ("done", String::new()),
                HostEvent::Failed(why) => ("FAILED", format!(": {why}")),
                HostEvent::Halted => ("halted", String::new()),
                _ => ("other", String::new()),
            };
            (offset + t, format!("{:>9}  {what:<6}  {text}{why}\n", time(offset + t)))
        })
        .collect()
}

/// The faults injected between `from` and `to` (the world's clock), as timeline entries.
fn fault_entries(program: &Program, injected: &[(i64, String)], from: i64, to: Option<i64>) -> Vec<Entry> {
    injected
        .iter()
        .filter(|(t, _)| *t >= from && to.is_none_or(|to| *t < to))
        .map(|(t, what)| (*t, format!("{:>9}  FAULT   {what}\n", program.time_text(*t))))
        .collect()
}

/// Runs a program once: on the trace host, or on the simulated arms without replanning (a
/// bytecode file carries no KB to replan with).
#[allow(clippy::too_many_arguments)]
fn run_once(
    args: &RunArgs,
    color: bool,
    session: Option<Session>,
    problem: usize,
    program: Program,
    planned: Option<i64>,
    sim: Option<kbvm::sim::SimHost>,
) -> ExitCode {
    let max_time = args.max_time_units(&program);
    let format = args.planning.message_format;
    let mut diagnostics = Diagnostics::new();
    let empty = SourceDb::new();
    let fail = |session: &Option<Session>, diagnostics: &Diagnostics| {
        super::fail(session.as_ref().map_or(&empty, |s| s.db()), diagnostics, format, color)
    };
    let (result, log, world) = match sim {
        None => {
            let mut host = Logged::new(TraceHost::default());
            let result = vm_run::run(&program, &mut host, max_time, args.max_ticks);
            (result, host.log, None)
        }
        Some(sim) => {
            let mut host = Logged::new(sim);
            let result = vm_run::run(&program, &mut host, max_time, args.max_ticks);
            // The world at the program's end (the tree may end on a wait that calls no host).
            host.host.advance_to(result.end);
            (result, host.log, Some(host.host))
        }
    };
    let time = |t: i64| program.time_text(t);
    let mut entries = timeline_entries(&program, 0, &log);
    if let Some(sim) = &world {
        entries.extend(fault_entries(&program, sim.injected(), 0, None));
    }
    entries.sort_by_key(|e| e.0);
    let mut out = String::from("% time      event   action\n");
    entries.iter().for_each(|(_, line)| out.push_str(line));
    let end = time(result.end);
    match &result.outcome {
        Outcome::Success => out.push_str(&format!("% success at {}; {} ticks\n", end, result.ticks)),
        _ => out.push_str(&format!("% stopped at {}; {} ticks\n", end, result.ticks)),
    }
    if let Some(planned) = planned {
        out.push_str(&format!("% makespan: planned {}, achieved {}\n", time(planned), end));
    }
    let _ = std::io::stdout().lock().write_all(out.as_bytes());
    if let (Some(path), Some(sim)) = (&args.record, &world)
        && let Err(status) = write_output(path, record_json(sim).as_bytes())
    {
        return status;
    }
    if let (Some(path), Some(sim)) = (&args.view, &world) {
        let title = args.planning.files.first().map_or(String::new(), |f| f.display().to_string());
        let summary = summary_of(&out);
        if let Err(status) = write_view(path, &title, &summary, sim, &[(&program, 0, &log)], None) {
            return status;
        }
    }
    if let Some(diagnostic) = execute::outcome_diagnostic(&program, &result.outcome, &end, args.budget()) {
        diagnostics.push(diagnostic);
        if world.is_some() && !args.fault.is_empty() {
            diagnostics.push(Diagnostic::note("replanning after a fault needs the KB files, not a bytecode file"));
        }
        return fail(&session, &diagnostics);
    }
    let Some(mut session) = session else {
        // A bytecode file carries no goal: show the world as it ends.
        if let Some(sim) = &world {
            let (facts, unaccounted) = sim.world().facts();
            let mut out = String::from("% the world read back (the bytecode carries no goal to check):\n");
            for f in &facts {
                out.push_str(&format!("%   {f}\n"));
            }
            for u in &unaccounted {
                out.push_str(&format!("%   unaccounted: {u}\n"));
            }
            let _ = std::io::stdout().lock().write_all(out.as_bytes());
            if !unaccounted.is_empty() {
                diagnostics
                    .push(Diagnostic::error(codes::GOAL_NOT_REACHED, "some blocks are not on a cell of the table"));
                return fail(&None, &diagnostics);
            }
        }
        return ExitCode::SUCCESS;
    };
    // Planned here (on the trace host): the executed timeline must satisfy the KB.
    let timeline = execute::check_timeline(&mut session, problem, &program, &result);
    if timeline.has_errors() {
        diagnostics.extend(timeline);
        return super::fail(session.db(), &diagnostics, format, color);
    }
    let _ = writeln!(std::io::stdout().lock(), "% the executed timeline is valid for the KB");
    ExitCode::SUCCESS
}

/// Runs a planned program on the simulated arms, replanning after faults as asked, and
/// checks the goal in the world read back.
fn run_with_recovery(
    args: &RunArgs,
    color: bool,
    mut session: Session,
    program: Program,
    first_plan: &session::Planned,
    sim: kbvm::sim::SimHost,
) -> ExitCode {
    let format = args.planning.message_format;
    let problem = first_plan.problem;
    let plan_settings = args.planning.settings();
    let settings = recover::Settings {
        replan: !args.no_replan,
        max_recoveries: args.max_recoveries,
        plan: &plan_settings,
        profile: HostProfile::SIMULATED_ARMS,
        max_time: args.max_time_units(&program),
        max_ticks: args.max_ticks,
    };
    let planned = first_plan.timed.schedule.makespan;
    let execution = recover::execute(&mut session, problem, program, planned, sim, &settings);
    let first = &execution.rounds[0].program;
    let time = |t: i64| first.time_text(t);
    let injected = execution.sim.injected();
    let mut out = String::from("% time      event   action\n");
    for (i, round) in execution.rounds.iter().enumerate() {
        let end = round.offset + round.run.end;
        let next = execution.rounds.get(i + 1).map(|r| r.offset);
        let mut entries = timeline_entries(&round.program, round.offset, &round.log);
        entries.extend(fault_entries(&round.program, injected, round.offset, next));
        entries.sort_by_key(|e| e.0);
        entries.iter().for_each(|(_, line)| out.push_str(line));
        if let Some(why) = &round.detected {
            out.push_str(&format!("% detected at {}: {why}\n", time(end)));
        }
        for line in &round.recovery {
            out.push_str(&format!("% recovery: {line}\n"));
        }
        if let Some(next) = execution.rounds.get(i + 1) {
            let actions = next
                .program
                .module()
                .nodes
                .iter()
                .filter(|n| matches!(n, Instr::Start { .. } | Instr::Act { .. }))
                .count();
            out.push_str(&format!(
                "% replanned from the world read back at {}: {actions} actions, makespan {}\n",
                time(next.offset),
                time(next.planned_makespan)
            ));
        }
    }
    let last = execution.rounds.last().expect("at least one round");
    let end = time(last.offset + last.run.end);
    let recoveries = execution.rounds.len() - 1;
    let after = match recoveries {
        0 => String::new(),
        1 => " after 1 recovery".to_string(),
        n => format!(" after {n} recoveries"),
    };
    match &last.run.outcome {
        Outcome::Success => out.push_str(&format!("% success at {end}; {} ticks\n", last.run.ticks)),
        _ => out.push_str(&format!("% stopped at {end}; {} ticks\n", last.run.ticks)),
    }
    out.push_str(&format!("% makespan: planned {}, achieved {end}{after}\n", time(planned)));
    let _ = std::io::stdout().lock().write_all(out.as_bytes());
    if let Some(path) = &args.record
        && let Err(status) = write_output(path, record_json(&execution.sim).as_bytes())
    {
        return status;
    }
    let chart = (args.gantt_svg.is_some() || args.view.is_some())
        .then(|| run_chart(&session, &first_plan.timed.pop, &first_plan.timed.schedule, &execution));
    if let (Some(path), Some(svg)) = (&args.gantt_svg, &chart)
        && let Err(status) = write_output(path, svg.as_bytes())
    {
        return status;
    }
    if let Some(path) = &args.view {
        let title = session.interner().resolve(session.kb().problems[problem].name).to_string();
        let rounds: Vec<_> = execution.rounds.iter().map(|r| (&r.program, r.offset, r.log.as_slice())).collect();
        let summary = summary_of(&out);
        if let Err(status) = write_view(path, &title, &summary, &execution.sim, &rounds, chart.as_deref()) {
            return status;
        }
    }
    let (goal, waived) = recover::waive(&session, problem, &execution.sim.world().stopped_arms());
    if let recover::Verdict::GoalReached = &execution.verdict {
        let show =
            |t: &crate::ir::hir::Term| crate::ir::hir::term_to_string(session.interner(), t, &Default::default());
        let waived: Vec<String> = waived.iter().map(|t| format!("`{}`", show(t))).collect();
        let mut out = String::from("% the executed timeline is valid for the KB\n");
        out.push_str(&format!(
            "% goal reached{after}: all {} goal literals hold in the world read back at {end}\n",
            goal.len()
        ));
        if !waived.is_empty() {
            let stopped = execution.sim.world().stopped_arms().join(", ");
            out.push_str(&format!("% waived: {} (stopped for good: {stopped})\n", waived.join(", ")));
        }
        let _ = std::io::stdout().lock().write_all(out.as_bytes());
        return ExitCode::SUCCESS;
    }
    let diagnostics = execution.diagnostics(&mut session, problem, &settings, args.budget());
    super::fail(session.db(), &diagnostics, format, color)
}

/// The chart of `--gantt-svg`: per arm, a lane of the first plan's schedule and a lane of
/// what the arms did (every round, failed actions outlined, halted ones grey), with the
/// faults marked.
fn run_chart(
    session: &Session,
    pop: &crate::ir::pop::Pop,
    schedule: &crate::ir::schedule::Schedule,
    execution: &recover::Execution,
) -> String {
    use crate::render::gantt::{self, Bar};
    let arms = execution.sim.world().arm_names();
    let mut lanes = Vec::new();
    for arm in &arms {
        lanes.push(format!("{arm} planned"));
        lanes.push(format!("{arm} executed"));
    }
    let planned_lane = |name: &str| arms.iter().position(|a| a == name).map(|i| 2 * i);
    let mut bars = gantt::schedule_bars(session.interner(), session.kb(), pop, schedule, &planned_lane);
    let mut end = schedule.makespan;
    for round in &execution.rounds {
        for ran in ran_actions(&round.program, &arms, round.offset, &round.log) {
            end = end.max(ran.end);
            if let Some(arm) = ran.arm {
                let label = ran.text.split('(').next().unwrap_or(&ran.text).to_string();
                let bar = Bar {
                    lane: 2 * arm + 1,
                    label,
                    title: ran.text,
                    start: ran.start,
                    end: ran.end,
                    ending: ran.ending,
                };
                bars.push(bar);
            }
        }
    }
    let last = execution.rounds.last().expect("at least one round");
    end = end.max(last.offset + last.run.end);
    let marks: Vec<(i64, String)> = execution.sim.injected().to_vec();
    let name = session.interner().resolve(session.kb().problems[execution.rounds[0].problem].name);
    let first = &execution.rounds[0].program;
    let title = format!(
        "{name}: planned makespan {}, executed {} ({})",
        first.time_text(schedule.makespan),
        first.time_text(end),
        crate::diag::plural(execution.rounds.len(), "round")
    );
    gantt::draw(&title, &lanes, &bars, &marks, end)
}

pub(super) fn disasm(args: DisasmArgs, color: bool) -> ExitCode {
    let mut diagnostics = Diagnostics::new();
    match load(&args.file, &mut diagnostics) {
        Some(program) => {
            let _ = std::io::stdout().lock().write_all(program.module().disassemble().as_bytes());
            ExitCode::SUCCESS
        }
        None => {
            report(&SourceDb::new(), &diagnostics, MessageFormat::Human, color);
            ExitCode::from(1)
        }
    }
}
