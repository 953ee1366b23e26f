//! The invariants ARCHITECTURE.md states, checked on the source tree (in the spirit of rustc's
//! `tidy`): each test reads the files and fails with the places that break one. Codes, pages
//! and UI tests are kept in step by `tests/diagnostic_registry.rs`.

mod common;

use std::path::{Path, PathBuf};

/// Every `.rs` file under `dir`, sorted.
fn rust_files(dir: &str) -> Vec<PathBuf> {
    common::files_under(dir, "rs")
}

/// The lines of `path` outside `#[cfg(test)]` modules and comments, numbered from 1.
fn code_lines(path: &Path) -> Vec<(usize, String)> {
    let text = std::fs::read_to_string(path).expect("readable source");
    let mut lines = Vec::new();
    for (i, line) in text.lines().enumerate() {
        if line.trim_start() == "#[cfg(test)]" {
            break; // test modules come last in a file, by convention here
        }
        let code = line.split("//").next().unwrap_or_default();
        if !code.trim().is_empty() {
            lines.push((i + 1, code.to_string()));
        }
    }
    lines
}

fn under(path: &Path, prefixes: &[&str]) -> bool {
    let path = path.to_string_lossy().replace('\\', "/");
    prefixes.iter().any(|p| path.starts_with(p))
}

/// The places in `files` (outside `allowed`) whose code contains one of `needles`.
fn offending(files: &[PathBuf], allowed: &[&str], needles: &[&str]) -> Vec<String> {
    let mut found = Vec::new();
    for file in files.iter().filter(|f| !under(f, allowed)) {
        for (number, line) in code_lines(file) {
            if let Some(needle) = needles.iter().find(|n| line.contains(*n)) {
                found.push(format!("{}:{number}: `{needle}` in `{}`", file.display(), line.trim()));
            }
        }
    }
    found
}

#[test]
fn only_the_shells_print_and_only_source_fs_reads_files() {
    let needles = [
        "std::fs::",
        "fs::File",
        "println!",
        "eprintln!",
        "print!(",
        "eprint!(",
        "stdout()",
        "stderr()",
        "std::net",
        "std::process::Command",
        "env::var",
    ];
    let found = offending(&rust_files("src"), &["src/cli/", "src/lsp/", "src/main.rs", "src/source/fs.rs"], &needles);
    assert!(found.is_empty(), "IO outside the shells and src/source/fs.rs:\n{}", found.join("\n"));
}

#[test]
fn the_pass_order_is_written_once_in_the_session() {
    // Outside the session (and the planner's own modules), nothing runs the search, the
    // temporal passes or the back end itself.
    let needles = [
        "planner::search(",
        "search_scored(",
        "passes::task::build(",
        "passes::pop::build(",
        "passes::stn::build(",
        "passes::bt::build(",
        "schedule::solve(",
        "codegen::generate(",
        "codegen::refinements(",
    ];
    let found = offending(&rust_files("src"), &["src/session/", "src/planner/"], &needles);
    assert!(found.is_empty(), "a pass called outside src/session:\n{}", found.join("\n"));
}

#[test]
fn a_compiler_bug_is_reported_in_one_place() {
    let found = offending(&rust_files("src"), &["src/session/mod.rs"], &["internal compiler error"]);
    assert!(found.is_empty(), "internal errors reported outside session::internal_error:\n{}", found.join("\n"));
}

#[test]
fn only_the_language_server_knows_the_protocol_and_the_shells_do_not_import_each_other() {
    let found = offending(&rust_files("src"), &["src/lsp/"], &["lsp_types", "lsp_server"]);
    assert!(found.is_empty(), "the protocol's types outside src/lsp:\n{}", found.join("\n"));
    let found = offending(&rust_files("src/lsp"), &[], &["crate::cli"]);
    assert!(found.is_empty(), "src/lsp imports the CLI:\n{}", found.join("\n"));
    let found = offending(&rust_files("src"), &["src/cli/", "src/main.rs", "src/lib.rs"], &["crate::cli", "kbc::cli"]);
    assert!(found.is_empty(), "the library imports the CLI:\n{}", found.join("\n"));
}

#[test]
fn the_vm_never_depends_on_the_compiler_nor_reads_a_clock() {
    let manifest = std::fs::read_to_string("vm/Cargo.toml").expect("vm/Cargo.toml");
    assert!(!manifest.lines().any(|l| l.trim_start().starts_with("kbc")), "vm/Cargo.toml depends on the compiler");
    let found = offending(&rust_files("vm/src"), &[], &["kbc::", "Instant::now", "SystemTime"]);
    assert!(found.is_empty(), "the VM uses the compiler or a clock:\n{}", found.join("\n"));
}

#[test]
fn every_source_path_architecture_md_names_exists() {
    let text = std::fs::read_to_string("ARCHITECTURE.md").expect("ARCHITECTURE.md");
    let mut missing = Vec::new();
    for piece in text.split('`').skip(1).step_by(2) {
        let looks_like_path = ["src/", "vm/", "tests/", "benches/", "std/", "docs/", "examples/", "editors/"]
            .iter()
            .any(|p| piece.starts_with(p))
            && !piece.contains(['*', '<', ' ', '$']);
        if looks_like_path && !Path::new(piece.trim_end_matches('/')).exists() {
            missing.push(piece.to_string());
        }
    }
    assert!(missing.is_empty(), "ARCHITECTURE.md names paths that do not exist: {missing:?}");
}
