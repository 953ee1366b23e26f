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
