//! Simulated seconds per wall-clock second of the simulated arms (issue 6: at least 100 times
//! real time for 4 arms and 20 blocks, release build).
//!
//! `cargo bench --bench sim_realtime` plans, schedules and compiles the ladder's three 20-block,
//! 4-arm problems (not timed), then times `kbvm::run::run` of each program on a fresh simulated
//! world (world construction included), best of three runs in this process, and prints the
//! simulated makespan, the wall time and their ratio. Each run must reach Success, so a figure
//! never comes from a run that stopped early.

use std::time::{Duration, Instant};

use kbc::execute;
use kbc::ladder::{Family, Rung};
use kbc::planner::Silent;
use kbc::session::{HostProfile, PlanSettings, Session};
use kbvm::Program;
use kbvm::run::{self, Outcome};
use kbvm::sim::{PRIMITIVES, SimConfig, SimHost};

fn program(rung: &Rung) -> Program {
    let mut session = Session::from_text(&format!("{}.pl", rung.name()), rung.source());
    assert!(!session.has_errors(), "{} checks clean", rung.name());
    let settings = PlanSettings { timeout: Some(Duration::from_secs(60)), reassign: false, ..PlanSettings::default() };
    let planned = session.plan(0, &settings, &mut Silent).unwrap_or_else(|_| panic!("a plan for {}", rung.name()));
    session.build(&planned, Some(HostProfile { name: "sim", actions: PRIMITIVES })).expect("builds").program()
}

fn main() {
    println!("{:<22} {:>12} {:>10} {:>14}", "problem", "simulated s", "wall ms", "sim s / wall s");
    for family in [Family::Build, Family::Reverse, Family::Swap] {
        let rung = Rung { family, blocks: 20, arms: 4, seed: 1 };
        let program = program(&rung);
        let mut best = Duration::MAX;
        let mut makespan = 0;
        for _ in 0..3 {
            let started = Instant::now();
            let sim = SimHost::new(execute::sim_world(&program, SimConfig::default(), &[]).expect("a world"));
            let mut host = run::Logged::new(sim);
            let run = run::run(&program, &mut host, 100_000_000, 100_000_000);
            let elapsed = started.elapsed();
            assert_eq!(run.outcome, Outcome::Success, "{}: {:?}", rung.name(), host.log.last());
            best = best.min(elapsed);
            makespan = run.end;
        }
        let simulated = makespan as f64 / program.module().time_scale as f64;
        println!(
            "{:<22} {:>12.2} {:>10.1} {:>14.0}",
            rung.name(),
            simulated,
            best.as_secs_f64() * 1000.0,
            simulated / best.as_secs_f64()
        );
    }
}
