//! Pass `bt`: the scheduled plan to a behaviour tree, the paper's way.
//!
//! A depth-first walk from the STN's origin: an action with one successor continues its
//! sequence, an action with several opens a parallel with one sequence per successor. The
//! walk follows the transitive reduction of the orderings (the paper's "parse action" that
//! removes backward links, which keeps the tree narrow). A step with several predecessors (a
//! join) is placed once, under the predecessor that finishes last in the schedule, and waits
//! there for the others: a wait node before it lists every step that must precede it and is
//! not already done before it in the tree, with the STN's least separation (a thousandth, or
//! zero from an end to a start). The least duration of a durative action is kept by its end
//! node, the greatest is checked at run time, so every execution the tree allows keeps the
//! STN's constraints (`ir::bt::verify` checks that ordering by ordering).

use crate::ir::bt::{Bt, Node};
use crate::ir::hir::Snap;
use crate::ir::pop::Pop;
use crate::ir::schedule::Schedule;
use crate::ir::stn::{EdgeKind, Stn};

/// A set of steps as bits.
#[derive(Clone)]
struct Bits(Vec<u64>);

impl Bits {
    fn new(n: usize) -> Bits {
        Bits(vec![0; n.div_ceil(64)])
    }
    fn insert(&mut self, i: usize) {
        self.0[i / 64] |= 1 << (i % 64);
    }
    fn contains(&self, i: usize) -> bool {
        self.0[i / 64] & (1 << (i % 64)) != 0
    }
    fn union_with(&mut self, other: &Bits) {
        for (a, b) in self.0.iter_mut().zip(&other.0) {
            *a |= b;
        }
    }
}

/// Builds the behaviour tree of a scheduled plan.
pub fn build(pop: &Pop, stn: &Stn, schedule: &Schedule) -> Bt {
    let n = pop.steps.len();
    // Every step that must precede each step, with the least separation.
    let mut preds: Vec<Vec<(usize, i64)>> = vec![Vec::new(); n];
    for edge in stn.graph.raw_edges() {
        if let EdgeKind::Precedence { before, after, .. } = edge.weight.kind {
            preds[after].push((before, -edge.weight.weight));
        }
    }
    for list in &mut preds {
        // One entry per step, with the largest separation.
        list.sort_by(|a, b| a.0.cmp(&b.0).then(b.1.cmp(&a.1)));
        list.dedup_by_key(|p| p.0);
    }
    // Orderings follow the total order, so plan order is a topological order.
    let mut ancestors: Vec<Bits> = Vec::with_capacity(n);
    for (s, list) in preds.iter().enumerate() {
        let mut set = Bits::new(n);
        for &(p, _) in list {
            debug_assert!(p < s, "an ordering against the total order");
            set.union_with(&ancestors[p]);
            set.insert(p);
        }
        ancestors.push(set);
    }
    // The walk's tree: each step under its last-finishing direct (reduced) predecessor.
    let mut children: Vec<Vec<usize>> = vec![Vec::new(); n + 1];
    for (s, list) in preds.iter().enumerate() {
        let direct =
            list.iter().map(|&(p, _)| p).filter(|&p| !list.iter().any(|&(q, _)| q != p && ancestors[q].contains(p)));
        let home = direct.max_by_key(|&p| (schedule.earliest[p], p));
        children[home.unwrap_or(n)].push(s);
    }
    let mut walk = Walk { pop, stn, preds: &preds, children: &children, on_path: vec![false; n] };
    let root = match children[n].as_slice() {
        [] => Node::Sequence(Vec::new()),
        [only] => Node::Sequence(walk.chain(*only)),
        many => Node::Parallel(many.iter().map(|&c| sequence(walk.chain(c))).collect()),
    };
    Bt { root }
}

/// One node for a list of sequence items.
fn sequence(mut items: Vec<Node>) -> Node {
    if items.len() == 1 { items.pop().unwrap_or(Node::Sequence(Vec::new())) } else { Node::Sequence(items) }
}

struct Walk<'a> {
    pop: &'a Pop,
    stn: &'a Stn,
    preds: &'a [Vec<(usize, i64)>],
    children: &'a [Vec<usize>],
    /// The steps on the walk's path from the origin: done before the current one.
    on_path: Vec<bool>,
}

impl Walk<'_> {
    /// The sequence items from `first` on: its wait, its action, then its successors (one
    /// continues the sequence, several open a parallel).
    fn chain(&mut self, first: usize) -> Vec<Node> {
        let mut items = Vec::new();
        let mut path = Vec::new();
        let mut step = first;
        loop {
            let wait = self.wait_before(step);
            if !wait.is_empty() {
                items.push(Node::Wait(wait));
            }
            items.push(Node::Action(step));
            self.on_path[step] = true;
            path.push(step);
            match self.children[step].as_slice() {
                [] => break,
                [only] => step = *only,
                many => {
                    let branches = many.iter().map(|&c| sequence(self.chain(c))).collect();
                    items.push(Node::Parallel(branches));
                    break;
                }
            }
        }
        for s in path {
            self.on_path[s] = false;
        }
        items
    }

    /// What `step` must wait for: each predecessor not done before it on the path, and each
    /// done before it whose separation a sequence does not give (a thousandth), except an
    /// end's own start within its least duration, which the end node keeps.
    fn wait_before(&self, step: usize) -> Vec<(usize, i64)> {
        let own_start = match self.pop.steps[step].snap {
            Snap::End => self.pop.steps[step].start,
            _ => None,
        };
        self.preds[step]
            .iter()
            .copied()
            .filter(|&(p, separation)| {
                if Some(p) == own_start {
                    let min = self.stn.durations.get(p).copied().flatten().map_or(0, |d| d.min);
                    return separation > min || !self.on_path[p];
                }
                !self.on_path[p] || separation > 0
            })
            .collect()
    }
}
