//! The back end end to end: the paper's examples and the ladder compile to bytecode that
//! loads, runs to Success against the trace host, and whose executed timeline the timed
//! validator accepts; the output is byte-identical across runs.

mod common;

use common::{load, planned};
use kbc::execute;
use kbc::session::Session;
use kbvm::Program;
use kbvm::run::{self, Outcome, TraceHost};

/// Builds, runs and validates one problem; returns the bytecode and the executed makespan.
fn build_run_validate(session: &mut Session, problem: usize, what: &str) -> (Vec<u8>, i64) {
    let planned = planned(session, problem);
    let built = session.build(&planned, None).expect("builds");
    let bytes = built.module.encode();
    let program = Program::load(&bytes).unwrap_or_else(|e| panic!("{what}: the bytecode does not load: {e}"));
    let mut host = TraceHost::default();
    let run = run::run(&program, &mut host, 10_000_000, 1_000_000);
    assert_eq!(run.outcome, Outcome::Success, "{what}");
    // Every snap action happened.
    assert!(run.events.iter().all(Option::is_some), "{what}: some events never happened");
    let timeline = execute::check_timeline(session, problem, &program, &run);
    let text = execute::timed_plan(&program, &run);
    assert!(!timeline.has_errors(), "{what}: {:?}\n{text}", common::messages(&timeline));
    // With actions taking their least durations, execution keeps the earliest schedule.
    assert_eq!(run.end, planned.timed.schedule.makespan, "{what}: executed makespan");
    (bytes, run.end)
}

#[test]
fn the_papers_examples_run_to_success_and_their_timelines_validate() {
    for paths in [
        &["examples/02_llm_stacking/test_case.pl"][..],
        &["examples/06_partial_order/kb.pl"][..],
        &["examples/03_paper_schema/kb.pl"][..],
    ] {
        let mut session = load(paths);
        for problem in 0..session.kb().problems.len() {
            build_run_validate(&mut session, problem, &format!("{paths:?} #{problem}"));
        }
    }
}

#[test]
fn the_ladder_runs_to_success_and_its_timelines_validate() {
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("backend-ladder");
    std::fs::create_dir_all(&dir).expect("writable");
    for rung in kbc::ladder::standard().into_iter().filter(|r| r.blocks <= 10) {
        let path = dir.join(format!("{}.pl", rung.name()));
        std::fs::write(&path, rung.source()).expect("writable");
        let path = path.display().to_string();
        let mut session = load(&[&path]);
        build_run_validate(&mut session, 0, &rung.name());
    }
}

#[test]
fn the_bytecode_is_byte_identical_across_runs() {
    let build = || {
        let mut session = load(&["examples/02_llm_stacking/test_case.pl"]);
        build_run_validate(&mut session, 0, "test_case").0
    };
    let first = build();
    assert_eq!(first, build());
    assert_eq!(&first[..4], b"KBBC");
}
