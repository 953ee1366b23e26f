//! The behaviour tree: sequences, parallels, waits for synchronisation and one action node per
//! snap action of the plan. Leaves refer to the steps of the partial-order plan, whose
//! conditions and effects the code generator reads.

use std::fmt::Write;

use crate::intern::Interner;
use crate::ir::hir::{self, Snap, VarTable};
use crate::ir::pop::Pop;
use crate::ir::stn::{EdgeKind, Stn, format_time};

/// A node of the behaviour tree.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Node {
    /// Children one after the other.
    Sequence(Vec<Node>),
    /// Children at the same time.
    Parallel(Vec<Node>),
    /// Wait until each step has happened and the given STN time has passed since it.
    Wait(Vec<(usize, i64)>),
    /// The snap action at this index of the plan: a start, an end or an instantaneous action.
    Action(usize),
}

/// A behaviour tree for a scheduled plan.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Bt {
    /// The root.
    pub root: Node,
}

impl Node {
    /// Calls `f` on this node and every node under it, depth first, with its depth.
    pub fn walk<'a>(&'a self, depth: usize, f: &mut impl FnMut(&'a Node, usize)) {
        f(self, depth);
        if let Node::Sequence(children) | Node::Parallel(children) = self {
            for child in children {
                child.walk(depth + 1, f);
            }
        }
    }
}

fn step_name(interner: &Interner, pop: &Pop, step: usize) -> String {
    hir::term_to_string(interner, &pop.steps[step].name, &VarTable::default())
}

/// The text form (`kbc build --dump-after bt`): one node a line, indented by depth; steps are
/// `aN` as in the partial-order plan's dump, waits list `aN+delay` in thousandths.
pub fn print(interner: &Interner, pop: &Pop, bt: &Bt) -> String {
    let mut out = String::new();
    bt.root.walk(0, &mut |node, depth| {
        let _ = write!(out, "{:indent$}", "", indent = depth * 2);
        let _ = match node {
            Node::Sequence(c) => writeln!(out, "sequence ({})", c.len()),
            Node::Parallel(c) => writeln!(out, "parallel ({})", c.len()),
            Node::Wait(after) => {
                let list: Vec<String> = after.iter().map(|&(s, d)| format!("a{}+{}", s + 1, format_time(d))).collect();
                writeln!(out, "wait {}", list.join(" "))
            }
            Node::Action(step) => writeln!(out, "a{} {}", step + 1, step_name(interner, pop, *step)),
        };
    });
    out
}

/// Checks the invariants: every step is one action node, exactly once; composites below the
/// root are not empty; and every ordering of the STN is kept: when a step's action node runs, each step
/// that must precede it has run before it in an enclosing sequence or is waited for, with at
/// least the STN's least separation, by a wait before it. A failure is a compiler bug.
pub fn verify(pop: &Pop, stn: &Stn, bt: &Bt) -> Result<(), String> {
    let n = pop.steps.len();
    let mut seen = vec![0u32; n];
    let mut problem = None;
    bt.root.walk(0, &mut |node, depth| match node {
        Node::Action(s) if *s < n => seen[*s] += 1,
        Node::Action(s) => problem = Some(format!("action node for step {} of {n}", s + 1)),
        Node::Sequence(c) | Node::Parallel(c) if c.is_empty() && depth > 0 => {
            problem = Some("an empty composite below the root".into())
        }
        Node::Wait(after) if after.iter().any(|&(s, d)| s >= n || d < 0) => problem = Some("a bad wait".into()),
        _ => {}
    });
    if let Some(p) = problem {
        return Err(p);
    }
    if let Some(s) = seen.iter().position(|&c| c != 1) {
        return Err(format!("step a{} has {} action nodes", s + 1, seen[s]));
    }
    // What is guaranteed when each action node runs: the steps done before it (in enclosing
    // sequences) and the waits before it, with the separation each wait guarantees.
    let mut before: Vec<Vec<(usize, i64)>> = vec![Vec::new(); n];
    guaranteed(&bt.root, &mut Vec::new(), &mut before);
    for edge in stn.graph.raw_edges() {
        let EdgeKind::Precedence { before: b, after: a, .. } = edge.weight.kind else { continue };
        let needed = -edge.weight.weight;
        // An end keeps its start's least duration itself.
        let own_start = pop.steps[a].snap == Snap::End && pop.steps[a].start == Some(b);
        let min = stn.durations.get(b).copied().flatten().map_or(0, |d| d.min);
        if own_start && needed <= min && before[a].iter().any(|&(s, _)| s == b) {
            continue;
        }
        if !before[a].iter().any(|&(s, d)| s == b && d >= needed) {
            return Err(format!("a{} may run before a{} + {} (STN ordering)", a + 1, b + 1, format_time(needed)));
        }
    }
    Ok(())
}

/// Fills `out[step]` with the steps (and separations) guaranteed done when `step` runs.
/// `done` holds what is guaranteed on entry to `node`; returns what is guaranteed after it.
fn guaranteed(node: &Node, done: &mut Vec<(usize, i64)>, out: &mut [Vec<(usize, i64)>]) -> Vec<(usize, i64)> {
    match node {
        Node::Action(s) => {
            out[*s] = done.clone();
            vec![(*s, 0)]
        }
        Node::Wait(after) => after.clone(),
        Node::Sequence(children) => {
            let mut added = Vec::new();
            let mark = done.len();
            for child in children {
                let more = guaranteed(child, done, out);
                done.extend(more.iter().copied());
                added.extend(more);
            }
            done.truncate(mark);
            added
        }
        Node::Parallel(children) => {
            let mut added = Vec::new();
            for child in children {
                added.extend(guaranteed(child, done, out));
            }
            added
        }
    }
}
