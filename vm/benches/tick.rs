//! Tick and load speed of the VM: `cargo bench -p kbvm --bench tick`.
//!
//! Trees of 100, 1,000 and 10,000 durative actions, each a branch of a root parallel that
//! starts its action and then waits for its end; the host never finishes an action, so after
//! the first tick every tick polls every action: one leaf tick per action. Reported per size:
//! ticks per second, nanoseconds per leaf tick, and, when valgrind is installed, instructions
//! per leaf tick counted by callgrind (the bench runs itself under callgrind twice, with 10
//! and 30 ticks, and divides the difference, so loading and setup cancel out). Then load plus
//! verify throughput on the largest program's bytes.

use std::hint::black_box;
use std::process::Command;
use std::time::Instant;

mod common;

use common::{Busy, program};
use kbvm::{Program, Status, Vm};

/// Loads the program of `actions` actions and makes `ticks` steady-state ticks.
fn workload(actions: usize, ticks: u64) {
    let program = Program::load(&program(actions).encode()).expect("valid");
    let mut vm = Vm::new(&program);
    assert_eq!(vm.tick(&mut Busy, 0), Status::Running);
    for t in 1..=ticks {
        black_box(vm.tick(&mut Busy, black_box(t as i64)));
    }
}

/// Instructions executed by `workload(actions, ticks)` under callgrind, or `None`.
fn callgrind(actions: usize, ticks: u64) -> Option<u64> {
    let exe = std::env::current_exe().ok()?;
    let out_file = std::env::temp_dir().join(format!("kbvm-callgrind-{}-{actions}-{ticks}", std::process::id()));
    let status = Command::new("valgrind")
        .arg("--tool=callgrind")
        .arg(format!("--callgrind-out-file={}", out_file.display()))
        .arg(&exe)
        .env("KBVM_BENCH_WORKLOAD", format!("{actions} {ticks}"))
        .output()
        .ok()?;
    if !status.status.success() {
        return None;
    }
    let text = std::fs::read_to_string(&out_file).ok()?;
    let _ = std::fs::remove_file(&out_file);
    text.lines().find_map(|l| l.strip_prefix("summary: ")).and_then(|n| n.trim().parse().ok())
}

fn main() {
    if let Ok(spec) = std::env::var("KBVM_BENCH_WORKLOAD") {
        let mut parts = spec.split_whitespace().map(|p| p.parse::<u64>().expect("numbers"));
        let (actions, ticks) = (parts.next().expect("actions"), parts.next().expect("ticks"));
        workload(actions as usize, ticks);
        return;
    }
    println!("{:>8} {:>14} {:>14} {:>22}", "actions", "ticks/s", "ns/leaf tick", "instructions/leaf tick");
    for actions in [100usize, 1_000, 10_000] {
        let program = Program::load(&program(actions).encode()).expect("valid");
        let mut vm = Vm::new(&program);
        vm.tick(&mut Busy, 0);
        let ticks = (2_000_000 / actions as u64).max(20);
        let started = Instant::now();
        for t in 1..=ticks {
            black_box(vm.tick(&mut Busy, black_box(t as i64)));
        }
        let seconds = started.elapsed().as_secs_f64();
        let per_leaf = seconds * 1e9 / (ticks as f64 * actions as f64);
        let instructions = match (callgrind(actions, 10), callgrind(actions, 30)) {
            (Some(a), Some(b)) => format!("{:.1}", (b.saturating_sub(a)) as f64 / (20.0 * actions as f64)),
            _ => "- (no valgrind)".to_string(),
        };
        println!("{actions:>8} {:>14.0} {per_leaf:>14.2} {instructions:>22}", ticks as f64 / seconds);
    }
    let bytes = program(10_000).encode();
    let rounds = 20;
    let started = Instant::now();
    for _ in 0..rounds {
        black_box(Program::load(black_box(&bytes)).expect("valid"));
    }
    let seconds = started.elapsed().as_secs_f64() / rounds as f64;
    println!(
        "load + verify: {:.2} MB in {:.2} ms: {:.0} MB/s",
        bytes.len() as f64 / 1e6,
        seconds * 1e3,
        bytes.len() as f64 / 1e6 / seconds
    );
}
