//! Helpers shared by the integration tests (`mod common;` in each that uses them; not every
//! test uses every helper). Every test reaches the compiler through a `Session`, as the CLI does.

#![allow(dead_code)]

use std::path::PathBuf;
use std::time::Duration;

use kbc::diag::Diagnostics;
use kbc::ir::plan::Plan;
use kbc::planner::Silent;
use kbc::session::{PlanSettings, Session, Timed};

/// Opens a session on KB files that must check clean.
pub fn load(paths: &[&str]) -> Session {
    let paths: Vec<PathBuf> = paths.iter().map(PathBuf::from).collect();
    let session = Session::open_files(&paths);
    assert!(!session.has_errors(), "{paths:?} must check clean: {:?}", messages(session.diagnostics()));
    session
}

/// The messages of `diagnostics`, for an assertion's failure message.
pub fn messages(diagnostics: &Diagnostics) -> Vec<String> {
    diagnostics.iter().map(|d| d.message.clone()).collect()
}

/// The search settings of these tests: the heuristic search with a 60 s budget, its plans as
/// found (no `reassign`).
pub fn settings() -> PlanSettings {
    PlanSettings { timeout: Some(Duration::from_secs(60)), reassign: false, ..PlanSettings::default() }
}

/// A plan for `problem` from the heuristic search (60 s budget).
pub fn search(session: &mut Session, problem: usize) -> Plan {
    session.search(problem, &settings(), &mut Silent).expect("a plan").plans[0].clone()
}

/// The temporal passes on a plan that must schedule.
pub fn timed(session: &mut Session, plan: &Plan) -> Timed {
    session.schedule(plan).expect("a consistent network")
}

/// A scheduled plan for `problem` (the heuristic search's, as found: no `reassign`).
pub fn planned(session: &mut Session, problem: usize) -> std::rc::Rc<kbc::session::Planned> {
    session
        .plan(problem, &settings(), &mut Silent)
        .unwrap_or_else(|e| panic!("no plan for problem {problem}: {e:?} {:?}", messages(session.diagnostics())))
}

/// Holds each output against the expectation file beside its case (`KBC_BLESS=1` writes the
/// outputs as the expectations instead), and fails listing every case that differs or could
/// not be run. `outputs` are (case, expectation file, output or why there is none).
pub fn expect_files(kind: &str, outputs: Vec<(PathBuf, PathBuf, Result<String, String>)>) {
    let bless = std::env::var_os("KBC_BLESS").is_some();
    let total = outputs.len();
    let mut failures = Vec::new();
    for (case, expected_path, actual) in outputs {
        let actual = match actual {
            Ok(actual) => actual,
            Err(problem) => {
                failures.push(format!("--- {}: {problem}", case.display()));
                continue;
            }
        };
        if bless {
            std::fs::write(&expected_path, &actual).expect("writable expectation");
            continue;
        }
        let expected = std::fs::read_to_string(&expected_path).unwrap_or_default();
        if actual != expected {
            failures.push(format!("--- {} (expected)\n{expected}+++ actual\n{actual}", expected_path.display()));
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {total} {kind} differ (re-bless with KBC_BLESS=1 after checking the change is right):\n\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// Every file under `dir` (at any depth) whose name ends in `.extension`, sorted.
pub fn files_under(dir: &str, extension: &str) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut stack = vec![PathBuf::from(dir)];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display())) {
            let path = entry.expect("a directory entry").path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == extension) {
                files.push(path);
            }
        }
    }
    files.sort();
    files
}
