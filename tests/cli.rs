//! The `kbc` binary as users run it: exit statuses, output streams and formats.

use std::path::Path;
use std::process::{Command, Output};

fn kbc(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_kbc")).args(args).output().expect("kbc runs")
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

fn stdout(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout).into_owned()
}

#[test]
fn clean_files_exit_zero_and_print_only_the_std_note() {
    let out = kbc(&["check", "examples/01_paper_tests/tests.pl"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(stderr(&out).starts_with("note: no action schemas given"), "{}", stderr(&out));
    assert!(stdout(&out).is_empty());
}

#[test]
fn errors_exit_one_with_a_summary() {
    let out = kbc(&["check", "tests/ui/syntax/missing_period.pl"]);
    assert_eq!(out.status.code(), Some(1));
    let err = stderr(&out);
    assert!(err.contains("error[E0102]: missing `.` at the end of the clause"), "{err}");
    assert!(err.trim_end().ends_with("error: aborting due to 1 error"), "{err}");
}

#[test]
fn warnings_alone_exit_zero() {
    let out = kbc(&["check", "tests/ui/warnings/singleton_variables.pl"]);
    assert_eq!(out.status.code(), Some(0));
    assert!(stderr(&out).contains("warning[W0001]"));
}

#[test]
fn usage_errors_exit_two() {
    assert_eq!(kbc(&[]).status.code(), Some(2));
    assert_eq!(kbc(&["check"]).status.code(), Some(2), "FILE is required");
    assert_eq!(kbc(&["check", "--message-format", "xml", "a.pl"]).status.code(), Some(2));
    assert_eq!(kbc(&["frobnicate"]).status.code(), Some(2));
}

#[test]
fn unreadable_files_are_user_errors() {
    let out = kbc(&["check", "no/such/file.pl"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        stderr(&out).contains("error[E0120]: cannot read `no/such/file.pl`: No such file or directory"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn every_subcommand_has_help() {
    for args in [&["--help"][..], &["check", "--help"], &["explain", "--help"], &["help", "check"]] {
        let out = kbc(args);
        assert_eq!(out.status.code(), Some(0), "{args:?}");
        assert!(stdout(&out).contains("Usage: kbc"), "{args:?}: {}", stdout(&out));
    }
}

#[test]
fn json_prints_one_object_per_diagnostic_on_stdout() {
    let out = kbc(&["check", "--message-format", "json", "tests/ui/syntax/missing_comma_in_list.pl"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr(&out).is_empty(), "human output must not mix with JSON: {}", stderr(&out));
    let lines: Vec<serde_json::Value> =
        stdout(&out).lines().map(|l| serde_json::from_str(l).expect("each line is a JSON object")).collect();
    let error = lines.iter().find(|d| d["code"] == "E0109").expect("the E0109 diagnostic");
    assert_eq!(error["severity"], "error");
    assert_eq!(error["file"], "tests/ui/syntax/missing_comma_in_list.pl");
    assert_eq!((error["line_start"].as_u64(), error["column_start"].as_u64()), (Some(1), Some(46)));
    assert_eq!(error["byte_start"], error["byte_end"], "an insertion point");
    assert_eq!(error["fixes"][0]["edits"][0]["replacement"], ",");
    assert!(error["labels"].as_array().is_some_and(|l| l.len() == 2));
    assert!(error["rendered"].as_str().is_some_and(|r| r.contains("missing `,`")));
}

#[test]
fn colour_only_when_asked_or_on_a_terminal() {
    let plain = kbc(&["check", "tests/ui/syntax/not_equal_bang.pl"]);
    assert!(!stderr(&plain).contains('\x1b'), "no escape codes when stderr is a pipe");
    let coloured = kbc(&["--color", "always", "check", "tests/ui/syntax/not_equal_bang.pl"]);
    assert!(stderr(&coloured).contains('\x1b'));
}

#[test]
fn explain_prints_the_page_and_rejects_unknown_codes() {
    let out = kbc(&["explain", "E0102"]);
    assert_eq!(out.status.code(), Some(0));
    assert!(stdout(&out).starts_with("# E0102: missing `.` at the end of a clause"));
    assert_eq!(kbc(&["explain", "w0001"]).status.code(), Some(0), "codes are case-insensitive");
    assert_eq!(kbc(&["explain", "0102"]).status.code(), Some(0), "the E may be left out");
    let unknown = kbc(&["explain", "E9999"]);
    assert_eq!(unknown.status.code(), Some(1));
    assert!(stderr(&unknown).contains("`E9999` is not a kbc diagnostic code"));
}

#[test]
fn dumps_go_to_stdout() {
    let out = kbc(&["check", "--dump-after", "hir", "examples/03_paper_schema/kb.pl"]);
    assert_eq!(out.status.code(), Some(0));
    let text = stdout(&out);
    assert!(text.contains("action grip_ontable_start(A, B)  % start of grip_ontable"), "{text}");
    assert!(text.contains("problem test1"));
    let parse = kbc(&["check", "--dump-after", "parse", "examples/03_paper_schema/kb.pl"]);
    assert!(stdout(&parse).contains("test1 :- go([available(a1), ontable(b1, 1, 1), clear(b1)]"));
}

#[test]
fn includes_resolve_relative_to_the_including_file() {
    // Run from another directory: the include paths must not depend on the working directory.
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = Command::new(env!("CARGO_BIN_EXE_kbc"))
        .current_dir(std::env::temp_dir())
        .args(["check", root.join("examples/04_split_kb/main.pl").to_str().expect("UTF-8 path")])
        .output()
        .expect("kbc runs");
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
}
