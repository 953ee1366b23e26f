//! `kbc export pddl`: writes one problem of a KB as a PDDL 2.1 domain and problem (and the
//! names file that maps them back), for other planners.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::ValueEnum;

use super::{MessageFormat, report};
use crate::diag::Diagnostic;
use crate::render::pddl::{self, Durations};
use crate::session::Session;

#[derive(clap::Subcommand)]
pub(super) enum ExportCommand {
    /// Write a PDDL 2.1 domain and problem equivalent to one problem of the KB.
    ///
    /// Writes DIR/domain.pddl, DIR/problem.pddl and DIR/names.json (PDDL names back to the
    /// KB's terms and snap actions). Durative actions become PDDL durative actions, Invalid
    /// literals negative (existential) conditions, OnKB goals and InvalidAtEnd literals static
    /// predicates listing their solutions, `duration/3` the actions' durations. What PDDL
    /// cannot express is an error naming the schema (E0404); nothing is written then.
    Pddl(PddlArgs),
}

#[derive(clap::Args)]
pub(super) struct PddlArgs {
    /// KB and goal files, read together.
    #[arg(required = true, value_name = "FILE")]
    files: Vec<PathBuf>,
    /// The problem to export (a test name such as `test1`, or a goal file's stem).
    #[arg(long, value_name = "NAME")]
    problem: Option<String>,
    /// The directory to write the files to (created if missing).
    #[arg(short, long, value_name = "DIR")]
    output: PathBuf,
    /// Compile negative conditions away into complement predicates (`not_p`), for planners
    /// without `:negative-preconditions` (LPG, for one).
    #[arg(long)]
    no_negative_preconditions: bool,
    /// How to write a duration with a range: as inequalities, or its minimum only (for
    /// planners without `:duration-inequalities`).
    #[arg(long, value_enum, default_value_t = DurationsArg::Exact)]
    durations: DurationsArg,
    /// The most action instances the export may explore, and the most complement facts or
    /// expanded conditions it may write.
    #[arg(long, value_name = "N", default_value_t = 2_000_000)]
    limit: usize,
    /// How to print diagnostics: for people, or one JSON object per line on stdout.
    #[arg(long, value_enum, default_value_t = MessageFormat::Human)]
    message_format: MessageFormat,
    /// Also plan the problem (heuristic search, scheduled as `kbc plan --schedule` does) and
    /// write the timed plan in the export's names to DIR/plan.pddl, for checking kbc's plan
    /// with other tools (`kairos validate DIR/domain.pddl DIR/problem.pddl DIR/plan.pddl`).
    #[arg(long)]
    with_plan: bool,
    /// With `--with-plan`: the least time between two ordered snap actions of the plan, as
    /// for `kbc plan --epsilon`.
    #[arg(long, value_name = "TIME", default_value = "0.001", value_parser = super::plan::parse_epsilon, requires = "with_plan")]
    epsilon: i64,
}

#[derive(Clone, Copy, ValueEnum)]
enum DurationsArg {
    /// `[min, max]` as `(and (>= ?duration min) (<= ?duration max))`.
    Exact,
    /// `(= ?duration min)`; `--with-plan` then schedules kbc's plan with every duration at
    /// its minimum (an error when its order needs a longer one).
    Min,
    /// As `exact`, with no maximum written as 1,000,000 time units: closed intervals only,
    /// for tools that read nothing else (unified-planning).
    Bounded,
}

