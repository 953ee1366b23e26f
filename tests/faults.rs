//! Fault injection and recovery on the simulated arms: seeded scenarios (a block dropped while
//! carried, an arm stalled or stopped for good, a block nudged to another cell) on the paper's
//! cases and ladder rungs. Each must end with the goal reached after replanning, or with a
//! clear report of why it cannot be; never a panic or a hang, and every block accounted for:
//! on a cell, held, or named in the report.

mod common;

use common::load;
use kbc::ir::hir::{Term, term_to_string};
use kbc::planner::Silent;
use kbc::recover::{self, Settings, Verdict};
use kbc::session::{HostProfile, PlanSettings};
use kbvm::sim::{FaultSpec, PRIMITIVES, Rng, SimConfig, SimHost};

/// One scenario's result: did it reach the goal, the rounds, the report.
struct Ended {
    reached: bool,
    rounds: usize,
    report: String,
}

/// Plans problem 0 of `files`, injects `fault` (open parts drawn from `seed`) and runs with
/// recovery; checks the invariants every scenario must keep.
fn scenario(files: &[&str], fault: &str, seed: u64) -> Ended {
    let what = format!("{files:?} --fault {fault} --seed {seed}");
    let mut session = load(files);
    let first = PlanSettings { reassign: false, ..common::settings() };
    let planned = session.plan(0, &first, &mut Silent).unwrap_or_else(|e| panic!("{what}: {e:?}"));
    let timed = &planned.timed;
    let built = session
        .build(&planned, Some(HostProfile { name: "sim", actions: PRIMITIVES }))
        .unwrap_or_else(|| panic!("{what}: {:?}", common::messages(session.diagnostics())));
    let program = built.program();
    let cells = kbc::execute::kb_cells(&mut session, 0);
    let world = kbc::execute::sim_world(&program, SimConfig::default(), &cells).expect("a world");
    let spec: FaultSpec = fault.parse().expect("a fault");
    let horizon = timed.schedule.makespan as f64 / program.module().time_scale as f64;
    let blocks = world.block_names();
    let resolved = spec.resolve(&world.arm_names(), &blocks, horizon, &mut Rng::new(seed));
    let sim = SimHost::with_faults(world, vec![resolved], seed);
    // A small search budget: a replan that needs more is reported, not waited for.
    let replan = PlanSettings { max_states: 20_000, ..PlanSettings::default() };
    let settings = Settings {
        replan: true,
        max_recoveries: 3,
        plan: &replan,
        profile: HostProfile { name: "sim", actions: PRIMITIVES },
        max_time: 1_000_000,
        max_ticks: 1_000_000,
    };
    let makespan = timed.schedule.makespan;
    let execution = recover::execute(&mut session, 0, program, makespan, sim, &settings);
    let (facts, unaccounted) = &kbc::execute::world_facts(execution.sim.world(), session.interner_mut());
    let interner = session.interner();
    let show = |t: &Term| term_to_string(interner, t, &Default::default());
    let world: Vec<String> = facts.iter().map(show).collect();
    // Every block is accounted for: on a cell, held, or named in an unaccounted line.
    for block in &blocks {
        let placed = world.iter().any(|f| {
            (f.starts_with("ontable(") || f.starts_with("on(") || f.starts_with("gripped("))
                && f.split(['(', ',', ')', ' ']).any(|part| part == block)
        });
        let reported = unaccounted.iter().any(|u| u.block == *block);
        assert!(placed || reported, "{what}: `{block}` is unaccounted for: {world:?} {unaccounted:?}");
    }
    let (reached, report) = match &execution.verdict {
        Verdict::GoalReached => {
            let (goal, _) = recover::waive(&session, 0, &execution.sim.world().stopped_arms());
            let unmet: Vec<String> = kbc::execute::unmet_goals(&goal, facts).into_iter().map(show).collect();
            assert!(unmet.is_empty() && unaccounted.is_empty(), "{what}: goal reached, yet {unmet:?} {unaccounted:?}");
            (true, "goal reached".to_string())
        }
        Verdict::GaveUp { why, .. } | Verdict::Unrecoverable { why } => (false, why.clone()),
        Verdict::NoPlan { .. } => (false, "no plan from the world read back".to_string()),
        Verdict::NotCompiled(d) => panic!("{what}: a replanned plan does not compile: {:?}", d.iter().next()),
        Verdict::InvalidTimeline(d) => panic!("{what}: an executed timeline breaks the KB: {:?}", d.iter().next()),
    };
    Ended { reached, rounds: execution.rounds.len(), report }
}

