//! The `kbc` command line: argument parsing, reading files, printing results.
//!
//! This module and `src/lsp` are the shells around the library: each subcommand opens a
//! [`Session`] on its files, asks it for the stages it needs, and prints or writes the results. Exit status: 0 when
//! the input is fine (warnings allowed), 1 when it has errors, 2 for usage errors (clap's
//! default for bad arguments).

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};

use crate::diag::{Diagnostics, codes, render};
use crate::session::{Pass, Session};
use crate::source::SourceDb;

mod bench;
mod build;
mod draft;
mod export;
pub mod llm;
mod plan;
mod validate;

/// The version `--version` prints: the crate's, and the commit it was built from.
const VERSION: &str = concat!(env!("CARGO_PKG_VERSION"), " (", env!("KBC_COMMIT"), ")");

/// Compile robot knowledge bases into behaviour trees.
#[derive(Parser)]
#[command(name = "kbc", version = VERSION, about, long_about = None, propagate_version = true)]
struct Cli {
    /// When to use colour in diagnostics.
    #[arg(long, value_enum, default_value_t = ColorWhen::Auto, global = true)]
    color: ColorWhen,
    /// Print no notes (such as "using the standard blocks world") and no status lines
    /// ("wrote ..."); warnings, errors and results are printed as ever.
    #[arg(short, long, global = true)]
    quiet: bool,
    /// Also print, on stderr after the command's output, each compiler pass it ran (parse,
    /// hir, check, task, search, refine, pop, stn, schedule, reassign, bt, codegen, validate)
    /// with its time and what it produced.
    #[arg(short, long, global = true, conflicts_with = "quiet")]
    verbose: bool,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Check KB and goal files and report every problem found.
    ///
    /// Reads the files (and the files they include), resolves them into a knowledge base, and
    /// reports syntax errors, structural mistakes in actions and problems, unknown predicates
    /// and arities, unbound effect variables and singleton variables. When no file declares
    /// an action schema, the standard blocks world (std/blocks.pl) is the domain.
    Check(CheckArgs),
    /// Find a plan for one problem: a total order of snap actions.
    ///
    /// Plans the problem chosen with `--problem` (or the only one) with the heuristic search
    /// (the default) or the paper's depth-first search, and prints the numbered plan and the
    /// search's figures. The output is a valid plan file for `kbc validate`.
    Plan(plan::PlanArgs),
    /// Check a plan: replay it on the KB and report the first step that does not apply.
    ///
    /// Takes the KB and goal files, then the plan file (one ground action per line, optionally
    /// numbered; `%` comments). The replay is independent of the planner's search code. Exits
    /// with 0 when every step applies, the goal holds at the end and no action is left running.
    Validate(validate::ValidateArgs),
    /// Run the planner's scaling ladder: generated multi-arm blocks-world problems.
    ///
    /// Plans every rung (build, reverse and swap problems from 2 blocks and 3 arms up to 100
    /// blocks and 10 arms, and grid KBs in other authors' style from 6 to 20 blocks) with the
    /// heuristic search and the paper's search, each under a
    /// time budget, validates every plan, and prints plan length, makespan, states expanded
    /// (by every search `kbc plan` runs for the rung), the makespan's lower bound (marked `*`
    /// where a search of the rung's schedules proved it the optimum) and their ratio, time and
    /// the paper/heuristic time ratio.
    /// `--write DIR` writes the goal files instead.
    Bench(bench::BenchArgs),
    /// Compile a problem into behaviour-tree bytecode for the VM.
    ///
    /// Plans and schedules the problem like `kbc plan`, turns the schedule into a behaviour
    /// tree (sequences, parallels, waits for synchronisation) and writes it as verified
    /// bytecode (`-o plan.kbb`), or as BehaviorTree.CPP v4 XML or Graphviz with `--emit`.
    Build(build::BuildArgs),
    /// Run a program on a host: a bytecode file, or KB files planned and built first.
    ///
    /// Ticks the behaviour tree in virtual time and prints the timeline. With KB files, the
    /// executed timeline is replayed by the timed validator. Exits with 0 when the tree
    /// succeeds.
    Run(build::RunArgs),
    /// Print a readable listing of a bytecode file.
    Disasm(build::DisasmArgs),
    /// Write a problem of the KB for other tools (PDDL 2.1).
    #[command(subcommand)]
    Export(export::ExportCommand),
    /// Ask a language model for a new test case (or action schemas), checked and repaired.
    ///
    /// Shows the model the KB's named test cases as examples (the paper's prompt), asks for a
    /// new one for the task, then checks the answer: syntax, names, the states (every block in
    /// one place, `clear` right, known cells and agents) and that the planner solves it. The
    /// diagnostics go back to the model until the answer passes or `--rounds` are used up.
    /// Nothing the model writes is run: it is read as data. `kbc draft check` checks an answer
    /// file; `kbc draft eval` scores models in the paper's Table layout.
    Draft(draft::DraftArgs),
    /// Print a completion script for a shell, e.g. `kbc completions bash >> ~/.bashrc`.
    Completions {
        /// The shell.
        #[arg(value_enum)]
        shell: clap_complete::Shell,
    },
    /// Print a manual page in roff, e.g. `kbc man plan | man -l -`: kbc's own, or a
    /// subcommand's.
    Man {
        /// The subcommand (`plan`, `export`, ...); kbc's own page without one.
        subcommand: Option<String>,
    },
    /// Print the explanation of a diagnostic code, e.g. `kbc explain E0102`.
    Explain {
        /// The code, such as E0102 or W0001.
        code: String,
    },
    /// Run the language server for editors, on stdin and stdout.
    ///
    /// Speaks the Language Server Protocol: diagnostics as you type (the files of a folder are
    /// checked together, as `kbc check` would check them), hover, go to definition, find
    /// references, document and workspace symbols, completion and quick fixes. README.md shows
    /// how to hook it into Neovim and VS Code.
    Lsp {
        /// Accepted for clients that pass it (VS Code's language client does); stdio is the
        /// only transport.
        #[arg(long)]
        stdio: bool,
    },
}

