//! `kbc draft`: asks a language model for a new test case (or action schemas), checks the
//! answer with the compiler and feeds the diagnostics back until it passes; `kbc draft check`
//! checks an answer already written; `kbc draft eval` scores models on a set of cases in the
//! paper's Table layout.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Duration;

use super::llm::{Client, Endpoint, Retry};
use super::{MessageFormat, report};
use crate::diag::{Code, Diagnostics, plural};
use crate::draft::check::{Checked, Checker, KbFile, Limits, States};
use crate::draft::eval::{self, Row};
use crate::draft::repair::{self, Drafted, Ending};
use crate::draft::{Message, Model, Recorded, Want, prompt};
use crate::session::Session;
use crate::source::SourceDb;
use crate::source::fs::FsLoader;

#[derive(clap::Args)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub(super) struct DraftArgs {
    #[command(subcommand)]
    command: Option<DraftCommand>,
    #[command(flatten)]
    ask: AskArgs,
}

#[derive(clap::Subcommand)]
enum DraftCommand {
    /// Check a drafted answer (a model's reply or code) against a KB, as `kbc draft` would.
    ///
    /// The last file is the answer: its code is taken from Markdown fences or from between
    /// prose, read with the KB files before it, its states checked and the test case planned.
    Check(CheckArgs),
    /// Score models on a set of cases, in the columns of the paper's Table of LLM results.
    ///
    /// CASES_DIR holds `kb.pl` (the KB whose test cases are the examples) and one folder per
    /// case with `task.txt` and `reference.pl`. Without `--model`, the answers recorded in
    /// `CASES_DIR/recorded/MODEL/CASE/1.txt, 2.txt, ...` are played; with it, each model is
    /// asked at `--endpoint`. Each model gets two rows: its first answers, and its answers after
    /// the repair loop.
    Eval(EvalArgs),
}

#[derive(clap::Args)]
struct AskArgs {
    /// The KB files whose test cases (or action schemas) are shown to the model as examples,
    /// and against which its answer is checked.
    #[arg(required = true, value_name = "KB")]
    files: Vec<PathBuf>,
    /// The task in plain language.
    #[arg(long, value_name = "TEXT", required_unless_present = "task_file", conflicts_with = "task_file")]
    task: Option<String>,
    /// A file holding the task in plain language.
    #[arg(long, value_name = "FILE")]
    task_file: Option<PathBuf>,
    /// What to ask for: a new test case, or new action schemas.
    #[arg(long, value_enum, default_value_t = What::Case)]
    what: What,
    /// The name of the new test case.
    #[arg(long, value_name = "NAME", default_value = "test_case")]
    name: String,
    #[command(flatten)]
    model: ModelArgs,
    /// The model's name, as the endpoint knows it (llama.cpp's server accepts any).
    #[arg(long = "model", value_name = "NAME", required = true)]
    model_name: Option<String>,
    /// Write the checked result to this file (atomically); without it, print it on stdout.
    #[arg(short, long, value_name = "FILE")]
    output: Option<PathBuf>,
    /// How to print diagnostics: for people, or one JSON object per line on stdout (which
    /// then needs `-o` for the result).
    #[arg(long, value_enum, default_value_t = MessageFormat::Human, requires_if("json", "output"))]
    message_format: MessageFormat,
}

