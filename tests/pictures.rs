//! Every picture kbc draws is read by the tool it is for: Graphviz's `dot` lays out each DOT
//! file (the partial order, the STN, the behaviour tree) without a warning, and Python's XML
//! parser reads each SVG (the Gantt charts, and `dot`'s own output). Names that need escaping
//! (quotes, a backslash, `<`, `&`) come out in the drawing as the KB wrote them.
//!
//! Graphviz comes from Debian (`.ci/run` installs it); without it the test says so and passes.

use std::path::{Path, PathBuf};
use std::process::Command;

const KB: &str = r#"% Names a DOT or XML writer must escape: quotes, a backslash, angle brackets, an ampersand.
place('room "A"'). place('back\\slash'). place('<hall> & co').
action(go_start(F, T), [at(F)], [], [], [place(T), F \= T], [del(at(F)), add(moving(F, T))]).
action(go_end(F, T), [moving(F, T)], [], [], [], [del(moving(F, T)), add(at(T)), add(visited(T))]).
duration(go(_, _), 1, 2).
trip :- go([at('room "A"')], [visited('<hall> & co'), at('back\\slash')]).
"#;

/// The names as the plan's drawings must show them: quoted as the KB writes them (and as
/// `kbc plan` prints them), with the backslash doubled inside the quotes.
const NAMES: [&str; 3] = ["'room \"A\"'", "'back\\\\slash'", "'<hall> & co'"];

/// The same names as the behaviour tree shows them: the bytecode's action text, unquoted.
const BT_NAMES: [&str; 3] = ["room \"A\"", "back\\slash", "<hall> & co"];

fn kbc(dir: &Path, args: &[&str]) {
    let output = Command::new(env!("CARGO_BIN_EXE_kbc")).args(args).current_dir(dir).output().expect("kbc runs");
    assert!(output.status.success(), "kbc {args:?}: {}", String::from_utf8_lossy(&output.stderr));
}

/// The text of an SVG file, every text node joined, as an XML parser reads it (unescaped).
fn svg_text(path: &Path) -> String {
    let script = "import sys, xml.etree.ElementTree as E; print(' '.join(E.parse(sys.argv[1]).getroot().itertext()))";
    let output = Command::new("python3").args(["-c", script]).arg(path).output().expect("python3 runs");
    assert!(output.status.success(), "{} is not XML: {}", path.display(), String::from_utf8_lossy(&output.stderr));
    String::from_utf8_lossy(&output.stdout).into_owned()
}

#[test]
fn graphviz_and_an_xml_parser_read_every_picture_with_its_names_intact() {
    if !Command::new("dot").arg("-V").output().is_ok_and(|o| o.status.success()) {
        eprintln!("skipped: Graphviz's `dot` is not installed (apt-get install graphviz); .ci/run installs it");
        return;
    }
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("pictures");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("writable");
    std::fs::write(dir.join("trip.pl"), KB).expect("writable");
    let example = std::fs::canonicalize("examples/02_llm_stacking/test_case.pl").expect("the example");
    let example = example.to_str().expect("UTF-8");
    kbc(&dir, &["plan", "-q", "trip.pl", "--emit", "pop-dot", "-o", "trip-pop.dot"]);
    kbc(&dir, &["plan", "-q", "trip.pl", "--emit", "stn-dot", "-o", "trip-stn.dot"]);
    kbc(&dir, &["build", "-q", "trip.pl", "--emit", "bt-dot", "-o", "trip-bt.dot"]);
    kbc(&dir, &["plan", "-q", "trip.pl", "--emit", "gantt-svg", "-o", "trip-gantt.svg"]);
    kbc(&dir, &["plan", "-q", example, "--emit", "pop-dot", "-o", "stack-pop.dot"]);
    kbc(&dir, &["plan", "-q", example, "--emit", "stn-dot", "-o", "stack-stn.dot"]);
    kbc(&dir, &["build", "-q", example, "--emit", "bt-dot", "-o", "stack-bt.dot"]);
    kbc(&dir, &["run", "-q", example, "--fault", "drop:a2@1", "--gantt-svg", "stack-run.svg"]);
    for name in ["trip-pop", "trip-stn", "trip-bt", "stack-pop", "stack-stn", "stack-bt"] {
        let svg = dir.join(format!("{name}.svg"));
        let output = Command::new("dot")
            .arg("-Tsvg")
            .arg(dir.join(format!("{name}.dot")))
            .arg("-o")
            .arg(&svg)
            .output()
            .expect("dot");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(output.status.success() && stderr.trim().is_empty(), "dot on {name}.dot: {stderr}");
        let text = svg_text(&svg);
        if name.starts_with("trip") {
            for shown in if name == "trip-bt" { BT_NAMES } else { NAMES } {
                assert!(text.contains(shown), "{name}: `{shown}` is not in the drawing:\n{text}");
            }
        }
    }
    let gantt = svg_text(&dir.join("trip-gantt.svg"));
    assert!(gantt.contains("go"), "the trip's chart names its actions: {gantt}");
    assert!(svg_text(&dir.join("stack-run.svg")).contains("planned"), "the run's chart has its planned lanes");
}
