//! A corpus of KBs in other people's styles (tests/corpus/): split domains, test wrappers,
//! the two-level spelling, non-blocks domains, and the slips language models make. Each case
//! (a file, or a folder whose files load together) states in `% expect:` lines what kbc must
//! do with it, and this test checks every line:
//!
//! - `plan NAME [length N]`: problem NAME plans (heuristic search), N snap actions if given,
//!   and `kbc validate` accepts the plan as `kbc plan` prints it;
//! - `warn CODE`: checking the KB reports warning CODE;
//! - `note`: checking reports at least one note and no error;
//! - `refuse CODE`: checking or planning fails with error CODE;
//! - `arm NAME length N`: problem NAME's plan refines into N arm-level snap actions
//!   (`kbc plan --level arm`), and the validator, replaying the arm-level actions, accepts
//!   them as printed;
//! - `refuse-arm NAME CODE`: NAME plans but refining it fails with error CODE.

mod common;

use std::path::PathBuf;

use kbc::diag::{Diagnostics, Severity};
use kbc::planner::{Failure, Silent};
use kbc::session::{PlanSettings, Session};

fn cases() -> Vec<(String, Vec<PathBuf>)> {
    let mut cases = Vec::new();
    for entry in std::fs::read_dir("tests/corpus").expect("tests/corpus exists") {
        let path = entry.expect("readable entry").path();
        let name = path.file_stem().unwrap().to_string_lossy().to_string();
        if path.is_dir() {
            let mut files: Vec<PathBuf> = std::fs::read_dir(&path)
                .expect("readable folder")
                .map(|e| e.expect("readable entry").path())
                .filter(|p| p.extension().is_some_and(|e| e == "pl"))
                .collect();
            files.sort();
            cases.push((name, files));
        } else if path.extension().is_some_and(|e| e == "pl") {
            cases.push((name, vec![path]));
        }
    }
    cases.sort();
    cases
}

fn expectations(files: &[PathBuf]) -> Vec<Vec<String>> {
    files
        .iter()
        .flat_map(|f| {
            std::fs::read_to_string(f).expect("readable case").lines().map(str::to_string).collect::<Vec<_>>()
        })
        .filter_map(|l| l.strip_prefix("% expect: ").map(|e| e.split_whitespace().map(str::to_string).collect()))
        .collect()
}

fn codes(diagnostics: &Diagnostics, severity: Severity) -> Vec<String> {
    diagnostics.iter().filter(|d| d.severity == severity).filter_map(|d| d.code.map(|c| c.to_string())).collect()
}

