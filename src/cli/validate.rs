//! `kbc validate`: replays a plan file on a KB and says whether it reaches the goal.

use std::path::PathBuf;
use std::process::ExitCode;

use super::{MessageFormat, report};
use crate::diag::Diagnostics;
use crate::driver;
use crate::planner;
use crate::source::SourceDb;
use crate::validate;

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
}

pub(super) fn run(args: ValidateArgs, color: bool) -> ExitCode {
    let Some((plan_path, kb_paths)) = args.files.split_last() else {
        // clap requires two files; this is only reachable through a clap bug.
        eprintln!("error: expected KB files and a plan file");
        return ExitCode::from(2);
    };
    let mut db = SourceDb::new();
    let mut diagnostics = Diagnostics::new();
    let roots = super::read_roots(kb_paths, &mut db, &mut diagnostics);
    let plan_file = super::read_roots(std::slice::from_ref(plan_path), &mut db, &mut diagnostics);
    let mut frontend = driver::frontend(&mut db, &roots, &mut super::FsLoader);
    diagnostics.extend(frontend.diagnostics);
    if diagnostics.has_errors() {
        return super::fail(&db, &diagnostics, args.message_format, color);
    }
    let kb = &frontend.kb;
    let problem = match driver::select_problem(kb, &frontend.interner, args.problem.as_deref()) {
        Ok(problem) => problem,
        Err(diagnostic) => {
            diagnostics.push(*diagnostic);
            return super::fail(&db, &diagnostics, args.message_format, color);
        }
    };
    let Some(&plan_file) = plan_file.first() else {
        return super::fail(&db, &diagnostics, args.message_format, color);
    };
    let text = db.file(plan_file).text_arc();
    let steps = validate::read_plan(plan_file, &text, &mut frontend.interner, &mut diagnostics);
    if diagnostics.has_errors() {
        return super::fail(&db, &diagnostics, args.message_format, color);
    }
    let program = planner::program_for(kb, problem);
    let timed = steps.first().is_some_and(|s| s.timing.is_some());
    let verdict = if timed {
        validate::validate_timed(kb, &frontend.interner, &program, problem, &steps)
    } else {
        validate::validate(kb, &frontend.interner, &program, problem, &steps)
    };
    let problem_name = frontend.interner.resolve(kb.problems[problem].name).to_string();
    diagnostics.extend(verdict.diagnostics);
    report(&db, &diagnostics, args.message_format, color);
    if diagnostics.has_errors() {
        return ExitCode::from(1);
    }
    let message = if timed {
        let makespan = steps.iter().filter_map(|s| s.timing.map(|(t, d)| t + d.unwrap_or(0))).max().unwrap_or(0);
        format!(
            "the timed plan is valid: its {} actions reach the goal of `{problem_name}` at {}",
            steps.len(),
            crate::ir::stn::format_time(makespan)
        )
    } else {
        format!("the plan is valid: its {} steps reach the goal of `{problem_name}`", steps.len())
    };
    match args.message_format {
        MessageFormat::Human => println!("{message}"),
        MessageFormat::Json => {
            println!(
                "{}",
                serde_json::json!({ "valid": true, "timed": timed, "problem": problem_name, "steps": steps.len() })
            )
        }
    }
    ExitCode::SUCCESS
}
