//! `kbc plan`: finds a total-order plan for one problem and prints it.
//!
//! The text output is itself a plan file: numbered snap actions, with statistics and traces as
//! `%` comment lines, so `kbc plan ... > plan.txt` feeds `kbc validate`.

use std::io::{IsTerminal, Write};
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::{Duration, Instant};

use clap::ValueEnum;

use super::{MessageFormat, report};
use crate::diag::{Diagnostic, Diagnostics, codes};
use crate::driver;
use crate::ir::hir::{self, Kb, VarTable};
use crate::ir::plan::{self, Plan};
use crate::passes;
use crate::planner::{self, BudgetKind, Failure, Options, Progress, SearchKind, Stats};
use crate::source::SourceDb;

#[derive(clap::Args)]
pub(super) struct PlanArgs {
    /// KB and goal files.
    #[arg(required = true, value_name = "FILE")]
    files: Vec<PathBuf>,
    /// The problem to plan, when the files define several.
    #[arg(long, value_name = "NAME")]
    problem: Option<String>,
    /// The search: the paper's depth-first search, or best-first with a heuristic.
    #[arg(long, value_enum, default_value_t = SearchArg::Heuristic)]
    search: SearchArg,
    /// The paper's depth limit, in snap actions (default: the problem's go/5 value, else 25).
    #[arg(long, value_name = "N")]
    max_depth: Option<u32>,
    /// Give up after expanding this many states.
    #[arg(long, value_name = "N", default_value_t = 1_000_000)]
    max_states: u64,
    /// Give up after this many seconds.
    #[arg(long, value_name = "SECONDS")]
    timeout: Option<f64>,
    /// Give up when the stored states exceed this many megabytes.
    #[arg(long, value_name = "MB", default_value_t = 2048)]
    max_memory: u64,
    /// Print the state after each step.
    #[arg(long)]
    trace: bool,
    /// The output format.
    #[arg(long, value_enum, default_value_t = OutputFormat::Text)]
    format: OutputFormat,
    /// How to print diagnostics.
    #[arg(long, value_enum, default_value_t = MessageFormat::Human)]
    message_format: MessageFormat,
    /// Print the planning task (schemas as patterns, initial state, goal) on stdout first.
    #[arg(long, value_enum, value_name = "PASS")]
    dump_after: Option<PlanDump>,
}

#[derive(Clone, Copy, ValueEnum)]
enum PlanDump {
    /// The planning task the search runs on.
    Task,
}

#[derive(Clone, Copy, ValueEnum)]
enum SearchArg {
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

pub(super) fn run(args: PlanArgs, color: bool) -> ExitCode {
    let mut db = SourceDb::new();
    let mut diagnostics = Diagnostics::new();
    let roots = super::read_roots(&args.files, &mut db, &mut diagnostics);
    let frontend = driver::frontend(&mut db, &roots, &mut super::FsLoader);
    diagnostics.extend(frontend.diagnostics);
    if diagnostics.has_errors() {
        report(&db, &diagnostics, args.message_format, color);
        return ExitCode::from(1);
    }
    let kb = &frontend.kb;
    let interner = &frontend.interner;
    let problem = match driver::select_problem(kb, interner, args.problem.as_deref()) {
        Ok(problem) => problem,
        Err(diagnostic) => {
            diagnostics.push(*diagnostic);
            report(&db, &diagnostics, args.message_format, color);
            return ExitCode::from(1);
        }
    };
    let mut task = passes::task::build(kb, problem);
    if cfg!(debug_assertions) {
        crate::ir::task::verify(&task)
            .unwrap_or_else(|e| panic!("internal compiler error: the task verifier failed: {e}"));
    }
    if let Some(PlanDump::Task) = args.dump_after {
        let _ = std::io::stdout().lock().write_all(crate::ir::task::print(interner, kb, &task).as_bytes());
    }
    let search = match args.search {
        SearchArg::Paper => SearchKind::Paper,
        SearchArg::Heuristic => SearchKind::Heuristic,
    };
    let options = Options {
        search,
        max_depth: args.max_depth,
        budget: planner::Budget {
            max_states: args.max_states,
            deadline: args.timeout.map(|s| Instant::now() + Duration::from_secs_f64(s.max(0.0))),
            max_bytes: (args.max_memory as usize).saturating_mul(1 << 20),
            ..planner::Budget::default()
        },
    };
    let mut progress = TerminalProgress {
        started: Instant::now(),
        enabled: std::io::stderr().is_terminal(),
        shown: false,
        drawn: None,
    };
    let outcome = planner::search(kb, interner, &mut task, &options, &mut progress);
    if progress.shown {
        eprint!("\r{:60}\r", "");
    }
    let problem_name = interner.resolve(kb.problems[problem].name).to_string();
    let search_name = match search {
        SearchKind::Paper => "paper",
        SearchKind::Heuristic => "heuristic",
    };
    match outcome.result {
        Ok(plan) => {
            if cfg!(debug_assertions) {
                plan::verify(kb, &plan)
                    .unwrap_or_else(|e| panic!("internal compiler error: the plan verifier failed: {e}"));
            }
            report(&db, &diagnostics, args.message_format, color);
            let text = match args.format {
                OutputFormat::Text => {
                    plan_text(interner, &mut task, &plan, &problem_name, search_name, &outcome.stats, args.trace)
                }
                OutputFormat::Json => plan_json(kb, interner, &plan, &problem_name, search_name, &outcome.stats),
            };
            let _ = std::io::stdout().lock().write_all(text.as_bytes());
            ExitCode::SUCCESS
        }
        Err(failure) => {
            diagnostics.push(failure_diagnostic(
                kb,
                interner,
                &task,
                &problem_name,
                &failure,
                &outcome.stats,
                &options,
            ));
            report(&db, &diagnostics, args.message_format, color);
            ExitCode::from(1)
        }
    }
}

/// The process's peak resident memory in bytes (`VmHWM`), where the system reports it.
fn process_peak_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kilobytes: u64 = line.trim_start_matches("VmHWM:").trim().trim_end_matches("kB").trim().parse().ok()?;
    Some(kilobytes * 1024)
}