/// Checks one case; the list of what did not hold.
fn check(files: &[PathBuf]) -> Vec<String> {
    let mut session = Session::open_files(files);
    let errors = codes(session.diagnostics(), Severity::Error);
    let warnings = codes(session.diagnostics(), Severity::Warning);
    let has_note = session.diagnostics().iter().any(|d| d.severity == Severity::Note);
    let settings = PlanSettings::default();
    let mut wrong = Vec::new();
    let expected = expectations(files);
    if expected.is_empty() {
        wrong.push("no `% expect:` line".to_string());
    }
    for line in expected {
        match line.iter().map(String::as_str).collect::<Vec<_>>().as_slice() {
            ["warn", code] => {
                if !warnings.iter().any(|w| w == code) {
                    wrong.push(format!("expected warning {code}, got {warnings:?}"));
                }
            }
            ["note"] => {
                if !has_note || !errors.is_empty() {
                    wrong.push(format!("expected a note and no error, got errors {errors:?}"));
                }
            }
            ["refuse", code] => {
                let mut found = errors.clone();
                if errors.is_empty() {
                    for problem in 0..session.kb().problems.len() {
                        if let Err(failed) = session.search(problem, &settings, &mut Silent)
                            && let Failure::Unsolvable(d) = &failed.failure
                        {
                            found.extend(d.code.map(|c| c.to_string()));
                        }
                    }
                }
                if !found.iter().any(|c| c == code) {
                    wrong.push(format!("expected error {code}, got {found:?}"));
                }
            }
            ["plan", name, rest @ ..] => {
                if !errors.is_empty() {
                    wrong.push(format!("expected a plan for {name}, but the KB is refused: {errors:?}"));
                    continue;
                }
                let Some(problem) = session.problem(Some(name)) else {
                    wrong.push(format!("no problem {name}"));
                    continue;
                };
                let plan = match session.search(problem, &settings, &mut Silent) {
                    Ok(searched) => searched.plans[0].clone(),
                    Err(failed) => {
                        wrong.push(format!("no plan for {name}: {:?}", failed.failure));
                        continue;
                    }
                };
                if let ["length", n] = rest
                    && plan.steps.len().to_string() != *n
                {
                    wrong.push(format!("{name}: expected {n} steps, got {}", plan.steps.len()));
                }
                // kbc validate reads what kbc plan prints.
                let printed = kbc::ir::plan::print(session.interner(), session.kb(), &plan);
                let file = session.add_text("plan.txt", printed.clone());
                let verdict = session.read_plan_steps(file).map(|steps| session.validate(problem, &steps));
                if verdict.as_ref().is_none_or(|v| v.diagnostics.has_errors()) {
                    wrong.push(format!(
                        "{name}: kbc validate rejects\n{printed}{:?}",
                        verdict.map(|v| common::messages(&v.diagnostics))
                    ));
                }
            }
            ["arm", name, "length", n] => {
                let Some(problem) = session.problem(Some(name)) else {
                    wrong.push(format!("no problem {name}"));
                    continue;
                };
                let refined = session
                    .plan(problem, &settings, &mut Silent)
                    .and_then(|high| session.refine(high, &settings, &mut Silent));
                let Ok(arm) = refined else {
                    wrong.push(format!(
                        "{name}: no arm-level plan: {:?}",
                        common::messages(&session.take_diagnostics())
                    ));
                    continue;
                };
                if arm.plan().steps.len().to_string() != *n {
                    wrong.push(format!("{name}: expected {n} arm-level steps, got {}", arm.plan().steps.len()));
                }
                let refinement = arm.refinement.as_ref().expect("an arm-level plan says where it comes from");
                let printed = kbc::ir::plan::print_arm(
                    session.interner(),
                    session.kb(),
                    refinement.high.plan(),
                    arm.plan(),
                    &refinement.origin,
                );
                let file = session.add_text("arm_plan.txt", printed.clone());
                // As `kbc validate --level arm` does: on the arm-level problem as written, whose
                // initial variables the replay binds itself.
                let arm_problem = session.arm_problem(problem);
                let verdict = session.read_plan_steps(file).map(|steps| session.validate(arm_problem, &steps));
                if verdict.as_ref().is_none_or(|v| v.diagnostics.has_errors()) {
                    wrong.push(format!(
                        "{name}: the validator rejects the arm-level plan\n{printed}{:?}",
                        verdict.map(|v| common::messages(&v.diagnostics))
                    ));
                }
            }
            ["refuse-arm", name, code] => {
                let Some(problem) = session.problem(Some(name)) else {
                    wrong.push(format!("no problem {name}"));
                    continue;
                };
                // The search for another plan that refines backtracks over the whole space
                // within its budget; a small one keeps this test quick in debug builds.
                let settings = PlanSettings { max_states: 20_000, ..settings.clone() };
                let refined = session
                    .plan(problem, &settings, &mut Silent)
                    .and_then(|high| session.refine(high, &settings, &mut Silent));
                let errors = codes(&session.take_diagnostics(), Severity::Error);
                if refined.is_ok() || !errors.iter().any(|c| c == code) {
                    wrong.push(format!("{name}: expected refining to fail with {code}, got {errors:?}"));
                }
            }
            other => wrong.push(format!("unknown expectation {other:?}")),
        }
    }
    wrong
}

#[test]
fn every_corpus_kb_does_what_it_states() {
    let cases = cases();
    assert!(cases.len() >= 6, "the corpus has {} cases", cases.len());
    let mut failures = Vec::new();
    for (name, files) in &cases {
        for problem in check(files) {
            failures.push(format!("{name}: {problem}"));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
