//! `kbc run --view run.html`: one self-contained HTML page that replays a simulated run.
//!
//! The page carries everything it needs: the recorded poses (the `--record` JSON, see
//! docs/json.md), the actions as they ran, the planned-versus-executed Gantt chart as inline
//! SVG, and the drawing code (`view.js`, `view.css`, written for kbc; no third-party code, no
//! network). It draws a top view and a side view of the table, the blocks with their names and
//! the arms (base, elbow, gripper) on two canvases, with a time slider, play and pause, the
//! actions running at the moment, faults marked on the slider and the chart, and a table of
//! each block's position and cell.
//!
//! A URL fragment chooses the moment to show: `run.html#t=end`, `#t=mid` or `#t=12.5`
//! (seconds). The block table's rows carry `data-block`, `data-cell` and `data-level`
//! attributes, and `<body>` carries `data-time` and `data-drawn` (pixels the top view drew),
//! so a headless browser's DOM says what the page shows.

use serde::Serialize;

use super::xml_escape as escape;

/// An action as it ran on the simulated arms.
#[derive(Clone, Debug, Serialize)]
pub struct RanAction {
    /// The arm that ran it, if its name has one.
    pub arm: Option<String>,
    /// The action as the program names it.
    pub text: String,
    /// Seconds of simulated time, from the start of the run.
    pub start: f64,
    /// Seconds; the action's end, or when it failed or was halted.
    pub end: f64,
    /// How it ended.
    pub ending: super::gantt::Ending,
}

/// What the page shows.
pub struct RunView<'a> {
    /// The page's heading (the problem's name).
    pub title: &'a str,
    /// How the run ended, one line.
    pub summary: &'a str,
    /// The recorded poses, as `--record` writes them.
    pub record: &'a serde_json::Value,
    /// The actions as they ran.
    pub actions: &'a [RanAction],
    /// The planned-versus-executed Gantt chart (SVG), when there is a plan to compare with.
    pub gantt_svg: Option<&'a str>,
}

const SCRIPT: &str = include_str!("view.js");
const STYLE: &str = include_str!("view.css");

/// The page.
pub fn html(view: &RunView<'_>) -> String {
    let data = serde_json::json!({ "record": view.record, "actions": view.actions });
    // Inside <script>, "</" would end the element: JSON allows "<" escaped as \u003c.
    let data = serde_json::to_string(&data).expect("JSON of plain values").replace('<', "\\u003c");
    let gantt = match view.gantt_svg {
        Some(svg) => svg.to_string(),
        None => "<p>No plan to compare with: the run was of a bytecode file.</p>".to_string(),
    };
    let title = escape(view.title);
    let summary = escape(view.summary);
    format!(
        r#"<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<meta name="generator" content="kbc {version}">
<title>kbc run: {title}</title>
<style>
{STYLE}</style>
</head>
<body data-time="0" data-drawn="0">
<header>
<h1>{title}</h1>
<p id="summary">{summary}</p>
</header>
<section class="views">
<figure><canvas id="top" width="580" height="440" aria-label="top view of the table"></canvas>
<figcaption>Top view: x to the right, y up; darker blocks stand higher</figcaption></figure>
<figure><canvas id="side" width="580" height="440" aria-label="side view of the table"></canvas>
<figcaption>Side view, looking along y: x to the right, z up</figcaption></figure>
</section>
<section class="controls">
<button id="play" type="button" title="play or pause (space)">Play</button>
<div class="track"><input id="slider" type="range" min="0" max="0" step="0.01" value="0" aria-label="time">
<div id="marks"></div></div>
<output id="clock">0.00 s</output>
<label>speed <select id="speed"><option value="0.25">¼×</option><option value="0.5">½×</option><option value="1" selected>1×</option><option value="2">2×</option><option value="4">4×</option></select></label>
</section>
<section class="now">
<div><h2>Running now</h2><ul id="running"></ul></div>
<div><h2>Faults</h2><ul id="faults"></ul></div>
</section>
<section class="gantt">
<h2>Planned and executed</h2>
<div id="gantt">
{gantt}
</div>
</section>
<section class="blocks">
<h2>Blocks at this moment</h2>
<table id="readout"><thead><tr><th>block</th><th>x (m)</th><th>y (m)</th><th>z (m)</th><th>where</th></tr></thead><tbody></tbody></table>
</section>
<footer>Written by kbc {version}. Keys: space plays or pauses, ← and → step a tenth of a second, Home and End jump.</footer>
<script type="application/json" id="run-data">{data}</script>
<script>
{SCRIPT}</script>
</body>
</html>
"#,
        version = env!("CARGO_PKG_VERSION"),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_embedded_data_cannot_close_its_script_element() {
        let record = serde_json::json!({ "blocks": ["</script><b>"] });
        let page = html(&RunView { title: "t<1>", summary: "a & b", record: &record, actions: &[], gantt_svg: None });
        let data = page.split("id=\"run-data\">").nth(1).and_then(|rest| rest.split("</script>").next());
        let parsed: serde_json::Value = serde_json::from_str(data.expect("the data element")).expect("JSON");
        assert_eq!(parsed["record"]["blocks"][0], "</script><b>");
        assert!(page.contains("<h1>t&lt;1&gt;</h1>") && page.contains("a &amp; b"));
    }
}