/// Where the model is and how patiently to ask it.
#[derive(clap::Args)]
struct ModelArgs {
    /// The OpenAI-compatible API's base URL (a local llama.cpp server listens on
    /// http://127.0.0.1:8080/v1, Ollama on http://127.0.0.1:11434/v1).
    #[arg(long, value_name = "URL", default_value = "http://127.0.0.1:8080/v1")]
    endpoint: String,
    /// The environment variable holding the API key, if the endpoint needs one (its value is
    /// never printed).
    #[arg(long, value_name = "VAR", default_value = "OPENAI_API_KEY")]
    api_key_env: String,
    /// Answers asked for in all, the first included; after an answer with errors, the
    /// diagnostics go back to the model for another (1: no repair).
    #[arg(long, value_name = "N", default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..=20))]
    rounds: u32,
    /// The longest one request may take, in seconds (then it fails; 429 and 5xx answers are
    /// retried with backoff).
    #[arg(long, value_name = "SECONDS", default_value_t = 120.0)]
    request_timeout: f64,
    /// How often to retry a request the endpoint answered with 429 or a 5xx status (after
    /// 0.5 s, then doubling up to 8 s, or the server's `Retry-After`).
    #[arg(long, value_name = "N", default_value_t = 3)]
    retries: u32,
    /// The most states the planner may expand to show a drafted test case solvable.
    #[arg(long, value_name = "N", default_value_t = 200_000)]
    max_states: u64,
}

#[derive(Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum What {
    /// A test case: `NAME :- go(InitialState, GoalState).`
    Case,
    /// New `action/6` schemas.
    Actions,
}

#[derive(clap::Args)]
struct CheckArgs {
    /// KB files, then the answer file last.
    #[arg(required = true, value_name = "FILE")]
    files: Vec<PathBuf>,
    /// What the answer should hold.
    #[arg(long, value_enum, default_value_t = What::Case)]
    what: What,
    /// The name the test case should have.
    #[arg(long, value_name = "NAME", default_value = "test_case")]
    name: String,
    /// The most states the planner may expand to show the test case solvable.
    #[arg(long, value_name = "N", default_value_t = 200_000)]
    max_states: u64,
    /// How to print diagnostics.
    #[arg(long, value_enum, default_value_t = MessageFormat::Human)]
    message_format: MessageFormat,
}

#[derive(clap::Args)]
struct EvalArgs {
    /// The folder of cases.
    #[arg(value_name = "CASES_DIR")]
    cases: PathBuf,
    /// Ask these models (at `--endpoint`) instead of playing the recorded answers.
    #[arg(long = "model", value_name = "NAME")]
    models: Vec<String>,
    #[command(flatten)]
    model: ModelArgs,
    /// Print each case's result under the table.
    #[arg(long)]
    verbose: bool,
}

impl What {
    fn want(self, name: &str) -> Want {
        match self {
            What::Case => Want::TestCase { name: name.to_string() },
            What::Actions => Want::Actions,
        }
    }
}

pub(super) fn run(args: DraftArgs, color: bool) -> ExitCode {
    match args.command {
        Some(DraftCommand::Check(check)) => run_check(check, color),
        Some(DraftCommand::Eval(eval)) => run_eval(eval, color),
        None => run_ask(args.ask, color),
    }
}

/// Reads KB files (as every command reads its files); unreadable ones become diagnostics.
fn read_kb(paths: &[PathBuf], diagnostics: &mut Diagnostics) -> Vec<KbFile> {
    let mut db = SourceDb::new();
    let roots = crate::source::fs::read_roots(paths, &mut db, diagnostics);
    roots
        .into_iter()
        .map(|id| {
            let file = db.file(id);
            KbFile {
                name: file.name().to_string(),
                path: file.path().map(Path::to_path_buf),
                text: file.text().to_string(),
            }
        })
        .collect()
}

/// The front end on the KB alone: its errors must be fixed before anything is drafted against
/// it, and are printed (exit status 1) when there are any.
fn clean_kb(checker: &mut Checker<'_>, format: MessageFormat, color: bool) -> Result<Session, ExitCode> {
    let session = checker.kb_alone();
    if session.has_errors() {
        eprintln!("error: the KB has errors; fix them before drafting against it");
        return Err(super::fail(session.db(), session.diagnostics(), format, color));
    }
    Ok(session)
}