#[derive(clap::Args)]
struct CheckArgs {
    /// KB and goal files, checked together.
    #[arg(required = true, value_name = "FILE")]
    files: Vec<PathBuf>,
    /// How to print diagnostics: for people, or one JSON object per line on stdout.
    #[arg(long, value_enum, default_value_t = MessageFormat::Human)]
    message_format: MessageFormat,
    /// Print the intermediate representation after this pass on stdout (`parse` or `hir`).
    #[arg(long, value_enum, value_name = "PASS")]
    dump_after: Option<Pass>,
    /// Treat these findings as errors: `-D warnings` makes every warning an error (exit
    /// status 1), for a KB that must be clean.
    #[arg(short = 'D', long = "deny", value_enum, value_name = "LINT")]
    deny: Vec<Lint>,
}

/// Findings `-D`/`--deny` can turn into errors.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum Lint {
    /// Every warning.
    Warnings,
}

#[derive(Clone, Copy, ValueEnum)]
enum ColorWhen {
    /// Colour when stderr is a terminal and NO_COLOR is not set.
    Auto,
    Always,
    Never,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum MessageFormat {
    Human,
    Json,
}

/// Runs the command line and returns the process's exit status.
pub fn main() -> ExitCode {
    // The compiler walks terms recursively, and a KB's terms can be as deep as they are long
    // (a list of a million items, a body of a million goals, an operator chain): the work
    // runs on a thread whose stack can grow to STACK_BYTES. Only the pages a run touches are
    // committed, so an ordinary KB uses no more memory than on the main thread's stack.
    match std::thread::Builder::new().name("kbc".into()).stack_size(STACK_BYTES).spawn(run) {
        Ok(worker) => worker.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic)),
        Err(_) => run(), // no thread (a restricted environment): the main thread's stack
    }
}

/// Whether `--color auto` colours: on a terminal, unless `NO_COLOR` is set (and not empty)
/// or the terminal says it is `dumb`.
fn auto_color(terminal: bool, no_color: Option<std::ffi::OsString>, term: Option<std::ffi::OsString>) -> bool {
    terminal && no_color.is_none_or(|v| v.is_empty()) && term.is_none_or(|t| t != "dumb")
}