fn ladder_file(name: &str) -> String {
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("fault-ladder");
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    let rung = kbc::ladder::standard().into_iter().find(|r| r.name() == name).expect("a rung of that name");
    let path = dir.join(format!("{name}.pl"));
    std::fs::write(&path, rung.source()).expect("written");
    path.to_str().expect("utf-8").to_string()
}

#[test]
fn fifty_seeded_fault_scenarios_recover_or_say_why() {
    let paper = "examples/02_llm_stacking/test_case.pl".to_string();
    let rungs: Vec<String> =
        kbc::ladder::standard().into_iter().filter(|r| r.blocks <= 6 && r.arms <= 3).map(|r| r.name()).collect();
    let problems: Vec<String> = std::iter::once(paper).chain(rungs.iter().map(|n| ladder_file(n))).collect();
    let kinds = ["drop", "stall", "stop", "nudge"];
    let mut rows = Vec::new();
    for seed in 0..50u64 {
        let file = &problems[seed as usize % problems.len()];
        let kind = kinds[(seed as usize / problems.len() + seed as usize) % kinds.len()];
        let ended = scenario(&[file], kind, seed);
        rows.push((seed, kind, file.rsplit('/').next().unwrap_or(file).to_string(), ended));
    }
    let reached = rows.iter().filter(|r| r.3.reached).count();
    let recovered = rows.iter().filter(|r| r.3.reached && r.3.rounds > 1).count();
    eprintln!("seed  fault   problem                       rounds  outcome");
    for (seed, kind, file, ended) in &rows {
        eprintln!("{seed:>4}  {kind:<6}  {file:<28}  {:>6}  {}", ended.rounds, ended.report);
    }
    eprintln!("goal reached in {reached} of {} scenarios ({recovered} after replanning)", rows.len());
    for kind in kinds {
        let of_kind: Vec<_> = rows.iter().filter(|r| r.1 == kind).collect();
        let ok = of_kind.iter().filter(|r| r.3.reached).count();
        eprintln!("  {kind}: {ok} of {}", of_kind.len());
    }
    // Each kind of fault is recovered from in most scenarios (measured: see the issue note);
    // a drop in the rate is a regression.
    assert!(reached * 10 >= rows.len() * 7, "goal reached in only {reached} of {}", rows.len());
    assert!(recovered >= 10, "only {recovered} scenarios needed and survived a replan");
}

#[test]
fn a_dropped_block_is_put_back_and_the_goal_reached_by_replanning() {
    let ended = scenario(&["examples/02_llm_stacking/test_case.pl"], "drop:a2@move_block(a2", 1);
    assert!(ended.reached, "{}", ended.report);
    assert_eq!(ended.rounds, 2, "one recovery");
}

#[test]
fn a_stopped_arm_holding_a_needed_block_is_reported() {
    // a1 is the only arm: once it stops holding b1, nothing can be done.
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"));
    let path = dir.join("only_arm.pl");
    std::fs::write(
        &path,
        "only_arm :- go([available(a1), ontable(b1, 1, 1), clear(b1)], [ontable(b1, 2, 2), clear(b1)]).\n",
    )
    .expect("written");
    let ended = scenario(&[path.to_str().unwrap()], "stop:a1@move_block", 0);
    assert!(!ended.reached);
    assert!(ended.report.contains("which a1 holds and a1 has stopped"), "{}", ended.report);
}

#[test]
fn the_same_seed_gives_the_same_recovery() {
    let a = scenario(&["examples/02_llm_stacking/test_case.pl"], "nudge", 3);
    let b = scenario(&["examples/02_llm_stacking/test_case.pl"], "nudge", 3);
    assert_eq!((a.reached, a.rounds, a.report), (b.reached, b.rounds, b.report));
}
