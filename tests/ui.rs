//! UI tests: each `tests/ui/<phase>/<case>.pl` is checked on its own, and the diagnostics,
//! rendered as a terminal without colour shows them, must equal `<case>.stderr` beside it.
//!
//! Run with `KBC_BLESS=1` to write the current output as the expectation (then review the
//! diff). Files in subdirectories are only reachable through `include`, not checked directly.
//! Every mismatch is reported, not just the first.

use std::path::{Path, PathBuf};

use kbc::cli::FsLoader;
use kbc::diag::render;
use kbc::source::SourceDb;

fn cases() -> Vec<PathBuf> {
    let root = Path::new("tests/ui");
    let mut cases = Vec::new();
    for phase in std::fs::read_dir(root).expect("tests/ui exists") {
        let phase = phase.expect("readable directory entry").path();
        if !phase.is_dir() {
            continue;
        }
        for entry in std::fs::read_dir(&phase).expect("readable phase directory") {
            let path = entry.expect("readable directory entry").path();
            if path.extension().is_some_and(|e| e == "pl") {
                cases.push(path);
            }
        }
    }
    cases.sort();
    cases
}

/// Runs the front end on one file, as `kbc check` does, and renders its diagnostics.
pub fn render_case(path: &Path) -> String {
    let text = std::fs::read_to_string(path).expect("case is readable UTF-8");
    let mut db = SourceDb::new();
    let canonical = std::fs::canonicalize(path).expect("case path exists");
    let root = db.add(path.display().to_string(), Some(canonical), text);
    let frontend = kbc::driver::frontend(&mut db, &[root], &mut FsLoader);
    render::all_to_string(&db, &frontend.diagnostics)
}

#[test]
fn ui() {
    let bless = std::env::var_os("KBC_BLESS").is_some();
    let cases = cases();
    assert!(cases.len() >= 40, "expected at least 40 UI cases, found {}", cases.len());
    let mut failures = Vec::new();
    for case in &cases {
        let actual = render_case(case);
        let expected_path = case.with_extension("stderr");
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
        "{} of {} UI cases differ (re-bless with KBC_BLESS=1 after checking the change is right):\n\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n")
    );
}