/// The stack of the thread that does the work: 2 GiB of address space. A clause has at most
/// 2,500,000 tokens (E0115), so no term nests deeper; a chain of unary minus (the shape with
/// the largest frames measured) 4,000,000 deep overflowed a 1 GiB stack and ran in this one
/// (release build).
const STACK_BYTES: usize = 2 << 30;

fn run() -> ExitCode {
    let cli = Cli::parse();
    QUIET.store(cli.quiet, std::sync::atomic::Ordering::Relaxed);
    use crate::syntax::parser::{MAX_CLAUSE_TOKENS_VAR, set_max_clause_tokens};
    if let Some(limit) = std::env::var(MAX_CLAUSE_TOKENS_VAR).ok().and_then(|v| v.trim().parse().ok()) {
        set_max_clause_tokens(limit);
    }
    let color = match cli.color {
        ColorWhen::Always => true,
        ColorWhen::Never => false,
        ColorWhen::Auto => {
            auto_color(std::io::stderr().is_terminal(), std::env::var_os("NO_COLOR"), std::env::var_os("TERM"))
        }
    };
    // (Not for the language server: nothing would ever print what it records.)
    if cli.verbose && !matches!(cli.command, Command::Lsp { .. }) {
        crate::session::timing::enable();
    }
    let status = match cli.command {
        Command::Check(args) => check(args, color),
        Command::Plan(args) => plan::run(args, color),
        Command::Validate(args) => validate::run(args, color),
        Command::Bench(args) => bench::run(args),
        Command::Export(command) => export::run(command, color),
        Command::Build(args) => build::build(args, color),
        Command::Run(args) => build::run(args, color),
        Command::Disasm(args) => build::disasm(args, color),
        Command::Draft(args) => draft::run(args, color),
        Command::Explain { code } => explain(&code),
        Command::Completions { shell } => {
            use clap::CommandFactory;
            clap_complete::generate(shell, &mut Cli::command(), "kbc", &mut std::io::stdout());
            ExitCode::SUCCESS
        }
        Command::Man { subcommand } => man(subcommand.as_deref()),
        Command::Lsp { stdio: _ } => crate::lsp::run_stdio(),
    };
    if cli.verbose {
        let times = crate::session::timing::take();
        if !times.is_empty() {
            eprint!("{}", crate::session::timing::render(&times));
        }
    }
    status
}

/// `kbc man [SUBCOMMAND]`: the manual page, in roff, on stdout.
fn man(subcommand: Option<&str>) -> ExitCode {
    use clap::CommandFactory;
    let kbc = Cli::command();
    let page = match subcommand {
        None => kbc,
        Some(name) => match kbc.find_subcommand(name) {
            Some(command) => command.clone().display_name(format!("kbc-{name}")).bin_name(format!("kbc {name}")),
            None => {
                let names: Vec<&str> = kbc.get_subcommands().map(|c| c.get_name()).collect();
                eprintln!("error: no subcommand `{name}`; kbc has {}", names.join(", "));
                return ExitCode::from(2);
            }
        },
    };
    let mut out = Vec::new();
    if let Err(error) = clap_mangen::Man::new(page).render(&mut out) {
        eprintln!("error: cannot write the manual page: {error}");
        return ExitCode::from(1);
    }
    let _ = std::io::stdout().lock().write_all(&out);
    ExitCode::SUCCESS
}

pub(crate) use crate::source::fs::{io_reason, read_text, unreadable};

/// Writes an output file all at once (or not at all), `-` meaning stdout; a failure is
/// reported and gives exit status 1.
pub(crate) fn write_output(path: &Path, bytes: &[u8]) -> Result<(), ExitCode> {
    if path.as_os_str() == "-" {
        let _ = std::io::stdout().lock().write_all(bytes);
        return Ok(());
    }
    write_atomically(path, bytes).map_err(|error| {
        eprintln!("error: cannot write `{}`: {}", path.display(), io_reason(&error));
        ExitCode::from(1)
    })
}

/// Writes `bytes` to `path` through a temporary file in the same directory and a rename, so
/// `path` never holds a half-written file.
pub(crate) fn write_atomically(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let temporary = path.with_file_name(format!(".{name}.kbc-{}.tmp", std::process::id()));
    let result = std::fs::write(&temporary, bytes).and_then(|()| std::fs::rename(&temporary, path));
    if result.is_err() {
        let _ = std::fs::remove_file(&temporary);
    }
    result
}

