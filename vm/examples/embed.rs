//! Embedding the VM: load a program built by `kbc build`, run it against a host of our own.
//!
//!     kbc build examples/02_llm_stacking/test_case.pl -o plan.kbb
//!     cargo run -p kbvm --example embed -- plan.kbb
//!
//! The host below pretends to be a robot whose actions take exactly their least duration.
//! A real one would send each start to its controllers and report back from `poll`.

use std::collections::BTreeMap;

use kbvm::{Host, Invocation, Poll, Program, Status, Vm};

/// Running actions by id, with the time each will be done.
struct Robot {
    busy: BTreeMap<u32, i64>,
}

impl Host for Robot {
    fn start(&mut self, action: &Invocation<'_>, now: i64) -> Result<(), String> {
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
            None => Poll::Failure("not started".into()),
        }
    }

    fn halt(&mut self, action: &Invocation<'_>, now: i64) {
        println!("{now:>8}  halt  {}", action.text());
        self.busy.remove(&action.id.0);
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
    let mut vm = Vm::new(&program);
    let mut robot = Robot { busy: BTreeMap::new() };
    // A fixed-rate control loop: a tick every 50 program units (50 ms if a unit is a ms).
    let mut now = 0;
    let status = loop {
        match vm.tick(&mut robot, now) {
            Status::Running if now < 10_000_000 => now += 50,
            other => break other,
        }
    };
    match (status, vm.failure()) {
        (Status::Success, _) => println!("success at {now}"),
        (_, Some(failure)) => println!("failure: {}", failure.describe(&program)),
        _ => println!("gave up at {now}"),
    }
}
