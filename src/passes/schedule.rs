//! Pass `schedule`: consistency of an STN and its earliest-start schedule.
//!
//! In the distance graph (`u -> v` of weight `w` is `t(v) - t(u) <= w`) the network is
//! consistent exactly when there is no negative cycle. The earliest time of a point is minus
//! the shortest distance from it to the origin, so one single-source shortest-path run on the
//! reversed graph, from the origin, gives every earliest time or finds a negative cycle; a
//! second run on the graph itself, with every point bounded by the makespan, gives the latest
//! times. Both are Bellman-Ford with a FIFO queue of the points whose distance changed (SPFA):
//! on the networks plans produce, nearly acyclic, a point is relaxed a handful of times, so a
//! run costs little more than a pass over the edges. A shortest path with as many edges as
//! there are points repeats a point, so there is a negative cycle; walking the parent edges
//! back from its end finds the cycle, edge by edge, for the diagnostic.

use std::collections::VecDeque;

use petgraph::graph::EdgeIndex;
use petgraph::visit::EdgeRef;

use crate::ir::schedule::Schedule;
use crate::ir::stn::{Stn, TimePoint};

/// A cycle of constraints whose weights sum below zero: the network has no solution.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct NegativeCycle {
    /// The edges of the cycle, in order along it.
    pub edges: Vec<EdgeIndex>,
    /// Their total weight (below zero).
    pub weight: i64,
}

/// Edges by source node, in compressed rows: `(target, weight, edge)`.
struct Adjacency {
    start: Vec<u32>,
    items: Vec<(u32, i64, EdgeIndex)>,
    /// Whether the edges are the graph's, reversed.
    reversed: bool,
}