/// What commands that work on one problem start with: read the files, run the front end, pick
/// the problem (`--problem`). The problem is `None` when that failed; the reasons are in the
/// session's diagnostics.
pub(crate) fn open_for_problem(files: &[PathBuf], problem: Option<&str>) -> (Session, Option<usize>) {
    let mut session = Session::open_files(files);
    let problem = session.problem(problem);
    (session, problem)
}

fn check(args: CheckArgs, color: bool) -> ExitCode {
    if let Some(pass) = args.dump_after.filter(|p| !p.is_frontend()) {
        eprintln!(
            "error: `kbc check` stops after `hir`; `--dump-after {}` needs a problem: use `kbc plan` or `kbc build`",
            pass.name()
        );
        return ExitCode::from(2);
    }
    let mut session = Session::open_files(&args.files);
    if args.deny.contains(&Lint::Warnings) {
        session.deny_warnings();
    }
    if let Some(pass) = args.dump_after {
        let _ = session.dump_frontend(pass, &mut std::io::stdout().lock());
    }
    report(session.db(), session.diagnostics(), args.message_format, color);
    if session.has_errors() { ExitCode::from(1) } else { ExitCode::SUCCESS }
}

/// Prints the diagnostics and gives exit status 1: how a command ends on errors in its input.
pub(crate) fn fail(db: &SourceDb, diagnostics: &Diagnostics, format: MessageFormat, color: bool) -> ExitCode {
    report(db, diagnostics, format, color);
    ExitCode::from(1)
}

/// `--quiet`: set once, when the arguments are parsed.
static QUIET: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Whether `--quiet` was given: no notes, no status lines.
pub(crate) fn quiet() -> bool {
    QUIET.load(std::sync::atomic::Ordering::Relaxed)
}

/// Prints a status line ("wrote ...") on stderr, unless `--quiet`.
pub(crate) fn status(line: &str) {
    if !quiet() {
        eprintln!("{line}");
    }
}

pub(crate) fn report(db: &SourceDb, diagnostics: &Diagnostics, format: MessageFormat, color: bool) {
    let kept;
    let diagnostics = if quiet() {
        let mut without_notes = Diagnostics::new();
        for diagnostic in diagnostics.iter().filter(|d| d.severity != crate::diag::Severity::Note) {
            without_notes.push(diagnostic.clone());
        }
        kept = without_notes;
        &kept
    } else {
        diagnostics
    };
    match format {
        MessageFormat::Human => {
            if render::emit_to_terminal(db, diagnostics, color).is_err() {
                // stderr is gone (a closed pipe); there is nowhere left to report to.
            }
        }
        MessageFormat::Json => {
            let mut out = std::io::stdout().lock();
            for diagnostic in diagnostics.iter() {
                if writeln!(out, "{}", render::to_json(db, diagnostic)).is_err() {
                    break;
                }
            }
        }
    }
}

fn explain(code: &str) -> ExitCode {
    let normalized =
        if code.chars().next().is_some_and(|c| c.is_ascii_digit()) { format!("E{code}") } else { code.to_string() };
    match codes::lookup(&normalized) {
        Some(info) => {
            let mut out = std::io::stdout().lock();
            let _ = out.write_all(info.explanation.as_bytes());
            ExitCode::SUCCESS
        }
        None => {
            eprintln!("error: `{code}` is not a kbc diagnostic code");
            eprintln!("note: codes look like E0102 or W0001; `kbc check` prints them in brackets");
            ExitCode::from(1)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::auto_color;

    #[test]
    fn colour_needs_a_terminal_that_is_not_dumb_and_no_no_color() {
        let some = |s: &str| Some(std::ffi::OsString::from(s));
        assert!(auto_color(true, None, some("xterm-256color")));
        assert!(auto_color(true, some(""), None), "an empty NO_COLOR does not count");
        assert!(!auto_color(false, None, some("xterm")), "a pipe");
        assert!(!auto_color(true, some("1"), some("xterm")), "NO_COLOR");
        assert!(!auto_color(true, None, some("dumb")), "TERM=dumb");
    }
}
