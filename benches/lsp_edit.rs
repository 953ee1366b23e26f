//! Time from a one-character edit to published diagnostics in `kbc lsp`, on a 10,000-line KB
//! (issue 7: under 50 ms).
//!
//! `cargo bench --bench lsp_edit` generates a KB of 10,000 lines (durative action schemas
//! over shared fluents, durations, static facts and rules, tests), checks that it is clean,
//! then runs the server in-process (lsp-server's memory connection, the JSON values an editor
//! would exchange) and, 20 times over, inserts one character into a predicate name in the
//! middle of the file (an E0210 appears) and deletes it again (it goes), timing each
//! `didChange` to the `publishDiagnostics` that follows. Once with the server's default
//! debounce (the quiet period it waits for before checking, included in the figure) and once
//! with none, which is the cost of the check itself; and the front end alone on the same text.

#[path = "../tests/support/lsp_client.rs"]
mod client;

use std::fmt::Write as _;
use std::time::{Duration, Instant};

use kbc::session::Session;
use serde_json::json;

const ACTIONS: usize = 200;

/// A clean KB of exactly `lines` lines.
fn generate(lines: usize) -> String {
    let mut kb =
        String::from("% Generated for benches/lsp_edit.rs: a large KB that checks clean.\nresources(agent(_)).\n");
    for i in 0..ACTIONS {
        let next = (i + 1) % ACTIONS;
        writeln!(kb, "action(step{i}_start(A, B), [agent(A), stage{i}(B), clear(B)], [], [], [cell(B, _)],").unwrap();
        writeln!(kb, "    [del(agent(A)), del(stage{i}(B)), add(busy{i}(A, B))]).").unwrap();
        writeln!(kb, "action(step{i}_end(A, B), [busy{i}(A, B)], [], [], [],").unwrap();
        writeln!(kb, "    [del(busy{i}(A, B)), add(agent(A)), add(stage{next}(B))]).").unwrap();
    }
    for i in 0..ACTIONS {
        writeln!(kb, "duration(step{i}(_, _), 1, 3).").unwrap();
    }
    let problems = 100;
    let rest = lines - kb.lines().count() - problems;
    let rules = rest / 10;
    for r in 0..rules / 2 {
        writeln!(kb, "near(X, Y) :- cell(X, Y), link(X, Z{r}), Z{r} > 0.").unwrap();
    }
    for r in 0..rules - rules / 2 {
        writeln!(kb, "far(X, Y) :- cell(X, Y), \\+ near(X, Y), Y >= {r}.").unwrap();
    }
    let facts = rest - rules;
    for f in 0..facts / 2 {
        writeln!(kb, "cell(b{f}, {}).", f % 97).unwrap();
    }
    for f in 0..facts - facts / 2 {
        writeln!(kb, "link(b{f}, {}).", f % 89).unwrap();
    }
    for p in 0..problems {
        let stage = p % ACTIONS;
        writeln!(
            kb,
            "test{p} :- go([agent(a1), agent(a2), stage{stage}(b{p}), clear(b{p})], [stage{}(b{p})]).",
            (stage + 3) % ACTIONS
        )
        .unwrap();
    }
    kb
}

fn stats(label: &str, mut samples: Vec<Duration>) {
    samples.sort();
    let ms = |d: Duration| d.as_secs_f64() * 1e3;
    let median = samples[samples.len() / 2];
    let p90 = samples[samples.len() * 9 / 10];
    println!(
        "{label:<46} median {:>7.2} ms   p90 {:>7.2} ms   max {:>7.2} ms   ({} edits)",
        ms(median),
        ms(p90),
        ms(*samples.last().unwrap()),
        samples.len()
    );
}

fn session(text: &str, debounce: Option<u64>) -> Vec<Duration> {
    let dir = std::env::temp_dir().join(format!("kbc-bench-lsp-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let dir = std::fs::canonicalize(&dir).unwrap();
    let path = dir.join("big.pl");
    std::fs::write(&path, text).unwrap();
    let uri = lsp_types::Url::from_file_path(&path).unwrap().to_string();
    let options = match debounce {
        Some(ms) => json!({ "debounceMs": ms }),
        None => json!({}),
    };
    let mut client = client::Client::start(&dir, options);
    client.open(&uri, text);
    let initial = client.diagnostics(&uri);
    assert!(initial.is_empty(), "the generated KB checks clean: {:?}", initial.first());
    // `clear(B)` of the middle action's Valid list: `c|lear` becomes `cxlear` and back.
    let middle = text.lines().position(|l| l.starts_with(&format!("action(step{}_start", ACTIONS / 2))).unwrap();
    let column = text.lines().nth(middle).unwrap().find("clear(B)").unwrap() + 1;
    let at = json!({ "line": middle, "character": column });
    let after = json!({ "line": middle, "character": column + 1 });
    let mut samples = Vec::new();
    let mut version = 1;
    for _ in 0..20 {
        for (range, new_text, errors) in
            [(json!({ "start": at, "end": at }), "x", 1), (json!({ "start": at, "end": after }), "", 0)]
        {
            version += 1;
            let started = Instant::now();
            client.notify(
                "textDocument/didChange",
                json!({
                    "textDocument": { "uri": uri, "version": version },
                    "contentChanges": [{ "range": range, "text": new_text }],
                }),
            );
            let diagnostics = client.diagnostics(&uri);
            samples.push(started.elapsed());
            assert_eq!(diagnostics.len(), errors, "{diagnostics:?}");
        }
    }
    assert!(client.shutdown());
    let _ = std::fs::remove_dir_all(&dir);
    samples
}

fn main() {
    let text = generate(10_000);
    println!("KB: {} lines, {} bytes, {ACTIONS} durative actions", text.lines().count(), text.len());
    let frontend: Vec<Duration> = (0..20)
        .map(|_| {
            let started = Instant::now();
            let session = Session::from_text("big.pl", text.clone());
            assert!(!session.has_errors());
            started.elapsed()
        })
        .collect();
    stats("front end alone (Session::from_text)", frontend);
    stats("edit -> diagnostics, no debounce", session(&text, Some(0)));
    let default = kbc::lsp::DEFAULT_DEBOUNCE.as_millis();
    stats(&format!("edit -> diagnostics, default {default} ms debounce"), session(&text, None));
}
