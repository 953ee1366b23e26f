//! Consistency and the earliest-start schedule of a simple temporal network (STN): kbc's solver
//! against networkx, the paper's tool, timed in the same run.
//!
//! `cargo bench --bench stn_vs_networkx` builds STNs of 51 to 20,001 time points shaped like
//! the ones plans give (see [`plan_like`]), then
//! - times `kbc::passes::schedule::solve` on each (consistency, earliest and latest times and
//!   the makespan), best of several runs in this process;
//! - writes each network as an edge list and runs `benches/stn_networkx.py`, which times what
//!   the paper does with networkx (`negative_edge_cycle`, then Bellman-Ford from the origin for
//!   the earliest times) and networkx's cheapest equivalent (the Bellman-Ford alone), best of
//!   several runs, graph construction excluded on both sides;
//! - checks that both find the same makespan, and prints the times and ratios.
//!
//! The target (issue 4) is at least 100 times networkx at every size and 1,000 times at
//! 20,000 points. Without `python3` and networkx it reports kbc alone.
//! `KBC_BENCH_SIZES=51,501` runs only the sizes given.

use std::fmt::Write as _;
use std::process::Command;
use std::time::Instant;

use kbc::ir::pop::Reason;
use kbc::ir::stn::{DurationSource, Edge, EdgeKind, Stn, TimePoint, UNITS};
use kbc::passes::schedule;
use kbvm::rng::Rng;
use petgraph::graph::DiGraph;

const SIZES: &[usize] = &[51, 101, 501, 1001, 2001, 5001, 10001, 20001];
const ARMS: usize = 4;

/// Draws below `bound` from SplitMix64 (by modulo: a benchmark input needs no exact uniformity).
struct Random(Rng);

impl Random {
    fn next(&mut self, bound: u64) -> u64 {
        self.0.next_u64() % bound.max(1)
    }
}

/// An STN with `points` time points (the origin and a start and an end per action) in the
/// shape of a plan's: actions numbered in plan order, each on one of [`ARMS`] arms after the
/// arm's previous action, half of them also waiting for a recent action of another arm (its
/// end, or its start plus a separation), durations of 1 to 4 units with a maximum of 1 to 2
/// units more or none (like `move_block`'s `inf`), and every point after the origin.
fn plan_like(points: usize, seed: u64) -> Stn {
    let mut random = Random(Rng::new(seed));
    let actions = (points - 1) / 2;
    let mut graph: DiGraph<TimePoint, Edge> = DiGraph::new();
    let origin = graph.add_node(TimePoint::Origin);
    let nodes: Vec<_> = (0..2 * actions).map(|i| graph.add_node(TimePoint::Step(i))).collect();
    let mut durations = vec![None; 2 * actions];
    let mut last_on_arm: [Option<usize>; ARMS] = [None; ARMS];
    let source = DurationSource::Default;
    let precedence = |before, after, reason| EdgeKind::Precedence { before, after, reason };
    for action in 0..actions {
        let (start, end) = (2 * action, 2 * action + 1);
        let arm = random.next(ARMS as u64) as usize;
        let min = (1 + random.next(4) as i64) * UNITS;
        let max = match random.next(3) {
            0 => None,
            extra => Some(min + extra as i64 * UNITS),
        };
        graph.add_edge(nodes[end], nodes[start], Edge { weight: -min, kind: EdgeKind::MinDuration { start, source } });
        if let Some(max) = max {
            graph.add_edge(
                nodes[start],
                nodes[end],
                Edge { weight: max, kind: EdgeKind::MaxDuration { start, source } },
            );
        }
        durations[start] = Some(kbc::ir::stn::Bounds { min, max, source });
        if let Some(previous) = last_on_arm[arm] {
            let before = 2 * previous + 1;
            let kind = precedence(before, start, Reason::Achiever { condition: 0 });
            graph.add_edge(nodes[start], nodes[before], Edge { weight: 0, kind });
        }
        if action > 0 && random.next(2) == 0 {
            let other = action - 1 - random.next(action.min(20) as u64) as usize;
            let (before, weight) = if random.next(2) == 0 { (2 * other + 1, 0) } else { (2 * other, -1) };
            let kind = precedence(before, start, Reason::Achiever { condition: 0 });
            graph.add_edge(nodes[start], nodes[before], Edge { weight, kind });
        }
        last_on_arm[arm] = Some(action);
    }
    for &node in &nodes {
        graph.add_edge(node, origin, Edge { weight: 0, kind: EdgeKind::AfterOrigin });
    }
    Stn { graph, origin, nodes, durations, epsilon: kbc::ir::stn::EPSILON }
}

