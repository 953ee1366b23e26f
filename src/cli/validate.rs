//! `kbc validate`: replays a plan file on a KB and says whether it reaches the goal.

use std::path::PathBuf;
use std::process::ExitCode;

use super::{MessageFormat, report};
use crate::session::Session;
use crate::source::{FileId, Span};

#[derive(clap::Args)]
pub(super) struct ValidateArgs {
    /// KB and goal files, then the plan file last (as `kbc plan` prints it).
    #[arg(required = true, num_args = 2.., value_name = "FILE")]
    files: Vec<PathBuf>,
    /// The problem the plan is for, when the files define several.
    #[arg(long, value_name = "NAME")]
    problem: Option<String>,
    /// How to print diagnostics.
    #[arg(long, value_enum, default_value_t = MessageFormat::Human)]
    message_format: MessageFormat,
    /// The plan is another planner's, for the problem `kbc export pddl` wrote with this
    /// `names.json`: its PDDL actions and objects are read back as the KB's.
    #[arg(long, value_name = "FILE")]
    names: Option<PathBuf>,
    /// The plan's level: high-level actions, or arm-level actions (as `kbc plan --level arm`
    /// prints them), replayed on the problem's arm-level state and goal.
    #[arg(long, value_enum, default_value_t = super::plan::LevelArg::High, conflicts_with = "names")]
    level: super::plan::LevelArg,
}

pub(super) fn run(args: ValidateArgs, color: bool) -> ExitCode {
    let Some((plan_path, kb_paths)) = args.files.split_last() else {
        // clap requires two files; this is only reachable through a clap bug.
        eprintln!("error: expected KB files and a plan file");
        return ExitCode::from(2);
    };
    let mut session = Session::open_files(kb_paths);
    let plan_file = session.read_file(plan_path);
    let fail = |session: &Session| super::fail(session.db(), session.diagnostics(), args.message_format, color);
    let (Some(problem), Some(plan_file)) = (session.problem(args.problem.as_deref()), plan_file) else {
        return fail(&session);
    };
    let plan_file = match &args.names {
        Some(names) => match from_pddl(&mut session, plan_file, names) {
            Some(file) => file,
            None => return fail(&session),
        },
        None => plan_file,
    };
    let Some(steps) = session.read_plan_steps(plan_file) else { return fail(&session) };
    let problem = if args.level == super::plan::LevelArg::Arm { session.arm_problem(problem) } else { problem };
    let timed = steps.first().is_some_and(|s| s.timing.is_some());
    session.validate(problem, &steps);
    let problem_name = session.interner().resolve(session.kb().problems[problem].name).to_string();
    report(session.db(), session.diagnostics(), args.message_format, color);
    if session.has_errors() {
        return ExitCode::from(1);
    }
    let message = if timed {
        let makespan = steps.iter().filter_map(|s| s.timing.map(|(t, d)| t + d.unwrap_or(0))).max().unwrap_or(0);
        format!(
            "the timed plan is valid: in {} it reaches the goal of `{problem_name}` at {}",
            crate::diag::plural(steps.len(), "action"),
            crate::ir::stn::format_time(makespan)
        )
    } else {
        format!(
            "the plan is valid: in {} it reaches the goal of `{problem_name}`",
            crate::diag::plural(steps.len(), "step")
        )
    };
    match args.message_format {
        MessageFormat::Human => println!("{message}"),
        MessageFormat::Json => {
            println!(
                "{}",
                serde_json::json!({ "type": "validation", "valid": true, "timed": timed, "problem": problem_name, "steps": steps.len() })
            )
        }
    }
    ExitCode::SUCCESS
}

/// Writes the plan in `file` back in the KB's terms through `names` (`names.json` of `kbc
/// export pddl`): the new text's file, or `None` with the reason in the session.
fn from_pddl(session: &mut Session, file: FileId, names: &std::path::Path) -> Option<FileId> {
    use crate::diag::{Diagnostic, codes};
    let json = match crate::source::fs::read_text(names) {
        Ok(text) => serde_json::from_str::<serde_json::Value>(&text).map_err(|e| e.to_string()),
        Err(reason) => Err(reason),
    };
    let names_json = match json {
        Ok(value) => value,
        Err(reason) => {
            session.push(super::unreadable(names, &reason).with_help("give the names.json `kbc export pddl` wrote"));
            return None;
        }
    };
    let text = session.db().file(file).text_arc();
    match crate::render::pddl::plan_from_pddl(&text, &names_json) {
        Ok(mapped) => {
            let name = format!("{} (through {})", session.db().file(file).name(), names.display());
            Some(session.add_text(&name, mapped))
        }
        Err((line, why)) => {
            let start: usize = text.split_inclusive('\n').take(line).map(str::len).sum();
            let end = start + text[start..].find('\n').unwrap_or(text.len() - start);
            session.push(
                Diagnostic::error(
                    codes::BAD_PLAN_FILE,
                    format!("cannot read this step through `{}`: {why}", names.display()),
                )
                .primary(Span::new(file, start as u32, end as u32), "this step")
                .with_note("`--names` reads a plan for the PDDL problem `kbc export pddl` wrote with that file"),
            );
            None
        }
    }
}
