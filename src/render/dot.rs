//! Graphviz DOT for the partial-order plan (`--emit pop-dot`) and the STN (`--emit stn-dot`).
//!
//! Node and edge order follow the plan, so the text is the same on every run.

use std::fmt::Write;

use petgraph::visit::EdgeRef;

use crate::intern::Interner;
use crate::ir::hir::{self, VarTable};
use crate::ir::pop::{Pop, Reason};
use crate::ir::stn::{EdgeKind, Stn, TimePoint, format_time};

/// A DOT string literal: `text` in double quotes, with `"` and `\` escaped and line breaks
/// as `\n`. The one escaper of every Graphviz picture kbc writes.
pub(crate) fn quote(text: &str) -> String {
    let mut out = String::with_capacity(text.len() + 2);
    out.push('"');
    for c in text.chars() {
        match c {
            '"' | '\\' => {
                out.push('\\');
                out.push(c);
            }
            '\n' => out.push_str("\\n"),
            _ => out.push(c),
        }
    }
    out.push('"');
    out
}

fn step_label(interner: &Interner, pop: &Pop, i: usize) -> String {
    format!("a{}: {}", i + 1, hir::term_to_string(interner, &pop.steps[i].name, &VarTable::default()))
}

/// The partial order: a node per snap action, an edge per ordering (solid for achievers,
/// bold from a start to its end, dashed for threats).
pub fn pop(interner: &Interner, pop: &Pop) -> String {
    let mut out = String::from("digraph partial_order {\n  rankdir=LR;\n  node [shape=box, fontname=\"monospace\"];\n");
    let legend = "a box per snap action (aN: step N of the plan); an edge x -> y: x comes before y. \
                  solid: x achieves a condition of y; bold: a start and its end; dashed: a threat \
                  ordering (it keeps a deletion or an addition from breaking a causal link); dotted: the refinement's \
                  or one arm's order (arm-level plans); grey from a0: needs only the initial state";
    let _ = writeln!(out, "  labelloc=t;\n  fontname=\"Helvetica\";\n  label={};", quote(legend));
    let _ = writeln!(out, "  a0 [label={}, shape=ellipse];", quote("a0: initial state"));
    for i in 0..pop.steps.len() {
        let _ = writeln!(out, "  a{} [label={}];", i + 1, quote(&step_label(interner, pop, i)));
    }
    for (i, step) in pop.steps.iter().enumerate() {
        if step.conditions.iter().all(|c| c.last == crate::ir::pop::Achiever::Init) && step.start.is_none() {
            let _ = writeln!(out, "  a0 -> a{} [color=gray];", i + 1);
        }
    }
    for ordering in &pop.orderings {
        let style = match ordering.reason {
            Reason::Achiever { .. } => "",
            Reason::StartEnd => " [style=bold]",
            Reason::Threat { .. } => " [style=dashed]",
            Reason::Refinement | Reason::SameUnit => " [style=dotted]",
        };
        let _ = writeln!(out, "  a{} -> a{}{style};", ordering.before + 1, ordering.after + 1);
    }
    out.push_str("}\n");
    out
}

/// The STN's distance graph: an edge `u -> v` labelled `w` means `t(v) - t(u) <= w`, in time
/// units. The edges from every point to the origin are left out.
pub fn stn(interner: &Interner, pop: &Pop, stn: &Stn) -> String {
    let mut out = String::from("digraph stn {\n  node [shape=box, fontname=\"monospace\"];\n");
    let legend = "the distance graph: an edge x -> y labelled w is t(y) - t(x) <= w (in time units); \
                  black: orderings, blue: durations, grey dashed: no step starts before the origin \
                  (drawn for the steps nothing else orders)";
    let _ = writeln!(out, "  labelloc=t;\n  fontname=\"Helvetica\";\n  label={};", quote(legend));
    let _ = writeln!(out, "  origin [label=\"origin (t = 0)\", shape=ellipse];");
    // The steps some ordering puts after another: every other step hangs on the origin alone.
    let ordered: std::collections::BTreeSet<usize> = stn
        .graph
        .edge_references()
        .filter_map(|e| match e.weight().kind {
            EdgeKind::Precedence { after, .. } => Some(after),
            _ => None,
        })
        .collect();
    for i in 0..pop.steps.len() {
        let _ = writeln!(out, "  a{} [label={}];", i + 1, quote(&step_label(interner, pop, i)));
    }
    for edge in stn.graph.edge_references() {
        let weight = edge.weight();
        let (from, to) = (stn.graph[edge.source()], stn.graph[edge.target()]);
        let style = match weight.kind {
            EdgeKind::AfterOrigin => match from {
                TimePoint::Step(i) if !ordered.contains(&i) => ", style=dashed, color=gray",
                _ => continue,
            },
            EdgeKind::Precedence { .. } => "",
            EdgeKind::MinDuration { .. } | EdgeKind::MaxDuration { .. } => ", color=blue",
        };
        let _ =
            writeln!(out, "  {} -> {} [label={}{style}];", from.name(), to.name(), quote(&format_time(weight.weight)));
    }
    out.push_str("}\n");
    out
}
