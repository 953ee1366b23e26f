//! Criterion benchmarks of the VM: steady-state ticks on trees of 100, 1,000 and 10,000
//! actions (throughput in leaf ticks), and load plus verify (throughput in bytes).
//! `cargo bench -p kbvm --bench vm`. Instruction counts are in `--bench tick`.

mod common;

use std::hint::black_box;

use common::{Busy, program};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use kbvm::{Program, Vm};

fn ticks(c: &mut Criterion) {
    let mut group = c.benchmark_group("tick");
    for actions in [100usize, 1_000, 10_000] {
        let program = Program::load(&program(actions).encode()).expect("valid");
        let mut vm = Vm::new(&program);
        vm.tick(&mut Busy, 0);
        let mut now = 0i64;
        group.throughput(Throughput::Elements(actions as u64));
        group.bench_function(format!("{actions}_actions"), |b| {
            b.iter(|| {
                now += 1;
                black_box(vm.tick(&mut Busy, black_box(now)))
            })
        });
    }
    group.finish();
}

fn load(c: &mut Criterion) {
    let bytes = program(10_000).encode();
    let mut group = c.benchmark_group("load_and_verify");
    group.throughput(Throughput::Bytes(bytes.len() as u64));
    group.bench_function("10000_actions", |b| b.iter(|| black_box(Program::load(black_box(&bytes)).expect("valid"))));
    group.finish();
}

criterion_group!(benches, ticks, load);
criterion_main!(benches);