/// The network as the Python side reads it; parallel edges keep the tightest weight (a
/// networkx `DiGraph` holds one edge per pair).
fn edge_list(stn: &Stn) -> String {
    let mut tightest = std::collections::BTreeMap::new();
    for edge in stn.graph.raw_edges() {
        let key = (edge.source().index(), edge.target().index());
        let weight = tightest.entry(key).or_insert(edge.weight.weight);
        *weight = (*weight).min(edge.weight.weight);
    }
    let mut text = format!("{} {}\n", stn.graph.node_count(), stn.origin.index());
    for ((u, v), w) in tightest {
        writeln!(text, "{u} {v} {w}").expect("writing to a string");
    }
    text
}

/// Enough runs for a tenth of a second or so, at least three.
fn runs_for(points: usize) -> usize {
    (200_000 / points).clamp(3, 200)
}

struct Networkx {
    paper_way: f64,
    bellman_ford: f64,
    makespan: Option<i64>,
}

fn networkx(paths: &[std::path::PathBuf]) -> Result<Vec<Networkx>, String> {
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/benches/stn_networkx.py");
    let output = Command::new("python3")
        .arg(script)
        .arg("5")
        .args(paths)
        .output()
        .map_err(|e| format!("python3 could not be run: {e}"))?;
    if !output.status.success() {
        return Err(format!("the networkx script failed: {}", String::from_utf8_lossy(&output.stderr).trim()));
    }
    let mut results = Vec::new();
    for line in String::from_utf8_lossy(&output.stdout).lines() {
        let value: serde_json::Value = serde_json::from_str(line).map_err(|e| format!("bad line {line:?}: {e}"))?;
        results.push(Networkx {
            paper_way: value["paper_way"].as_f64().ok_or("no paper_way")?,
            bellman_ford: value["bellman_ford"].as_f64().ok_or("no bellman_ford")?,
            makespan: value["makespan"].as_i64(),
        });
    }
    Ok(results)
}

fn main() {
    let sizes: Vec<usize> = match std::env::var("KBC_BENCH_SIZES") {
        Ok(list) => list.split(',').map(|s| s.trim().parse().expect("KBC_BENCH_SIZES: numbers")).collect(),
        Err(_) => SIZES.to_vec(),
    };
    let dir = std::env::temp_dir().join(format!("kbc-stn-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temporary directory");
    let mut rows = Vec::new();
    let mut paths = Vec::new();
    for (i, &points) in sizes.iter().enumerate() {
        let stn = plan_like(points, 0x5eed + i as u64);
        let runs = runs_for(points);
        let mut best = f64::INFINITY;
        let mut makespan = None;
        for _ in 0..runs {
            let started = Instant::now();
            let result = schedule::solve(&stn);
            best = best.min(started.elapsed().as_secs_f64());
            makespan = result.ok().map(|s| s.makespan);
        }
        let path = dir.join(format!("stn-{points}.txt"));
        std::fs::write(&path, edge_list(&stn)).expect("temporary file is writable");
        paths.push(path);
        rows.push((points, stn.graph.edge_count(), best, runs, makespan));
    }
    let reference = networkx(&paths);
    let _ = std::fs::remove_dir_all(&dir);
    println!("STNs shaped like plans ({ARMS} arms); times are the best of several runs, construction excluded");
    println!(
        "{:>7} {:>7} {:>11} {:>13} {:>13} {:>9} {:>9}",
        "points", "edges", "kbc", "nx paper way", "nx BF alone", "ratio", "ratio BF"
    );
    match reference {
        Ok(results) => {
            let mut worst = f64::INFINITY;
            for ((points, edges, kbc, _, makespan), nx) in rows.iter().zip(&results) {
                assert_eq!(*makespan, nx.makespan, "kbc and networkx disagree on the {points}-point network");
                let (ratio, ratio_bf) = (nx.paper_way / kbc, nx.bellman_ford / kbc);
                worst = worst.min(ratio);
                println!(
                    "{points:>7} {edges:>7} {:>8.1} us {:>10.1} ms {:>10.1} ms {ratio:>8.0}x {ratio_bf:>8.0}x",
                    kbc * 1e6,
                    nx.paper_way * 1e3,
                    nx.bellman_ford * 1e3
                );
            }
            println!(
                "smallest ratio against the paper's way: {worst:.0}x (target: 100x at every size, 1000x at 20,001)"
            );
            println!("makespans agree on every network");
        }
        Err(why) => {
            for (points, edges, kbc, runs, _) in &rows {
                println!("{points:>7} {edges:>7} {:>8.1} us  (best of {runs})", kbc * 1e6);
            }
            println!("networkx not measured: {why}");
        }
    }
}
