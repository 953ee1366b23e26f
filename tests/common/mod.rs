//! Helpers shared by the integration tests (`mod common;` in each that uses them).

use kbc::cli::FsLoader;
use kbc::diag::Diagnostics;
use kbc::driver::{self, Frontend};
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
