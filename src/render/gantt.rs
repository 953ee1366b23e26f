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

use super::xml_escape as escape;

const PALETTE: [&str; 8] = ["#4e79a7", "#f28e2b", "#59a14f", "#e15759", "#76b7b2", "#edc948", "#b07aa1", "#9c755f"];
const LANE: i64 = 30;
const LEFT: i64 = 80;
const WIDTH: i64 = 900;

/// An estimate of the width of a character of the charts' 12 px sans-serif text, in pixels:
/// about an average letter's, so a label of wide letters (`m`, `w`) can still overrun a little.
const CHAR_WIDTH: i64 = 7;

/// `label` as it fits in `width` pixels: whole, or cut with `…`; `None` when not even three
/// characters fit (the bar's tooltip still has the whole text).
fn fitted(label: &str, width: i64) -> Option<String> {
    let fits = (width / CHAR_WIDTH).max(0) as usize;
    let length = label.chars().count();
    if length <= fits {
        Some(label.to_string())
    } else if fits >= 3 {
        Some(label.chars().take(fits - 1).chain(std::iter::once('…')).collect())
    } else {
        None
    }
}

/// A bar of a chart: a lane, a label (the action), a colour key, its interval (program time
/// units) and how it ended.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Bar {
    /// The lane, an index into the chart's lanes.
    pub lane: usize,
    /// The full text, shown on hover.
    pub title: String,
    /// The short text drawn on the bar, and the key of its colour.
    pub label: String,
    /// Start and end times.
    pub start: i64,
    /// End time.
    pub end: i64,
    /// How it ended.
    pub ending: Ending,
}

/// How a bar's action ended (`done`, `failed` or `halted` in the `--view` page's data).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Ending {
    /// As planned, or successfully.
    Done,
    /// It failed.
    Failed,
    /// The tree stopped it.
    Halted,
}

/// The SVG chart of `schedule`.
pub fn svg(interner: &Interner, kb: &Kb, pop: &Pop, schedule: &Schedule) -> String {
    let no_vars = VarTable::default();
    let units = kb.resource_units(&kb.problems[pop.problem].init);
    let actions = schedule::timed_actions(kb, pop, schedule);
    let lane_of = |name: &Term| -> usize {
        name.args().iter().find_map(|a| units.iter().position(|u| u == a)).unwrap_or(units.len())
    };
    let mut lanes: Vec<String> = units.iter().map(|u| hir::term_to_string(interner, u, &no_vars)).collect();
    if actions.iter().any(|a| lane_of(&a.name) == units.len()) {
        lanes.push("other".to_string());
    }
    let bars: Vec<Bar> = actions
        .iter()
        .filter_map(|action| {
            let duration = action.duration?;
            let shown = hir::term_to_string(interner, &action.name, &no_vars);
            let short = action.name.callable().map_or(shown.clone(), |(name, _)| interner.resolve(name).to_string());
            Some(Bar {
                lane: lane_of(&action.name),
                title: shown,
                label: short,
                start: action.time,
                end: action.time + duration,
                ending: Ending::Done,
            })
        })
        .collect();
    let title = format!(
        "schedule of {}: makespan {}",
        interner.resolve(kb.problems[pop.problem].name),
        format_time(schedule.makespan)
    );
    draw(&title, &lanes, &bars, &[], schedule.makespan)
}

/// The bars of a schedule's durative actions on lanes named by unit: an action goes to the
/// lane `lane_of` gives the first of its arguments it knows (actions it places nowhere are
/// left out).
pub fn schedule_bars(
    interner: &Interner,
    kb: &Kb,
    pop: &Pop,
    schedule: &Schedule,
    lane_of: &dyn Fn(&str) -> Option<usize>,
) -> Vec<Bar> {
    let no_vars = VarTable::default();
    schedule::timed_actions(kb, pop, schedule)
        .iter()
        .filter_map(|action| {
            let duration = action.duration?;
            let lane = action.name.args().iter().find_map(|a| lane_of(&hir::term_to_string(interner, a, &no_vars)))?;
            let shown = hir::term_to_string(interner, &action.name, &no_vars);
            let short = action.name.callable().map_or(shown.clone(), |(name, _)| interner.resolve(name).to_string());
            Some(Bar {
                lane,
                title: shown,
                label: short,
                start: action.time,
                end: action.time + duration,
                ending: Ending::Done,
            })
        })
        .collect()
}

