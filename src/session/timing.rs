//! What each pass of a session took, for `--verbose`: the pass, its wall-clock time and a
//! line of what it produced.
//!
//! Recording is off unless [`enable`] was called on the thread (the CLI does it for
//! `--verbose`); then every pass a session runs on that thread is appended, in the order run,
//! and [`take`] hands them over. Off, [`time`] costs one thread-local read. A pass that runs
//! inside another (the schedules `reassign` tries, the plans a search scores) is part of the
//! outer pass's time and is not listed on its own.

use std::cell::{Cell, RefCell};
use std::time::{Duration, Instant};

/// One pass, as it ran.
#[derive(Clone, Debug, PartialEq)]
pub struct PassTime {
    /// The pass's name (`parse`, `search`, `stn`, ...).
    pub pass: &'static str,
    /// Wall-clock time.
    pub elapsed: Duration,
    /// What it produced, one line (may be empty).
    pub what: String,
}

thread_local! {
    static ENABLED: Cell<bool> = const { Cell::new(false) };
    /// How many timed passes are running on this thread.
    static DEPTH: Cell<u32> = const { Cell::new(0) };
    static TIMES: RefCell<Vec<PassTime>> = const { RefCell::new(Vec::new()) };
}

/// Starts recording on this thread.
pub fn enable() {
    ENABLED.with(|e| e.set(true));
}

/// Whether this thread records.
pub fn enabled() -> bool {
    ENABLED.with(Cell::get)
}

/// The passes recorded on this thread since the last call, in the order they ran.
pub fn take() -> Vec<PassTime> {
    TIMES.with(|t| std::mem::take(&mut *t.borrow_mut()))
}

/// Runs `f` as pass `pass`; `what` describes its result (called only when recording).
pub(crate) fn time<T>(pass: &'static str, f: impl FnOnce() -> T, what: impl FnOnce(&T) -> String) -> T {
    if !enabled() || DEPTH.with(Cell::get) > 0 {
        return f();
    }
    let started = Instant::now();
    DEPTH.with(|d| d.set(1));
    let result = f();
    DEPTH.with(|d| d.set(0));
    let elapsed = started.elapsed();
    let what = what(&result);
    TIMES.with(|t| t.borrow_mut().push(PassTime { pass, elapsed, what }));
    result
}

/// The recorded passes as a table, for people: one line per pass, then the total.
pub fn render(times: &[PassTime]) -> String {
    use std::fmt::Write;
    let mut out = String::new();
    let total: Duration = times.iter().map(|t| t.elapsed).sum();
    // The names right-aligned in a column as wide as the longest.
    let width = times.iter().map(|t| t.pass.len()).max().unwrap_or(0).max(10);
    let _ = writeln!(out, "{:>width$}  {:>10}  what", "pass", "time");
    for t in times {
        let _ = writeln!(out, "{:>width$}  {:>10}  {}", t.pass, millis(t.elapsed), t.what);
    }
    let _ = writeln!(out, "{:>width$}  {:>10}", "total", millis(total));
    out
}

fn millis(d: Duration) -> String {
    format!("{:.3} ms", d.as_secs_f64() * 1e3)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn passes_are_recorded_only_when_enabled_and_in_order() {
        // Each test runs on a thread of its own, so this thread starts disabled.
        assert_eq!(time("a", || 1, |_| "one".into()), 1);
        assert!(take().is_empty(), "nothing is recorded before `enable`");
        enable();
        time("parse", || (), |_| "3 files".into());
        time("hir", || time("inner", || (), |_| String::new()), |_| String::new());
        let times = take();
        assert_eq!(times.iter().map(|t| t.pass).collect::<Vec<_>>(), ["parse", "hir"], "not the inner pass");
        assert_eq!(times[0].what, "3 files");
        assert!(take().is_empty(), "`take` empties the record");
        let table = render(&times);
        assert!(table.lines().count() == 4 && table.contains("total"), "{table}");
        // A name longer than the column widens it: the times stay in one column.
        let long = PassTime { pass: "a longer pass name", elapsed: Duration::from_millis(2), what: String::new() };
        let table = render(&[times[0].clone(), long]);
        let ends: Vec<Option<usize>> =
            table.lines().map(|l| l.find(" ms").map(|i| i + 3).or(l.find("time").map(|i| i + 4))).collect();
        assert!(ends.len() == 4 && ends.iter().all(|&end| end.is_some() && end == ends[0]), "{table}");
    }
}