fn stats_line(stats: &Stats) -> String {
    let makespan = match stats.makespan {
        Some(makespan) => format!("makespan {makespan} (achiever-based, before scheduling); "),
        None => String::new(),
    };
    format!(
        "{makespan}expanded {} {}, generated {}, evaluated {}; {:.3} s; states stored {:.1} MB{}",
        stats.expanded,
        if stats.expanded == 1 { "state" } else { "states" },
        stats.generated,
        stats.evaluated,
        stats.elapsed.as_secs_f64(),
        stats.peak_bytes as f64 / 1e6,
        process_peak_bytes().map_or(String::new(), |b| format!(", process peak {:.1} MB", b as f64 / 1e6))
    )
}

fn plan_text(
    interner: &crate::intern::Interner,
    task: &mut crate::ir::task::Task,
    plan: &Plan,
    problem: &str,
    search: &str,
    stats: &Stats,
    trace: bool,
) -> String {
    let mut out = format!("% plan for {problem} ({search} search): {} snap actions\n", plan.steps.len());
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
        out.push_str(&plan::print(interner, plan));
    }
    out.push_str(&format!("% {}\n", stats_line(stats)));
    out
}

fn plan_json(
    kb: &Kb,
    interner: &crate::intern::Interner,
    plan: &Plan,
    problem: &str,
    search: &str,
    stats: &Stats,
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
            })
        })
        .collect();
    let value = serde_json::json!({
        "problem": problem,
        "search": search,
        "steps": steps,
        "stats": {
            "expanded": stats.expanded,
            "generated": stats.generated,
            "evaluated": stats.evaluated,
            "seconds": stats.elapsed.as_secs_f64(),
            "stored_bytes": stats.peak_bytes,
            "process_peak_bytes": process_peak_bytes(),
            "makespan": stats.makespan,
        },
    });
    format!("{value}\n")
}

fn failure_diagnostic(
    kb: &Kb,
    interner: &crate::intern::Interner,
    task: &crate::ir::task::Task,
    problem: &str,
    failure: &Failure,
    stats: &Stats,
    options: &Options,
) -> Diagnostic {
    match failure {
        Failure::Exhausted { depth_limit: Some(limit) } => Diagnostic::error(
            codes::NO_PLAN,
            format!("no plan for `{problem}` within the depth limit of {limit} snap actions"),
        )
        .with_note(format!("the paper's search tried every plan up to that length: {}", stats_line(stats)))
        .with_help("raise the limit with `--max-depth`, or use the heuristic search, which has no depth limit"),
        Failure::Exhausted { depth_limit: None } => {
            Diagnostic::error(codes::NO_PLAN, format!("no plan exists for `{problem}`"))
                .with_note(format!("every state reachable from the initial state was explored: {}", stats_line(stats)))
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
            };
            Diagnostic::error(codes::SEARCH_BUDGET, format!("the search for `{problem}` ran out of {what}"))
                .with_note(format!("no plan found so far: {}", stats_line(stats)))
                .with_help(help)
        }
        Failure::Unsolvable(diagnostic) => (**diagnostic).clone(),
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