/// Draws a chart: a lane per name, the bars, vertical marks (time, text) such as faults, over
/// `[0, span]` program time units (1000 per KB time unit).
pub fn draw(title: &str, lanes: &[String], bars: &[Bar], marks: &[(i64, String)], span: i64) -> String {
    let span = span.max(UNITS);
    let x = |t: i64| LEFT + t.clamp(0, span) * WIDTH / span;
    // The chart, its axis, then a legend row.
    let height = 40 + LANE * lanes.len().max(1) as i64 + 30 + 22;
    let axis = 30 + LANE * lanes.len().max(1) as i64;
    let mut out = String::new();
    // The data attributes give the time axis (x0 at time 0, x1 at `span` program units, the
    // lanes from y0 to y1), for a page that draws a time cursor over the chart.
    let _ = writeln!(
        out,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{height}\" font-family=\"sans-serif\" font-size=\"11\" data-x0=\"{LEFT}\" data-x1=\"{}\" data-span=\"{span}\" data-y0=\"26\" data-y1=\"{axis}\">",
        LEFT + WIDTH + 20,
        LEFT + WIDTH
    );
    let _ = writeln!(out, "<text x=\"{LEFT}\" y=\"16\" font-size=\"13\">{}</text>", escape(title));
    for (lane, label) in lanes.iter().enumerate() {
        let y = 30 + LANE * lane as i64;
        let _ = writeln!(out, "<text x=\"4\" y=\"{}\">{}</text>", y + LANE / 2 + 4, escape(label));
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
    let mut colours: Vec<&str> = Vec::new();
    for bar in bars {
        let colour = match colours.iter().position(|&c| c == bar.label) {
            Some(i) => i,
            None => {
                colours.push(&bar.label);
                colours.len() - 1
            }
        };
        let (x0, x1) = (x(bar.start), x(bar.end));
        let y = 30 + LANE * bar.lane as i64 + 4;
        let (fill, stroke, ended) = match bar.ending {
            Ending::Done => (PALETTE[colour % PALETTE.len()], "none", ""),
            Ending::Failed => (PALETTE[colour % PALETTE.len()], "#d00", ", failed"),
            Ending::Halted => ("#bbb", "none", ", halted"),
        };
        let _ = writeln!(
            out,
            "<rect x=\"{x0}\" y=\"{y}\" width=\"{}\" height=\"{}\" fill=\"{fill}\" stroke=\"{stroke}\" stroke-width=\"2\" opacity=\"0.85\"><title>{} from {} to {}{ended}</title></rect>",
            (x1 - x0).max(1),
            LANE - 8,
            escape(&bar.title),
            format_time(bar.start),
            format_time(bar.end)
        );
        if let Some(label) = fitted(&bar.label, x1 - x0 - 6) {
            let _ = writeln!(out, "<text x=\"{}\" y=\"{}\" fill=\"white\">{}</text>", x0 + 3, y + 15, escape(&label));
        }
    }
    for (t, text) in marks {
        let _ = writeln!(
            out,
            "<line x1=\"{0}\" y1=\"26\" x2=\"{0}\" y2=\"{axis}\" stroke=\"#d00\" stroke-dasharray=\"4 3\"><title>{1}</title></line>",
            x(*t),
            escape(text)
        );
    }
    // The legend: a swatch per action, then what outlines, grey and dashed lines mean where
    // the chart has them. (Widths estimated at 7 px a character.)
    let legend_y = axis + 30;
    let mut at = LEFT;
    let mut entries: Vec<(String, String)> = colours
        .iter()
        .enumerate()
        .map(|(i, name)| (format!("fill=\"{}\"", PALETTE[i % PALETTE.len()]), (*name).to_string()))
        .collect();
    if bars.iter().any(|b| b.ending == Ending::Failed) {
        entries.push(("fill=\"white\" stroke=\"#d00\" stroke-width=\"2\"".to_string(), "failed".to_string()));
    }
    if bars.iter().any(|b| b.ending == Ending::Halted) {
        entries.push(("fill=\"#bbb\"".to_string(), "halted".to_string()));
    }
    for (style, text) in &entries {
        let _ = writeln!(
            out,
            "<rect x=\"{at}\" y=\"{}\" width=\"10\" height=\"10\" {style}/><text x=\"{}\" y=\"{legend_y}\">{}</text>",
            legend_y - 9,
            at + 14,
            escape(text)
        );
        at += 14 + 7 * text.chars().count() as i64 + 16;
    }
    if !marks.is_empty() {
        let _ = writeln!(
            out,
            "<line x1=\"{at}\" y1=\"{0}\" x2=\"{at}\" y2=\"{1}\" stroke=\"#d00\" stroke-dasharray=\"4 3\"/><text x=\"{2}\" y=\"{legend_y}\">fault</text>",
            legend_y - 10,
            legend_y + 2,
            at + 6
        );
    }
    out.push_str("</svg>\n");
    out
}

#[cfg(test)]
mod tests {
    use super::fitted;

    #[test]
    fn labels_are_cut_to_the_bar() {
        assert_eq!(fitted("grip", 100).as_deref(), Some("grip"));
        assert_eq!(fitted("move_block", 49).as_deref(), Some("move_b…"), "7 characters fit in 49 px");
        assert_eq!(fitted("move_block", 20), None, "2 characters fit: none drawn");
    }
}
