//! Reading and checking a large KB: kbc's front end against SWI-Prolog consulting the same
//! file, timed in the same run.
//!
//! `cargo bench --bench frontend_vs_swipl` writes a generated KB of 100,000 facts and 1,000
//! action schemas to a temporary file, then
//! - runs kbc's whole front end on it (read, lex, parse, lower to the HIR, every check) twenty
//!   times in this process and keeps the fastest run;
//! - runs `swipl` twenty times, each consulting the file and reporting the CPU time
//!   `consult/1` took (startup excluded), and keeps the fastest.
//!
//! Twenty runs because the machines are shared: with ten, the best kbc run varied by a tenth
//! from one invocation to the next.
//!
//! It prints MB/s and clauses/s for both and their ratio. The target (issue 2) is at least
//! 10 times SWI-Prolog's clause rate. Without `swipl` on the PATH it reports kbc alone.

#[path = "generate.rs"]
mod generate;

use std::process::Command;
use std::time::Instant;

const FACTS: usize = 100_000;
const SCHEMAS: usize = 1_000;
const RUNS: usize = 20;

fn main() {
    let text = generate::large_kb(FACTS, SCHEMAS);
    let clauses = generate::clause_count(FACTS, SCHEMAS);
    let megabytes = text.len() as f64 / 1e6;
    let path = std::env::temp_dir().join(format!("kbc-bench-{}.pl", std::process::id()));
    std::fs::write(&path, &text).expect("temporary file is writable");

    let mut kbc_best = f64::INFINITY;
    for _ in 0..RUNS {
        let started = Instant::now();
        let text = std::fs::read_to_string(&path).expect("readable");
        let session = kbc::session::Session::from_text("bench.pl", text);
        let seconds = started.elapsed().as_secs_f64();
        assert!(
            session.diagnostics().is_empty(),
            "the benchmark KB must check clean: {:?}",
            session.diagnostics().iter().next()
        );
        assert_eq!(session.kb().actions.len(), SCHEMAS);
        kbc_best = kbc_best.min(seconds);
    }

    println!("input: {FACTS} facts and {SCHEMAS} action schemas, {clauses} clauses, {megabytes:.2} MB");
    println!(
        "kbc check:    {:8.1} ms  {:7.1} MB/s  {:10.0} clauses/s  (best of {RUNS})",
        kbc_best * 1e3,
        megabytes / kbc_best,
        clauses as f64 / kbc_best
    );
    match swipl_consult_seconds(&path) {
        Some(swipl_best) => {
            println!(
                "swipl consult:{:8.1} ms  {:7.1} MB/s  {:10.0} clauses/s  (best of {RUNS}, CPU time of consult/1)",
                swipl_best * 1e3,
                megabytes / swipl_best,
                clauses as f64 / swipl_best
            );
            println!(
                "ratio: kbc reads and checks {:.1} times as many clauses per second as swipl consults",
                swipl_best / kbc_best
            );
        }
        None => println!("swipl: not on the PATH, no comparison (install swi-prolog-nox)"),
    }
    let _ = std::fs::remove_file(&path);
}

fn swipl_consult_seconds(path: &std::path::Path) -> Option<f64> {
    let goal = format!(
        "statistics(cputime, T0), consult('{}'), statistics(cputime, T1), T is T1 - T0, format('~6f~n', [T]), halt",
        path.display()
    );
    let mut best = f64::INFINITY;
    for _ in 0..RUNS {
        let output = Command::new("swipl").args(["-q", "-g", &goal]).output().ok()?;
        if !output.status.success() {
            eprintln!("swipl failed: {}", String::from_utf8_lossy(&output.stderr));
            return None;
        }
        let seconds: f64 = String::from_utf8_lossy(&output.stdout).trim().parse().ok()?;
        best = best.min(seconds);
    }
    Some(best)
}