impl Adjacency {
    fn new(stn: &Stn, reversed: bool) -> Adjacency {
        let n = stn.graph.node_count();
        let mut start = vec![0u32; n + 1];
        for edge in stn.graph.edge_references() {
            let from = if reversed { edge.target() } else { edge.source() };
            start[from.index() + 1] += 1;
        }
        for i in 0..n {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut items = vec![(0u32, 0i64, EdgeIndex::new(0)); stn.graph.edge_count()];
        for edge in stn.graph.edge_references() {
            let (from, to) = if reversed { (edge.target(), edge.source()) } else { (edge.source(), edge.target()) };
            items[fill[from.index()] as usize] = (to.index() as u32, edge.weight().weight, edge.id());
            fill[from.index()] += 1;
        }
        Adjacency { start, items, reversed }
    }

    fn of(&self, node: usize) -> &[(u32, i64, EdgeIndex)] {
        &self.items[self.start[node] as usize..self.start[node + 1] as usize]
    }
}

/// Shortest distances from `source` given initial upper bounds `dist`, or a negative cycle.
fn shortest(adjacency: &Adjacency, source: usize, mut dist: Vec<i64>) -> Result<Vec<i64>, NegativeCycle> {
    let reversed = adjacency.reversed;
    let n = dist.len();
    let mut parent: Vec<Option<(usize, EdgeIndex, i64)>> = vec![None; n];
    // The number of edges on each point's current shortest path: n or more means the path
    // repeats a point, so a negative cycle exists.
    let mut edges_on_path = vec![0u32; n];
    let mut queued = vec![false; n];
    let mut queue: VecDeque<usize> = VecDeque::with_capacity(n);
    // Every point with a finite bound starts in the queue, the source first: only the source
    // in the earliest-time run, every point in the latest-time run. Steps are numbered in plan
    // order, and latest times flow from later steps to earlier ones, so the latest-time run
    // queues them last step first: in that order each point is final, on most plans, the first
    // time it is taken from the queue (in plan order the run took quadratic time).
    queue.push_back(source);
    queued[source] = true;
    for (node, &d) in dist.iter().enumerate().rev() {
        if d < i64::MAX && !queued[node] {
            queue.push_back(node);
            queued[node] = true;
        }
    }
    while let Some(node) = queue.pop_front() {
        queued[node] = false;
        let base = dist[node];
        for &(to, weight, edge) in adjacency.of(node) {
            let to = to as usize;
            let candidate = base.saturating_add(weight);
            if candidate < dist[to] {
                dist[to] = candidate;
                parent[to] = Some((node, edge, weight));
                edges_on_path[to] = edges_on_path[node] + 1;
                if edges_on_path[to] as usize >= n {
                    return Err(cycle_through(&parent, to, n, reversed));
                }
                if !queued[to] {
                    queued[to] = true;
                    queue.push_back(to);
                }
            }
        }
    }
    Ok(dist)
}

/// The negative cycle behind `node` in the parent graph, its edges in the order they follow
/// each other in the distance graph (walking the parents of a run on the reversed graph
/// already goes that way; on the graph itself, backwards).
fn cycle_through(parent: &[Option<(usize, EdgeIndex, i64)>], node: usize, n: usize, reversed: bool) -> NegativeCycle {
    // Walk back n steps to be sure to stand on the cycle.
    let mut at = node;
    for _ in 0..n {
        match parent[at] {
            Some((from, _, _)) => at = from,
            None => break,
        }
    }
    let mut edges = Vec::new();
    let mut weight = 0i64;
    let first = at;
    while let Some((from, edge, w)) = parent[at] {
        edges.push(edge);
        weight += w;
        at = from;
        if at == first || edges.len() > n {
            break;
        }
    }
    if !reversed {
        edges.reverse();
    }
    NegativeCycle { edges, weight }
}

/// Checks `stn` for consistency and computes its earliest-start schedule, the latest times
/// that keep the makespan, and the makespan.
pub fn solve(stn: &Stn) -> Result<Schedule, NegativeCycle> {
    let n = stn.graph.node_count();
    let origin = stn.origin.index();
    let mut init = vec![i64::MAX; n];
    init[origin] = 0;
    // Earliest: shortest distances *to* the origin, run from it on the reversed graph.
    let to_origin = shortest(&Adjacency::new(stn, true), origin, init)?;
    let earliest: Vec<i64> = stn.nodes.iter().map(|node| -to_origin[node.index()]).collect();
    let makespan = earliest.iter().copied().max().unwrap_or(0);
    // Latest: shortest distances from the origin with every point at most the makespan.
    let mut bounds = vec![makespan; n];
    bounds[origin] = 0;
    let from_origin = shortest(&Adjacency::new(stn, false), origin, bounds)?;
    let latest: Vec<i64> = stn.nodes.iter().map(|node| from_origin[node.index()]).collect();
    debug_assert!(stn.graph[stn.origin] == TimePoint::Origin);
    Ok(Schedule { earliest, latest, makespan })
}

/// The minimal network of a consistent STN, one point at a time: the tightest bounds the
/// constraints imply between every pair of time points, which are the shortest distances
/// between them in the distance graph.
///
/// Johnson's method: any solution of the network (the earliest schedule) is a potential that
/// makes every reduced weight `w(u, v) + t(u) - t(v)` non-negative, so Dijkstra's algorithm
/// finds the distances from one point, on the graph, and to it, on the reversed graph
/// (potential `-t`). A point costs two runs, `O(E log N)`; the whole network, which has `N²`
/// entries, is produced point by point so that no `N × N` table is ever held.
pub struct MinimalNetwork {
    forward: Adjacency,
    backward: Adjacency,
    /// A solution of the network, by node index.
    potential: Vec<i64>,
}

impl MinimalNetwork {
    /// Prepares the runs; `schedule` must be the one [`solve`] found for `stn`.
    pub fn new(stn: &Stn, schedule: &Schedule) -> MinimalNetwork {
        let mut potential = vec![0i64; stn.len()];
        for (i, node) in stn.nodes.iter().enumerate() {
            potential[node.index()] = schedule.earliest[i];
        }
        MinimalNetwork { forward: Adjacency::new(stn, false), backward: Adjacency::new(stn, true), potential }
    }

    /// `(from, to)` for the point `node`: `from[v]` is the largest `t(v) - t(node)` can be and
    /// `to[v]` the largest `t(node) - t(v)` can be, by node index; `None` is unbounded.
    pub fn row(&self, node: usize) -> (Vec<Option<i64>>, Vec<Option<i64>>) {
        (self.dijkstra(&self.forward, node, 1), self.dijkstra(&self.backward, node, -1))
    }

    fn dijkstra(&self, adjacency: &Adjacency, source: usize, sign: i64) -> Vec<Option<i64>> {
        use std::cmp::Reverse;
        use std::collections::BinaryHeap;
        let p = |v: usize| sign * self.potential[v];
        let n = self.potential.len();
        let mut reduced = vec![i64::MAX; n];
        let mut done = vec![false; n];
        let mut heap = BinaryHeap::new();
        reduced[source] = 0;
        heap.push(Reverse((0i64, source)));
        while let Some(Reverse((d, node))) = heap.pop() {
            if done[node] {
                continue;
            }
            done[node] = true;
            for &(to, weight, _) in adjacency.of(node) {
                let to = to as usize;
                let w = weight + p(node) - p(to);
                debug_assert!(w >= 0, "the potential is not a solution of the network");
                let candidate = d.saturating_add(w);
                if candidate < reduced[to] {
                    reduced[to] = candidate;
                    heap.push(Reverse((candidate, to)));
                }
            }
        }
        (0..n).map(|v| (reduced[v] < i64::MAX).then(|| reduced[v] - p(source) + p(v))).collect()
    }
}