fn run_check(args: CheckArgs, color: bool) -> ExitCode {
    let mut read_errors = Diagnostics::new();
    let Some((answer_path, kb_paths)) = args.files.split_last() else {
        eprintln!("error: expected an answer file");
        return ExitCode::from(2);
    };
    let kb = read_kb(kb_paths, &mut read_errors);
    let answer = match super::read_text(answer_path) {
        Ok(text) => text,
        Err(reason) => {
            read_errors.push(super::unreadable(answer_path, &reason));
            String::new()
        }
    };
    if read_errors.has_errors() {
        return super::fail(&SourceDb::new(), &read_errors, args.message_format, color);
    }
    let mut loader = FsLoader;
    let limits = Limits { max_states: args.max_states, ..Limits::default() };
    let mut checker = Checker::new(&kb, &mut loader, args.what.want(&args.name), limits);
    if let Err(code) = clean_kb(&mut checker, args.message_format, color) {
        return code;
    }
    let checked = checker.check(&answer);
    report(&checked.db, &checked.diagnostics, args.message_format, color);
    if checked.passed() {
        if args.message_format == MessageFormat::Human {
            eprintln!("{}", passed_line(&checked));
        }
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}

fn passed_line(checked: &Checked) -> String {
    match checked.plan_steps {
        Some(steps) => format!("passed every check; the planner solves it in {}", plural(steps, "snap action")),
        None => "passed every check".to_string(),
    }
}

/// A model behind an OpenAI-compatible endpoint.
struct Remote {
    client: Client,
}

impl Model for Remote {
    fn answer(&mut self, conversation: &[Message]) -> Result<String, String> {
        self.client.complete(conversation).map(|c| c.content).map_err(|e| e.to_string())
    }
}

fn remote(args: &ModelArgs, model: &str) -> Result<Remote, String> {
    let api_key = std::env::var(&args.api_key_env).ok().filter(|k| !k.is_empty());
    let endpoint = Endpoint { url: args.endpoint.clone(), model: model.to_string(), api_key };
    let timeout = Duration::from_secs_f64(args.request_timeout.clamp(0.001, 86_400.0));
    let retry = Retry { attempts: args.retries.saturating_add(1), ..Retry::default() };
    Client::new(endpoint, timeout, retry).map(|client| Remote { client }).map_err(|e| e.to_string())
}

fn run_ask(args: AskArgs, color: bool) -> ExitCode {
    let mut diagnostics = Diagnostics::new();
    let kb = read_kb(&args.files, &mut diagnostics);
    let task = match (&args.task, &args.task_file) {
        (Some(task), _) => task.clone(),
        (None, Some(path)) => match super::read_text(path) {
            Ok(text) => text,
            Err(reason) => {
                diagnostics.push(super::unreadable(path, &reason));
                String::new()
            }
        },
        (None, None) => unreachable!("clap requires --task or --task-file"),
    };
    if diagnostics.has_errors() {
        return super::fail(&SourceDb::new(), &diagnostics, args.message_format, color);
    }
    if task.trim().is_empty() {
        eprintln!("error: the task is empty");
        return ExitCode::from(2);
    }
    let model_name = args.model_name.clone().unwrap_or_default();
    let mut model = match remote(&args.model, &model_name) {
        Ok(model) => model,
        Err(why) => {
            eprintln!("error: {why}");
            return ExitCode::from(2);
        }
    };
    let mut loader = FsLoader;
    let want = args.what.want(&args.name);
    let limits = Limits { max_states: args.model.max_states, ..Limits::default() };
    let mut checker = Checker::new(&kb, &mut loader, want.clone(), limits);
    let session = match clean_kb(&mut checker, args.message_format, color) {
        Ok(kb) => kb,
        Err(code) => return code,
    };
    let examples = match want {
        Want::TestCase { .. } => prompt::test_case_examples(session.db(), session.kb()),
        Want::Actions => prompt::action_examples(session.db(), session.kb()),
    };
    if examples.is_empty() {
        let what = if want == Want::Actions { "action schemas" } else { "named test cases (`name :- go(...)`)" };
        eprintln!("error: the KB has no {what} to show the model as examples");
        eprintln!("help: give a KB with some, e.g. examples/01_paper_tests/tests.pl");
        return ExitCode::from(1);
    }
    eprintln!(
        "asking `{model_name}` at {} for {} ({} as examples, at most {})",
        args.model.endpoint,
        describe(&want),
        plural(examples.len(), if want == Want::Actions { "action schema" } else { "test case" }),
        plural(args.model.rounds as usize, "round")
    );
    let drafted = repair::draft(&mut model, &mut checker, &task, &examples, args.model.rounds as usize);
    print_rounds(&drafted, args.message_format, color);
    match drafted.ending {
        Ending::Passed(round) => {
            let code = drafted.rounds[round].checked.code.clone().unwrap_or_default();
            let text = written_file(&code, &task, &model_name, round + 1, &args.files, &drafted.rounds[round].checked);
            match &args.output {
                Some(path) => {
                    if let Err(status) = super::write_output(path, text.as_bytes()) {
                        return status;
                    }
                    if path.as_os_str() != "-" {
                        super::status(&format!("wrote {}", path.display()));
                    }
                }
                None => print!("{text}"),
            }
            ExitCode::SUCCESS
        }
        Ending::OutOfRounds => {
            let last = drafted.rounds.last().map_or(0, |r| r.checked.diagnostics.error_count());
            eprintln!(
                "error: the draft still has {} after {}; nothing written",
                plural(last, "error"),
                plural(drafted.rounds.len(), "round")
            );
            eprintln!(
                "help: allow more rounds with `--rounds`, or fix the last answer by hand and `kbc draft check` it"
            );
            ExitCode::from(1)
        }
        Ending::ModelFailed(why) => {
            eprintln!("error: {why}");
            if why.starts_with("cannot reach") {
                eprintln!(
                    "help: is the server running? `--endpoint` is the API's base URL, e.g. http://127.0.0.1:8080/v1"
                );
            }
            ExitCode::from(1)
        }
    }
}

fn describe(want: &Want) -> String {
    match want {
        Want::TestCase { name } => format!("test case `{name}`"),
        Want::Actions => "new action schemas".to_string(),
    }
}

/// The report of each round on stderr: its diagnostics, then what it fixed.
fn print_rounds(drafted: &Drafted, format: MessageFormat, color: bool) {
    for (i, round) in drafted.rounds.iter().enumerate() {
        let checked = &round.checked;
        let errors = checked.diagnostics.error_count();
        let mut line = format!("round {}: ", i + 1);
        if !round.fixed.is_empty() {
            line.push_str(&format!("fixed {}: {}; ", round.fixed.len(), codes_of(round.fixed.iter().map(|m| m.code))));
        }
        if checked.passed() {
            line.push_str(&passed_line(checked));
        } else {
            line.push_str(&format!("{} ({})", plural(errors, "error"), codes_of(round.new.iter().map(|m| m.code))));
        }
        eprintln!("{line}");
        if !checked.passed() {
            report(&checked.db, &checked.diagnostics, format, color);
        }
    }
}

/// `E0601, E0606`: the codes, sorted, each once; `none new` for none.
fn codes_of(codes: impl Iterator<Item = Option<Code>>) -> String {
    let mut codes: Vec<&str> = codes.flatten().map(Code::as_str).collect();
    codes.sort_unstable();
    codes.dedup();
    if codes.is_empty() { "none new".to_string() } else { codes.join(", ") }
}

/// The file written: a header saying where the code came from and what it passed, then the
/// code as the model wrote it.
fn written_file(code: &str, task: &str, model: &str, rounds: usize, kb: &[PathBuf], checked: &Checked) -> String {
    let mut text = String::new();
    let kb: Vec<String> = kb.iter().map(|p| p.display().to_string()).collect();
    text.push_str(&format!("% Drafted by `kbc draft` with the model `{model}` in {}.\n", plural(rounds, "round")));
    text.push_str(&format!("% Checked against {}: front end, states", kb.join(", ")));
    match checked.plan_steps {
        Some(steps) => text.push_str(&format!(", and a plan of {}.\n", plural(steps, "snap action"))),
        None => text.push_str(".\n"),
    }
    text.push_str("% Task:\n");
    for line in task.trim().lines() {
        text.push_str(&format!("%   {line}\n"));
    }
    text.push('\n');
    text.push_str(code);
    if !code.ends_with('\n') {
        text.push('\n');
    }
    text
}

/// One case of an evaluation.
struct Case {
    name: String,
    task: String,
    reference: States,
}

fn run_eval(args: EvalArgs, color: bool) -> ExitCode {
    let dir = &args.cases;
    let mut diagnostics = Diagnostics::new();
    let kb = read_kb(&[dir.join("kb.pl")], &mut diagnostics);
    if diagnostics.has_errors() {
        return super::fail(&SourceDb::new(), &diagnostics, MessageFormat::Human, color);
    }
    let mut loader = FsLoader;
    let limits = Limits { max_states: args.model.max_states, ..Limits::default() };
    let want = Want::TestCase { name: "test_case".to_string() };
    let mut checker = Checker::new(&kb, &mut loader, want, limits);
    let session = match clean_kb(&mut checker, MessageFormat::Human, color) {
        Ok(kb) => kb,
        Err(code) => return code,
    };
    let examples = prompt::test_case_examples(session.db(), session.kb());
    let cases = match read_cases(dir, &mut checker) {
        Ok(cases) => cases,
        Err(code) => return code,
    };
    if cases.is_empty() {
        eprintln!("error: `{}` holds no case (a folder with task.txt and reference.pl)", dir.display());
        return ExitCode::from(1);
    }
    // The models: asked live, or played from the recordings.
    let recorded_dir = dir.join("recorded");
    let models: Vec<String> = if args.models.is_empty() {
        let mut names: Vec<String> = std::fs::read_dir(&recorded_dir)
            .map(|entries| {
                entries
                    .filter_map(Result::ok)
                    .filter(|e| e.path().is_dir())
                    .map(|e| e.file_name().to_string_lossy().into_owned())
                    .collect()
            })
            .unwrap_or_default();
        names.sort();
        if names.is_empty() {
            eprintln!("error: no recorded answers in `{}` and no `--model` to ask", recorded_dir.display());
            return ExitCode::from(1);
        }
        names
    } else {
        args.models.clone()
    };
    let mut rows = Vec::new();
    let mut details = String::new();
    for model_name in &models {
        let mut first = Row { label: model_name.clone(), scores: Vec::new() };
        let mut repaired = Row { label: format!("{model_name} + repair"), scores: Vec::new() };
        details.push_str(&format!("{model_name}\n"));
        for case in &cases {
            let mut model: Box<dyn Model> = if args.models.is_empty() {
                match recorded_answers(&recorded_dir.join(model_name).join(&case.name)) {
                    Ok(answers) => Box::new(Recorded::new(answers)),
                    Err(why) => {
                        eprintln!("error: {why}");
                        return ExitCode::from(1);
                    }
                }
            } else {
                match remote(&args.model, model_name) {
                    Ok(model) => Box::new(model),
                    Err(why) => {
                        eprintln!("error: {why}");
                        return ExitCode::from(2);
                    }
                }
            };
            let drafted =
                repair::draft(model.as_mut(), &mut checker, &case.task, &examples, args.model.rounds as usize);
            if let Ending::ModelFailed(why) = &drafted.ending {
                if drafted.rounds.is_empty() {
                    eprintln!("error: {model_name} on {}: {why}", case.name);
                    return ExitCode::from(1);
                }
            }
            let score_of = |round: Option<&repair::Round>| match round {
                Some(round) => eval::score(&case.reference, round.checked.states.as_ref(), round.checked.passed()),
                None => eval::score(&case.reference, None, false),
            };
            let at_first = score_of(drafted.rounds.first());
            let at_end = score_of(drafted.rounds.last());
            first.scores.push(at_first);
            repaired.scores.push(at_end);
            details.push_str(&format!(
                "  {:<28} {}\n",
                case.name,
                case_line(&drafted, at_first.success, at_end.success)
            ));
        }
        rows.push(first);
        rows.push(repaired);
    }
    println!(
        "{} cases, {}; repair: at most {}\n",
        cases.len(),
        if args.models.is_empty() { "recorded answers" } else { "asked live" },
        plural(args.model.rounds as usize, "round")
    );
    print!("{}", eval::table(&rows));
    if args.verbose {
        println!("\n{details}");
    }
    ExitCode::SUCCESS
}

/// What happened to one case: the first answer's verdict, and the repair's.
fn case_line(drafted: &Drafted, first_right: bool, end_right: bool) -> String {
    let verdict = |round: &repair::Round, right: bool| {
        if round.checked.passed() {
            if right { "right".to_string() } else { "passed the checks, differs from the reference".to_string() }
        } else {
            let errors = round.checked.diagnostics.iter().filter(|d| d.is_error());
            format!(
                "{} ({})",
                plural(round.checked.diagnostics.error_count(), "error"),
                codes_of(errors.map(|d| d.code))
            )
        }
    };
    let Some(first) = drafted.rounds.first() else { return "no answer".to_string() };
    let mut line = format!("first answer: {}", verdict(first, first_right));
    if drafted.rounds.len() > 1 {
        let last = drafted.rounds.last().expect("more than one round");
        line.push_str(&format!("; after {}: {}", plural(drafted.rounds.len(), "round"), verdict(last, end_right)));
    }
    if let Ending::ModelFailed(why) = &drafted.ending {
        line.push_str(&format!("; then: {why}"));
    }
    line
}

/// The cases of `dir`, each folder with a task and a reference, in name order. A reference
/// that does not pass the checks is an error in the case set.
fn read_cases(dir: &Path, checker: &mut Checker<'_>) -> Result<Vec<Case>, ExitCode> {
    let mut folders: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(|e| {
            eprintln!("error: cannot read `{}`: {}", dir.display(), super::io_reason(&e));
            ExitCode::from(1)
        })?
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.join("task.txt").is_file() && p.join("reference.pl").is_file())
        .collect();
    folders.sort();
    let mut cases = Vec::new();
    for folder in folders {
        let name = folder.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        let read = |file: &str| {
            super::read_text(&folder.join(file)).map_err(|reason| {
                eprintln!("error: cannot read `{}`: {reason}", folder.join(file).display());
                ExitCode::from(1)
            })
        };
        let task = read("task.txt")?;
        let reference = read("reference.pl")?;
        let checked = checker.check(&reference);
        let states = match (&checked.states, checked.passed()) {
            (Some(states), true) => states.clone(),
            _ => {
                eprintln!("error: the reference of case `{name}` does not pass the checks");
                report(&checked.db, &checked.diagnostics, MessageFormat::Human, false);
                return Err(ExitCode::from(1));
            }
        };
        cases.push(Case { name, task, reference: states });
    }
    Ok(cases)
}

/// The recorded answers of one model on one case: `1.txt`, `2.txt`, ... in round order.
fn recorded_answers(dir: &Path) -> Result<Vec<String>, String> {
    let mut answers = Vec::new();
    for round in 1.. {
        let path = dir.join(format!("{round}.txt"));
        if !path.is_file() {
            break;
        }
        answers.push(super::read_text(&path).map_err(|why| format!("cannot read `{}`: {why}", path.display()))?);
    }
    if answers.is_empty() {
        return Err(format!("no recorded answer `{}`", dir.join("1.txt").display()));
    }
    Ok(answers)
}