pub(super) fn run(command: ExportCommand, color: bool) -> ExitCode {
    let ExportCommand::Pddl(args) = command;
    let (mut session, problem) = super::open_for_problem(&args.files, args.problem.as_deref());
    let fail = |session: &Session| super::fail(session.db(), session.diagnostics(), args.message_format, color);
    let Some(problem) = problem else { return fail(&session) };
    let options = pddl::Options {
        negative_preconditions: !args.no_negative_preconditions,
        durations: match args.durations {
            DurationsArg::Exact => Durations::Exact,
            DurationsArg::Min => Durations::Min,
            DurationsArg::Bounded => Durations::Bounded,
        },
        limit: args.limit,
    };
    // A problem whose initial facts have variables (W0015) is exported as one of its ground
    // copies: with a plan, the one the plan is for; without, the first (the variables' own
    // values), which a warning names.
    let settings = crate::session::PlanSettings { epsilon: args.epsilon, ..Default::default() };
    let planned = if args.with_plan {
        match session.plan(problem, &settings, &mut crate::planner::Silent) {
            Ok(planned) => Some(planned),
            Err(_) => return fail(&session),
        }
    } else {
        None
    };
    let exported_problem = match &planned {
        Some(planned) => planned.problem,
        None => {
            if let Some(grounded) = session.groundings(problem) {
                let values = grounded.groundings.shown(session.interner(), 0);
                session.push(
                    Diagnostic::warning(
                        crate::diag::codes::EXPORT_LEAVES_OUT,
                        "PDDL has no variables in an initial state: the problem is exported with \
                         the variables' own values",
                    )
                    .with_note(format!("the initial state's variables are written as {}", values.join(", ")))
                    .with_help("export with `--with-plan` to write the values kbc's plan uses"),
                );
            }
            problem
        }
    };
    let Some(exported) = session.export_pddl(exported_problem, options) else { return fail(&session) };
    if let Err(error) = std::fs::create_dir_all(&args.output) {
        session.push(Diagnostic::error(
            crate::diag::codes::UNREADABLE_FILE,
            format!("cannot create `{}`: {}", args.output.display(), super::io_reason(&error)),
        ));
        return fail(&session);
    }
    let plan_text = if let Some(planned) = planned {
        let names: serde_json::Value = serde_json::from_str(&exported.names).expect("the export writes valid JSON");
        let (kb, interner) = (session.kb(), session.interner());
        let timed = &planned.timed;
        // With durations fixed to their minimum, the plan is scheduled again that way: an
        // action that waited longer than its minimum starts later instead.
        let fixed;
        let (stn, schedule) = match options.durations {
            Durations::Exact | Durations::Bounded => (&timed.stn, &timed.schedule),
            Durations::Min => match session.minimum_duration_schedule(timed) {
                Some(scheduled) => {
                    fixed = scheduled;
                    (&fixed.0, &fixed.1)
                }
                None => {
                    session.push(
                        Diagnostic::error(
                            crate::diag::codes::EXPORT_INEXPRESSIBLE,
                            "kbc's plan has no schedule with every duration at its minimum",
                        )
                        .with_note("some action must last longer than its minimum for the plan's order to hold")
                        .with_help("export with `--durations exact` (the default) to write the plan"),
                    );
                    return fail(&session);
                }
            },
        };
        match pddl::plan_to_pddl(&names, kb, interner, planned.plan(), &timed.pop, stn, schedule) {
            Ok(text) => Some(text),
            Err(why) => {
                session.push(Diagnostic::error(
                    crate::diag::codes::EXPORT_INEXPRESSIBLE,
                    format!("kbc's plan cannot be written in the export's names: {why}"),
                ));
                return fail(&session);
            }
        }
    } else {
        None
    };
    let mut files =
        vec![("domain.pddl", &exported.domain), ("problem.pddl", &exported.problem), ("names.json", &exported.names)];
    if let Some(text) = &plan_text {
        files.push(("plan.pddl", text));
    }
    for (name, text) in files {
        let path = args.output.join(name);
        if let Err(error) = super::write_atomically(&path, text.as_bytes()) {
            report(session.db(), session.diagnostics(), args.message_format, color);
            eprintln!("error: cannot write `{}`: {}", path.display(), super::io_reason(&error));
            return ExitCode::from(1);
        }
    }
    report(session.db(), session.diagnostics(), args.message_format, color);
    if args.message_format == MessageFormat::Human {
        let plan = if plan_text.is_some() { ", plan.pddl" } else { "" };
        super::status(&format!("wrote {}/{{domain.pddl, problem.pddl, names.json{plan}}}", args.output.display()));
    }
    ExitCode::SUCCESS
}
