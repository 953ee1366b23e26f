//! Pass file-tests, in the manner of Cranelift's filetests: each `tests/passes/<pass>/<case>.pl`
//! is compiled up to `<pass>` through a session, and the pass's text form (what
//! `--dump-after <pass>` prints) must equal `<case>.<pass>` beside it.
//!
//! A case's first line may give arguments as `% args: ...`: `--problem NAME`, `--plan FILE`
//! (a plan file, relative to the case's directory, scheduled instead of searched for),
//! `--search paper`, `--no-reassign`, `--level arm` (the arm-level plan; the `refine` pass
//! needs it). Without them the problem is the only one, planned as
//! `kbc plan` plans it. A case must compile without errors. Files in subdirectories are
//! inputs of cases, not cases.
//!
//! `KBC_BLESS=1` writes the current output as the expectation (then review the diff);
//! `KBC_CASE=TEXT` runs only the cases whose path contains TEXT.

mod common;

use std::path::{Path, PathBuf};

use kbc::planner::{SearchKind, Silent};
use kbc::session::{Pass, PlanSettings, Session};

const PASSES: [Pass; 9] =
    [Pass::Parse, Pass::Hir, Pass::Task, Pass::Refine, Pass::Pop, Pass::Stn, Pass::Schedule, Pass::Minimal, Pass::Bt];

/// Every case, with its pass, sorted; only those `KBC_CASE` selects.
fn cases() -> Vec<(Pass, PathBuf)> {
    let filter = std::env::var("KBC_CASE").unwrap_or_default();
    let mut cases = Vec::new();
    for pass in PASSES {
        let dir = Path::new("tests/passes").join(pass.name());
        let Ok(entries) = std::fs::read_dir(&dir) else { continue };
        for entry in entries {
            let path = entry.expect("a directory entry").path();
            if path.extension().is_some_and(|e| e == "pl") && path.to_string_lossy().contains(&filter) {
                cases.push((pass, path));
            }
        }
    }
    cases.sort();
    cases
}

/// The case's `% args:` line, as words.
fn args(path: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(path).expect("readable case");
    let line = text.lines().next().and_then(|l| l.strip_prefix("% args:")).unwrap_or_default();
    line.split_whitespace().map(str::to_string).collect()
}

/// The text of `pass` after compiling `path`, or why there is none.
fn dump(pass: Pass, path: &Path) -> Result<String, String> {
    let mut session = Session::open_files(&[path.to_path_buf()]);
    let rendered = |session: &Session| kbc::diag::render::all_to_string(session.db(), session.diagnostics());
    if session.has_errors() {
        return Err(rendered(&session));
    }
    let mut out = Vec::new();
    if pass.is_frontend() {
        session.dump_frontend(pass, &mut out).map_err(|e| e.to_string())?;
        return Ok(String::from_utf8(out).expect("UTF-8"));
    }
    let words = args(path);
    let value = |flag: &str| words.iter().position(|w| w == flag).and_then(|i| words.get(i + 1)).cloned();
    let problem = session.problem(value("--problem").as_deref());
    let problem = problem.ok_or_else(|| rendered(&session))?;
    if pass == Pass::Task {
        session.dump_task(problem, &mut out).map_err(|e| e.to_string())?;
        return Ok(String::from_utf8(out).expect("UTF-8"));
    }
    let mut settings = PlanSettings {
        reassign: !words.iter().any(|w| w == "--no-reassign"),
        search: if value("--search").as_deref() == Some("paper") { SearchKind::Paper } else { SearchKind::Heuristic },
        ..PlanSettings::default()
    };
    if let Some(plan) = value("--plan") {
        let file = path.parent().expect("a directory").join(plan);
        settings.plan_file = Some(session.read_file(&file).ok_or_else(|| rendered(&session))?);
    }
    let mut planned = session.plan(problem, &settings, &mut Silent).map_err(|_| rendered(&session))?;
    if value("--level").as_deref() == Some("arm") {
        planned = session.refine(planned, &settings, &mut Silent).map_err(|_| rendered(&session))?;
    }
    session.dump_planned(pass, &planned, &mut out).map_err(|e| e.to_string())?;
    Ok(String::from_utf8(out).expect("UTF-8"))
}

#[test]
fn passes() {
    let cases = cases();
    if std::env::var_os("KBC_CASE").is_none() {
        for pass in PASSES {
            assert!(cases.iter().any(|(p, _)| *p == pass), "no case for the `{}` pass", pass.name());
        }
    }
    let outputs = cases
        .iter()
        .map(|(pass, case)| {
            let output = dump(*pass, case).map_err(|why| format!("does not compile to `{}`:\n{why}", pass.name()));
            (case.clone(), case.with_extension(pass.name()), output)
        })
        .collect();
    common::expect_files("pass cases", outputs);
}
