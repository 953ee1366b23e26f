//! `kbc run --view run.html` in a real browser: headless Chromium loads the page at the start,
//! the middle and the end of a run with a fault and a recovery, takes a screenshot of each,
//! and dumps the DOM the page's script built. At the end, the cell and level the page shows for
//! each block must be where the goal puts it (the run checked the goal in the world read back)
//! and where the recorded poses put it (computed here, not by the page).
//!
//! Chromium comes from Debian (`.ci/run` installs it); without it the test says so and passes.

mod common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

const WIDTH: u32 = 1280;
const HEIGHT: u32 = 1400;

fn chromium() -> Option<&'static str> {
    ["chromium", "chromium-browser", "google-chrome"]
        .into_iter()
        .find(|name| Command::new(name).arg("--version").output().is_ok_and(|o| o.status.success()))
}

/// Runs headless Chromium on `page` with `args` (a screenshot or a DOM dump); its stdout.
fn browse(browser: &str, page: &Path, fragment: &str, args: &[String]) -> String {
    let url = format!("file://{}#t={fragment}", page.display());
    let output = Command::new(browser)
        .args(["--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars", "--no-first-run"])
        .arg(format!("--window-size={WIDTH},{HEIGHT}"))
        .args(args)
        .arg(&url)
        .output()
        .expect("the browser runs");
    assert!(output.status.success(), "{browser} on {url}: {}", String::from_utf8_lossy(&output.stderr));
    String::from_utf8_lossy(&output.stdout).into_owned()
}

/// A PNG's width and height, from its signature and IHDR chunk.
fn png_size(bytes: &[u8]) -> Option<(u32, u32)> {
    let signature = [0x89, b'P', b'N', b'G', b'\r', b'\n', 0x1a, b'\n'];
    if bytes.len() < 24 || bytes[..8] != signature || &bytes[12..16] != b"IHDR" {
        return None;
    }
    let word = |at: usize| u32::from_be_bytes(bytes[at..at + 4].try_into().expect("four bytes"));
    Some((word(16), word(20)))
}

/// The value of attribute `name` in an element's start tag.
fn attribute<'a>(tag: &'a str, name: &str) -> Option<&'a str> {
    let start = tag.find(&format!(" {name}=\""))? + name.len() + 3;
    Some(&tag[start..start + tag[start..].find('"')?])
}

/// Each block the page lists: (cell, level) when it stands on a cell.
fn shown_blocks(dom: &str) -> BTreeMap<String, Option<(String, u32)>> {
    dom.split("<tr ")
        .skip(1)
        .filter_map(|rest| {
            let tag = format!(" {}", &rest[..rest.find('>')?]);
            let tag = tag.as_str();
            let block = attribute(tag, "data-block")?.to_string();
            let place = attribute(tag, "data-cell")
                .map(|cell| (cell.to_string(), attribute(tag, "data-level").and_then(|l| l.parse().ok()).unwrap_or(0)));
            Some((block, place))
        })
        .collect()
}

/// Where the goal of the example's problem puts each block: (cell, level).
fn goal_places(file: &str) -> BTreeMap<String, (String, u32)> {
    let session = common::load(&[file]);
    let kb = session.kb();
    let problem = &kb.problems[0];
    let mut table = BTreeMap::new();
    let mut above = BTreeMap::new();
    for literal in &problem.goal {
        let text = kbc::ir::hir::term_to_string(session.interner(), &literal.term, &problem.vars);
        let args: Vec<String> = text
            .split_once('(')
            .map(|(_, rest)| rest.trim_end_matches(')').split(',').map(|a| a.trim().to_string()).collect())
            .unwrap_or_default();
        if text.starts_with("ontable(") {
            table.insert(args[0].clone(), format!("{},{}", args[1], args[2]));
        } else if text.starts_with("on(") {
            above.insert(args[0].clone(), (args[1].clone(), format!("{},{}", args[2], args[3])));
        }
    }
    let mut places: BTreeMap<String, (String, u32)> = table.into_iter().map(|(b, c)| (b, (c, 0))).collect();
    while !above.is_empty() {
        let ready: Vec<(String, (String, u32))> = above
            .iter()
            .filter_map(|(b, (below, cell))| places.get(below).map(|(_, level)| (b.clone(), (cell.clone(), level + 1))))
            .collect();
        if ready.is_empty() {
            break;
        }
        for (block, place) in ready {
            above.remove(&block);
            places.insert(block, place);
        }
    }
    places
}

#[test]
fn the_run_page_renders_in_a_browser_and_ends_where_the_run_ended() {
    let Some(browser) = chromium() else {
        eprintln!("skipped: no Chromium on this machine (CI installs it; `apt-get install chromium`)");
        return;
    };
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("view");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    let example = "examples/02_llm_stacking/test_case.pl";
    let (page, record) = (dir.join("run.html"), dir.join("run.json"));
    let output = Command::new(env!("CARGO_BIN_EXE_kbc"))
        .args(["run", "-q", example, "--fault", "drop:a2@move_block(a2", "--view"])
        .arg(&page)
        .arg("--record")
        .arg(&record)
        .output()
        .expect("kbc runs");
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{stdout}{}", String::from_utf8_lossy(&output.stderr));
    assert!(stdout.contains("goal reached after 1 recovery"), "{stdout}");

    for moment in ["0", "mid", "end"] {
        let shot = dir.join(format!("run-{moment}.png"));
        browse(browser, &page, moment, &[format!("--screenshot={}", shot.display())]);
        let bytes = std::fs::read(&shot).expect("the screenshot is written");
        assert_eq!(png_size(&bytes), Some((WIDTH, HEIGHT)), "{moment}: a PNG of the window's size");
        let dom = browse(browser, &page, moment, &["--dump-dom".to_string()]);
        let body = &dom[dom.find("<body").expect("a body")..];
        let body = &body[..body.find('>').expect("a tag")];
        let drawn: u32 = attribute(body, "data-drawn").and_then(|d| d.parse().ok()).expect("data-drawn");
        assert!(drawn > 50_000, "{moment}: the top view drew {drawn} pixels");
        assert!(dom.contains("<li class=\"fault\">") == (moment != "0"), "{moment}: the fault is marked once past");
    }

    // At the end: the goal's places, as the page shows them and as the recorded poses say.
    let dom = browse(browser, &page, "end", &["--dump-dom".to_string()]);
    let shown = shown_blocks(&dom);
    let goal = goal_places(example);
    assert_eq!(goal.len(), 4, "the example stacks four blocks: {goal:?}");
    for (block, place) in &goal {
        assert_eq!(shown.get(block), Some(&Some(place.clone())), "{block}: the page at the end vs the goal");
    }
    let record: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&record).expect("the record")).expect("JSON");
    let (cell, size) = (record["cell_size"].as_f64().unwrap(), record["block_size"].as_f64().unwrap());
    let last = record["frames"].as_array().unwrap().last().expect("frames").clone();
    for (i, name) in record["blocks"].as_array().unwrap().iter().enumerate() {
        let pose: Vec<f64> = last["blocks"][i].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
        let at = format!("{},{}", (pose[0] / cell).round(), (pose[1] / cell).round());
        let level = ((pose[2] - size / 2.0) / size).round() as u32;
        assert_eq!(shown[name.as_str().unwrap()], Some((at, level)), "{name}: the page vs the recorded pose");
    }
}
