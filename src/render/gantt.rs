//! A Gantt chart of a schedule as SVG (`--emit gantt-svg`): one lane per unit of a resource
//! (each arm), a bar per durative action from its start to its end.
//!
//! An action's lane is the first argument of its name that is a unit of a declared resource
//! (`a1` in `grip(a1, b2)` under `resources(available(_))`); actions that name no unit go to a
//! last lane, "other". Colours follow the action's name, in order of first appearance.

use std::fmt::Write;

use crate::intern::Interner;
use crate::ir::hir::{self, Kb, Term, VarTable};
use crate::ir::pop::Pop;
use crate::ir::schedule::{self, Schedule};
use crate::ir::stn::{UNITS, format_time};

const PALETTE: [&str; 8] = ["#4e79a7", "#f28e2b", "#59a14f", "#e15759", "#76b7b2", "#edc948", "#b07aa1", "#9c755f"];
const LANE: i64 = 30;
const LEFT: i64 = 80;
const WIDTH: i64 = 900;

fn escape(text: &str) -> String {
    text.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

/// The units of the declared resources in the problem's initial state, in the order they
/// appear there: the value at the template's variable position (`a1` of `available(a1)`).
pub fn resource_units(kb: &Kb, problem: usize) -> Vec<Term> {
    let mut units: Vec<Term> = Vec::new();
    for fact in &kb.problems[problem].init {
        for resource in &kb.resources {
            let template = &resource.template;
            if template.name() != fact.name() || template.arity() != fact.arity() {
                continue;
            }
            let mut unit = None;
            let mut matches = true;
            for (slot, value) in template.term.args().iter().zip(fact.term.args()) {
                match slot {
                    Term::Var(_) => unit = unit.or(Some(value.clone())),
                    constant => matches &= constant == value,
                }
            }
            if let (true, Some(unit)) = (matches, unit)
                && !units.contains(&unit)
            {
                units.push(unit);
            }
        }
    }
    units
}

/// The SVG chart of `schedule`.
pub fn svg(interner: &Interner, kb: &Kb, pop: &Pop, schedule: &Schedule) -> String {
    let no_vars = VarTable::default();
    let units = resource_units(kb, pop.problem);
    let actions = schedule::timed_actions(kb, pop, schedule);
    let lane_of = |name: &Term| -> usize {
        name.args().iter().find_map(|a| units.iter().position(|u| u == a)).unwrap_or(units.len())
    };
    let lanes = units.len() + usize::from(actions.iter().any(|a| lane_of(&a.name) == units.len()));
    let span = schedule.makespan.max(UNITS);
    let x = |t: i64| LEFT + t * WIDTH / span;
    let height = 40 + LANE * lanes.max(1) as i64 + 30;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{height}\" font-family=\"sans-serif\" font-size=\"11\">",
        LEFT + WIDTH + 20
    );
    let _ = writeln!(
        out,
        "<text x=\"{LEFT}\" y=\"16\" font-size=\"13\">schedule of {}: makespan {}</text>",
        escape(interner.resolve(kb.problems[pop.problem].name)),
        format_time(schedule.makespan)
    );
    for lane in 0..lanes {
        let y = 30 + LANE * lane as i64;
        let label = units.get(lane).map_or("other".to_string(), |u| hir::term_to_string(interner, u, &no_vars));
        let _ = writeln!(out, "<text x=\"4\" y=\"{}\">{}</text>", y + LANE / 2 + 4, escape(&label));
        let _ = writeln!(
            out,
            "<line x1=\"{LEFT}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"#ddd\"/>",
            y + LANE,
            LEFT + WIDTH,
            y + LANE
        );
    }
    // A tick per time unit, at most twenty of them.
    let units_total = span / UNITS;
    let step = (units_total / 20).max(1) * UNITS;
    let axis = 30 + LANE * lanes.max(1) as i64;
    let mut t = 0;
    while t <= span {
        let _ = writeln!(
            out,
            "<line x1=\"{0}\" y1=\"26\" x2=\"{0}\" y2=\"{axis}\" stroke=\"#eee\"/><text x=\"{0}\" y=\"{1}\" text-anchor=\"middle\">{2}</text>",
            x(t),
            axis + 14,
            t / UNITS
        );
        t += step;
    }
    let mut colours: Vec<crate::intern::Symbol> = Vec::new();
    for action in &actions {
        let Some(duration) = action.duration else { continue };
        let lane = lane_of(&action.name) as i64;
        let base = action.name.callable().map(|(name, _)| name).unwrap_or(crate::intern::sym::TRUE);
        let colour = match colours.iter().position(|&c| c == base) {
            Some(i) => i,
            None => {
                colours.push(base);
                colours.len() - 1
            }
        };
        let (x0, x1) = (x(action.time), x(action.time + duration));
        let y = 30 + LANE * lane + 4;
        let shown = hir::term_to_string(interner, &action.name, &no_vars);
        let _ = writeln!(
            out,
            "<rect x=\"{x0}\" y=\"{y}\" width=\"{}\" height=\"{}\" fill=\"{}\" opacity=\"0.85\"><title>{} from {} to {}</title></rect>",
            (x1 - x0).max(1),
            LANE - 8,
            PALETTE[colour % PALETTE.len()],
            escape(&shown),
            format_time(action.time),
            format_time(action.time + duration)
        );
        if x1 - x0 > 40 {
            let short = action.name.callable().map_or(shown.clone(), |(name, _)| interner.resolve(name).to_string());
            let _ = writeln!(out, "<text x=\"{}\" y=\"{}\" fill=\"white\">{}</text>", x0 + 3, y + 15, escape(&short));
        }
    }
    out.push_str("</svg>\n");
    out
}
