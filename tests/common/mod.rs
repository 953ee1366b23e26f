//! Helpers shared by the integration tests (`mod common;` in each that uses them; not every
//! test uses every helper).

#![allow(dead_code)]

use std::time::{Duration, Instant};

use kbc::cli::FsLoader;
use kbc::diag::Diagnostics;
use kbc::driver::{self, Frontend, Timed};
use kbc::ir::plan::Plan;
use kbc::passes;
use kbc::planner::{self, Budget, Options, SearchKind, Silent};
use kbc::source::SourceDb;

/// Runs the front end on KB files that must check clean; returns it with its sources.
pub fn load(paths: &[&str]) -> (Frontend, SourceDb) {
    let mut db = SourceDb::new();
    let roots: Vec<_> = paths
        .iter()
        .map(|p| {
            let text = std::fs::read_to_string(p).expect("readable file");
            db.add(p.to_string(), Some(std::fs::canonicalize(p).expect("exists")), text)
        })
        .collect();
    let frontend = driver::frontend(&mut db, &roots, &mut FsLoader);
    assert!(!frontend.diagnostics.has_errors(), "{paths:?} must check clean");
    (frontend, db)
}

/// The messages of `diagnostics`, for an assertion's failure message.
pub fn messages(diagnostics: &Diagnostics) -> Vec<String> {
    diagnostics.iter().map(|d| d.message.clone()).collect()
}

/// A plan for `problem` from the heuristic search (60 s budget).
pub fn search(frontend: &Frontend, problem: usize) -> Plan {
    let mut task = passes::task::build(&frontend.kb, problem);
    let budget = Budget { deadline: Some(Instant::now() + Duration::from_secs(60)), ..Budget::default() };
    let options = Options { search: SearchKind::Heuristic, max_depth: None, budget, plans: 1, improve: None };
    let outcome = planner::search(&frontend.kb, &frontend.interner, &mut task, &options, &mut Silent);
    outcome.result.expect("a plan")
}

/// The temporal passes on a plan that must schedule.
pub fn timed(frontend: &Frontend, plan: &Plan) -> Timed {
    let program = planner::program_for(&frontend.kb, plan.problem);
    let mut diags = Diagnostics::new();
    driver::schedule(&frontend.kb, &frontend.interner, &program, plan, &mut diags).expect("a consistent network")
}
