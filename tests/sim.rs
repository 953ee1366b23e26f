//! The simulated arms end to end: the paper's test cases and the ladder up to 10 blocks and
//! 4 arms are planned, compiled for the simulated-arms host, run in the rigid-body world, and
//! the world read back must satisfy every goal literal with every block on a cell.

mod common;

use common::{load, planned};
use kbc::execute;
use kbc::session::{HostProfile, Session};
use kbvm::run::{self, Outcome};
use kbvm::sim::{PRIMITIVES, SimConfig, SimHost};

/// Plans, builds and runs one problem on the simulated arms; returns the read-back facts as
/// text and the achieved makespan.
fn run_physically(session: &mut Session, problem: usize, what: &str) -> (Vec<String>, i64) {
    let planned = planned(session, problem);
    let built = session
        .build(&planned, Some(HostProfile { name: "sim", actions: PRIMITIVES }))
        .unwrap_or_else(|| panic!("{what}: {:?}", common::messages(session.diagnostics())));
    assert!(!built.module.refinements.is_empty(), "{what}: the std mappings refine the actions");
    let program = built.program();
    let cells = execute::kb_cells(session, problem);
    let world = execute::sim_world(&program, SimConfig::default(), &cells);
    let sim = SimHost::new(world.expect("a world"));
    let mut host = run::Logged::new(sim);
    let run = run::run(&program, &mut host, 10_000_000, 10_000_000);
    assert_eq!(run.outcome, Outcome::Success, "{what}: {:?}", host.log.last());
    let (facts, unaccounted) = execute::world_facts(host.host.world(), session.interner_mut());
    let show = |t: &kbc::ir::hir::Term| kbc::ir::hir::term_to_string(session.interner(), t, &Default::default());
    assert!(unaccounted.is_empty(), "{what}: {unaccounted:?}");
    let goal: Vec<_> = session.kb().problems[problem].goal.iter().map(|l| l.term.clone()).collect();
    let unmet: Vec<String> = execute::unmet_goals(&goal, &facts).into_iter().map(show).collect();
    assert!(unmet.is_empty(), "{what}: the world lacks {unmet:?}");
    // The goals of these problems describe every block: the read-back world is the goal's
    // blocks state exactly, not a superset.
    let world: Vec<String> = facts.iter().map(show).collect();
    let goal_text: Vec<String> = goal.iter().map(show).collect();
    for fact in &world {
        if fact.starts_with("on(") || fact.starts_with("ontable(") {
            assert!(goal_text.contains(fact), "{what}: `{fact}` is in the world but not in the goal");
        }
    }
    (world, run.end)
}

#[test]
fn the_papers_test_cases_reach_their_goals_physically() {
    let mut session = load(&["examples/01_paper_tests/tests.pl"]);
    for problem in 0..session.kb().problems.len() {
        run_physically(&mut session, problem, &format!("test{}", problem + 1));
    }
    let mut session = load(&["examples/02_llm_stacking/test_case.pl"]);
    let (world, _) = run_physically(&mut session, 0, "test_case");
    for fact in ["ontable(b4, 5, 5)", "on(b3, b4, 5, 5)", "on(b2, b3, 5, 5)", "on(b1, b2, 5, 5)", "clear(b1)"] {
        assert!(world.contains(&fact.to_string()), "{fact} in {world:?}");
    }
}

#[test]
fn the_ladder_up_to_10_blocks_and_4_arms_reaches_its_goals_physically() {
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("sim-ladder");
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    for rung in kbc::ladder::standard().into_iter().filter(|r| r.blocks <= 10 && r.arms <= 4) {
        let path = dir.join(format!("{}.pl", rung.name()));
        std::fs::write(&path, rung.source()).expect("written");
        let mut session = load(&[path.to_str().expect("utf-8")]);
        run_physically(&mut session, 0, &rung.name());
    }
}

#[test]
fn the_same_program_gives_the_same_run() {
    let mut session = load(&["examples/02_llm_stacking/test_case.pl"]);
    let a = run_physically(&mut session, 0, "first");
    let b = run_physically(&mut session, 0, "second");
    assert_eq!(a, b);
}
