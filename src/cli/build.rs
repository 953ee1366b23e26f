//! `kbc build`, `kbc run` and `kbc disasm`: the back end and the VM from the command line.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::ValueEnum;
use kbvm::Program;
use kbvm::bytecode::MAGIC;

use super::plan::{Planned, PlanningArgs, plan_and_schedule};
use super::{MessageFormat, report};
use crate::diag::{Diagnostic, Diagnostics, codes};
use crate::execute::{self, HostEvent, Logged, Outcome, TraceHost};
use crate::render;
use crate::source::SourceDb;
use crate::{driver, validate};
use kbvm::sim::SimConfig;

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
    /// Print the behaviour tree on stdout first.
    #[arg(long, value_enum, value_name = "PASS")]
    dump_after: Option<BuildDump>,
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

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum BuildDump {
    /// The behaviour tree.
    Bt,
}

#[derive(clap::Args)]
pub(super) struct RunArgs {
    /// The files, and how to plan them when they are KB files.
    #[command(flatten)]
    planning: PlanningArgs,
    /// The host that runs the actions.
    #[arg(long, value_enum, default_value_t = HostKind::Sim)]
    host: HostKind,
    /// Give up when the virtual clock passes this many KB time units.
    #[arg(long, value_name = "UNITS", default_value_t = 100_000.0)]
    max_time: f64,
    /// Give up after this many ticks.
    #[arg(long, value_name = "N", default_value_t = 10_000_000)]
    max_ticks: u64,
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
    fn profile(self) -> Option<(&'static str, &'static [(&'static str, usize)])> {
        match self {
            HostKind::Sim => Some(("simulated-arms", kbvm::sim::PRIMITIVES)),
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
    let planned = match plan_and_schedule(&args.planning, color, false) {
        Ok(planned) => planned,
        Err(status) => return status,
    };
    let Planned { db, diagnostics, frontend, plans, index, timed, .. } = planned;
    let (kb, interner) = (&frontend.kb, &frontend.interner);
    let mut diagnostics = diagnostics;
    let (bt, module) =
        match driver::build_bytecode(kb, interner, &db, &plans[index], &timed, args.host.and_then(HostKind::profile)) {
            Ok(built) => built,
            Err(diagnostic) => {
                diagnostics.push(*diagnostic);
                report(&db, &diagnostics, args.planning.message_format, color);
                return ExitCode::from(1);
            }
        };
    report(&db, &diagnostics, args.planning.message_format, color);
    if args.dump_after == Some(BuildDump::Bt) {
        let _ = std::io::stdout().lock().write_all(crate::ir::bt::print(interner, &timed.pop, &bt).as_bytes());
    }
    let bytes = match args.emit {
        BuildEmit::Bytecode => module.encode(),
        BuildEmit::BtXml => render::bt::xml(&module).into_bytes(),
        BuildEmit::BtDot => render::bt::dot(&module).into_bytes(),
    };
    match &args.output {
        Some(path) => {
            if let Err(error) = super::write_atomically(path, &bytes) {
                eprintln!("error: cannot write `{}`: {error}", path.display());
                return ExitCode::from(1);
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
    let mut db = SourceDb::new();
    let mut diagnostics = Diagnostics::new();
    let fail = |db: &SourceDb, diagnostics: &Diagnostics| {
        report(db, diagnostics, args.planning.message_format, color);
        ExitCode::from(1)
    };
    // The program: loaded, or planned and built here (keeping the KB to check the timeline
    // and the goal).
    let files = &args.planning.files;
    let (program, frontend, problem, planned) = if files.len() == 1 && is_bytecode(&files[0]) {
        match load(&files[0], &mut diagnostics) {
            Some(program) => (program, None, 0, None),
            None => return fail(&db, &diagnostics),
        }
    } else {
        let planned = match plan_and_schedule(&args.planning, color, false) {
            Ok(planned) => planned,
            Err(status) => return status,
        };
        diagnostics.extend(planned.diagnostics);
        db = planned.db;
        let built = driver::build_bytecode(
            &planned.frontend.kb,
            &planned.frontend.interner,
            &db,
            &planned.plans[planned.index],
            &planned.timed,
            args.host.profile(),
        );
        let module = match built {
            Ok((_, module)) => module,
            Err(diagnostic) => {
                diagnostics.push(*diagnostic);
                return fail(&db, &diagnostics);
            }
        };
        match Program::load(&module.encode()) {
            Ok(program) => (program, Some(planned.frontend), planned.problem, Some(planned.timed.schedule.makespan)),
            Err(error) => panic!("internal compiler error: the generated bytecode does not load: {error}"),
        }
    };
    report(&db, &diagnostics, args.planning.message_format, color);
    let mut diagnostics = Diagnostics::new();
    let scale = program.module().time_scale as f64;
    let max_time = (args.max_time * scale).min(i64::MAX as f64 / 2.0) as i64;
    let (result, log, world) = match args.host {
        HostKind::Trace => {
            let mut host = Logged::new(TraceHost::default());
            let result = execute::run(&program, &mut host, max_time, args.max_ticks);
            (result, host.log, None)
        }
        HostKind::Sim => {
            let config = SimConfig { units_per_second: program.module().time_scale as i64, ..SimConfig::default() };
            let sim = match execute::sim_host(&program, config) {
                Ok(sim) => sim,
                Err(error) => {
                    diagnostics.push(
                        Diagnostic::error(codes::RUN_FAILED, format!("cannot build the simulated world: {error}"))
                            .with_help("the initial state must place every block with `ontable/3` or `on/4` and name the arms with `available/1`"),
                    );
                    return fail(&db, &diagnostics);
                }
            };
            let mut host = Logged::new(sim);
            let result = execute::run(&program, &mut host, max_time, args.max_ticks);
            (result, host.log, Some(host.host))
        }
    };
    let time = |t: i64| execute::format_time(&program, t);
    let mut out = String::new();
    out.push_str("% time      event   action\n");
    for (t, id, event) in &log {
        let text = program.action_text(*id);
        let (what, why) = match event {
            HostEvent::Start => ("start", String::new()),
            HostEvent::Done => ("done", String::new()),
            HostEvent::Failed(why) => ("FAILED", format!(": {why}")),
            HostEvent::Halted => ("halted", String::new()),
        };
        out.push_str(&format!("{:>9}  {what:<6}  {text}{why}\n", time(*t)));
    }
    let end = time(result.end);
    match &result.outcome {
        Outcome::Success => out.push_str(&format!("% success at {}; {} ticks\n", end, result.ticks)),
        _ => out.push_str(&format!("% stopped at {}; {} ticks\n", end, result.ticks)),
    }
    if let Some(planned) = planned {
        out.push_str(&format!("% makespan: planned {}, achieved {}\n", time(planned), end));
    }
    let _ = std::io::stdout().lock().write_all(out.as_bytes());
    let failed = match &result.outcome {
        Outcome::Success => None,
        Outcome::Failure(failure) => Some(Diagnostic::error(codes::RUN_FAILED, failure.describe(&program))),
        Outcome::Stuck => Some(
            Diagnostic::error(
                codes::RUN_FAILED,
                format!("the tree is stuck at time {}: it waits for an event no node will record", end),
            )
            .with_help("the program is malformed; rebuild it with `kbc build`"),
        ),
        Outcome::Budget => Some(
            Diagnostic::error(
                codes::RUN_FAILED,
                format!("the run stopped at time {} without finishing: it passed its budget", end),
            )
            .with_note(format!(
                "the budget: {} time units (`--max-time`), {} ticks (`--max-ticks`)",
                args.max_time, args.max_ticks
            ))
            .with_help("raise `--max-time` if the plan is meant to take longer"),
        ),
    };
    if let Some(diagnostic) = failed {
        diagnostics.push(diagnostic);
        return fail(&db, &diagnostics);
    }
    let Some(mut frontend) = frontend else {
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
                return fail(&db, &diagnostics);
            }
        }
        return ExitCode::SUCCESS;
    };
    // Planned here: the executed timeline must satisfy the KB, checked by the timed validator.
    let text = execute::timed_plan(&program, &result);
    let file = db.add("<executed timeline>", None, text.clone());
    let steps = validate::read_plan(file, &text, &mut frontend.interner, &mut diagnostics);
    let kb_program = crate::planner::program_for(&frontend.kb, problem);
    let verdict = validate::validate_timed(&frontend.kb, &frontend.interner, &kb_program, problem, &steps);
    if verdict.diagnostics.has_errors() {
        diagnostics.extend(verdict.diagnostics);
        diagnostics.push(Diagnostic::note("the executed timeline breaks the KB: this is a compiler bug"));
        return fail(&db, &diagnostics);
    }
    let _ = writeln!(std::io::stdout().lock(), "% the executed timeline is valid for the KB");
    // On the simulated arms: the goal must hold in the world read back.
    if let Some(sim) = &world {
        let (facts, unaccounted) = execute::world_facts(sim.world(), &mut frontend.interner);
        let goal: Vec<_> = frontend.kb.problems[problem].goal.iter().map(|l| l.term.clone()).collect();
        let unmet = execute::unmet_goals(&goal, &facts);
        if unmet.is_empty() && unaccounted.is_empty() {
            let _ = writeln!(
                std::io::stdout().lock(),
                "% goal reached: all {} goal literals hold in the world read back at {}",
                goal.len(),
                end
            );
            return ExitCode::SUCCESS;
        }
        let show =
            |t: &crate::ir::hir::Term| crate::ir::hir::term_to_string(&frontend.interner, t, &Default::default());
        let mut diagnostic = Diagnostic::error(
            codes::GOAL_NOT_REACHED,
            match unmet.len() {
                0 => "the tree succeeded, but some blocks are not on a cell of the table".to_string(),
                1 => "the tree succeeded, but a goal literal does not hold in the world".to_string(),
                n => format!("the tree succeeded, but {n} goal literals do not hold in the world"),
            },
        );
        for g in &unmet {
            diagnostic = diagnostic.with_note(format!("not in the world: `{}`", show(g)));
        }
        for u in &unaccounted {
            diagnostic = diagnostic.with_note(format!("unaccounted: {u}"));
        }
        let world: Vec<String> = facts.iter().map(show).collect();
        diagnostic = diagnostic.with_note(format!("the world read back: {}", world.join(", ")));
        diagnostics.push(diagnostic);
        return fail(&db, &diagnostics);
    }
    ExitCode::SUCCESS
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
