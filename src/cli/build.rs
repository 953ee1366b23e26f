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
use crate::execute::{self, Outcome, TraceHost};
use crate::render;
use crate::source::SourceDb;
use crate::{driver, validate};

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
    /// The host that runs the actions: `trace` completes each after its least duration.
    #[arg(long, value_enum, default_value_t = HostKind::Trace)]
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
    /// A scripted host: every action succeeds after its least duration.
    Trace,
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
    let (bt, module) = driver::build_bytecode(kb, interner, &db, &plans[index], &timed);
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
    // The program: loaded, or planned and built here (keeping the KB to check the timeline).
    let files = &args.planning.files;
    let (program, frontend, problem) = if files.len() == 1 && is_bytecode(&files[0]) {
        match load(&files[0], &mut diagnostics) {
            Some(program) => (program, None, 0),
            None => return fail(&db, &diagnostics),
        }
    } else {
        let planned = match plan_and_schedule(&args.planning, color, false) {
            Ok(planned) => planned,
            Err(status) => return status,
        };
        let (_, module) = driver::build_bytecode(
            &planned.frontend.kb,
            &planned.frontend.interner,
            &planned.db,
            &planned.plans[planned.index],
            &planned.timed,
        );
        diagnostics.extend(planned.diagnostics);
        db = planned.db;
        match Program::load(&module.encode()) {
            Ok(program) => (program, Some(planned.frontend), planned.problem),
            Err(error) => panic!("internal compiler error: the generated bytecode does not load: {error}"),
        }
    };
    report(&db, &diagnostics, args.planning.message_format, color);
    let mut diagnostics = Diagnostics::new();
    let scale = program.module().time_scale as f64;
    let max_time = (args.max_time * scale).min(i64::MAX as f64 / 2.0) as i64;
    let mut host = match args.host {
        HostKind::Trace => TraceHost::default(),
    };
    let result = execute::run(&program, &mut host, max_time, args.max_ticks);
    // The timeline: each host start and completion.
    let time = |t: i64| execute::format_time(&program, t);
    let mut out = String::new();
    out.push_str("% time      event   action\n");
    for &(t, id, started) in &host.log {
        let text = program.action_text(id);
        out.push_str(&format!("{:>9}  {:<6}  {text}\n", time(t), if started { "start" } else { "done" }));
    }
    let end = time(result.end);
    let outcome_line = match &result.outcome {
        Outcome::Success => format!("% success at {}; {} ticks", end, result.ticks),
        _ => format!("% stopped at {}; {} ticks", end, result.ticks),
    };
    out.push_str(&outcome_line);
    out.push('\n');
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
    // Planned here: the executed timeline must satisfy the KB, checked by the timed validator.
    if let Some(frontend) = frontend {
        let text = execute::timed_plan(&program, &result);
        let mut interner = frontend.interner;
        let file = db.add("<executed timeline>", None, text.clone());
        let steps = validate::read_plan(file, &text, &mut interner, &mut diagnostics);
        let kb_program = crate::planner::program_for(&frontend.kb, problem);
        let verdict = validate::validate_timed(&frontend.kb, &interner, &kb_program, problem, &steps);
        if verdict.diagnostics.has_errors() {
            diagnostics.extend(verdict.diagnostics);
            diagnostics.push(Diagnostic::note("the executed timeline breaks the KB: this is a compiler bug"));
            return fail(&db, &diagnostics);
        }
        let _ = writeln!(std::io::stdout().lock(), "% the executed timeline is valid for the KB (makespan {})", end);
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
