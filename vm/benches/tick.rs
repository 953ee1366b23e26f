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

use kbvm::bytecode::{
    Check, Effect, EventId, Fluent, FluentId, Import, ImportId, Instr, MaxTime, Module, NodeRef, Time, Value,
};
use kbvm::{Host, Invocation, Poll, Program, Status, Vm};

/// par(seq(start a_i, end a_i) for each i), each action with a condition and two effects.
fn program(actions: usize) -> Module {
    let mut nodes = vec![Instr::Parallel { children: Vec::new() }];
    let mut branches = Vec::new();
    let mut fluents = Vec::new();
    for i in 0..actions {
        let free = FluentId(2 * i as u32);
        let busy = FluentId(2 * i as u32 + 1);
        fluents.push(Fluent { functor: 1, args: vec![Value::Int(i as i64)], initial: true });
        fluents.push(Fluent { functor: 2, args: vec![Value::Int(i as i64)], initial: false });
        let at = nodes.len() as u32;
        branches.push(NodeRef(at));
        nodes.push(Instr::Sequence { children: vec![NodeRef(at + 1), NodeRef(at + 2)] });
        nodes.push(Instr::Start {
            event: EventId(2 * i as u32),
            import: ImportId(0),
            args: vec![Value::Int(i as i64), Value::Atom(3)],
            min: Time(1000),
            max: MaxTime(None),
            check: Check { require: vec![free], forbid: vec![busy], any: vec![] },
            effects: vec![Effect { add: false, fluent: free }, Effect { add: true, fluent: busy }],
        });
        nodes.push(Instr::End {
            event: EventId(2 * i as u32 + 1),
            start: EventId(2 * i as u32),
            check: Check { require: vec![busy], forbid: vec![], any: vec![] },
            effects: vec![Effect { add: false, fluent: busy }, Effect { add: true, fluent: free }],
        });
    }
    nodes[0] = Instr::Parallel { children: branches };
    Module {
        symbols: vec!["work".into(), "free".into(), "busy".into(), "a1".into()],
        imports: vec![Import { name: 0, arity: 2 }],
        fluents,
        events: 2 * actions as u32,
        time_scale: 1000,
        root: NodeRef(0),
        nodes,
        debug: None,
    }
}

/// A host whose actions never finish.
struct Busy;

impl Host for Busy {
    fn start(&mut self, _: &Invocation<'_>, _: i64) -> Result<(), String> {
        Ok(())
    }
    fn poll(&mut self, _: &Invocation<'_>, _: i64) -> Poll {
        Poll::Running
    }
    fn halt(&mut self, _: &Invocation<'_>, _: i64) {}
}

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
