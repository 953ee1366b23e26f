//! The KB language is a subset of SWI-Prolog's: every example and the standard library load
//! in `swipl` without errors or warnings. Skips, saying so, where `swipl` is not installed
//! (`.ci/run` installs it).

use std::path::{Path, PathBuf};
use std::process::Command;

fn swipl_available() -> bool {
    Command::new("swipl").arg("--version").output().is_ok_and(|o| o.status.success())
}

fn kb_files() -> Vec<PathBuf> {
    let mut files = vec![PathBuf::from("std/blocks.pl")];
    for dir in std::fs::read_dir("examples").expect("examples/ exists") {
        let dir = dir.expect("readable entry").path();
        if !dir.is_dir() {
            continue;
        }
        for file in std::fs::read_dir(&dir).expect("readable example") {
            let file = file.expect("readable entry").path();
            if file.extension().is_some_and(|e| e == "pl") {
                files.push(file);
            }
        }
    }
    files.sort();
    files
}

/// Consults `file` in a fresh swipl and returns what it printed on stderr.
fn consult(file: &Path) -> (bool, String) {
    let goal = format!("consult('{}'), halt", file.display());
    let output = Command::new("swipl").args(["-q", "-g", &goal, "-t", "halt(1)"]).output().expect("swipl runs");
    (output.status.success(), String::from_utf8_lossy(&output.stderr).into_owned())
}

#[test]
fn swi_prolog_loads_every_example_and_the_standard_library() {
    if !swipl_available() {
        eprintln!("skipped: swipl is not installed (apt-get install swi-prolog-nox)");
        return;
    }
    let mut failures = Vec::new();
    for file in kb_files() {
        let (ok, stderr) = consult(&file);
        if !ok || !stderr.trim().is_empty() {
            failures.push(format!("{}:\n{stderr}", file.display()));
        }
    }
    assert!(failures.is_empty(), "swipl does not load these cleanly:\n{}", failures.join("\n"));
}
