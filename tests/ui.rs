//! UI tests: each `tests/ui/<phase>/<case>.pl` is checked on its own, and the diagnostics,
//! rendered as a terminal without colour shows them, must equal `<case>.stderr` beside it.
//!
//! A case whose first line is `% ui: kbc ARGS` is instead run through the `kbc` binary with
//! those arguments (`$CASE` stands for the case's path; `VAR=value` words before `kbc` set
//! environment variables), and its stderr is compared; the exit
//! status must be 1 when that shows an error and 0 otherwise. Timings and memory figures in
//! search statistics vary from run to run and are replaced by `[TIME]` and `[MEMORY]`.
//!
//! Run with `KBC_BLESS=1` to write the current output as the expectation (then review the
//! diff), and with `KBC_CASE=TEXT` to run only the cases whose path contains TEXT. Files in subdirectories are only reachable through `include` or a `ui:` line, not
//! checked directly. Every mismatch is reported, not just the first.

mod common;

use std::path::{Path, PathBuf};

use kbc::diag::render;
use kbc::session::Session;

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
    // `KBC_CASE=TEXT` runs only the cases whose path contains TEXT.
    let filter = std::env::var("KBC_CASE").unwrap_or_default();
    cases.retain(|case| case.to_string_lossy().contains(&filter));
    cases
}

/// Runs the front end on one file, as `kbc check` does, and renders its diagnostics; or runs
/// the command of its `% ui:` line.
pub fn render_case(path: &Path) -> Result<String, String> {
    let text = std::fs::read_to_string(path).expect("case is readable UTF-8");
    if let Some(line) = text.lines().next().and_then(|line| line.strip_prefix("% ui: ")) {
        // `VAR=value ... kbc ARGS`: environment variables, then the command.
        let words: Vec<&str> = line.split_whitespace().collect();
        let env_count = words.iter().take_while(|w| w.contains('=')).count();
        let env: Vec<(&str, &str)> = words[..env_count].iter().filter_map(|w| w.split_once('=')).collect();
        if words.get(env_count) == Some(&"kbc") {
            return run_command(path, &words[env_count + 1..].join(" "), &env);
        }
    }
    let session = Session::open_files(&[path.to_path_buf()]);
    Ok(render::all_to_string(session.db(), session.diagnostics()))
}

fn run_command(path: &Path, command: &str, env: &[(&str, &str)]) -> Result<String, String> {
    let case = path.display().to_string();
    let args: Vec<String> = command.split_whitespace().map(|a| a.replace("$CASE", &case)).collect();
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_kbc"))
        .args(&args)
        .envs(env.iter().copied())
        .env("NO_COLOR", "1")
        .output()
        .map_err(|e| format!("cannot run kbc: {e}"))?;
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    let has_error = stderr.lines().any(|line| line.starts_with("error"));
    let expected_status = if has_error { 1 } else { 0 };
    if output.status.code() != Some(expected_status) {
        return Err(format!("`kbc {command}` exited with {}, expected {expected_status}", output.status));
    }
    Ok(normalize_figures(&stderr))
}

/// Replaces `0.123 s` by `[TIME]` and `4.5 MB` by `[MEMORY]`.
fn normalize_figures(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for (i, word) in text.split(' ').enumerate() {
        if i > 0 {
            out.push(' ');
        }
        let is_decimal = |w: &str| w.contains('.') && w.chars().all(|c| c.is_ascii_digit() || c == '.');
        if is_decimal(word) {
            out.push_str("[FIGURE]");
        } else {
            out.push_str(word);
        }
    }
    out.replace("[FIGURE] s", "[TIME]").replace("[FIGURE] MB", "[MEMORY]")
}

#[test]
fn ui() {
    let cases = cases();
    if std::env::var_os("KBC_CASE").is_none() {
        assert!(cases.len() >= 40, "expected at least 40 UI cases, found {}", cases.len());
    }
    let outputs = cases.iter().map(|case| (case.clone(), case.with_extension("stderr"), render_case(case))).collect();
    common::expect_files("UI cases", outputs);
}
