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

/// `text` written as `file` in the test's own directory `dir` (see [`scratch`]).
fn scratch_file(dir: &str, file: &str, text: &str) -> std::path::PathBuf {
    let path = scratch(dir).join(file);
    std::fs::write(&path, text).expect("a writable file");
    path
}

/// A directory of the test's own under the target directory.
fn scratch(name: &str) -> std::path::PathBuf {
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    dir
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
    for args in [
        &["--help"][..],
        &["check", "--help"],
        &["explain", "--help"],
        &["help", "check"],
        &["plan", "--help"],
        &["validate", "--help"],
        &["bench", "--help"],
    ] {
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
    // What each dump says is checked by the pass file-tests (tests/passes.rs); here, where
    // it goes: stdout, with the diagnostics apart on stderr.
    assert!(stdout(&out).starts_with("% actions\n"), "{}", stdout(&out));
    assert!(stderr(&out).is_empty(), "{}", stderr(&out));
    let parse = kbc(&["check", "--dump-after", "parse", "examples/03_paper_schema/kb.pl"]);
    assert!(stdout(&parse).starts_with("% examples/03_paper_schema/kb.pl\n"), "{}", stdout(&parse));
    // `check` stops after the front end: a later pass is a usage error.
    let later = kbc(&["check", "--dump-after", "pop", "examples/03_paper_schema/kb.pl"]);
    assert_eq!(later.status.code(), Some(2));
    assert!(stderr(&later).contains("`kbc check` stops after `hir`"), "{}", stderr(&later));
    // `plan` and `build` reach every pass.
    let kb = "examples/03_paper_schema/kb.pl";
    for (args, start) in [
        (&["plan", "--dump-after", "bt", kb][..], "sequence (6)\n"),
        (&["build", "--dump-after", "task", kb, "--emit", "bt-xml"][..], "% task for problem test1\n"),
    ] {
        let out = kbc(args);
        assert_eq!(out.status.code(), Some(0), "{args:?}: {}", stderr(&out));
        assert!(stdout(&out).starts_with(start), "{args:?}: {}", stdout(&out));
    }
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

/// The plan lines of `kbc plan`'s text output, without the comment lines (figures vary).
fn plan_lines(text: &str) -> Vec<String> {
    text.lines().filter(|l| !l.starts_with('%')).map(str::to_string).collect()
}

#[test]
fn plan_output_is_deterministic_and_validates() {
    let first = kbc(&["plan", "examples/02_llm_stacking/test_case.pl"]);
    assert_eq!(first.status.code(), Some(0), "{}", stderr(&first));
    let text = stdout(&first);
    assert!(text.starts_with("% plan for test_case (heuristic search"), "{text}");
    assert!(text.lines().last().is_some_and(|l| l.starts_with("% makespan ")), "{text}");
    for _ in 0..2 {
        assert_eq!(plan_lines(&stdout(&kbc(&["plan", "examples/02_llm_stacking/test_case.pl"]))), plan_lines(&text));
    }
    let check = validate_text("examples/02_llm_stacking/test_case.pl", &text, "plan");
    assert_eq!(check.status.code(), Some(0), "{}", stderr(&check));
    assert!(stdout(&check).starts_with("the plan is valid: in "), "{}", stdout(&check));
}

#[test]
fn plan_json_and_trace() {
    let out = kbc(&["plan", "examples/01_paper_tests/tests.pl", "--problem", "test1", "--format", "json"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let value: serde_json::Value = serde_json::from_str(stdout(&out).trim()).expect("one JSON object");
    assert_eq!(value["problem"], "test1");
    let steps = value["steps"].as_array().expect("steps");
    assert_eq!(steps.len(), 12);
    assert_eq!(steps[0]["index"], 1);
    assert!(steps.iter().all(|s| s["snap"] == "start" || s["snap"] == "end"));
    assert!(value["stats"]["expanded"].as_u64().is_some_and(|n| n > 0));

    let traced =
        kbc(&["plan", "examples/01_paper_tests/tests.pl", "--problem", "test1", "--search", "paper", "--trace"]);
    let text = stdout(&traced);
    let states = text.lines().filter(|l| l.contains("state: [")).count();
    assert_eq!(states, 13, "the initial state and one after each step: {text}");
    assert!(text.contains("ontable(b2, 3, 3)"), "{text}");
}

#[test]
fn plan_needs_a_problem_name_when_there_are_several() {
    let out = kbc(&["plan", "examples/01_paper_tests/tests.pl"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr(&out).contains("error[E0302]"), "{}", stderr(&out));
    assert_eq!(kbc(&["plan", "examples/01_paper_tests/tests.pl", "--search", "dfs"]).status.code(), Some(2));
}

#[test]
fn bench_writes_the_ladder_and_runs_a_rung() {
    let dir = std::env::temp_dir().join(format!("kbc-cli-ladder-{}", std::process::id()));
    let out = kbc(&["bench", "--filter", "_b02_", "--write", dir.to_str().expect("UTF-8 path")]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let written: Vec<_> = std::fs::read_dir(&dir).expect("written").collect();
    assert_eq!(written.len(), 3, "one rung per family");
    let planned = kbc(&["plan", dir.join("swap_b02_a3_s1.pl").to_str().expect("UTF-8 path")]);
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(planned.status.code(), Some(0), "{}", stderr(&planned));

    // The table ends with a line on the whole: here every plan is within 1.15x of its bound.
    let text = kbc(&["bench", "--filter", "_b02_", "--search", "heuristic"]);
    assert_eq!(text.status.code(), Some(0), "{}", stderr(&text));
    let last = stdout(&text).lines().last().unwrap_or_default().to_string();
    assert!(last.starts_with("heuristic search: 3 of 3 rungs solved, slowest "), "{last}");
    assert!(last.contains("within 1.3x of the bound on 3, within 1.15x on 3; "), "{last}");
    // Two blocks: the search of the schedules finds every rung's optimum, and the plans meet it.
    assert!(last.contains("; the bound is the optimum (*) on 3, met on 3; sum of makespans "), "{last}");
    assert_eq!(stdout(&text).lines().filter(|l| l.contains("* ")).count(), 3, "{}", stdout(&text));

    let run = kbc(&["bench", "--filter", "build_b02_", "--search", "heuristic", "--format", "json"]);
    assert_eq!(run.status.code(), Some(0), "{}", stderr(&run));
    let rows: serde_json::Value = serde_json::from_str(stdout(&run).trim()).expect("a JSON array");
    assert_eq!(rows[0]["problem"], "build_b02_a3_s1");
    assert_eq!(rows[0]["solved"], true);
    // The heuristic search's row for the rung `filter` names, with `extra` arguments.
    let row = |filter: &str, extra: &[&str]| -> serde_json::Value {
        let mut args = vec!["bench", "--filter", filter, "--search", "heuristic", "--format", "json"];
        args.extend_from_slice(extra);
        let run = kbc(&args);
        assert_eq!(run.status.code(), Some(0), "{}", stderr(&run));
        let rows: serde_json::Value = serde_json::from_str(stdout(&run).trim()).expect("a JSON array");
        assert_eq!(rows[0]["solved"], true, "{rows}");
        rows[0].clone()
    };
    // `--lookahead` reaches the search: the same rung solved, by another way (deterministic).
    let expanded = |extra: &[&str]| row("build_b10_", extra)["expanded"].as_u64().expect("a count");
    assert_ne!(expanded(&[]), expanded(&["--lookahead"]));
    assert_eq!(kbc(&["bench", "--filter", "no_such_rung"]).status.code(), Some(2));
    // `--improve` reaches the plan: on this rung a restart finds a shorter makespan.
    let makespan = |extra: &[&str]| {
        let args = [&["--seed", "2"], extra].concat();
        row("reverse_b05_", &args)["makespan"].as_f64().expect("a makespan")
    };
    assert!(makespan(&["--improve", "1"]) < makespan(&[]));
    let refused = kbc(&["bench", "--filter", "build_b06_", "--improve", "0"]);
    assert_eq!(refused.status.code(), Some(2));
    assert!(stderr(&refused).contains("--improve"), "{}", stderr(&refused));
}

#[test]
fn schedule_output_is_a_timed_plan_that_validates() {
    let out = kbc(&["plan", "examples/02_llm_stacking/test_case.pl", "--schedule"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let text = stdout(&out);
    let first = text.lines().find(|l| !l.starts_with('%')).expect("a timed action");
    assert!(first.starts_with("0.000: (grip a"), "{text}");
    assert!(first.ends_with(']'), "{text}");
    let check = validate_text("examples/02_llm_stacking/test_case.pl", &text, "schedule");
    assert_eq!(check.status.code(), Some(0), "{}", stderr(&check));
    assert!(stdout(&check).starts_with("the timed plan is valid"), "{}", stdout(&check));
}

/// The `% makespan N` figure of `kbc plan`'s last line.
fn makespan_of(text: &str) -> f64 {
    let line = text.lines().last().expect("a last line");
    line.strip_prefix("% makespan ").and_then(|rest| rest.split(' ').next()).expect("% makespan").parse().unwrap()
}

/// One rung of the ladder, written by `kbc bench --write` into a directory of its own that is
/// removed when the value is dropped.
struct Rung {
    dir: std::path::PathBuf,
    kb: String,
}

impl Rung {
    /// Writes the rung called `name` (e.g. `build_b08_a3_s1`, of seed 1); `tag` keeps tests
    /// apart.
    fn write(name: &str, tag: &str) -> Rung {
        let dir = std::env::temp_dir().join(format!("kbc-cli-{tag}-{}", std::process::id()));
        let seed = name.rsplit("_s").next().expect("a seed");
        let written = kbc(&["bench", "--filter", name, "--seed", seed, "--write", dir.to_str().expect("UTF-8 path")]);
        assert_eq!(written.status.code(), Some(0), "{}", stderr(&written));
        let kb = dir.join(format!("{name}.pl")).to_str().expect("UTF-8 path").to_string();
        Rung { dir, kb }
    }
}

impl Drop for Rung {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

#[test]
fn improving_keeps_the_shortest_reassigned_schedule() {
    let rung = Rung::write("build_b04_a3_s1", "improve");
    let kb = rung.kb.as_str();
    // A budget of states rather than time ends the improvement the same way on any machine.
    let improve = ["plan", kb, "--schedule", "--improve", "600", "--max-states", "2000"];
    let improved = stdout(&kbc(&improve));
    let first = stdout(&kbc(&["plan", kb, "--schedule"]));
    assert!(makespan_of(&improved) < makespan_of(&first), "{improved}\n{first}");
    assert_eq!(plan_lines(&stdout(&kbc(&improve))), plan_lines(&improved), "the same plan under a states budget");
    let check = validate_text(kb, &improved, "improved");
    assert_eq!(check.status.code(), Some(0), "{}", stderr(&check));
}

#[test]
fn improving_for_a_number_of_states_gives_the_same_shorter_plan_every_run() {
    // A grid KB in other authors' style where the default plan makes a block detour far (7.004
    // when written); a makespan of 5 is possible (b1 waits on b3's cell), and no plan is
    // shorter: the rung's proven lower bound is 5.
    let rung = Rung::write("grid_b06_a2_s6", "improve-states");
    let kb = rung.kb.as_str();
    let improve = ["plan", kb, "--schedule", "--improve-states", "8000"];
    let improved = stdout(&kbc(&improve));
    let first = stdout(&kbc(&["plan", kb, "--schedule"]));
    assert!(makespan_of(&improved) < makespan_of(&first), "{improved}\n{first}");
    assert!(makespan_of(&improved) >= 5.0, "{improved}");
    assert_eq!(plan_lines(&stdout(&kbc(&improve))), plan_lines(&improved), "the same plan on every run");
    let check = validate_text(kb, &improved, "improved-states");
    assert_eq!(check.status.code(), Some(0), "{}", stderr(&check));
    // A time and a number of states at once is a usage error, not a silent choice of one.
    let both = kbc(&["plan", kb, "--improve", "1", "--improve-states", "10"]);
    assert_eq!(both.status.code(), Some(2), "{}", stderr(&both));
    assert!(stderr(&both).contains("--improve-states"), "{}", stderr(&both));
}

#[test]
fn replans_after_a_fault_are_reassigned_too() {
    let rung = Rung::write("reverse_b08_a3_s1", "replan-reassign");
    let kb = rung.kb.as_str();
    // The replanned makespan, from `% replanned from the world read back at T: N actions, makespan M`.
    let replanned = |extra: &[&str]| -> f64 {
        let mut args = vec!["run", kb, "--fault", "drop:a2@move_block(a2"];
        args.extend_from_slice(extra);
        let out = kbc(&args);
        assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
        let text = stdout(&out);
        let line = text.lines().find(|l| l.starts_with("% replanned from")).unwrap_or_else(|| panic!("{text}"));
        line.rsplit("makespan ").next().and_then(|m| m.trim().parse().ok()).unwrap_or_else(|| panic!("{line}"))
    };
    let (reassigned, searched) = (replanned(&[]), replanned(&["--no-reassign"]));
    // (26.000 against 37.001 when written.)
    assert!(reassigned < searched, "the replan is not reassigned: {reassigned} vs {searched}");
}

#[test]
fn reassigned_schedules_say_so_and_validate() {
    // (A rung whose plan is the first search's: where a second search with the lookahead is
    // kept, `--no-reassign`, which runs no second search, schedules another plan.)
    let rung = Rung::write("reverse_b10_a4_s1", "reassign");
    let kb = rung.kb.as_str();
    let reassigned = kbc(&["plan", kb, "--schedule"]);
    let kept = kbc(&["plan", kb, "--schedule", "--no-reassign"]);
    let (reassigned_text, kept_text) = (stdout(&reassigned), stdout(&kept));
    let first_line = reassigned_text.lines().next().expect("a header");
    let before: f64 = first_line
        .split("jobs reassigned from a makespan of ")
        .nth(1)
        .and_then(|rest| rest.split([')', ',']).next())
        .unwrap_or_else(|| panic!("the header says the jobs were reassigned: {first_line}"))
        .parse()
        .expect("a number");
    assert!(!kept_text.contains("reassigned"), "{kept_text}");
    assert_eq!(makespan_of(&kept_text), before, "--no-reassign keeps the search's schedule");
    assert!(makespan_of(&reassigned_text) < before, "{reassigned_text}");
    for text in [&reassigned_text, &kept_text] {
        let check = validate_text(kb, text, "reassigned");
        assert_eq!(check.status.code(), Some(0), "{}", stderr(&check));
    }
}

#[test]
fn a_given_plan_is_checked_then_scheduled() {
    let args = ["plan", "examples/06_partial_order/kb.pl", "--plan", "examples/06_partial_order/plan.txt"];
    let out = kbc(&[&args[..], &["--dump-after", "pop"]].concat());
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    // The partial order itself is tests/passes/pop/paper_partial_order.pop.
    assert!(stdout(&out).starts_with("% partial-order plan: 8 steps"), "{}", stdout(&out));
    let invalid = kbc(&["plan", "examples/06_partial_order/kb.pl", "--plan", "tests/ui/plan/aux/invalid_step.plan"]);
    assert_eq!(invalid.status.code(), Some(1));
    assert!(stderr(&invalid).contains("error[E0309]"), "{}", stderr(&invalid));
}

#[test]
fn the_schedule_dump_gives_latest_times_and_slack() {
    let args = ["plan", "examples/06_partial_order/kb.pl", "--plan", "examples/06_partial_order/plan.txt"];
    let out = kbc(&[&args[..], &["--dump-after", "schedule"]].concat());
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let text = stdout(&out);
    let slack = |step: &str| {
        let line = text.lines().find(|l| l.starts_with(step)).unwrap_or_else(|| panic!("{step}: {text}"));
        line.rsplit(' ').next().expect("a slack").to_string()
    };
    // The second arm's chain is the critical path; the first arm's may slip by its difference.
    assert_eq!(slack("a7 "), "0.000", "{text}");
    assert_eq!(slack("a8 "), "0.000", "{text}");
    assert_eq!(slack("a1 "), "2.001", "{text}");
}

#[test]
fn the_minimal_network_bounds_every_pair_of_time_points() {
    let args = ["plan", "examples/06_partial_order/kb.pl", "--plan", "examples/06_partial_order/plan.txt"];
    let out = kbc(&[&args[..], &["--dump-after", "minimal"]].concat());
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let text = stdout(&out);
    let pairs: Vec<&str> = text.lines().filter(|l| !l.starts_with('%') && l.ends_with(']')).collect();
    assert_eq!(pairs.len(), 9 * 8 / 2, "every pair of the 9 time points once: {text}");
    // a1 starts the grip that a2 ends: its duration, [1, 2] time units.
    assert!(pairs.contains(&"a1 a2 [1000, 2000]"), "{text}");
    // The second arm's chain (a4 onwards) is not ordered against the first arm's start.
    assert!(pairs.contains(&"a1 a4 [-inf, inf]"), "{text}");
    // The first arm's move ends at least its minimum (4 units on this path, and one ε between the
    // grip's end and the move's start) after the grip starts.
    assert!(pairs.contains(&"a1 a8 [4001, inf]"), "{text}");
}

#[test]
fn pictures_of_the_partial_order_the_stn_and_the_schedule() {
    let pop = kbc(&["plan", "examples/06_partial_order/kb.pl", "--emit", "pop-dot"]);
    assert_eq!(pop.status.code(), Some(0), "{}", stderr(&pop));
    assert!(stdout(&pop).starts_with("digraph partial_order {"));
    assert!(stdout(&pop).contains("a7 -> a8;"), "{}", stdout(&pop));
    assert!(stdout(&pop).contains("label=\"a box per snap action"), "a legend: {}", stdout(&pop));
    let stn = kbc(&["plan", "examples/06_partial_order/kb.pl", "--emit", "stn-dot"]);
    assert!(stdout(&stn).starts_with("digraph stn {"));
    assert!(stdout(&stn).contains("color=blue"), "duration edges: {}", stdout(&stn));
    let path = std::env::temp_dir().join(format!("kbc-cli-gantt-{}.svg", std::process::id()));
    let out = kbc(&[
        "plan",
        "examples/02_llm_stacking/test_case.pl",
        "--emit",
        "gantt-svg",
        "-o",
        path.to_str().expect("UTF-8 path"),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let svg = std::fs::read_to_string(&path).expect("the chart was written");
    let _ = std::fs::remove_file(&path);
    assert!(svg.starts_with("<svg"));
    for arm in ["a1", "a2", "a3"] {
        assert!(svg.contains(&format!(">{arm}</text>")), "a lane for {arm}");
    }
    // The legend: a swatch and a name for each action, in the bars' colours.
    for action in ["grip", "move_block", "release"] {
        let swatch = svg.lines().find(|l| l.contains(&format!(">{action}</text>")) && l.starts_with("<rect"));
        assert!(swatch.is_some_and(|l| l.contains("width=\"10\"")), "a legend entry for {action}: {svg}");
    }
    assert_eq!(
        kbc(&["plan", "examples/06_partial_order/kb.pl", "-o", "x.svg"]).status.code(),
        Some(2),
        "-o needs --emit"
    );
}

#[test]
fn build_disasm_and_run_a_program() {
    let kb = "examples/02_llm_stacking/test_case.pl";
    let dir = std::env::temp_dir().join(format!("kbc-cli-build-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("writable");
    let path = dir.join("plan.kbb");
    let path_str = path.to_str().expect("UTF-8 path");
    let out = kbc(&["build", kb, "-o", path_str]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let first = std::fs::read(&path).expect("written");
    assert_eq!(kbc(&["build", kb, "-o", path_str]).status.code(), Some(0));
    assert_eq!(first, std::fs::read(&path).expect("written"), "byte-identical across runs");
    let listing = kbc(&["disasm", path_str]);
    assert_eq!(listing.status.code(), Some(0), "{}", stderr(&listing));
    assert!(stdout(&listing).contains("start event=e0 import=grip/2 args=[a"), "{}", stdout(&listing));
    // The trace host runs each action for its minimum duration, so the tree succeeds at the
    // schedule's makespan.
    let run = kbc(&["run", path_str, "--host", "trace"]);
    assert_eq!(run.status.code(), Some(0), "{}", stderr(&run));
    let makespan = makespan_of(&stdout(&kbc(&["plan", kb, "--schedule"])));
    assert!(stdout(&run).contains(&format!("% success at {makespan:.3};")), "{makespan}: {}", stdout(&run));
    // On the simulated arms (the default host), a bytecode file carries no goal: the run
    // shows the world it leaves, the stack the KB's goal asks for.
    let run = kbc(&["run", path_str]);
    assert_eq!(run.status.code(), Some(0), "{}", stderr(&run));
    for fact in ["ontable(b4, 5, 5)", "on(b3, b4, 5, 5)", "on(b2, b3, 5, 5)", "on(b1, b2, 5, 5)"] {
        assert!(stdout(&run).contains(&format!("%   {fact}\n")), "{fact}: {}", stdout(&run));
    }
    let xml = kbc(&["build", kb, "--emit", "bt-xml"]);
    let xml = stdout(&xml);
    assert!(xml.contains("<root BTCPP_format=\"4\""), "{xml}");
    assert!(xml.contains("<Action ID=\"grip_start\">"), "the model declares every node type: {xml}");
    assert_eq!(xml.matches("<Sequence>").count(), xml.matches("</Sequence>").count());
    // Bytecode needs a file; a corrupted one is E0501.
    assert_eq!(kbc(&["build", kb]).status.code(), Some(2));
    let mut corrupted = first.clone();
    corrupted[4] = 77;
    std::fs::write(&path, &corrupted).expect("writable");
    let bad = kbc(&["run", path_str]);
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(bad.status.code(), Some(1));
    assert!(stderr(&bad).contains("error[E0501]") && stderr(&bad).contains("format version 77"), "{}", stderr(&bad));
}

#[test]
fn behaviortree_cpp_loads_and_runs_the_xml() {
    let probe = std::process::Command::new("python3").args(["-c", "import behaviortreepy"]).output();
    if !probe.is_ok_and(|o| o.status.success()) {
        eprintln!(
            "skipped: BehaviorTree.CPP's Python bindings are absent (pip install behaviortreepy); .ci/run installs them"
        );
        return;
    }
    let out = kbc(&["build", "examples/02_llm_stacking/test_case.pl", "--emit", "bt-xml"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let xml = stdout(&out);
    let path = std::env::temp_dir().join(format!("kbc-cli-btcpp-{}.xml", std::process::id()));
    std::fs::write(&path, &xml).expect("writable");
    let run = std::process::Command::new("python3")
        .arg("tests/support/run_btcpp.py")
        .arg(&path)
        .output()
        .expect("python3 runs");
    let _ = std::fs::remove_file(&path);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let text = String::from_utf8_lossy(&run.stdout).to_string();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("NodeStatus.SUCCESS"), "{text}");
    let ticked: Vec<&str> = lines.next().unwrap_or("").split_whitespace().collect();
    // Every leaf ran once, starts and ends of each of the plan's actions among them.
    assert_eq!(ticked.len(), xml.matches("/>").count() - xml.matches("<input_port").count(), "{text}");
    let plan = plan_lines(&stdout(&kbc(&["plan", "-q", "examples/02_llm_stacking/test_case.pl"])));
    let actions = plan.iter().filter(|l| l.contains("_start(")).count();
    assert!(actions > 0, "{plan:?}");
    assert_eq!(ticked.iter().filter(|n| n.ends_with("_start")).count(), actions, "{text}");
    assert_eq!(ticked.iter().filter(|n| n.ends_with("_end")).count(), actions, "{text}");
}

/// `kbc validate KB FILE` on `text` written to a temporary file named after `tag`.
fn validate_text(kb: &str, text: &str, tag: &str) -> std::process::Output {
    let path = std::env::temp_dir().join(format!("kbc-cli-{tag}-{}.txt", std::process::id()));
    std::fs::write(&path, text).expect("writable temporary file");
    let check = kbc(&["validate", kb, path.to_str().expect("UTF-8 path")]);
    let _ = std::fs::remove_file(&path);
    check
}

#[test]
fn the_validator_runs_onkb_goals_as_the_planner_generates_a_step() {
    // `S2 \== S1` runs before `target(P, S2)` binds S2, so it holds, as in SWI-Prolog: the
    // planner may carry p1 from spot 1 to spot 1, and the validator must agree. With the goals
    // the other way round the same step is refused, and so is a spot `target/2` forbids.
    let kb = |conditions: &str| {
        format!(
            "resources(idle(_)).
spot(1). spot(2). spot(3).
target(P, S) :- spot(S), \\+ forbidden(P, S).
forbidden(p1, 3).
action(carry_start(R, P, S1, S2), [idle(R), at(P, S1)], [], [], {conditions},
    [del(idle(R)), del(at(P, S1)), add(carrying(R, P, S1, S2))]).
action(carry_end(R, P, S1, S2), [carrying(R, P, S1, S2)], [at(_, S2)], [], [],
    [del(carrying(R, P, S1, S2)), add(at(P, S2)), add(idle(R))]).
init_state([idle(r1), at(p1, 1)]).
goal_state([at(p1, 2)]).
"
        )
    };
    let first = scratch_file("onkb-order", "first.pl", &kb("[S2 \\== S1, target(P, S2)]"));
    let last = scratch_file("onkb-order", "last.pl", &kb("[target(P, S2), S2 \\== S1]"));
    let (first, last) = (first.to_str().expect("UTF-8 path"), last.to_str().expect("UTF-8 path"));
    let same_spot =
        "carry_start(r1, p1, 1, 1)\ncarry_end(r1, p1, 1, 1)\ncarry_start(r1, p1, 1, 2)\ncarry_end(r1, p1, 1, 2)\n";
    let check = validate_text(first, same_spot, "onkb-first");
    assert_eq!(check.status.code(), Some(0), "{}", stderr(&check));
    let check = validate_text(last, same_spot, "onkb-last");
    assert_eq!(check.status.code(), Some(1), "{}", stderr(&check));
    assert!(stderr(&check).contains("step 1 `carry_start(r1, p1, 1, 1)` does not apply"), "{}", stderr(&check));
    let forbidden = "carry_start(r1, p1, 1, 3)\n";
    let check = validate_text(first, forbidden, "onkb-forbidden");
    assert_eq!(check.status.code(), Some(1), "{}", stderr(&check));
    assert!(stderr(&check).contains("its OnKB goals are not provable"), "{}", stderr(&check));
    // And the plan the search finds for the first KB is one the validator accepts.
    let plan = kbc(&["plan", "-q", first]);
    assert_eq!(plan.status.code(), Some(0), "{}", stderr(&plan));
    let check = validate_text(first, &stdout(&plan), "onkb-found");
    assert_eq!(check.status.code(), Some(0), "{}", stderr(&check));
}

#[test]
fn run_recovers_from_a_fault_and_records_it() {
    let kb = "examples/02_llm_stacking/test_case.pl";
    let dir = std::env::temp_dir().join(format!("kbc-cli-fault-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("writable");
    let (record, chart) = (dir.join("run.json"), dir.join("run.svg"));
    let run = kbc(&[
        "run",
        kb,
        "--fault",
        "drop:a2@move_block(a2",
        "--record",
        record.to_str().expect("UTF-8"),
        "--gantt-svg",
        chart.to_str().expect("UTF-8"),
    ]);
    assert_eq!(run.status.code(), Some(0), "{}", stderr(&run));
    let out = stdout(&run);
    // (Whichever block the plan gives a2 first.)
    let fault = out.lines().find(|l| l.contains("FAULT   drop:a2@move_block(a2: `b")).expect("the fault, reported");
    assert!(fault.contains("` slipped from a2's gripper"), "{out}");
    assert!(out.contains("% recovery: ") || out.contains("% replanned from the world read back"), "{out}");
    assert!(out.contains("% goal reached after 1 recovery"), "{out}");
    // The record: every frame has a pose per block and a position per gripper, in time order,
    // and the block that slipped leaves the gripper when the fault says.
    let json: serde_json::Value = serde_json::from_slice(&std::fs::read(&record).expect("written")).expect("JSON");
    assert_eq!(json["format"], "kbc-sim-record");
    let frames = json["frames"].as_array().expect("frames");
    assert!(frames.len() > 100, "{} frames", frames.len());
    let times: Vec<f64> = frames.iter().map(|f| f["t"].as_f64().expect("t")).collect();
    assert!(times.windows(2).all(|w| w[0] < w[1]), "frames in time order");
    assert!(frames.iter().all(|f| f["blocks"].as_array().unwrap().len() == 4));
    assert!(frames.iter().all(|f| f["grippers"].as_array().unwrap().len() == 3));
    assert_eq!(json["faults"].as_array().expect("faults").len(), 1);
    // The chart: a planned and an executed lane per arm, the failed action outlined, the
    // fault marked.
    let svg = std::fs::read_to_string(&chart).expect("written");
    for lane in ["a1 planned", "a1 executed", "a3 executed"] {
        assert!(svg.contains(&format!(">{lane}</text>")), "{lane}: {svg}");
    }
    assert!(svg.contains("stroke=\"#d00\" stroke-width=\"2\""), "a failed bar");
    assert!(svg.contains("stroke-dasharray"), "a fault mark");
    // Without replanning, the same fault is the run's error.
    let run = kbc(&["run", kb, "--fault", "drop:a2@move_block(a2", "--no-replan"]);
    assert_eq!(run.status.code(), Some(1));
    assert!(stderr(&run).contains("error[E0502]") && stderr(&run).contains("`--no-replan`"), "{}", stderr(&run));
    // A fault that does not parse is a usage error.
    assert_eq!(kbc(&["run", kb, "--fault", "stall:a1:soon"]).status.code(), Some(2));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_bytecode_file_the_host_cannot_run_is_refused_before_it_starts() {
    let dir = scratch("unlinked");
    let program = dir.join("paper_schema.kbb");
    let program = program.to_str().expect("UTF-8 path");
    // Built for no host in particular: its actions have no arm-level refinement.
    let built = kbc(&["build", "examples/03_paper_schema/kb.pl", "-o", program]);
    assert_eq!(built.status.code(), Some(0), "{}", stderr(&built));
    let on_arms = kbc(&["run", program]);
    assert_eq!(on_arms.status.code(), Some(1));
    let text = stderr(&on_arms);
    assert!(text.contains("error[E0502]: the program does not link with the host"), "{text}");
    assert!(text.contains("`grip_ontable/2`"), "{text}");
    assert!(stdout(&on_arms).contains("0 ticks"), "nothing ran: {}", stdout(&on_arms));
    // The trace host runs any action.
    assert_eq!(kbc(&["run", program, "--host", "trace"]).status.code(), Some(0));
}

#[test]
fn a_timed_plan_with_quoted_atoms_validates() {
    // The PDDL-style printer drops the spaces between an argument's tokens; those inside a
    // quoted atom are part of the name and must stay, or `kbc validate` rejects the plan.
    let kb = scratch_file(
        "quoted",
        "quoted.pl",
        "room('room & hall'). room(lab).\n\
         action(go_start(R, P), [at(lab)], [], [], [room(R), P = f(R, 'a b')], [del(at(lab)), add(going(R))]).\n\
         action(go_end(R, P), [going(R)], [], [], [], [del(going(R)), add(at(R))]).\n\
         t :- go([at(lab)], [at('room & hall')]).\n",
    );
    let kb = kb.to_str().expect("UTF-8 path");
    let out = kbc(&["plan", kb, "--schedule"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(text.contains("(go 'room & hall' f('room & hall','a b'))"), "{text}");
    let plan = scratch_file("quoted", "timed.txt", &text);
    let check = kbc(&["validate", kb, plan.to_str().expect("UTF-8 path")]);
    assert_eq!(check.status.code(), Some(0), "{}\n{text}", stderr(&check));
}

#[test]
fn a_picture_is_the_whole_output_and_a_dash_means_stdout() {
    let kb = "examples/02_llm_stacking/test_case.pl";
    let dir = scratch("emit");
    // To a file: nothing else on stdout (the plan is not printed as well).
    let svg = dir.join("gantt.svg");
    let out = kbc(&["plan", kb, "--emit", "gantt-svg", "-o", svg.to_str().expect("UTF-8")]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stdout(&out), "");
    assert!(std::fs::read_to_string(&svg).expect("written").starts_with("<svg"));
    // `-o -`: stdout, and no file named `-`.
    let out = Command::new(env!("CARGO_BIN_EXE_kbc"))
        .current_dir(&dir)
        .args(["plan", &std::fs::canonicalize(kb).expect("exists").to_string_lossy(), "--emit", "pop-dot", "-o", "-"])
        .output()
        .expect("kbc runs");
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(stdout(&out).starts_with("digraph"), "{}", stdout(&out));
    assert!(!dir.join("-").exists(), "a file named `-` was written");
}

#[test]
fn the_version_names_the_commit() {
    let version = stdout(&kbc(&["--version"]));
    assert!(version.starts_with("kbc 0.1.0 (") && version.trim_end().ends_with(')'), "{version}");
}

#[test]
fn every_json_line_says_what_it_is() {
    // Diagnostics, then the result, on one stream: each line's `type` tells them apart.
    let out = kbc(&["plan", "examples/02_llm_stacking/test_case.pl", "--format", "json", "--message-format", "json"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let types: Vec<String> = stdout(&out)
        .lines()
        .map(|line| {
            let value: serde_json::Value = serde_json::from_str(line).expect("a JSON object a line");
            value["type"].as_str().expect("a type").to_string()
        })
        .collect();
    assert_eq!(types.last().map(String::as_str), Some("plan"), "{types:?}");
    assert!(types[..types.len() - 1].iter().all(|t| t == "diagnostic"), "{types:?}");
    assert!(types.len() >= 2, "the std-domain note comes first: {types:?}");
}

#[test]
fn quiet_drops_notes_and_status_lines_but_not_warnings() {
    let noisy = kbc(&["check", "examples/02_llm_stacking/test_case.pl"]);
    assert!(stderr(&noisy).contains("note: no action schemas given"), "{}", stderr(&noisy));
    let quiet = kbc(&["check", "-q", "examples/02_llm_stacking/test_case.pl"]);
    assert_eq!((quiet.status.code(), stderr(&quiet).as_str()), (Some(0), ""));
    // Warnings stay.
    let warned = kbc(&["--quiet", "check", "tests/ui/warnings/singleton_variables.pl"]);
    assert!(stderr(&warned).contains("warning[W0001]"), "{}", stderr(&warned));
    let dir = scratch("quiet-pddl");
    let export =
        kbc(&["export", "pddl", "examples/02_llm_stacking/test_case.pl", "-q", "-o", dir.to_str().expect("UTF-8")]);
    assert_eq!(export.status.code(), Some(0), "{}", stderr(&export));
    assert!(!stderr(&export).contains("wrote"), "no status line: {}", stderr(&export));
    assert!(stderr(&export).contains("warning[W0007]"), "the warning stays: {}", stderr(&export));
    assert!(dir.join("domain.pddl").exists());
}

#[test]
fn validate_reads_timed_plans_as_other_planners_print_them() {
    // Upper-case names, `;` comments, four decimals: kbc's own schedule, printed as LPG would.
    let kb = "examples/02_llm_stacking/test_case.pl";
    let schedule = stdout(&kbc(&["plan", kb, "--schedule", "-q"]));
    let mut other = String::from("; Plan computed by another planner\n; Time 0.02\n");
    for line in schedule.lines().filter(|l| !l.starts_with('%')) {
        let (time, rest) = line.split_once(": ").expect("a timed line");
        let (action, duration) = rest.rsplit_once(" [").expect("a duration");
        let duration = duration.trim_end_matches(']');
        other.push_str(&format!("{time}0: {} [{duration}0] ; step\n", action.to_uppercase()));
    }
    let path = scratch_file("other-planner", "plan.txt", &other);
    let out = kbc(&["validate", kb, path.to_str().expect("UTF-8")]);
    assert_eq!(out.status.code(), Some(0), "{}\n{other}", stderr(&out));
}

#[test]
fn completion_scripts_know_the_subcommands_and_their_options() {
    for shell in ["bash", "zsh", "fish"] {
        let out = kbc(&["completions", shell]);
        assert_eq!(out.status.code(), Some(0), "{shell}: {}", stderr(&out));
        let script = stdout(&out);
        for word in ["plan", "validate", "dump-after", "message-format"] {
            assert!(script.contains(word), "{shell}: no `{word}` in the script");
        }
    }
    // bash reads its script without a syntax error.
    let bash = stdout(&kbc(&["completions", "bash"]));
    if let Ok(mut child) = Command::new("bash").arg("-n").stdin(std::process::Stdio::piped()).spawn() {
        use std::io::Write;
        child.stdin.take().expect("piped").write_all(bash.as_bytes()).expect("written");
        assert!(child.wait().expect("bash runs").success(), "bash rejects the script");
    }
    assert_eq!(kbc(&["completions", "tcsh"]).status.code(), Some(2), "an unknown shell is a usage error");
}

#[test]
fn graphviz_labels_escape_backslashes_and_quotes() {
    // The atom's text is `c:\tmp "x"`: in a DOT string its `\` and `"` are escaped, so dot
    // shows the name as it is.
    let kb = scratch_file(
        "dot-escape",
        "kb.pl",
        "action(go_start(R), [at(home)], [], [], [dir(R)], [del(at(home)), add(going(R))]).\n\
         action(go_end(R), [going(R)], [], [], [], [del(going(R)), add(at(R))]).\n\
         duration(go(_), 1, 1).\ndir('c:\\\\tmp \"x\"').\nt :- go([at(home)], [at('c:\\\\tmp \"x\"')]).\n",
    );
    let out = kbc(&["build", kb.to_str().expect("UTF-8"), "--emit", "bt-dot"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(stdout(&out).contains(r#"[label="e0: go_start(c:\\tmp \"x\")", shape=ellipse]"#), "{}", stdout(&out));
}

#[test]
fn a_recorded_run_has_the_documented_shape() {
    // docs/dsl.md, "Recording a run": the fields a viewer relies on.
    let dir = scratch("record");
    let path = dir.join("run.json");
    let out = kbc(&["run", "examples/02_llm_stacking/test_case.pl", "-q", "--record", path.to_str().expect("UTF-8")]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let record: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).expect("written")).expect("JSON");
    assert_eq!((record["format"].as_str(), record["version"].as_u64()), (Some("kbc-sim-record"), Some(1)));
    let blocks = record["blocks"].as_array().expect("block names").len();
    let arms = record["arms"].as_array().expect("arm names").len();
    assert_eq!((blocks, arms), (4, 3));
    let frames = record["frames"].as_array().expect("frames");
    assert!(frames.len() > 10);
    for frame in frames {
        assert!(frame["t"].as_f64().is_some());
        let poses = frame["blocks"].as_array().expect("block poses");
        assert!(poses.len() == blocks && poses.iter().all(|p| p.as_array().is_some_and(|p| p.len() == 7)));
        let grippers = frame["grippers"].as_array().expect("gripper positions");
        assert!(grippers.len() == arms && grippers.iter().all(|g| g.as_array().is_some_and(|g| g.len() == 3)));
    }
    assert!(record["faults"].as_array().is_some_and(Vec::is_empty));
}

#[test]
fn every_event_a_wait_names_is_shown_on_an_action() {
    let out = kbc(&["build", "examples/02_llm_stacking/test_case.pl", "--emit", "bt-dot", "-q"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let dot = stdout(&out);
    assert!(dot.contains("rankdir=LR") && dot.contains("label=\"boxes: sequences"), "a legend: {dot}");
    let labels: Vec<&str> = dot.lines().filter_map(|l| l.split("label=\"").nth(1)).collect();
    let mut waited = 0;
    for wait in labels.iter().filter(|l| l.starts_with("wait ")) {
        for event in wait.trim_start_matches("wait ").split(['"', ';']).filter_map(|e| e.split('+').next()) {
            if event.starts_with('e') {
                waited += 1;
                assert!(
                    labels.iter().any(|l| l.starts_with(&format!("{event}: "))),
                    "`{event}` is on no action: {dot}"
                );
            }
        }
    }
    assert!(waited > 0, "the example's tree waits for something: {dot}");
}

#[test]
fn the_stn_picture_ties_the_first_steps_to_the_origin() {
    // In the paper's example the two arms' first steps (a1, a4) follow nothing but the origin.
    let out = kbc(&[
        "plan",
        "examples/06_partial_order/kb.pl",
        "--plan",
        "examples/06_partial_order/plan.txt",
        "--emit",
        "stn-dot",
        "-q",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let dot = stdout(&out);
    let to_origin: Vec<&str> =
        dot.lines().filter(|l| l.contains("-> origin")).map(|l| l.split_whitespace().next().unwrap_or("")).collect();
    assert_eq!(to_origin, ["a1", "a4"], "{dot}");
    assert!(dot.contains("label=\"the distance graph"), "a legend: {dot}");
}

#[test]
fn epsilon_separates_an_end_from_the_start_that_depends_on_it() {
    let kb = "examples/03_paper_schema/kb.pl";
    // The put-down needs the grip's effect: by default it starts 0.001 after the grip ends,
    // with --epsilon 0.01 that much later; nothing starts at the instant of its achiever's end.
    for (epsilon, start) in [(None, "1.001: (put_down a1 b1 2 2)"), (Some("0.01"), "1.010: (put_down a1 b1 2 2)")] {
        let mut args = vec!["plan", "--schedule", kb];
        args.extend(epsilon.map(|e| ["--epsilon", e]).into_iter().flatten());
        let out = kbc(&args);
        assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
        assert!(stdout(&out).contains(start), "{epsilon:?}: {}", stdout(&out));
    }
    for bad in ["0", "0.0001", "-1", "x", "1e9"] {
        let out = kbc(&["plan", "--epsilon", bad, kb]);
        assert_eq!(out.status.code(), Some(2), "--epsilon {bad}: {}", stderr(&out));
    }
}

#[test]
fn manual_pages_come_from_the_same_definitions_as_help() {
    let main = kbc(&["man"]);
    assert_eq!(main.status.code(), Some(0), "{}", stderr(&main));
    assert!(stdout(&main).contains(".TH kbc 1"), "{}", stdout(&main));
    let plan = kbc(&["man", "plan"]);
    assert_eq!(plan.status.code(), Some(0), "{}", stderr(&plan));
    let page = stdout(&plan);
    assert!(page.contains(".TH kbc-plan 1") && page.contains("\\fBkbc plan\\fR"), "{page}");
    // Every option `kbc plan --help` lists is on the page (roff escapes the dashes).
    for option in ["--epsilon", "--level", "--schedule", "--max-states"] {
        assert!(page.contains(&option.replace('-', "\\-")), "{option} missing from the page");
    }
    assert_eq!(kbc(&["man", "nope"]).status.code(), Some(2), "an unknown subcommand is a usage error");
}

/// The pass names of a `--verbose` table on stderr, in order.
fn verbose_passes(stderr: &str) -> Vec<String> {
    let table = &stderr[stderr.find("      pass        time  what").expect("the table's header")..];
    table.lines().skip(1).filter_map(|l| l.split_whitespace().next().map(str::to_string)).collect()
}

#[test]
fn verbose_lists_the_passes_each_command_ran_after_its_output() {
    let file = "examples/02_llm_stacking/test_case.pl";
    let check = kbc(&["check", "--verbose", file]);
    assert_eq!(check.status.code(), Some(0));
    assert_eq!(verbose_passes(&stderr(&check)), ["parse", "hir", "check", "total"]);
    let build = kbc(&["build", "-v", file, "--emit", "bt-xml"]);
    assert_eq!(build.status.code(), Some(0));
    let passes = verbose_passes(&stderr(&build));
    let expected = [
        "parse",
        "hir",
        "check",
        "task",
        "search",
        "pop",
        "stn",
        "schedule",
        "eliminate",
        "reassign",
        "relocate",
        "detour",
        "relocate",
        "merge",
    ];
    assert_eq!(passes[..expected.len()], expected, "{passes:?}");
    // (Detours, relocations and merges again while they gain, then the back end.)
    assert!(passes.ends_with(&["bt".to_string(), "codegen".to_string(), "total".to_string()]), "{passes:?}");
    assert!(stdout(&build).starts_with("<?xml"), "the output itself is unchanged");
    // The search's line says what it found and what it cost.
    let text = stderr(&build);
    let search = text.lines().find(|l| l.trim_start().starts_with("search ")).expect("a search line");
    // (The search's plan: merged jobs make the plan `kbc plan` prints shorter.)
    let steps = plan_lines(&stdout(&kbc(&["plan", "-q", "--no-reassign", file]))).len();
    assert!(search.contains(&format!("a plan of {steps} snap actions")) && search.contains("expanded"), "{search}");
    // The time before the first expansion (analyses, grounding) is shown apart.
    assert!(search.contains("; set-up ") && search.contains(" s; expanded"), "{search}");
    // Successors that only swap idle arms are left out and counted; `--no-symmetry` keeps them.
    assert!(search.contains(" symmetric left out)"), "{search}");
    let all = kbc(&["plan", "-v", "--no-symmetry", file]);
    assert_eq!(all.status.code(), Some(0));
    let text = stderr(&all);
    let search = text.lines().find(|l| l.trim_start().starts_with("search ")).expect("a search line");
    assert!(search.contains("expanded") && !search.contains("symmetric"), "{search}");
    // With `--lookahead`, states reached by following a relaxed plan are counted; by default
    // there are none.
    let text = stderr(&build);
    let search = text.lines().find(|l| l.trim_start().starts_with("search ")).expect("a search line");
    assert!(search.contains("expanded") && !search.contains("lookahead"), "{search}");
    let ahead = kbc(&["plan", "-v", "--lookahead", file]);
    assert_eq!(ahead.status.code(), Some(0));
    let text = stderr(&ahead);
    let search = text.lines().find(|l| l.trim_start().starts_with("search ")).expect("a search line");
    assert!(search.contains(" reached by lookahead)"), "{search}");
    // `--improve`'s restarts are one line, whatever their number (a states budget ends them).
    let improving = kbc(&["plan", "-v", "--improve", "60", "--max-states", "300", file]);
    assert_eq!(improving.status.code(), Some(0), "{}", stderr(&improving));
    let passes = verbose_passes(&stderr(&improving));
    let searches = |passes: &[String]| passes.iter().filter(|p| *p == "search").count();
    let default = verbose_passes(&stderr(&kbc(&["plan", "-v", file])));
    assert_eq!(searches(&passes), searches(&default), "{passes:?}\n{default:?}");
    assert_eq!(passes.iter().filter(|p| *p == "restarts").count(), 1, "{passes:?}");
    let text = stderr(&improving);
    let restarts = text.lines().find(|l| l.trim_start().starts_with("restarts ")).expect("a restarts line");
    assert!(restarts.contains(" restarts, makespan "), "{restarts}");
    // Without the flag, no table; with --quiet, a usage error.
    assert!(!stderr(&kbc(&["check", file])).contains("pass        time"));
    assert_eq!(kbc(&["check", "-v", "-q", file]).status.code(), Some(2));
}

#[test]
fn a_second_search_with_the_lookahead_is_kept_only_when_shorter() {
    // On reverse_b10_a4_s3 (a small problem: no lookahead by default) `kbc plan` also
    // searches with the lookahead; it kept that plan when written (28.019 against 29.018).
    let rung = Rung::write("reverse_b10_a4_s3", "second-search");
    let kb = rung.kb.as_str();
    let default = stdout(&kbc(&["plan", kb, "--schedule"]));
    let plain = stdout(&kbc(&["plan", kb, "--schedule", "--lookahead=off"]));
    let ahead = stdout(&kbc(&["plan", kb, "--schedule", "--lookahead=on"]));
    assert!(!plain.contains("with lookahead") && !ahead.contains("shorter than without"), "{plain}\n{ahead}");
    let best = makespan_of(&plain).min(makespan_of(&ahead));
    assert_eq!(makespan_of(&default), best, "the shorter of the two searches");
    assert!(default.contains("heuristic search with lookahead, shorter than without"), "{default}");
    assert_eq!(plan_lines(&default), plan_lines(&stdout(&kbc(&["plan", kb, "--schedule"]))), "deterministic");
    let check = validate_text(kb, &default, "second-search");
    assert_eq!(check.status.code(), Some(0), "{}", stderr(&check));
    // Without `reassign` the search's own plan is kept.
    let kept = stdout(&kbc(&["plan", kb, "--schedule", "--no-reassign"]));
    assert!(!kept.contains("with lookahead"), "{kept}");
}

#[test]
fn a_run_whose_actions_take_terms_of_every_kind_checks_its_timeline() {
    // The bytecode holds an argument that is no atom or integer as an atom of its text; the
    // executed timeline reads each back as the term (`1-2`, `2.5`, `[a,b]`, `"s"`,
    // `f(g(h))`), and an atom that needs quotes as the atom (`'odd name'`, `'_A'`).
    let run = kbc(&["run", "tests/corpus/term_arguments.pl", "--host", "trace"]);
    assert_eq!(run.status.code(), Some(0), "{}", stderr(&run));
    assert!(stdout(&run).contains("% the executed timeline is valid for the KB"), "{}", stdout(&run));
    assert!(
        stdout(&run).contains("put(r1, i3, [a, b])") || stdout(&run).contains("put(r2, i3, [a, b])"),
        "{}",
        stdout(&run)
    );
}

#[test]
fn a_test_with_arguments_is_chosen_by_its_head() {
    // `test(1) :- go(...)` and `test(2) :- go(...)`: two problems, named as their heads are
    // written, each planned for its own goal.
    let kb = "test(1) :- go([available(a1), ontable(b1, 1, 1), clear(b1)], [ontable(b1, 2, 1)]).\n\
              test(2) :- go([available(a1), ontable(b1, 1, 1), clear(b1)], [ontable(b1, 3, 3)]).\n";
    let path = scratch_file("tests-with-arguments", "tests.pl", kb);
    let path = path.to_str().expect("UTF-8 path");
    for (problem, target) in [("test(1)", "2 1"), ("test(2)", "3 3")] {
        let out = kbc(&["plan", "-q", "--problem", problem, path]);
        assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
        let plan = stdout(&out);
        assert!(plan.contains(&format!("move_block_start(a1, b1, 1, 1, {})", target.replace(' ', ", "))), "{plan}");
    }
    // Without `--problem`, the error lists both by those names.
    let out = kbc(&["plan", "-q", path]);
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr(&out).contains("the problems are `test(1)`, `test(2)`"), "{}", stderr(&out));
}

/// `-v` names the resource a KB without `resources/1` implies for the search (its units alike
/// in the initial state), and names none where the KB declares one.
#[test]
fn the_task_pass_names_an_implied_resource() {
    let kb = "agent(r1). agent(r2).
action(pick_start(R, B), [free(R), loose(B)], [], [], [agent(R)], [del(free(R)), del(loose(B)), add(picking(R, B))]).
action(pick_end(R, B), [picking(R, B)], [], [], [], [del(picking(R, B)), add(held(B)), add(free(R))]).
duration(pick(_, _), 1, 2).
test1 :- go([free(r1), free(r2), loose(x), loose(y)], [held(x), held(y)]).
";
    let task_line = |text: &str| -> String {
        let file = scratch_file("implied-resource", "kb.pl", text);
        let out = kbc(&["plan", "-v", file.to_str().expect("a UTF-8 path")]);
        assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
        stderr(&out).lines().find(|l| l.trim_start().starts_with("task ")).expect("a task line").to_string()
    };
    let implied = task_line(kb);
    assert!(implied.ends_with(", resource `free(_)` implied"), "{implied}");
    let declared = task_line(&format!("{kb}resources(free(_)).\n"));
    assert!(!declared.contains("implied"), "{declared}");
}
