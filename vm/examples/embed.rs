//! Embedding the VM: load a program built by `kbc build`, run it against a host of our own.
//!
//!     kbc build examples/02_llm_stacking/test_case.pl -o plan.kbb
//!     cargo run -p kbvm --example embed -- plan.kbb
//!
//! The host below pretends to be a robot whose actions take exactly their least duration, and
//! `kbvm::run::run` drives it in virtual time (jumping from one event to the next). A real
//! robot would send each start to its controllers, report back from `poll`, and call
//! `Vm::tick` from its own control loop at wall-clock times instead.

use std::collections::BTreeMap;

use kbvm::run::{Outcome, VirtualHost, run};
use kbvm::{Host, Invocation, Poll, Program};

/// Running actions by id, with the time each will be done.
struct Robot {
    busy: BTreeMap<u32, i64>,
}

impl Host for Robot {
    fn start(&mut self, action: &Invocation<'_>, now: i64) -> Result<(), kbvm::HostError> {
        println!("{now:>8}  start {}", action.text());
        self.busy.insert(action.id.0, now + action.min());
        Ok(())
    }

    fn poll(&mut self, action: &Invocation<'_>, now: i64) -> Poll {
        match self.busy.get(&action.id.0) {
            Some(&done) if now >= done => {
                self.busy.remove(&action.id.0);
                println!("{now:>8}  done  {}", action.text());
                Poll::Success
            }
            Some(_) => Poll::Running,
            None => Poll::Failure(kbvm::HostError::NotRunning(format!("`{}` was never started", action.text()))),
        }
    }

    fn halt(&mut self, action: &Invocation<'_>, now: i64) {
        println!("{now:>8}  halt  {}", action.text());
        self.busy.remove(&action.id.0);
    }
}

impl VirtualHost for Robot {
    fn next_completion(&self, now: i64) -> Option<i64> {
        self.busy.values().copied().filter(|&done| done > now).min()
    }
}

fn main() {
    let Some(path) = std::env::args().nth(1) else {
        eprintln!("usage: embed PLAN.kbb   (write one with `kbc build KB -o PLAN.kbb`)");
        std::process::exit(2);
    };
    let bytes = std::fs::read(&path).unwrap_or_else(|e| {
        eprintln!("error: cannot read {path}: {e}");
        std::process::exit(1);
    });
    let program = Program::load(&bytes).unwrap_or_else(|e| {
        eprintln!("error: {path}: {e}");
        std::process::exit(1);
    });
    let mut robot = Robot { busy: BTreeMap::new() };
    // Budgets: ten million program units of time, a million ticks.
    let ran = run(&program, &mut robot, 10_000_000, 1_000_000);
    match &ran.outcome {
        Outcome::Success => println!("success at {}", ran.end),
        Outcome::Failure(failure) => println!("failure: {}", failure.describe(&program)),
        Outcome::Stuck => println!("stuck at {}: the tree waits for an event nothing records", ran.end),
        Outcome::Budget => println!("gave up at {}", ran.end),
        _ => println!("ended at {}", ran.end),
    }
}
