//! The README's tour runs as written: every command of its "A short tour" block is run by
//! `bash`, in order, in a scratch directory that sees the repository's `examples/` and
//! `tests/` (so the files the tour writes land there, not in the checkout), with this build's
//! `kbc` first on `PATH`. Each must exit 0, except the commands the tour shows failing on
//! purpose, which must exit 1 (an error, never a crash or a usage error).

use std::path::{Path, PathBuf};
use std::process::Command;

/// The tour's commands that demonstrate an error, by a piece of their text.
const FAILING_ON_PURPOSE: [&str; 4] = [
    "tests/ui/syntax/missing_comma_in_list.pl",
    "plan tests/ui/plan/unreachable_position.pl",
    "build tests/ui/sim/no_mapping.pl",
    "plan tests/ui/plan/arm_refinement_fails.pl",
];

/// The command lines of the README's tour block (comment lines skipped).
fn tour() -> Vec<String> {
    let readme = std::fs::read_to_string("README.md").expect("README.md");
    let start = readme.find("## A short tour").expect("a tour section");
    let block = &readme[start..];
    let open = block.find("```sh\n").expect("a shell block") + "```sh\n".len();
    let close = block[open..].find("```").expect("the block ends") + open;
    block[open..close]
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
        .map(str::to_string)
        .collect()
}

fn has(program: &str) -> bool {
    Command::new(program).arg("--version").output().is_ok_and(|o| o.status.success())
}

#[test]
fn the_readme_tour_runs_as_written() {
    let commands = tour();
    assert!(commands.len() >= 30, "the tour has {} commands", commands.len());
    for failing in FAILING_ON_PURPOSE {
        assert!(commands.iter().any(|c| c.contains(failing)), "the tour no longer runs `{failing}`");
    }
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("tour");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("writable");
    let repo = std::env::current_dir().expect("the repository");
    for shared in ["examples", "tests"] {
        std::os::unix::fs::symlink(repo.join(shared), dir.join(shared)).expect("a symlink");
    }
    let bin = Path::new(env!("CARGO_BIN_EXE_kbc")).parent().expect("the binary's directory");
    let path = format!("{}:{}", bin.display(), std::env::var("PATH").unwrap_or_default());
    let mut failures = Vec::new();
    for command in &commands {
        if command.starts_with("kairos ") && !has("kairos") {
            eprintln!("skipped (kairos is not installed; .ci/run installs it): {command}");
            continue;
        }
        let unified_planning = || {
            Command::new("python3").args(["-c", "import unified_planning"]).output().is_ok_and(|o| o.status.success())
        };
        if command.contains("up_validate.py") && !unified_planning() {
            eprintln!("skipped (unified-planning is not installed; .ci/run installs it): {command}");
            continue;
        }
        let output = Command::new("bash")
            .args(["-c", command])
            .current_dir(&dir)
            .env("PATH", &path)
            .output()
            .expect("bash runs");
        let expected = if FAILING_ON_PURPOSE.iter().any(|f| command.contains(f)) { 1 } else { 0 };
        if output.status.code() != Some(expected) {
            failures.push(format!(
                "`{command}` exited with {:?}, expected {expected}:\n{}",
                output.status.code(),
                String::from_utf8_lossy(&output.stderr)
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
    // What the tour wrote is what .gitignore lists for it.
    let ignore = std::fs::read_to_string(".gitignore").expect(".gitignore");
    for entry in std::fs::read_dir(&dir).expect("readable") {
        let name = entry.expect("an entry").file_name().to_string_lossy().to_string();
        if name == "examples" || name == "tests" {
            continue;
        }
        let listed = ignore.lines().any(|l| l.trim_end_matches('/') == format!("/{name}"));
        assert!(listed, "the tour writes `{name}`, which .gitignore does not list");
    }
}
